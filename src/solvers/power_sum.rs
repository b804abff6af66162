//! Minimise a sum of powers of absolute values on clarabel, the objective of static optimisation
//! with an activation exponent p other than 2:
//!
//! ```text
//! minimise    Σ |xᵢ|ᵖ            (p > 1)
//! subject to  A x = b
//!             lower ≤ x ≤ upper   (±∞: no bound)
//! ```
//!
//! Each term gets an epigraph variable tᵢ with (tᵢ, 1, xᵢ) in the power cone of exponent α = 1/p,
//! tᵢ^α · 1^(1−α) ≥ |xᵢ|, i.e. tᵢ ≥ |xᵢ|ᵖ, and Σ tᵢ is minimised: a convex conic programme whose
//! optimum is the problem's. The interior point method stops on the duality gap, and the objective
//! is flat at its minimum, so x is as accurate as about the square root of the tolerance, the
//! objective to the tolerance; variables next to a bound are then put on it and the equalities
//! restored to rounding by the least-norm change of the others.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, SupportedConeT};
use nalgebra::{DMatrix, DVector};

use super::qp::{clarabel_settings, ranges, status, QpError, QpSettings, QpStatus};
use super::sparse_qp::compressed_columns;

/// How the solve ended, x and Σ |xᵢ|ᵖ at x.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerSumSolution {
    pub status: QpStatus,
    pub x: Vec<f64>,
    pub objective: f64,
}

/// Solves the programme of the module documentation for exponent `p` (> 1).
pub fn minimise_power_sum(p: f64, matrix: &DMatrix<f64>, rhs: &[f64], lower: &[f64], upper: &[f64], settings: &QpSettings) -> Result<PowerSumSolution, QpError> {
    let n = matrix.ncols();
    if !(p > 1.0 && p.is_finite()) {
        return Err(QpError::Range { what: "exponent", index: 0, lower: p, upper: p });
    }
    if rhs.len() != matrix.nrows() {
        return Err(QpError::Dimension { what: "rhs", expected: matrix.nrows(), found: rhs.len() });
    }
    if matrix.iter().chain(rhs).any(|v| !v.is_finite()) {
        return Err(QpError::NotFinite { what: "the equality rows" });
    }
    ranges("variable", n, lower, upper)?;
    let rows = Rows::build(matrix, rhs, lower, upper, 1.0 / p);
    let linear: Vec<f64> = (0..2 * n).map(|j| if j < n { 0.0 } else { 1.0 }).collect();
    let hessian = CscMatrix::zeros((2 * n, 2 * n));
    let mut solution = PowerSumSolution { status: QpStatus::Failed, x: vec![f64::NAN; n], objective: f64::NAN };
    let Ok(mut solver) = DefaultSolver::new(&hessian, &linear, &compressed_columns(rows.rhs.len(), rows.columns), &rows.rhs, &rows.cones, clarabel_settings(settings, false)) else { return Ok(solution) };
    solver.solve();
    solution.status = status(solver.solution.status);
    if solution.status.is_solved() {
        solution.x = restore_equalities(matrix, rhs, lower, upper, &solver.solution.x[..n]);
        solution.objective = solution.x.iter().map(|x| x.abs().powf(p)).sum();
    }
    Ok(solution)
}

/// The interior point meets A x = b only to its feasibility tolerance and stays just inside its
/// bounds. Variables within 10⁻⁶ (relative) of a bound are put on it, and the least-norm change
/// of the others meets A x = b exactly — kept when that system is regular and the change stays
/// within the bounds, else x is returned as it is.
fn restore_equalities(matrix: &DMatrix<f64>, rhs: &[f64], lower: &[f64], upper: &[f64], x: &[f64]) -> Vec<f64> {
    let near = |gap: f64, bound: f64| bound.is_finite() && gap <= 1e-6 * bound.abs().max(1.0);
    let mut corrected = x.to_vec();
    let mut free = Vec::new();
    for j in 0..x.len() {
        if near(x[j] - lower[j], lower[j]) {
            corrected[j] = lower[j];
        } else if near(upper[j] - x[j], upper[j]) {
            corrected[j] = upper[j];
        } else {
            free.push(j);
        }
    }
    let residual = DVector::from_column_slice(rhs) - matrix * DVector::from_column_slice(&corrected);
    let columns = matrix.select_columns(&free);
    let Some(multipliers) = (&columns * columns.transpose()).lu().solve(&residual) else { return x.to_vec() };
    let change = columns.transpose() * multipliers;
    for (k, &j) in free.iter().enumerate() {
        corrected[j] += change[k];
    }
    let within = free.iter().all(|&j| lower[j] <= corrected[j] && corrected[j] <= upper[j]);
    if within && corrected.iter().all(|v| v.is_finite()) { corrected } else { x.to_vec() }
}

/// Rows of A z + s = b (z = [x, t]) with s in the cones, kept column by column.
struct Rows {
    /// Per column, its (row, value) entries.
    columns: Vec<Vec<(usize, f64)>>,
    rhs: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
}

impl Rows {
    fn build(matrix: &DMatrix<f64>, rhs: &[f64], lower: &[f64], upper: &[f64], alpha: f64) -> Rows {
        let n = matrix.ncols();
        let mut rows = Rows { columns: vec![Vec::new(); 2 * n], rhs: Vec::new(), cones: Vec::new() };
        for (i, &b) in rhs.iter().enumerate() {
            for j in 0..n {
                if matrix[(i, j)] != 0.0 {
                    rows.columns[j].push((i, matrix[(i, j)]));
                }
            }
            rows.rhs.push(b);
        }
        rows.cones.push(SupportedConeT::ZeroConeT(rhs.len()));
        let mut bounds = 0;
        for j in 0..n {
            for (sign, bound) in [(1.0, upper[j]), (-1.0, -lower[j])] {
                if bound.is_finite() {
                    rows.columns[j].push((rows.rhs.len(), sign));
                    rows.rhs.push(bound);
                    bounds += 1;
                }
            }
        }
        rows.cones.push(SupportedConeT::NonnegativeConeT(bounds));
        for j in 0..n {
            let first = rows.rhs.len();
            rows.columns[n + j].push((first, -1.0));
            rows.columns[j].push((first + 2, -1.0));
            rows.rhs.extend([0.0, 1.0, 0.0]);
            rows.cones.push(SupportedConeT::PowerConeT(alpha));
        }
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min |x₁|³ + |x₂|³ subject to x₁ + x₂ = 1: x = (½, ½) by symmetry; with x₂ ≤ 0.2 the bound
    /// holds and x₁ = 0.8.
    #[test]
    fn cubes_split_evenly_and_respect_bounds() {
        let matrix = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let free = minimise_power_sum(3.0, &matrix, &[1.0], &[f64::NEG_INFINITY; 2], &[f64::INFINITY; 2], &QpSettings::default()).unwrap();
        assert!(free.status.is_solved());
        assert!((free.x[0] - 0.5).abs() < 1e-5 && (free.x[1] - 0.5).abs() < 1e-5, "{:?}", free.x);
        assert!((free.objective - 0.25).abs() < 1e-9, "{}", free.objective);
        assert!((free.x[0] + free.x[1] - 1.0).abs() < 1e-15, "the equality holds to rounding");
        let bounded = minimise_power_sum(3.0, &matrix, &[1.0], &[f64::NEG_INFINITY; 2], &[f64::INFINITY, 0.2], &QpSettings::default()).unwrap();
        assert!((bounded.x[0] - 0.8).abs() < 1e-5 && (bounded.x[1] - 0.2).abs() < 1e-5, "{:?}", bounded.x);
    }

    /// With a negative demand the absolute value matters: x = (−½, −½).
    #[test]
    fn negative_values_cost_their_absolute_powers() {
        let matrix = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let solution = minimise_power_sum(1.5, &matrix, &[-1.0], &[-5.0; 2], &[5.0; 2], &QpSettings::default()).unwrap();
        assert!((solution.x[0] + 0.5).abs() < 1e-5 && (solution.x[1] + 0.5).abs() < 1e-5, "{:?}", solution.x);
        assert!((solution.objective - 2.0 * 0.5f64.powf(1.5)).abs() < 1e-9, "{}", solution.objective);
    }
}
