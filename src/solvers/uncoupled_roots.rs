//! The roots of an uncoupled vector function, x_i ↦ f_i(x_i), each bracketed in [a_i, b_i]:
//! Brent's method (bisection, secant and inverse quadratic interpolation) run on every component
//! at once, each iteration evaluating the whole vector — OpenSim's `RootSolver`, step for step, so
//! that CMC's excitations land where OpenSim's do (its tolerance is on the abscissa and coarse).

/// The roots of `f` (all components evaluated together; `f(x)` gives f_i(x_i) per component),
/// starting from the brackets `a`, `b` with abscissa tolerances `tolerance`: per component the
/// best approximation b once |c − b|/2 falls within 2ε|b| + tolerance/2 or f_i(b) = 0.
/// Components without a sign change end at the bracket end with the smaller |f| (as OpenSim).
pub fn uncoupled_roots<E>(mut f: impl FnMut(&[f64]) -> Result<Vec<f64>, E>, a: &[f64], b: &[f64], tolerance: &[f64]) -> Result<Vec<f64>, E> {
    let n = a.len();
    let (mut a, mut b) = (a.to_vec(), b.to_vec());
    let mut fa = f(&a)?;
    let mut fb = f(&b)?;
    let (mut c, mut fc) = (a.clone(), fa.clone());
    let mut converged = vec![false; n];
    while converged.iter().any(|done| !done) {
        for i in 0..n {
            if converged[i] {
                continue;
            }
            // c on the other side of b.
            if (fb[i] > 0.0 && fc[i] > 0.0) || (fb[i] < 0.0 && fc[i] < 0.0) {
                (c[i], fc[i]) = (a[i], fa[i]);
            }
            let previous_step = b[i] - a[i];
            // b the best approximation.
            if fc[i].abs() < fb[i].abs() {
                (a[i], b[i], c[i]) = (b[i], c[i], b[i]);
                (fa[i], fb[i], fc[i]) = (fb[i], fc[i], fb[i]);
            }
            let tolerance = 2.0 * f64::EPSILON * b[i].abs() + 0.5 * tolerance[i];
            let mut step = 0.5 * (c[i] - b[i]);
            if step.abs() <= tolerance || fb[i] == 0.0 {
                converged[i] = true;
                continue;
            }
            if previous_step.abs() >= tolerance && fa[i].abs() > fb[i].abs() {
                if let Some(interpolated) = interpolated_step(a[i], b[i], c[i], fa[i], fb[i], fc[i], previous_step, tolerance) {
                    step = interpolated;
                }
            }
            if step.abs() < tolerance {
                step = if step > 0.0 { tolerance } else { -tolerance };
            }
            (a[i], fa[i]) = (b[i], fb[i]);
            b[i] += step;
        }
        fb = f(&b)?;
    }
    Ok(b)
}

/// The secant (two distinct points) or inverse quadratic interpolation step from b, when it
/// stays within three quarters of the bracket and under half the previous step (else bisection).
#[allow(clippy::too_many_arguments)]
fn interpolated_step(a: f64, b: f64, c: f64, fa: f64, fb: f64, fc: f64, previous_step: f64, tolerance: f64) -> Option<f64> {
    let cb = c - b;
    let (mut p, mut q) = if a == c {
        let t1 = fb / fa;
        (cb * t1, 1.0 - t1)
    } else {
        let (q, t1, t2) = (fa / fc, fb / fc, fb / fa);
        (t2 * (cb * q * (q - t1) - (b - a) * (t1 - 1.0)), (q - 1.0) * (t1 - 1.0) * (t2 - 1.0))
    };
    if p > 0.0 {
        q = -q;
    } else {
        p = -p;
    }
    (p < 0.75 * cb * q - 0.5 * (tolerance * q).abs() && p < (0.5 * previous_step * q).abs()).then(|| p / q)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_component_finds_its_own_root_within_its_tolerance() {
        let roots = uncoupled_roots(|x| Ok::<_, ()>(vec![x[0] * x[0] - 2.0, (x[1] - 0.3).powi(3), 4.0 * x[2] - 1.0]), &[0.0, -1.0, -5.0], &[3.0, 1.0, 5.0], &[1e-10, 1e-6, 1e-12]).unwrap();
        assert!((roots[0] - 2f64.sqrt()).abs() < 1e-10);
        assert!((roots[1] - 0.3).abs() < 1e-6);
        assert!((roots[2] - 0.25).abs() < 1e-12);
    }

    #[test]
    fn a_linear_component_ends_at_its_root_not_a_tolerance_away() {
        // A coarse tolerance: Brent's last steps still return the secant's exact root.
        let roots = uncoupled_roots(|x| Ok::<_, ()>(vec![3.0 * x[0] - 1.0]), &[-10.0], &[10.0], &[4e-3]).unwrap();
        assert!((roots[0] - 1.0 / 3.0).abs() < 1e-12, "{}", roots[0]);
    }

    #[test]
    fn an_evaluation_error_stops_the_search() {
        let mut calls = 0;
        let result = uncoupled_roots(
            |x| {
                calls += 1;
                if calls > 2 { Err("failed") } else { Ok(vec![x[0] - 0.5]) }
            },
            &[0.0],
            &[2.0],
            &[1e-9],
        );
        assert_eq!(result, Err("failed"));
    }
}
