//! The box-constrained quadratic programme of a bounded Levenberg–Marquardt step:
//! minimise ½ δᵀPδ + gᵀδ subject to lower ≤ δ ≤ upper (infinite entries: no bound), P positive
//! definite. Solved by clarabel's interior point method, then polished: the bounds clarabel
//! (nearly) reaches are fixed exactly and the remaining variables solved from the reduced linear
//! system, kept when it is feasible and no worse.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::{DMatrix, DVector};

/// Why the QP gave no step.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BoxQpError {
    /// clarabel refused the problem data.
    #[error("the bounded step's QP could not be set up: {0}")]
    Setup(String),
    /// clarabel ended without a solution.
    #[error("the bounded step's QP ended with status {0:?}")]
    Status(SolverStatus),
}

/// A bound is taken as active when clarabel's solution is within this (relative) distance.
const ACTIVE_TOLERANCE: f64 = 1e-7;

/// The QP solver (stateless apart from its settings).
#[derive(Debug, Clone)]
pub struct BoxQp {
    settings: DefaultSettings<f64>,
}

impl Default for BoxQp {
    fn default() -> Self {
        let settings = DefaultSettings { verbose: false, tol_gap_abs: 1e-12, tol_gap_rel: 1e-12, tol_feas: 1e-12, max_iter: 100, ..DefaultSettings::default() };
        BoxQp { settings }
    }
}

impl BoxQp {
    /// The minimiser δ (a box with lower ≤ upper is assumed).
    pub fn solve(&self, p: &DMatrix<f64>, g: &DVector<f64>, lower: &[f64], upper: &[f64]) -> Result<DVector<f64>, BoxQpError> {
        let n = g.len();
        let (a, b) = bound_rows(lower, upper);
        let cones = [SupportedConeT::NonnegativeConeT(b.len())];
        let mut solver = DefaultSolver::new(&upper_triangle(p), g.as_slice(), &a, &b, &cones, self.settings.clone())
            .map_err(|e| BoxQpError::Setup(e.to_string()))?;
        solver.solve();
        let status = solver.solution.status;
        if !matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            return Err(BoxQpError::Status(status));
        }
        let mut step = DVector::from_iterator(n, solver.solution.x.iter().copied());
        for k in 0..n {
            step[k] = step[k].clamp(lower[k], upper[k]);
        }
        Ok(polish(p, g, lower, upper, step))
    }
}

/// The exact minimiser on clarabel's active set, if feasible and no worse than `step`.
fn polish(p: &DMatrix<f64>, g: &DVector<f64>, lower: &[f64], upper: &[f64], step: DVector<f64>) -> DVector<f64> {
    let n = g.len();
    let near = |value: f64, bound: f64| bound.is_finite() && (value - bound).abs() <= ACTIVE_TOLERANCE * (1.0 + bound.abs());
    let mut fixed: Vec<Option<f64>> = vec![None; n];
    for k in 0..n {
        if near(step[k], lower[k]) {
            fixed[k] = Some(lower[k]);
        } else if near(step[k], upper[k]) {
            fixed[k] = Some(upper[k]);
        }
    }
    let free: Vec<usize> = (0..n).filter(|&k| fixed[k].is_none()).collect();
    let mut polished = DVector::from_iterator(n, fixed.iter().map(|f| f.unwrap_or(0.0)));
    if !free.is_empty() {
        let reduced = DMatrix::from_fn(free.len(), free.len(), |i, j| p[(free[i], free[j])]);
        let coupling = p * &polished;
        let rhs = DVector::from_iterator(free.len(), free.iter().map(|&k| -(g[k] + coupling[k])));
        let Some(cholesky) = reduced.cholesky() else { return step };
        let solution = cholesky.solve(&rhs);
        for (i, &k) in free.iter().enumerate() {
            if solution[i] < lower[k] || solution[i] > upper[k] {
                return step;
            }
            polished[k] = solution[i];
        }
    }
    let objective = |d: &DVector<f64>| 0.5 * d.dot(&(p * d)) + g.dot(d);
    if objective(&polished) <= objective(&step) + 1e-15 * objective(&step).abs() {
        polished
    } else {
        step
    }
}

/// P's upper triangle in compressed columns (what clarabel expects).
fn upper_triangle(p: &DMatrix<f64>) -> CscMatrix<f64> {
    let n = p.nrows();
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..=j {
            rowval.push(i);
            nzval.push(p[(i, j)]);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(n, n, colptr, rowval, nzval)
}

/// Rows A δ ≤ b (as b − A δ ∈ ℝ₊): δ_k ≤ upper_k and −δ_k ≤ −lower_k for finite bounds.
fn bound_rows(lower: &[f64], upper: &[f64]) -> (CscMatrix<f64>, Vec<f64>) {
    let n = lower.len();
    let (mut rows, mut columns, mut values, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        for (bound, sign) in [(upper[k], 1.0), (lower[k], -1.0)] {
            if bound.is_finite() {
                rows.push(b.len());
                columns.push(k);
                values.push(sign);
                b.push(sign * bound);
            }
        }
    }
    (CscMatrix::new_from_triplets(b.len(), n, rows, columns, values), b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inactive_bounds_give_the_unconstrained_minimiser() {
        let p = DMatrix::from_row_slice(2, 2, &[4.0, 1.0, 1.0, 3.0]);
        let g = DVector::from_vec(vec![-1.0, -2.0]);
        let expected = p.clone().cholesky().unwrap().solve(&(-&g));
        let step = BoxQp::default().solve(&p, &g, &[-10.0, f64::NEG_INFINITY], &[10.0, f64::INFINITY]).unwrap();
        assert!((step - expected).amax() < 1e-14);
    }

    #[test]
    fn an_active_bound_is_met_exactly() {
        // Unconstrained minimiser (1, 2); with δ₁ ≤ 0.25 the optimum is δ₁ = 0.25, δ₂ = 2.
        let p = DMatrix::identity(2, 2);
        let g = DVector::from_vec(vec![-1.0, -2.0]);
        let step = BoxQp::default().solve(&p, &g, &[f64::NEG_INFINITY; 2], &[0.25, f64::INFINITY]).unwrap();
        assert_eq!(step[0], 0.25);
        assert!((step[1] - 2.0).abs() < 1e-14);
    }

    #[test]
    fn coupled_variables_with_one_bound_active() {
        // min ½δᵀPδ + gᵀδ, δ₀ ≥ 0: at δ₀ = 0, δ₁ = −g₁/P₁₁.
        let p = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        let g = DVector::from_vec(vec![1.0, -1.0]);
        let step = BoxQp::default().solve(&p, &g, &[0.0, f64::NEG_INFINITY], &[f64::INFINITY; 2]).unwrap();
        assert_eq!(step[0], 0.0);
        assert!((step[1] - 1.0).abs() < 1e-14);
    }
}
