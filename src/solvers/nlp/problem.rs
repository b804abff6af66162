//! The problem an [`Sqp`](super::Sqp) solves:
//!
//! ```text
//! minimise    f(x)
//! subject to  c_l ≤ c(x) ≤ c_u      (c_l = c_u: an equality; ±∞: no side)
//!             x_l ≤ x ≤ x_u          (±∞: no bound)
//! ```

use nalgebra::DMatrix;

use super::differences::central_differences;

/// A failed evaluation of f, c or their derivatives (e.g. an equilibrium that cannot be
/// computed at x). The solver treats it like a point outside the domain: a line search backs
/// off from it. A value that is not finite (NaN, ±∞) is treated the same way.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("evaluation failed: {message}")]
pub struct EvaluationError {
    pub message: String,
}

impl EvaluationError {
    pub fn new(message: impl Into<String>) -> EvaluationError {
        EvaluationError { message: message.into() }
    }
}

/// A smooth nonlinear programme. f and c are evaluated together ([`evaluate`](Self::evaluate))
/// because they usually share work; derivatives default to central differences
/// ([`central_differences`]), the Hessian of the Lagrangian to a damped BFGS approximation.
///
/// The solver calls `bounds` and `constraint_bounds` once, when it is built, and only
/// evaluates points inside the bounds.
pub trait NlpProblem {
    /// n, the number of variables.
    fn dimension(&self) -> usize;

    /// (x_l, x_u), n entries each; infinite entries are absent bounds. Default: none.
    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let n = self.dimension();
        (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n])
    }

    /// (c_l, c_u), one entry per constraint (m of them, possibly none).
    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>);

    /// f(x), and c(x) into `constraints` (m entries).
    fn evaluate(&mut self, x: &[f64], constraints: &mut [f64]) -> Result<f64, EvaluationError>;

    /// ∇f(x) into `gradient` (n) and ∂c/∂x into `jacobian` (m×n). Default: central
    /// differences of [`evaluate`](Self::evaluate), 2n evaluations.
    fn derivatives(&mut self, x: &[f64], gradient: &mut [f64], jacobian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        central_differences(self, x, gradient, jacobian)
    }

    /// Whether [`hessian`](Self::hessian) is implemented.
    fn has_hessian(&self) -> bool {
        false
    }

    /// The Hessian of the Lagrangian, ∇²f(x) + Σᵢ λᵢ ∇²cᵢ(x) (n×n, symmetric), with the
    /// multipliers λ of [`NlpMultipliers::constraints`](super::NlpMultipliers). Only called
    /// when [`has_hessian`](Self::has_hessian) is true.
    fn hessian(&mut self, x: &[f64], multipliers: &[f64], hessian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        let _ = (x, multipliers, hessian);
        Err(EvaluationError::new("the problem provides no Hessian"))
    }
}
