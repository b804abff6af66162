//! Stopping rules and algorithm parameters of the SQP solver.

/// Where the Hessian of the Lagrangian comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HessianMode {
    /// The problem's exact Hessian when it has one ([`NlpProblem::has_hessian`](super::NlpProblem::has_hessian)),
    /// else damped BFGS.
    Auto,
    /// Damped BFGS (Powell) even when the problem has an exact Hessian.
    Bfgs,
}

/// Settings of [`Sqp`](super::Sqp). All tolerances must be positive and finite.
///
/// Convergence (status `Converged`) at an iterate x with the multipliers (λ, ν) of its QP:
/// - stationarity ‖∇f + Jᵀλ + ν‖∞ ≤ `tolerance` · max(1, ‖∇f‖∞);
/// - complementarity maxᵢ |λᵢ|·(distance of cᵢ from the side λᵢ's sign names) — and the same
///   for ν and the bounds — ≤ `tolerance` · max(1, ‖∇f‖∞);
/// - violation maxᵢ dist(cᵢ(x), [c_l,i, c_u,i]) ≤ `feasibility_tolerance` (bounds always hold).
///
/// A QP step with ‖d‖∞ ≤ `step_tolerance` · max(1, ‖x‖∞) at a feasible x that is not
/// converged ends with `AcceptableStep`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NlpSettings {
    /// Relative stationarity and complementarity tolerance.
    pub tolerance: f64,
    /// Absolute tolerance on the largest constraint violation.
    pub feasibility_tolerance: f64,
    /// Relative size of a step taken as no step.
    pub step_tolerance: f64,
    /// An infeasible x is `LocallyInfeasible` when the ℓ1 violation V = Σᵢ dist(cᵢ, [c_l,i, c_u,i])
    /// is stationary there: the projected gradient of V over the bounds, Jᵀλ̂ with λ̂ ∈ [−1, 1]
    /// the feasibility QP's multipliers, is at most this, and the linearisation cannot halve V.
    pub infeasibility_tolerance: f64,
    /// SQP iterations (QP steps) allowed.
    pub max_iterations: usize,
    /// Exact Hessian or BFGS.
    pub hessian: HessianMode,
    /// First value of the ℓ1 penalty μ of the merit function f + μ V and of the elastic QP.
    pub initial_penalty: f64,
    /// μ is never raised above this.
    pub max_penalty: f64,
    /// Armijo constant η: a step α d is accepted when the merit function falls by at least
    /// η α times the reduction the QP model predicts.
    pub armijo: f64,
    /// Trial step lengths per line search.
    pub max_backtracks: usize,
    /// Try a second-order correction when the full step is rejected (Maratos effect).
    pub second_order_correction: bool,
    /// A feasible iterate with f ≤ this ends the solve as `ObjectiveTarget` (KNITRO's
    /// `fstopval`): for problems whose optimal value is known, e.g. 0 for a fit to exact data,
    /// where the KKT test degenerates. −∞: never.
    pub objective_target: f64,
    /// A feasible iterate whose objective changed by at most `stall_tolerance` · |f| over the
    /// last `stall_iterations` iterations ends the solve as `ObjectiveStalled` (KNITRO's
    /// `ftol`/`ftol_iters`): for degenerate problems (non-unique minimisers, e.g. a min–max fit
    /// whose parameters are not all identifiable) where the KKT test is never met. The test is
    /// relative to f alone, so an objective still falling towards 0 never stalls. 0: never.
    pub stall_iterations: usize,
    pub stall_tolerance: f64,
    /// clarabel's gap and feasibility tolerance for the QP subproblems.
    pub qp_tolerance: f64,
    /// clarabel's iteration limit per QP.
    pub qp_max_iterations: u32,
}

impl Default for NlpSettings {
    fn default() -> Self {
        NlpSettings {
            tolerance: 1e-8,
            feasibility_tolerance: 1e-8,
            step_tolerance: 1e-12,
            infeasibility_tolerance: 1e-8,
            max_iterations: 200,
            hessian: HessianMode::Auto,
            initial_penalty: 1.0,
            max_penalty: 1e8,
            armijo: 1e-4,
            max_backtracks: 40,
            second_order_correction: true,
            objective_target: f64::NEG_INFINITY,
            stall_iterations: 0,
            stall_tolerance: 1e-10,
            qp_tolerance: 1e-10,
            qp_max_iterations: 200,
        }
    }
}

impl NlpSettings {
    /// The first setting that is out of range, by name.
    pub(super) fn invalid(&self) -> Option<&'static str> {
        let positive = |v: f64| v > 0.0 && v.is_finite();
        [
            (positive(self.tolerance), "tolerance"),
            (positive(self.feasibility_tolerance), "feasibility_tolerance"),
            (positive(self.step_tolerance), "step_tolerance"),
            (positive(self.infeasibility_tolerance), "infeasibility_tolerance"),
            (positive(self.initial_penalty), "initial_penalty"),
            (positive(self.max_penalty) && self.max_penalty >= self.initial_penalty, "max_penalty"),
            (self.armijo > 0.0 && self.armijo < 0.5, "armijo"),
            (self.max_backtracks > 0, "max_backtracks"),
            (!self.objective_target.is_nan() && self.objective_target != f64::INFINITY, "objective_target"),
            (positive(self.stall_tolerance), "stall_tolerance"),
            (positive(self.qp_tolerance), "qp_tolerance"),
            (self.qp_max_iterations > 0, "qp_max_iterations"),
        ]
        .into_iter()
        .find_map(|(valid, name)| (!valid).then_some(name))
    }
}
