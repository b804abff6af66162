//! A root of a scalar function on a sign-changing bracket without derivatives: false position
//! with the Illinois modification (the retained end's value halved when the same end is kept
//! twice), which keeps the bracket and converges superlinearly on smooth functions.

/// x in [lo, hi] with f(x) = 0, to a bracket narrower than `x_tolerance`; `f_lo`, `f_hi` the
/// values at the ends, of opposite signs (or one of them zero). Returns the end of the last
/// bracket with the smaller |f|, or `None` when the signs do not differ, a value is not finite
/// or `max_iterations` pass first.
pub fn false_position(
    mut f: impl FnMut(f64) -> f64,
    [mut lo, mut hi]: [f64; 2],
    [mut f_lo, mut f_hi]: [f64; 2],
    x_tolerance: f64,
    max_iterations: usize,
) -> Option<f64> {
    if f_lo == 0.0 {
        return Some(lo);
    }
    if f_hi == 0.0 {
        return Some(hi);
    }
    if f_lo.signum() == f_hi.signum() || !f_lo.is_finite() || !f_hi.is_finite() {
        return None;
    }
    let mut kept = 0i8;
    for _ in 0..max_iterations {
        if hi - lo <= x_tolerance {
            return Some(if f_lo.abs() < f_hi.abs() { lo } else { hi });
        }
        let x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let x = if x > lo && x < hi { x } else { 0.5 * (lo + hi) };
        let fx = f(x);
        if !fx.is_finite() {
            return None;
        }
        if fx == 0.0 {
            return Some(x);
        }
        if fx.signum() == f_lo.signum() {
            (lo, f_lo) = (x, fx);
            if kept == 1 {
                f_hi *= 0.5;
            }
            kept = 1;
        } else {
            (hi, f_hi) = (x, fx);
            if kept == -1 {
                f_lo *= 0.5;
            }
            kept = -1;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_cube_root_of_two() {
        let f = |x: f64| x * x * x - 2.0;
        let root = false_position(f, [0.0, 3.0], [f(0.0), f(3.0)], 1e-14, 200).unwrap();
        assert!((root - 2f64.cbrt()).abs() < 1e-13, "{root}");
    }

    #[test]
    fn keeps_to_the_bracket_of_a_flat_function() {
        // Zero on [1, 2]: the root returned lies there.
        let f = |x: f64| if x < 1.0 { 1.0 - x } else if x > 2.0 { 2.0 - x } else { 0.0 };
        let root = false_position(f, [-5.0, 1.5], [6.0, 0.0], 1e-12, 100).unwrap();
        assert_eq!(root, 1.5);
        let root = false_position(f, [-5.0, 9.0], [6.0, -7.0], 1e-12, 200).unwrap();
        assert!((1.0..=2.0).contains(&root), "{root}");
    }

    #[test]
    fn refuses_ends_of_one_sign() {
        assert_eq!(false_position(|x| x, [1.0, 2.0], [1.0, 2.0], 1e-12, 10), None);
        assert_eq!(false_position(|x| x, [-1.0, 2.0], [f64::NAN, 2.0], 1e-12, 10), None);
    }
}
