//! A general constrained nonlinear programming solver: sequential quadratic programming (SQP)
//! with clarabel QP subproblems, an ℓ1 exact-penalty merit function and elastic mode.
//!
//! Problem ([`NlpProblem`]): minimise f(x) subject to c_l ≤ c(x) ≤ c_u (c_l = c_u an equality)
//! and x_l ≤ x ≤ x_u. Multipliers ([`NlpMultipliers`]) satisfy ∇f + Jᵀλ + ν = 0 at a KKT
//! point, positive at upper bounds and negative at lower bounds.
//!
//! Each iteration at x:
//! 1. B is the Hessian model: the problem's exact ∇²L(x, λ) shifted by δI until positive
//!    definite, or a damped BFGS (Powell) approximation updated with
//!    y = ∇ₓL(x⁺, λ⁺) − ∇ₓL(x, λ⁺) (`hessian.rs`);
//! 2. the elastic QP subproblem (`subproblem.rs`) linearises c, keeps the bounds on x exactly
//!    and relaxes the linearised constraints with ℓ1-penalised slacks, so it is always feasible;
//!    the penalty μ is steered (`steering.rs`) so that the step reduces the linearised
//!    violation, and a stationary point of the violation that is not feasible ends the solve
//!    as `LocallyInfeasible`;
//! 3. the convergence test (scaled KKT conditions, [`NlpSettings`]) uses the QP's multipliers;
//! 4. a backtracking Armijo line search on φ = f + μ V with an optional second-order
//!    correction (`line_search.rs`) gives the next iterate, always inside the bounds.
//!
//! Evaluations return `Result<_, EvaluationError>`; an error or a value that is not finite
//! makes the line search back off (halve the step); at the start point it ends the solve as
//! [`NlpStatus::EvaluationFailed`].
//!
//! Building ([`Sqp::new`]) checks sizes, bounds and settings and returns an [`NlpError`];
//! solving returns an [`NlpSolution`] whose [`NlpStatus`] says how it ended.

mod differences;
mod error;
mod hessian;
mod kkt;
mod limits;
mod line_search;
mod point;
mod problem;
mod settings;
mod solution;
mod solver;
mod steering;
mod subproblem;

pub use differences::central_differences;
pub use error::NlpError;
pub use problem::{EvaluationError, NlpProblem};
pub use settings::{HessianMode, NlpSettings};
pub use solution::{IterationRecord, NlpMultipliers, NlpSolution, NlpStatus};
pub use solver::Sqp;
