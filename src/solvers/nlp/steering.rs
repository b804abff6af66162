//! The search direction of one iteration: the penalty μ is steered (after Byrd, Nocedal and
//! Waltz 2008, "Steering exact penalty methods"), a feasibility-restoration step replaces the
//! step where the linearisation is inconsistent, and local infeasibility is detected.
//!
//! The QP with the current μ is solved first. When its step satisfies the linearised
//! constraints (V(c + Jd) ≈ 0) it is taken. Otherwise the feasibility QP — the same QP
//! without the objective's gradient, i.e. min ½dᵀ(B/μ)d + V(c + Jd) — shows what the
//! linearisation can do for the ℓ1 violation V:
//! - if its step satisfies the linearised constraints, or does so with a penalty 10³ times
//!   larger (capped at `max_penalty`), μ is raised (×10, at most to `max_penalty`) until the QP
//!   step does too: μ then exceeds the QP multipliers;
//! - if not, the linearisation is inconsistent near x (within the steps such a penalty allows)
//!   and the feasibility step is taken as a restoration step (line search on V alone), after
//!   which μ is raised ×10 so that the next feasibility QP allows longer steps;
//! - if, moreover, V > `feasibility_tolerance` is stationary — with the feasibility QP's
//!   multipliers scaled to [−1, 1], the projected gradient of V, Jᵀλ̂ less what the bounds at x
//!   absorb, is at most `infeasibility_tolerance` — and the feasibility step cannot halve V,
//!   the problem is locally infeasible at x.

use nalgebra::DVector;

use super::limits::Limits;
use super::settings::NlpSettings;
use super::subproblem::{Linearisation, QpStep, Subproblem};

/// Factor by which μ is raised.
const PENALTY_GROWTH: f64 = 10.0;
/// The linearisation counts as consistent when the feasibility QP with μ times this (at most
/// `max_penalty`) satisfies it: a bounded step can reach it.
const PENALTY_REACH: f64 = 1e3;

/// The outcome of one direction finding. `step` is always the QP with the objective (its
/// multipliers estimate the problem's); `feasibility` the feasibility QP.
pub(super) enum Direction {
    /// Take `step` (line search on f + μV).
    Optimality { step: QpStep },
    /// Take `feasibility` (line search on V).
    Restoration { step: QpStep, feasibility: QpStep },
    /// x is a stationary point of V with V > 0.
    Infeasible { step: QpStep, feasibility: QpStep },
    /// clarabel failed.
    QpFailed,
}

/// The direction from the linearisation `data` (whose gradient is set) at violation V.
pub(super) fn direction(subproblem: &mut Subproblem, limits: &Limits, data: &Linearisation, penalty: f64, violation: f64, settings: &NlpSettings) -> Direction {
    let Some(mut step) = subproblem.solve(limits, data, penalty) else { return Direction::QpFailed };
    let tolerance = linear_tolerance(settings, violation);
    if step.linear_violation <= tolerance {
        return Direction::Optimality { step };
    }
    let feasibility_data = Linearisation { gradient: None, ..*data };
    let Some(feasibility) = subproblem.solve(limits, &feasibility_data, penalty) else { return Direction::QpFailed };
    let consistent = feasibility.linear_violation <= tolerance
        || (penalty < settings.max_penalty && consistent_with_larger_penalty(subproblem, limits, &feasibility_data, penalty, tolerance, settings));
    if !consistent {
        return if violation > settings.feasibility_tolerance && is_infeasible_stationary(limits, &feasibility, data, violation, settings) {
            Direction::Infeasible { step, feasibility }
        } else {
            Direction::Restoration { step, feasibility }
        };
    }
    while step.linear_violation > tolerance && step.penalty < settings.max_penalty {
        let raised = (step.penalty * PENALTY_GROWTH).min(settings.max_penalty);
        let Some(next) = subproblem.solve(limits, data, raised) else { return Direction::QpFailed };
        step = next;
    }
    Direction::Optimality { step }
}

/// Whether the feasibility QP with μ·`PENALTY_REACH` (at most `max_penalty`) satisfies the
/// linearised constraints (false when clarabel fails on it).
fn consistent_with_larger_penalty(
    subproblem: &mut Subproblem,
    limits: &Limits,
    feasibility_data: &Linearisation,
    penalty: f64,
    tolerance: f64,
    settings: &NlpSettings,
) -> bool {
    let larger = (penalty * PENALTY_REACH).min(settings.max_penalty);
    subproblem.solve(limits, feasibility_data, larger).is_some_and(|step| step.linear_violation <= tolerance)
}

/// V(c + Jd) at most this counts as satisfying the linearised constraints.
fn linear_tolerance(settings: &NlpSettings, violation: f64) -> f64 {
    0.1 * settings.feasibility_tolerance + 1e-9 * violation
}

/// A variable counts as at a bound within this (relative to max(1, |bound|)).
const AT_BOUND: f64 = 1e-10;

/// The stationarity of V at x: λ̂ = the feasibility QP's multipliers / μ (in [−1, 1], the
/// signs of the violated rows), g = Jᵀλ̂ (a subgradient of V), ν̂ = −g on the bounds x sits at
/// when its sign is right, and the largest remaining component of g + ν̂ (the projected
/// gradient of V over the bounds).
pub(super) fn violation_stationarity(limits: &Limits, data: &Linearisation, feasibility: &QpStep) -> (DVector<f64>, DVector<f64>, f64) {
    let lambda = &feasibility.constraint_multipliers / feasibility.penalty;
    let gradient = data.jacobian.tr_mul(&lambda);
    let mut nu = DVector::zeros(gradient.len());
    let mut residual: f64 = 0.0;
    for k in 0..gradient.len() {
        let (x, lower, upper) = (data.x[k], limits.lower[k], limits.upper[k]);
        let at = |bound: f64| bound.is_finite() && (x - bound).abs() <= AT_BOUND * bound.abs().max(1.0);
        let g = gradient[k];
        if lower == upper || (at(lower) && g >= 0.0) || (at(upper) && g <= 0.0) {
            nu[k] = -g;
        } else {
            residual = residual.max(g.abs());
        }
    }
    (lambda, nu, residual)
}

/// V > 0 is stationary: the projected gradient of V is at most `infeasibility_tolerance` and
/// the feasibility step cannot halve V.
fn is_infeasible_stationary(limits: &Limits, feasibility: &QpStep, data: &Linearisation, violation: f64, settings: &NlpSettings) -> bool {
    let (_, _, residual) = violation_stationarity(limits, data, feasibility);
    residual <= settings.infeasibility_tolerance && feasibility.linear_violation >= 0.5 * violation
}
