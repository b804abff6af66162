//! Backtracking (Armijo) line search on the ℓ1 merit function φ(x) = f(x) + μ V(c(x)) (or on
//! V alone for a restoration step), with an optional second-order correction of the full step.
//!
//! The QP step d predicts the reduction pred = −∇fᵀd + μ (V(c) − V(c + Jd)) ≥ dᵀBd > 0 (the
//! QP is the model of φ). A trial x + αd (projected onto the bounds against rounding) is
//! accepted when φ(x + αd) ≤ φ(x) − η α pred, or, when α·pred is below what rounding of φ can
//! resolve, when φ does not measurably grow. A trial whose evaluation (or, once accepted, whose
//! derivatives) fails or is not finite halves α; a rejected trial takes α from the minimiser of
//! the quadratic through φ(x), −pred and φ(x + αd), kept in [0.1α, 0.5α].
//!
//! Second-order correction (Maratos effect): when the full step is rejected and V grew, the QP
//! is solved once more with c replaced by c(x + d) − J d. Its step d̂ is tried, and if it is
//! rejected too the search backtracks along the arc x + αd + α²(d̂ − d), which follows curved
//! constraints (with the same Armijo test).

use nalgebra::DVector;

use super::limits::Limits;
use super::point::Point;
use super::problem::NlpProblem;

/// Relative size of a change of φ that rounding can hide.
const RESOLUTION: f64 = 1e-14;

/// What the search needs besides the problem: the current point, the step, the merit data.
pub(super) struct Search<'a> {
    pub limits: &'a Limits,
    pub current: &'a Point,
    pub step: &'a DVector<f64>,
    /// The weight of f in the merit function: 1, or 0 for a restoration step.
    pub objective_weight: f64,
    pub penalty: f64,
    /// The model's predicted reduction pred (> 0).
    pub predicted: f64,
    pub armijo: f64,
    pub max_backtracks: usize,
}

/// Gives the second-order-corrected step for the constraint values at x + d (`None` when its
/// QP fails).
pub(super) type Correction<'a> = &'a mut dyn FnMut(&DVector<f64>) -> Option<DVector<f64>>;

/// Evaluation counters.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Counts {
    pub evaluations: usize,
    pub derivatives: usize,
}

impl Search<'_> {
    /// φ at c with this search's μ.
    fn merit(&self, objective: f64, constraints: &DVector<f64>) -> f64 {
        self.objective_weight * objective + self.penalty * self.limits.l1_violation(constraints.iter().copied())
    }

    /// Searches along the step; `trial` holds the accepted point, α is returned. `correction`
    /// gives the second-order-corrected step for the constraint values at x + d.
    pub fn run<P: NlpProblem + ?Sized>(
        &self,
        problem: &mut P,
        trial: &mut Point,
        counts: &mut Counts,
        mut correction: Option<Correction>,
    ) -> Option<f64> {
        let current_merit = self.merit(self.current.objective, &self.current.constraints);
        let current_violation = self.limits.l1_violation(self.current.constraints.iter().copied());
        let mut alpha = 1.0;
        let mut corrected: Option<DVector<f64>> = None;
        for _ in 0..self.max_backtracks {
            self.place(trial, alpha, corrected.as_ref());
            counts.evaluations += 1;
            if !trial.evaluate(problem) {
                alpha *= 0.5;
                continue;
            }
            let merit = self.merit(trial.objective, &trial.constraints);
            if self.acceptable(current_merit, merit, alpha) {
                counts.derivatives += 1;
                if trial.differentiate(problem) {
                    return Some(alpha);
                }
                alpha *= 0.5;
                continue;
            }
            let grew = self.limits.l1_violation(trial.constraints.iter().copied()) > current_violation;
            if alpha == 1.0 && grew && corrected.is_none() {
                if let Some(correct) = correction.take() {
                    corrected = correct(&trial.constraints);
                    if corrected.is_some() {
                        continue;
                    }
                }
            }
            alpha = self.next_alpha(current_merit, merit, alpha);
        }
        None
    }

    /// trial.x = x + α d, or x + α d + α² (d̂ − d) on the arc through the corrected step d̂,
    /// projected onto the bounds; at α = 1 a step component that is a bound's distance from x
    /// lands exactly on the bound.
    fn place(&self, trial: &mut Point, alpha: f64, corrected: Option<&DVector<f64>>) {
        let (x, limits) = (&self.current.x, self.limits);
        let full = if alpha == 1.0 { corrected.unwrap_or(self.step) } else { self.step };
        trial.x.copy_from(x);
        trial.x.axpy(alpha, full, 1.0);
        if let (Some(corrected), true) = (corrected, alpha < 1.0) {
            trial.x.axpy(alpha * alpha, corrected, 1.0);
            trial.x.axpy(-alpha * alpha, self.step, 1.0);
        }
        limits.project(trial.x.as_mut_slice());
        if alpha == 1.0 {
            for k in 0..x.len() {
                if full[k] == limits.lower[k] - x[k] {
                    trial.x[k] = limits.lower[k];
                } else if full[k] == limits.upper[k] - x[k] {
                    trial.x[k] = limits.upper[k];
                }
            }
        }
    }

    fn acceptable(&self, current: f64, merit: f64, alpha: f64) -> bool {
        let resolution = RESOLUTION * current.abs().max(1.0);
        merit <= current - self.armijo * alpha * self.predicted || (alpha * self.predicted <= resolution && merit <= current + resolution)
    }

    /// The minimiser of the quadratic through φ(0), φ'(0) = −pred and φ(α), in [0.1α, 0.5α].
    fn next_alpha(&self, current: f64, merit: f64, alpha: f64) -> f64 {
        let slope = -self.predicted;
        let curvature = merit - current - slope * alpha;
        let minimiser = if curvature > 0.0 { -slope * alpha * alpha / (2.0 * curvature) } else { 0.5 * alpha };
        minimiser.clamp(0.1 * alpha, 0.5 * alpha)
    }
}
