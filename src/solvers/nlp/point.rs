//! An evaluated iterate: x with f, c, ∇f and ∂c/∂x.

use nalgebra::{DMatrix, DVector};

use super::differences::finite_evaluation;
use super::problem::NlpProblem;

#[derive(Debug, Clone)]
pub(super) struct Point {
    pub x: DVector<f64>,
    pub objective: f64,
    pub constraints: DVector<f64>,
    pub gradient: DVector<f64>,
    pub jacobian: DMatrix<f64>,
}

impl Point {
    pub fn new(n: usize, m: usize) -> Point {
        Point {
            x: DVector::zeros(n),
            objective: f64::NAN,
            constraints: DVector::zeros(m),
            gradient: DVector::zeros(n),
            jacobian: DMatrix::zeros(m, n),
        }
    }

    /// f and c at `self.x`; false when the evaluation failed or gave values that are not finite.
    pub fn evaluate<P: NlpProblem + ?Sized>(&mut self, problem: &mut P) -> bool {
        match finite_evaluation(problem, self.x.as_slice(), self.constraints.as_mut_slice()) {
            Some(f) => {
                self.objective = f;
                true
            }
            None => false,
        }
    }

    /// ∇f and ∂c/∂x at `self.x`; false when they failed or are not finite.
    pub fn differentiate<P: NlpProblem + ?Sized>(&mut self, problem: &mut P) -> bool {
        let result = problem.derivatives(self.x.as_slice(), self.gradient.as_mut_slice(), &mut self.jacobian);
        result.is_ok() && self.gradient.iter().chain(self.jacobian.iter()).all(|v| v.is_finite())
    }
}
