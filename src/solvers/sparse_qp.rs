//! A sparse convex QP with a diagonal Hessian on clarabel, for problems over whole trajectories
//! (thousands of variables, a few nonzeros per row):
//!
//! ```text
//! minimise    ½ Σ hᵢ xᵢ² + qᵀx        (hᵢ ≥ 0)
//! subject to  rows with lower ≤ aᵀx ≤ upper   (lower = upper: an equality; ±∞: no side)
//!             lower ≤ x ≤ upper
//! ```

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, SupportedConeT};

use super::qp::{clarabel_settings, ranges, status, QpError, QpSettings, QpStatus};

/// One linear row: its (variable, coefficient) entries and its two sides.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseRow {
    pub entries: Vec<(usize, f64)>,
    pub lower: f64,
    pub upper: f64,
}

/// The problem of the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseQp {
    /// hᵢ, one per variable.
    pub hessian: Vec<f64>,
    /// q, one per variable.
    pub linear: Vec<f64>,
    pub rows: Vec<SparseRow>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

/// How the solve ended, and x.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseQpSolution {
    pub status: QpStatus,
    pub x: Vec<f64>,
}

impl SparseQp {
    /// Checks sizes, indices and ranges, then solves.
    pub fn solve(&self, settings: &QpSettings) -> Result<SparseQpSolution, QpError> {
        let n = self.hessian.len();
        if self.linear.len() != n {
            return Err(QpError::Dimension { what: "linear", expected: n, found: self.linear.len() });
        }
        if self.hessian.iter().chain(&self.linear).any(|v| !v.is_finite()) || self.hessian.iter().any(|&h| h < 0.0) {
            return Err(QpError::NotFinite { what: "the objective" });
        }
        ranges("variable", n, &self.lower, &self.upper)?;
        let (lower, upper): (Vec<f64>, Vec<f64>) = self.rows.iter().map(|r| (r.lower, r.upper)).unzip();
        ranges("row", self.rows.len(), &lower, &upper)?;
        if self.rows.iter().any(|r| r.entries.iter().any(|&(j, a)| j >= n || !a.is_finite())) {
            return Err(QpError::NotFinite { what: "a row (or it names a variable that does not exist)" });
        }
        let (matrix, rhs, cones) = self.constraints();
        let hessian = CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), self.hessian.clone());
        let mut solution = SparseQpSolution { status: QpStatus::Failed, x: vec![f64::NAN; n] };
        let Ok(mut solver) = DefaultSolver::new(&hessian, &self.linear, &matrix, &rhs, &cones, clarabel_settings(settings, false)) else { return Ok(solution) };
        solver.solve();
        solution.status = status(solver.solution.status);
        if solution.status.is_solved() {
            solution.x = solver.solution.x.clone();
        }
        Ok(solution)
    }

    /// clarabel's A z + s = b: equalities in the zero cone, then every finite side (rows, then
    /// bounds) as s ≥ 0.
    fn constraints(&self) -> (CscMatrix<f64>, Vec<f64>, Vec<SupportedConeT<f64>>) {
        let n = self.hessian.len();
        let mut columns: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        let mut rhs = Vec::new();
        let mut push = |entries: &[(usize, f64)], sign: f64, side: f64, rhs: &mut Vec<f64>| {
            for &(j, a) in entries {
                columns[j].push((rhs.len(), sign * a));
            }
            rhs.push(sign * side);
        };
        let equalities: Vec<&SparseRow> = self.rows.iter().filter(|r| r.lower == r.upper).collect();
        for row in &equalities {
            push(&row.entries, 1.0, row.upper, &mut rhs);
        }
        let zero = rhs.len();
        for row in self.rows.iter().filter(|r| r.lower != r.upper) {
            if row.upper.is_finite() {
                push(&row.entries, 1.0, row.upper, &mut rhs);
            }
            if row.lower.is_finite() {
                push(&row.entries, -1.0, row.lower, &mut rhs);
            }
        }
        for j in 0..n {
            if self.upper[j].is_finite() {
                push(&[(j, 1.0)], 1.0, self.upper[j], &mut rhs);
            }
            if self.lower[j].is_finite() {
                push(&[(j, 1.0)], -1.0, self.lower[j], &mut rhs);
            }
        }
        let cones = vec![SupportedConeT::ZeroConeT(zero), SupportedConeT::NonnegativeConeT(rhs.len() - zero)];
        (compressed_columns(rhs.len(), columns), rhs, cones)
    }
}

/// A `rows`-row matrix in clarabel's compressed columns from each column's (row, value) entries,
/// in any order.
pub(super) fn compressed_columns(rows: usize, columns: Vec<Vec<(usize, f64)>>) -> CscMatrix<f64> {
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    let width = columns.len();
    for mut column in columns {
        column.sort_by_key(|&(row, _)| row);
        for (row, value) in column {
            rowval.push(row);
            nzval.push(value);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, width, colptr, rowval, nzval)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min ½(x₁² + x₂² + x₃²) s.t. x₁ + x₂ + x₃ = 3, x₂ − x₁ ≤ −1, x₃ ≤ 0.5: the KKT point by hand
    /// is x₃ = 0.5 (bound active), then x₁ + x₂ = 2.5 with x₂ = x₁ − 1 → x = (1.75, 0.75, 0.5).
    #[test]
    fn a_small_qp_meets_its_hand_solution() {
        let qp = SparseQp {
            hessian: vec![1.0; 3],
            linear: vec![0.0; 3],
            rows: vec![
                SparseRow { entries: vec![(0, 1.0), (1, 1.0), (2, 1.0)], lower: 3.0, upper: 3.0 },
                SparseRow { entries: vec![(1, 1.0), (0, -1.0)], lower: f64::NEG_INFINITY, upper: -1.0 },
            ],
            lower: vec![f64::NEG_INFINITY; 3],
            upper: vec![f64::INFINITY, f64::INFINITY, 0.5],
        };
        let solution = qp.solve(&QpSettings::default()).unwrap();
        assert!(solution.status.is_solved());
        for (x, expected) in solution.x.iter().zip([1.75, 0.75, 0.5]) {
            assert!((x - expected).abs() < 1e-7, "{:?}", solution.x);
        }
    }
}
