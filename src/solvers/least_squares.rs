//! Bounded nonlinear least squares: minimise F(x) = ½‖r(x)‖² subject to lower ≤ x ≤ upper by
//! Levenberg–Marquardt (Gauss–Newton steps damped with Marquardt's diagonal scaling and
//! Nielsen's damping update).
//!
//! Each step solves (JᵀJ + λD) δ = −Jᵀr by Cholesky (nalgebra). Only when x + δ would leave
//! the box is the step recomputed as the box-constrained quadratic programme of
//! [`box_qp`](super::box_qp) (clarabel). A step is accepted when F decreases by more than
//! 10⁻⁴ of the decrease the linear model predicts; where both decreases are below what
//! rounding of F can resolve (10⁻¹²·F) the step is taken unless F measurably grows, so the
//! iteration can go on to steps far smaller than F can see.
//!
//! Convergence is tested on the step, not on F: an accepted step whose largest component is at
//! most [`LeastSquaresOptions::step_tolerance`] while the damping is small (λ ≤ 10⁻³: the step
//! is then the Gauss–Newton step to 0.1 %), or a projected gradient whose largest component is
//! at most [`LeastSquaresOptions::gradient_tolerance`], or (MINPACK's `ftol` test) an accepted
//! step whose actual and predicted decreases of F are both at most
//! [`LeastSquaresOptions::cost_tolerance`]·F: the local model sees nothing left to gain. The
//! last one ends slow crawls along a curved valley of a problem with a large residual, where
//! the damping never falls low enough for the step test. An iteration that reaches
//! [`LeastSquaresOptions::max_iterations`] has converged nonetheless when F is stationary to
//! rounding: its last [`STATIONARY_STEPS`] accepted steps did not lower the least F by more
//! than rounding can hide (10⁻¹²·F) — x drifting in directions F barely depends on (a
//! coordinate the markers hardly see), steps that never shrink, F wandering in its last digits.

use nalgebra::{DMatrix, DVector};

use super::box_qp::BoxQp;

/// A least-squares problem: residuals r(x) (fixed count) and their Jacobian ∂r/∂x.
pub trait LeastSquaresProblem {
    fn variable_count(&self) -> usize;
    fn residual_count(&self) -> usize;
    /// Fills `residuals` with r(x) and, when given, `jacobian` (residual_count × variable_count)
    /// with ∂r/∂x.
    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>);
}

/// Stopping rules. Tolerances are in the units of x (step) and of ∂F/∂x (gradient).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeastSquaresOptions {
    /// Converged when an accepted step's largest component is at most this (with λ ≤ 10⁻³).
    pub step_tolerance: f64,
    /// Converged when the projected gradient's largest component is at most this.
    pub gradient_tolerance: f64,
    /// Converged when an accepted step's actual and predicted relative decreases of F are both
    /// at most this (0: test off).
    pub cost_tolerance: f64,
    /// Iterations (Jacobian evaluations) allowed.
    pub max_iterations: usize,
}

impl Default for LeastSquaresOptions {
    fn default() -> Self {
        LeastSquaresOptions { step_tolerance: 1e-10, gradient_tolerance: 1e-14, cost_tolerance: 0.0, max_iterations: 200 }
    }
}

/// How a minimisation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeastSquaresStatus {
    /// A stopping test of [`LeastSquaresOptions`] passed.
    Converged,
    /// `max_iterations` reached first.
    MaxIterations,
    /// No step decreased F even with very strong damping (x is kept).
    Stalled,
    /// r(x) was not finite at the start point.
    NonFinite,
}

impl LeastSquaresStatus {
    /// A minimum: a stopping test passed, or no step could lower F any more (a minimum to the
    /// precision of r, possibly on the edge of where r is finite).
    pub fn at_minimum(self) -> bool {
        matches!(self, LeastSquaresStatus::Converged | LeastSquaresStatus::Stalled)
    }
}

/// What a minimisation did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeastSquaresReport {
    pub status: LeastSquaresStatus,
    /// Jacobian evaluations after the first.
    pub iterations: usize,
    /// F = ½‖r‖² at the returned x.
    pub cost: f64,
    /// Steps that needed the box-constrained QP.
    pub constrained_steps: usize,
}

/// Box bounds; infinite entries are absent bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

impl Bounds {
    /// No bounds on `n` variables.
    pub fn none(n: usize) -> Bounds {
        Bounds { lower: vec![f64::NEG_INFINITY; n], upper: vec![f64::INFINITY; n] }
    }

    pub fn is_unbounded(&self) -> bool {
        self.lower.iter().all(|l| *l == f64::NEG_INFINITY) && self.upper.iter().all(|u| *u == f64::INFINITY)
    }

    fn project(&self, x: &mut [f64]) {
        for ((value, lower), upper) in x.iter_mut().zip(&self.lower).zip(&self.upper) {
            *value = value.clamp(*lower, *upper);
        }
    }
}

/// Damping limits: λ starts at `INITIAL_DAMPING` (relative to the diagonal of JᵀJ), never
/// drops below `MIN_DAMPING` and the solver stalls above `MAX_DAMPING`.
const INITIAL_DAMPING: f64 = 1e-6;
const MIN_DAMPING: f64 = 1e-12;
const MAX_DAMPING: f64 = 1e16;
/// Step-based convergence needs the step to be (nearly) the Gauss–Newton step.
const CONVERGED_DAMPING: f64 = 1e-3;
/// Relative size of a change of F that rounding can hide.
const RESOLUTION: f64 = 1e-12;
/// Accepted steps in a row without a resolvable new least F after which F is stationary.
const STATIONARY_STEPS: usize = 10;
/// Scaling entries below this fraction of the largest are raised to it.
const SCALING_FLOOR: f64 = 1e-12;

/// F near x: F + gᵀδ + ½δᵀHδ with g = Jᵀr, H = JᵀJ.
struct LocalModel {
    gradient: DVector<f64>,
    hessian: DMatrix<f64>,
    cost: f64,
}

/// A step [`LeastSquares::find_step`] accepted.
struct AcceptedStep {
    /// Whether it needed the box QP.
    constrained: bool,
    /// Actual and predicted decrease of F.
    reduction: f64,
    predicted: f64,
}

/// Nielsen's damping update: λ shrinks after good steps, grows ever faster after failures.
struct Damping {
    value: f64,
    growth: f64,
}

impl Damping {
    fn new() -> Damping {
        Damping { value: INITIAL_DAMPING, growth: 2.0 }
    }

    fn accept(&mut self, ratio: f64) {
        self.value = (self.value * (1.0 - (2.0 * ratio - 1.0).powi(3)).max(1.0 / 3.0)).max(MIN_DAMPING);
        self.growth = 2.0;
    }

    /// `None` once λ exceeds `MAX_DAMPING`.
    fn reject(&mut self) -> Option<()> {
        self.value *= self.growth;
        self.growth *= 2.0;
        (self.value <= MAX_DAMPING).then_some(())
    }
}

/// Scratch buffers of the solver, reused between calls of the same size.
#[derive(Debug, Clone)]
pub struct LeastSquares {
    residuals: DVector<f64>,
    trial_residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
    trial_x: Vec<f64>,
    scaling: DVector<f64>,
    /// Non-zero entries of one Jacobian row.
    row: Vec<(usize, f64)>,
    qp: BoxQp,
}

impl LeastSquares {
    /// Buffers for problems of `variables` unknowns and `residuals` residuals.
    pub fn new(variables: usize, residuals: usize) -> LeastSquares {
        LeastSquares {
            residuals: DVector::zeros(residuals),
            trial_residuals: DVector::zeros(residuals),
            jacobian: DMatrix::zeros(residuals, variables),
            trial_x: vec![0.0; variables],
            scaling: DVector::zeros(variables),
            row: Vec::with_capacity(variables),
            qp: BoxQp::default(),
        }
    }

    /// Minimises from `x` (projected into `bounds` first); `x` holds the result.
    ///
    /// # Panics
    /// If `x`, `bounds` and the problem disagree on sizes.
    pub fn minimize(
        &mut self,
        problem: &mut impl LeastSquaresProblem,
        x: &mut [f64],
        bounds: &Bounds,
        options: &LeastSquaresOptions,
    ) -> LeastSquaresReport {
        let (n, m) = (problem.variable_count(), problem.residual_count());
        assert!(x.len() == n && bounds.lower.len() == n && bounds.upper.len() == n, "sizes of x, bounds and problem differ");
        if self.jacobian.shape() != (m, n) {
            *self = LeastSquares::new(n, m);
        }
        bounds.project(x);
        problem.evaluate(x, self.residuals.as_mut_slice(), Some(&mut self.jacobian));
        let mut cost = 0.5 * self.residuals.norm_squared();
        let mut report = LeastSquaresReport { status: LeastSquaresStatus::NonFinite, iterations: 0, cost, constrained_steps: 0 };
        if !cost.is_finite() || self.jacobian.iter().any(|v| !v.is_finite()) {
            return report;
        }
        self.scaling.fill(0.0);
        let mut damping = Damping::new();
        // The least F so far, and the accepted steps since F last fell below it by more than
        // rounding can hide.
        let (mut best, mut stalled) = (cost, 0);
        loop {
            let gradient = self.jacobian.tr_mul(&self.residuals);
            let hessian = gram(&self.jacobian, &mut self.row);
            if projected_gradient_norm(x, &gradient, bounds) <= options.gradient_tolerance {
                report.status = LeastSquaresStatus::Converged;
                break;
            }
            if report.iterations >= options.max_iterations {
                report.status = if stalled >= STATIONARY_STEPS { LeastSquaresStatus::Converged } else { LeastSquaresStatus::MaxIterations };
                break;
            }
            self.update_scaling(&hessian);
            let local = LocalModel { gradient, hessian, cost };
            let Some(accepted) = self.find_step(problem, x, bounds, &local, &mut damping) else {
                report.status = LeastSquaresStatus::Stalled;
                break;
            };
            let constrained = accepted.constrained;
            report.constrained_steps += usize::from(constrained);
            let step_size = x.iter().zip(&self.trial_x).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            x.copy_from_slice(&self.trial_x);
            report.iterations += 1;
            problem.evaluate(x, self.residuals.as_mut_slice(), Some(&mut self.jacobian));
            cost = 0.5 * self.residuals.norm_squared();
            let no_gain = accepted.reduction.abs().max(accepted.predicted) <= options.cost_tolerance * local.cost;
            stalled = if cost < best - RESOLUTION * best { 0 } else { stalled + 1 };
            best = best.min(cost);
            if (step_size <= options.step_tolerance && damping.value <= CONVERGED_DAMPING) || no_gain {
                report.status = LeastSquaresStatus::Converged;
                break;
            }
        }
        report.cost = cost;
        report
    }

    /// Raises the damping until a step decreases F enough; leaves the new point in `trial_x`
    /// (`None`: the damping ran out).
    fn find_step(&mut self, problem: &mut impl LeastSquaresProblem, x: &[f64], bounds: &Bounds, local: &LocalModel, damping: &mut Damping) -> Option<AcceptedStep> {
        let LocalModel { gradient, hessian, cost } = local;
        loop {
            let Some((step, constrained)) = self.step(hessian, gradient, damping.value, x, bounds) else {
                damping.reject()?;
                continue;
            };
            let predicted = -(gradient.dot(&step) + 0.5 * step.dot(&(hessian * &step)));
            for ((trial, value), delta) in self.trial_x.iter_mut().zip(x).zip(step.iter()) {
                *trial = value + delta;
            }
            bounds.project(&mut self.trial_x);
            problem.evaluate(&self.trial_x, self.trial_residuals.as_mut_slice(), None);
            // F − F_trial = −½ Σ (t − r)(t + r): exact where both costs round alike.
            let reduction = -0.5 * self.trial_residuals.iter().zip(self.residuals.iter()).map(|(t, r)| (t - r) * (t + r)).sum::<f64>();
            // Below `noise` neither decrease can be resolved: the step is taken as predicted.
            let noise = RESOLUTION * cost;
            let ratio = if predicted > noise { reduction / predicted } else if reduction >= -noise { 1.0 } else { -1.0 };
            if reduction.is_finite() && ratio > 1e-4 {
                damping.accept(ratio);
                return Some(AcceptedStep { constrained, reduction, predicted });
            }
            damping.reject()?;
        }
    }

    /// Marquardt's scaling: the running maximum of diag(JᵀJ), floored relative to its largest
    /// entry so that variables nothing depends on keep a positive (irrelevant) scale.
    fn update_scaling(&mut self, hessian: &DMatrix<f64>) {
        for (k, scale) in self.scaling.iter_mut().enumerate() {
            *scale = scale.max(hessian[(k, k)]);
        }
        let floor = SCALING_FLOOR * self.scaling.max().max(f64::MIN_POSITIVE);
        self.scaling.apply(|s| *s = s.max(floor));
    }

    /// The damped step and whether it needed the box QP; `None` when the damped matrix is not
    /// numerically positive definite or the QP failed (more damping helps both).
    fn step(&mut self, hessian: &DMatrix<f64>, gradient: &DVector<f64>, damping: f64, x: &[f64], bounds: &Bounds) -> Option<(DVector<f64>, bool)> {
        let mut damped = hessian.clone();
        for k in 0..damped.nrows() {
            damped[(k, k)] += damping * self.scaling[k];
        }
        let step = damped.clone().cholesky()?.solve(&(-gradient));
        let inside = step.iter().zip(x).enumerate().all(|(k, (delta, value))| {
            let next = value + delta;
            next >= bounds.lower[k] && next <= bounds.upper[k]
        });
        if inside {
            return Some((step, false));
        }
        let lower: Vec<f64> = x.iter().zip(&bounds.lower).map(|(value, lower)| lower - value).collect();
        let upper: Vec<f64> = x.iter().zip(&bounds.upper).map(|(value, upper)| upper - value).collect();
        self.qp.solve(&damped, gradient, &lower, &upper).ok().map(|step| (step, true))
    }
}

/// JᵀJ, skipping the zero entries of each row (a marker moves with the coordinates of its
/// chain only, so kinematic Jacobians are mostly zeros).
fn gram(jacobian: &DMatrix<f64>, row: &mut Vec<(usize, f64)>) -> DMatrix<f64> {
    let n = jacobian.ncols();
    let mut gram = DMatrix::zeros(n, n);
    for i in 0..jacobian.nrows() {
        row.clear();
        row.extend((0..n).map(|k| (k, jacobian[(i, k)])).filter(|(_, value)| *value != 0.0));
        for (a, &(k, value_k)) in row.iter().enumerate() {
            for &(l, value_l) in &row[a..] {
                gram[(k, l)] += value_k * value_l;
            }
        }
    }
    for l in 0..n {
        for k in l + 1..n {
            gram[(k, l)] = gram[(l, k)];
        }
    }
    gram
}

/// max_k |x_k − P(x_k − g_k)|: the gradient with components that push against an active bound
/// removed.
fn projected_gradient_norm(x: &[f64], gradient: &DVector<f64>, bounds: &Bounds) -> f64 {
    x.iter()
        .zip(gradient.iter())
        .enumerate()
        .map(|(k, (value, g))| (value - (value - g).clamp(bounds.lower[k], bounds.upper[k])).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as residuals (10(x₂ − x₁²), 1 − x₁): minimum 0 at (1, 1).
    struct Rosenbrock;

    impl LeastSquaresProblem for Rosenbrock {
        fn variable_count(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            2
        }
        fn evaluate(&mut self, x: &[f64], r: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
            r[0] = 10.0 * (x[1] - x[0] * x[0]);
            r[1] = 1.0 - x[0];
            if let Some(j) = jacobian {
                j[(0, 0)] = -20.0 * x[0];
                j[(0, 1)] = 10.0;
                j[(1, 0)] = -1.0;
                j[(1, 1)] = 0.0;
            }
        }
    }

    #[test]
    fn finds_the_rosenbrock_minimum_from_far() {
        let mut x = [-1.2, 1.0];
        let report = LeastSquares::new(2, 2).minimize(&mut Rosenbrock, &mut x, &Bounds::none(2), &LeastSquaresOptions::default());
        assert_eq!(report.status, LeastSquaresStatus::Converged, "{report:?}");
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12, "{x:?}");
        assert_eq!(report.constrained_steps, 0);
    }

    #[test]
    fn stops_on_an_active_bound_with_the_bounded_optimum() {
        // x₁ ≤ 0.5: the constrained minimum of Rosenbrock is (0.5, 0.25).
        let bounds = Bounds { lower: vec![f64::NEG_INFINITY; 2], upper: vec![0.5, f64::INFINITY] };
        let mut x = [-1.2, 1.0];
        let report = LeastSquares::new(2, 2).minimize(&mut Rosenbrock, &mut x, &bounds, &LeastSquaresOptions::default());
        assert_eq!(report.status, LeastSquaresStatus::Converged, "{report:?}");
        assert_eq!(x[0], 0.5);
        assert!((x[1] - 0.25).abs() < 1e-12, "{x:?}");
        assert!(report.constrained_steps > 0);
    }

    #[test]
    fn a_start_outside_the_box_is_projected() {
        let bounds = Bounds { lower: vec![2.0, f64::NEG_INFINITY], upper: vec![3.0, f64::INFINITY] };
        let mut x = [10.0, 0.0];
        let report = LeastSquares::new(2, 2).minimize(&mut Rosenbrock, &mut x, &bounds, &LeastSquaresOptions::default());
        assert_eq!(report.status, LeastSquaresStatus::Converged);
        assert_eq!(x[0], 2.0);
        assert!((x[1] - 4.0).abs() < 1e-12, "{x:?}");
    }

    #[test]
    fn gram_equals_the_dense_product() {
        let jacobian = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 2.0, 0.0, 0.0, 0.0, -1.5, 3.0, 0.0]);
        assert_eq!(gram(&jacobian, &mut Vec::new()), jacobian.tr_mul(&jacobian));
    }

    #[test]
    fn non_finite_residuals_are_a_status() {
        struct Nan;
        impl LeastSquaresProblem for Nan {
            fn variable_count(&self) -> usize {
                1
            }
            fn residual_count(&self) -> usize {
                1
            }
            fn evaluate(&mut self, _: &[f64], r: &mut [f64], _: Option<&mut DMatrix<f64>>) {
                r[0] = f64::NAN;
            }
        }
        let report = LeastSquares::new(1, 1).minimize(&mut Nan, &mut [0.0], &Bounds::none(1), &LeastSquaresOptions::default());
        assert_eq!(report.status, LeastSquaresStatus::NonFinite);
    }

    /// r = (x − 1 + 10⁻⁶·sin(10⁶·x), 100) with the Jacobian of x − 1 alone, as a finite-difference
    /// Jacobian blind to the ripple: F stops falling near x = 1 while gradient and steps stay
    /// ragged. The cost test ends it there; without it the iteration runs to its cap, where F is
    /// found stationary to rounding — converged all the same —, and a cap reached while F still
    /// falls is not convergence.
    #[test]
    fn the_cost_test_ends_a_crawl_at_a_large_residual_and_the_cap_finds_it_stationary() {
        struct Ripple;
        impl LeastSquaresProblem for Ripple {
            fn variable_count(&self) -> usize {
                1
            }
            fn residual_count(&self) -> usize {
                2
            }
            fn evaluate(&mut self, x: &[f64], r: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
                r[0] = x[0] - 1.0 + 1e-6 * (1e6 * x[0]).sin();
                r[1] = 100.0;
                if let Some(j) = jacobian {
                    j[(0, 0)] = 1.0;
                    j[(1, 0)] = 0.0;
                }
            }
        }
        let options = LeastSquaresOptions { step_tolerance: 0.0, gradient_tolerance: 0.0, cost_tolerance: 1e-10, max_iterations: 200 };
        let mut x = [3.0];
        let report = LeastSquares::new(1, 2).minimize(&mut Ripple, &mut x, &Bounds::none(1), &options);
        assert_eq!(report.status, LeastSquaresStatus::Converged, "{report:?}");
        assert!((x[0] - 1.0).abs() < 1e-5, "{x:?}");
        let mut x = [3.0];
        let report = LeastSquares::new(1, 2).minimize(&mut Ripple, &mut x, &Bounds::none(1), &LeastSquaresOptions { cost_tolerance: 0.0, ..options });
        assert_eq!((report.status, report.iterations), (LeastSquaresStatus::Converged, 200), "{report:?}");
        assert!((x[0] - 1.0).abs() < 1e-5, "{x:?}");
        let report = LeastSquares::new(1, 2).minimize(&mut Ripple, &mut [3.0], &Bounds::none(1), &LeastSquaresOptions { cost_tolerance: 0.0, max_iterations: 1, ..options });
        assert_eq!(report.status, LeastSquaresStatus::MaxIterations, "{report:?}");
    }
}
