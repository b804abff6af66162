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
//!    the penalty μ is steered (`steering.rs`) so that the step meets the linearised
//!    constraints where it can, a feasibility-restoration step is taken where it cannot, and a
//!    stationary point of the violation that is not feasible ends the solve as
//!    `LocallyInfeasible`; after a step that meets its linearised constraints μ is relaxed
//!    towards the multipliers (Powell's update, `solver.rs`);
//! 3. the convergence test (scaled KKT conditions, [`NlpSettings`]) uses the QP's multipliers;
//! 4. a backtracking Armijo line search on φ = f + μ V (V = Σᵢ dist(cᵢ, [c_l,i, c_u,i]), the ℓ1
//!    violation) with an optional second-order correction and arc search (`line_search.rs`)
//!    gives the next iterate, always inside the bounds.
//!
//! The QP subproblems are solved by [`DenseQp`](crate::solvers::qp::DenseQp) (clarabel, verbose
//! off, gap and feasibility tolerance [`NlpSettings::qp_tolerance`], then polished on the active
//! set so that active constraints are met to rounding).
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
