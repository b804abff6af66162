//! Safeguarded Newton's method on a bracket (Numerical Recipes' `rtsafe`): a Newton step when it
//! stays inside the bracket and shrinks the residual fast enough, a bisection step otherwise.
//! Converges for any continuous residual that changes sign on the bracket.

/// A root of a residual on a bracket.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Root {
    pub x: f64,
    pub residual: f64,
    pub iterations: usize,
}

/// Why no root was returned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RootFailure {
    /// The residual has the same sign at both ends: `(r(lo), r(hi))`.
    NoSignChange(f64, f64),
    /// A residual or derivative was not finite at `x`.
    NotFinite(f64),
    /// Still not converged after the iteration limit; the best point so far.
    NotConverged(Root),
}

/// One end of a bracket: x and the residual there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BracketEnd {
    pub x: f64,
    pub residual: f64,
}

/// Finds x in [lo, hi] with |r(x)| ≤ `residual_tolerance` or a bracket narrower than
/// `x_tolerance`, starting at the midpoint. `residual` returns (r(x), dr/dx).
pub fn bracketed_newton(
    mut residual: impl FnMut(f64) -> (f64, f64),
    lo: f64,
    hi: f64,
    x_tolerance: f64,
    residual_tolerance: f64,
    max_iterations: usize,
) -> Result<Root, RootFailure> {
    let lo_end = BracketEnd { x: lo, residual: residual(lo).0 };
    let hi_end = BracketEnd { x: hi, residual: residual(hi).0 };
    bracketed_newton_from(
        residual,
        0.5 * (lo + hi),
        lo_end,
        hi_end,
        x_tolerance,
        residual_tolerance,
        max_iterations,
    )
}

/// `bracketed_newton` on a bracket whose end residuals the caller has, starting at `start`
/// (clamped into the bracket): a good first guess saves iterations, a bad one costs
/// bisections, never convergence.
pub fn bracketed_newton_from(
    residual: impl FnMut(f64) -> (f64, f64),
    start: f64,
    lo: BracketEnd,
    hi: BracketEnd,
    x_tolerance: f64,
    residual_tolerance: f64,
    max_iterations: usize,
) -> Result<Root, RootFailure> {
    let (r_lo, r_hi) = (lo.residual, hi.residual);
    for BracketEnd { x, residual: r } in [lo, hi] {
        if !r.is_finite() {
            return Err(RootFailure::NotFinite(x));
        }
        if r.abs() <= residual_tolerance {
            return Ok(Root {
                x,
                residual: r,
                iterations: 0,
            });
        }
    }
    if (r_lo > 0.0) == (r_hi > 0.0) {
        return Err(RootFailure::NoSignChange(r_lo, r_hi));
    }
    // Orient so that r(negative_end) < 0 < r(positive_end).
    let (negative_end, positive_end) = if r_lo < 0.0 { (lo.x, hi.x) } else { (hi.x, lo.x) };
    newton_between(residual, start, negative_end, positive_end, x_tolerance, residual_tolerance, max_iterations)
}

/// The safeguarded iteration of `bracketed_newton` when the caller knows, without evaluating
/// them, that r < 0 at `negative_end` and r > 0 at `positive_end`. Converging to either end
/// with a residual above `residual_tolerance` means that end's sign was wrong.
pub fn newton_between(
    mut residual: impl FnMut(f64) -> (f64, f64),
    start: f64,
    mut negative_end: f64,
    mut positive_end: f64,
    x_tolerance: f64,
    residual_tolerance: f64,
    max_iterations: usize,
) -> Result<Root, RootFailure> {
    let (lo, hi) = (negative_end.min(positive_end), negative_end.max(positive_end));
    let mut x = start.clamp(lo, hi);
    let mut last_step = hi - lo;
    let mut best = Root {
        x,
        residual: f64::INFINITY,
        iterations: 0,
    };
    for iteration in 1..=max_iterations {
        let (r, dr) = residual(x);
        if !r.is_finite() || !dr.is_finite() {
            return Err(RootFailure::NotFinite(x));
        }
        if r.abs() < best.residual.abs() {
            best = Root {
                x,
                residual: r,
                iterations: iteration,
            };
        }
        if r.abs() <= residual_tolerance {
            return Ok(Root {
                x,
                residual: r,
                iterations: iteration,
            });
        }
        if r < 0.0 {
            negative_end = x
        } else {
            positive_end = x
        }
        let newton = x - r / dr;
        let inside = (newton - negative_end) * (newton - positive_end) < 0.0;
        let fast = (2.0 * r).abs() <= (last_step * dr).abs();
        let next = if dr != 0.0 && inside && fast {
            newton
        } else {
            0.5 * (negative_end + positive_end)
        };
        last_step = (next - x).abs();
        x = next;
        if (positive_end - negative_end).abs() <= x_tolerance {
            let (r, _) = residual(x);
            return Ok(Root {
                x,
                residual: r,
                iterations: iteration,
            });
        }
    }
    Err(RootFailure::NotConverged(best))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_cubic_from_either_orientation() {
        let f = |x: f64| (x * x * x - 2.0, 3.0 * x * x);
        for (lo, hi) in [(0.0, 3.0), (3.0, 0.0)] {
            let root = bracketed_newton(f, lo, hi, 1e-15, 1e-14, 100).unwrap();
            assert!((root.x - 2f64.cbrt()).abs() < 1e-14, "{root:?}");
        }
    }

    #[test]
    fn flat_derivatives_fall_back_to_bisection() {
        // r' = 0 at the start point x = 1: Newton alone would divide by zero.
        let f = |x: f64| ((x - 1.0).powi(3) - 0.001, 3.0 * (x - 1.0).powi(2));
        let root = bracketed_newton(f, 0.0, 2.0, 1e-15, 1e-15, 200).unwrap();
        assert!((root.x - 1.1).abs() < 1e-12, "{root:?}");
    }

    #[test]
    fn reports_a_bracket_without_sign_change() {
        let f = |x: f64| (x * x + 1.0, 2.0 * x);
        assert!(matches!(
            bracketed_newton(f, -1.0, 1.0, 1e-12, 1e-12, 50),
            Err(RootFailure::NoSignChange(..))
        ));
    }
}
