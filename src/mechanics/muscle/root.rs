//! Safeguarded Newton's method on a bracket (Numerical Recipes' `rtsafe`): a Newton step when it
//! stays inside the bracket and shrinks the residual fast enough, a bisection step otherwise.
//! Converges for any continuous residual that changes sign on the bracket.

/// A root of a residual on a bracket.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Root {
    pub x: f64,
    /// r(x), or the bound predicted for |r(x)| when `predicted`.
    pub residual: f64,
    /// Evaluations of the residual.
    pub iterations: usize,
    /// x ends a Newton step that was not evaluated (`newton_between_predicting`).
    pub predicted: bool,
}

/// When the safeguarded iteration stops.
#[derive(Debug, Clone, Copy)]
struct Stopping {
    /// On the bracket width.
    x_tolerance: f64,
    /// On |r|.
    residual_tolerance: f64,
    max_iterations: usize,
    /// Whether a Newton step whose end is predicted to be a root ends the iteration unevaluated.
    predict: bool,
}

/// A Newton step's end is a root, unevaluated, when both predictions of its |r| are at most
/// this fraction of the tolerance.
const PREDICTION_MARGIN: f64 = 1e-3;

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
            return Ok(Root { x, residual: r, iterations: 0, predicted: false });
        }
    }
    if (r_lo > 0.0) == (r_hi > 0.0) {
        return Err(RootFailure::NoSignChange(r_lo, r_hi));
    }
    // Orient so that r(negative_end) < 0 < r(positive_end).
    let (negative_end, positive_end) = if r_lo < 0.0 { (lo.x, hi.x) } else { (hi.x, lo.x) };
    let stopping = Stopping { x_tolerance, residual_tolerance, max_iterations, predict: false };
    safeguarded_newton(residual, start, (negative_end, positive_end), stopping)
}

/// The safeguarded iteration of `bracketed_newton` when the caller knows, without evaluating
/// them, that r < 0 at `negative_end` and r > 0 at `positive_end` (converging to either end
/// with a residual above `residual_tolerance` means that end's sign was wrong), and without the
/// evaluation that would confirm the root: after two Newton steps in a row, when both the
/// residual's curvature (from the slopes at the last two iterates) and the convergence rate
/// observed (|r_k|³/r_(k−1)²) put |r| after the next step below 1/1000 of
/// `residual_tolerance`, that step's end is the root, unevaluated (`Root::predicted`). The step
/// is then so short that the caller can continue its state from the last evaluation along the
/// slopes.
pub fn newton_between_predicting(
    residual: impl FnMut(f64) -> (f64, f64),
    start: f64,
    negative_end: f64,
    positive_end: f64,
    x_tolerance: f64,
    residual_tolerance: f64,
    max_iterations: usize,
) -> Result<Root, RootFailure> {
    let stopping = Stopping { x_tolerance, residual_tolerance, max_iterations, predict: true };
    safeguarded_newton(residual, start, (negative_end, positive_end), stopping)
}

/// One evaluated iterate: x, r(x) and dr/dx.
#[derive(Debug, Clone, Copy)]
struct Iterate {
    x: f64,
    r: f64,
    dr: f64,
}

fn safeguarded_newton(
    mut residual: impl FnMut(f64) -> (f64, f64),
    start: f64,
    (mut negative_end, mut positive_end): (f64, f64),
    stopping: Stopping,
) -> Result<Root, RootFailure> {
    let (lo, hi) = (negative_end.min(positive_end), negative_end.max(positive_end));
    let mut x = start.clamp(lo, hi);
    let mut last_step = hi - lo;
    let mut best = Root { x, residual: f64::INFINITY, iterations: 0, predicted: false };
    // The iterate the last Newton step started from, while the steps are Newton steps.
    let mut newton_from: Option<Iterate> = None;
    for iteration in 1..=stopping.max_iterations {
        let (r, dr) = residual(x);
        if !r.is_finite() || !dr.is_finite() {
            return Err(RootFailure::NotFinite(x));
        }
        let here = Root { x, residual: r, iterations: iteration, predicted: false };
        if r.abs() < best.residual.abs() {
            best = here;
        }
        if r.abs() <= stopping.residual_tolerance {
            return Ok(here);
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
            let current = Iterate { x, r, dr };
            let predicted = newton_from.filter(|_| stopping.predict).map(|previous| predicted_residual(previous, current, newton));
            if let Some(residual) = predicted.filter(|p| p.abs() <= PREDICTION_MARGIN * stopping.residual_tolerance) {
                return Ok(Root { x: newton, residual, iterations: iteration, predicted: true });
            }
            newton_from = Some(current);
            newton
        } else {
            newton_from = None;
            0.5 * (negative_end + positive_end)
        };
        last_step = (next - x).abs();
        x = next;
        if (positive_end - negative_end).abs() <= stopping.x_tolerance {
            let (r, _) = residual(x);
            return Ok(Root { x, residual: r, iterations: iteration, predicted: false });
        }
    }
    Err(RootFailure::NotConverged(best))
}

/// |r| at `newton`, the end of the Newton step from `current` that followed a Newton step from
/// `previous`: the larger of r″ (newton − x)²/2, r″ from the slopes at the two iterates, and
/// |r|³/r_previous², the quadratic convergence observed continued.
fn predicted_residual(previous: Iterate, current: Iterate, newton: f64) -> f64 {
    let curvature = (current.dr - previous.dr) / (current.x - previous.x);
    let step = newton - current.x;
    let from_curvature = (0.5 * curvature * step * step).abs();
    let from_rate = current.r.abs() * (current.r / previous.r).powi(2);
    if from_curvature.is_nan() {
        return f64::INFINITY;
    }
    from_curvature.max(from_rate)
}

/// SimTK::sign: −1, 0 or 1.
pub(crate) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
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
    fn a_predicted_root_is_a_root_one_evaluation_sooner() {
        let f = |x: f64| (x * x * x - 2.0, 3.0 * x * x);
        let evaluated = bracketed_newton_from(f, 1.0, BracketEnd { x: 0.0, residual: -2.0 }, BracketEnd { x: 3.0, residual: 25.0 }, 1e-15, 1e-10, 50).unwrap();
        let predicted = newton_between_predicting(f, 1.0, 0.0, 3.0, 1e-15, 1e-10, 50).unwrap();
        assert!(predicted.predicted && !evaluated.predicted, "{predicted:?}");
        assert_eq!(predicted.iterations + 1, evaluated.iterations);
        assert!((predicted.x.powi(3) - 2.0).abs() <= PREDICTION_MARGIN * 1e-10, "{predicted:?}");
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
