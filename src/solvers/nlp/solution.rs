//! What an SQP solve returns.

/// How a solve ended. Only `Converged` (and `ObjectiveTarget`, by the caller's standard) meets the tests of [`NlpSettings`](super::NlpSettings).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NlpStatus {
    /// Scaled KKT conditions and feasibility met.
    Converged,
    /// A feasible iterate reached `objective_target`.
    ObjectiveTarget,
    /// Feasible, and the objective stalled over `stall_iterations` iterations.
    ObjectiveStalled,
    /// Feasible, and the QP step is below `step_tolerance`, but the KKT test is not met.
    AcceptableStep,
    /// `max_iterations` steps taken.
    MaxIterations,
    /// No trial step length decreased the merit function (also after a Hessian reset).
    LineSearchFailed,
    /// x is a stationary point of the constraint violation that does not satisfy the
    /// constraints: the problem is infeasible near x.
    LocallyInfeasible,
    /// f, c or their derivatives could not be evaluated at the start point.
    EvaluationFailed,
    /// clarabel failed on a QP subproblem (also after a Hessian reset).
    QpFailed,
}

/// Multipliers in one sign convention: ∇f + Jᵀλ + ν = 0 at a KKT point, where λᵢ ≥ 0 when
/// cᵢ is at its upper bound c_u,i and λᵢ ≤ 0 at its lower bound (free for equalities), and
/// νⱼ ≥ 0 when xⱼ is at x_u,j, νⱼ ≤ 0 at x_l,j.
#[derive(Debug, Clone, PartialEq)]
pub struct NlpMultipliers {
    /// λ, one per constraint.
    pub constraints: Vec<f64>,
    /// ν, one per variable.
    pub bounds: Vec<f64>,
}

/// One SQP iteration: the iterate's values and the step taken from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// f at the iterate.
    pub objective: f64,
    /// Largest constraint violation at the iterate.
    pub constraint_violation: f64,
    /// max(scaled stationarity, scaled complementarity) with the QP's multipliers.
    pub kkt_error: f64,
    /// ‖x_next − x‖∞ (0 when the solve ended at this iterate).
    pub step_norm: f64,
    /// Step length α accepted by the line search (0 when none was).
    pub step_length: f64,
    /// The penalty μ the QP and merit function used.
    pub penalty: f64,
}

/// The result of [`Sqp::solve`](super::Sqp::solve): the last iterate, never a panic.
#[derive(Debug, Clone, PartialEq)]
pub struct NlpSolution {
    pub status: NlpStatus,
    pub x: Vec<f64>,
    /// f(x).
    pub objective: f64,
    /// The multipliers of the last QP solved (zero when none was). For `LocallyInfeasible`
    /// the certificate of the violation's stationarity instead: Jᵀλ̂ + ν̂ ≈ 0 with λ̂ᵢ = +1 (−1)
    /// where cᵢ is above (below) its range, ν̂ on the bounds x sits at.
    pub multipliers: NlpMultipliers,
    /// Steps taken.
    pub iterations: usize,
    /// Largest constraint violation at x.
    pub constraint_violation: f64,
    /// max(scaled stationarity, scaled complementarity) at x (see `NlpSettings`); NaN when no
    /// QP was solved at x.
    pub kkt_error: f64,
    /// Calls of `NlpProblem::evaluate` made by the solver (not counting those inside
    /// `derivatives`).
    pub evaluations: usize,
    /// Calls of `NlpProblem::derivatives`.
    pub derivative_evaluations: usize,
    pub history: Vec<IterationRecord>,
}
