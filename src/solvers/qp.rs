//! A general dense convex quadratic programme solved by clarabel's interior point method:
//!
//! ```text
//! minimise    ½ xᵀPx + qᵀx
//! subject to  A x = b                 (equality rows)
//!             l ≤ G x ≤ u             (two-sided rows; l = u is an equality, ±∞ no side)
//!             lower ≤ x ≤ upper       (bounds; ±∞ no bound, lower = upper fixes x)
//! ```
//!
//! P is symmetric positive semidefinite (its upper triangle is used, after symmetrising). It may
//! be smaller than x: a k×k P is the leading block, the remaining variables enter linearly.
//!
//! Multipliers follow one sign convention for every row: at the solution
//! `P x + q + Aᵀy + Gᵀλ + ν = 0`, where λᵢ ≥ 0 when row i sits at its upper side and λᵢ ≤ 0 when
//! at its lower side (ν likewise for bounds), y is free.
//!
//! Building ([`DenseQp::new`] and the `with_*` methods) checks sizes and bounds and returns a
//! [`QpError`]; solving always returns a [`QpSolution`] whose [`QpStatus`] says how it ended.
//!
//! Polishing (on by default): clarabel's interior point solution meets the active constraints
//! only to its tolerance and leaves small multipliers on inactive ones. The polish takes the
//! sides whose slack is below their dual (s < z) as equalities, solves the equality-constrained
//! KKT system on that active set exactly (dense LU) and keeps the result when it is a KKT point
//! of the whole QP: inactive rows and free variables within their ranges (to 10⁻⁹ relative),
//! multipliers of the right sign. At a degenerate point the sides with negligible multipliers
//! are left out in a second try. Active sides are then met to rounding and inactive
//! multipliers are exactly 0.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::DMatrix;

use rows::{Activity, Kind, Link, RowSet};

mod polish;
mod rows;

/// Why a QP could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QpError {
    /// P is not square, or larger than x.
    #[error("the QP's Hessian is {rows}×{columns}; it must be square and at most {variables}×{variables}")]
    Hessian { rows: usize, columns: usize, variables: usize },
    /// A matrix or vector has the wrong size.
    #[error("{what} has size {found}, expected {expected}")]
    Dimension { what: &'static str, expected: usize, found: usize },
    /// A bound pair with lower > upper, lower = +∞, upper = −∞ or a NaN.
    #[error("{what} {index}: the range [{lower}, {upper}] is empty or not a number")]
    Range { what: &'static str, index: usize, lower: f64, upper: f64 },
    /// Problem data that is not finite.
    #[error("{what} contains a value that is not finite")]
    NotFinite { what: &'static str },
}

/// clarabel's stopping tolerances and iteration limit (verbose output is always off).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QpSettings {
    /// Absolute and relative duality gap and feasibility tolerance.
    pub tolerance: f64,
    /// Interior point iterations allowed.
    pub max_iterations: u32,
    /// Polish clarabel's solution on its active set (see the module documentation).
    pub polish: bool,
}

impl Default for QpSettings {
    fn default() -> Self {
        QpSettings { tolerance: 1e-10, max_iterations: 200, polish: true }
    }
}

/// How a QP solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QpStatus {
    /// Solved to the tolerance of [`QpSettings`].
    Solved,
    /// Solved to clarabel's reduced accuracy.
    AlmostSolved,
    /// The constraints cannot be met (certificate found).
    Infeasible,
    /// The objective is unbounded below on the feasible set.
    Unbounded,
    /// The iteration limit was reached.
    MaxIterations,
    /// clarabel refused the data or stopped on a numerical error or lack of progress.
    Failed,
}

impl QpStatus {
    /// Whether `x` and the multipliers are a solution (full or reduced accuracy).
    pub fn is_solved(self) -> bool {
        matches!(self, QpStatus::Solved | QpStatus::AlmostSolved)
    }
}

/// A QP's solution; the vectors are meaningful only when `status.is_solved()`.
#[derive(Debug, Clone, PartialEq)]
pub struct QpSolution {
    pub status: QpStatus,
    pub x: Vec<f64>,
    /// ½ xᵀPx + qᵀx.
    pub objective: f64,
    /// y, one per row of A.
    pub equality_multipliers: Vec<f64>,
    /// λ, one per row of G (0 for rows with no finite side).
    pub inequality_multipliers: Vec<f64>,
    /// ν, one per variable.
    pub bound_multipliers: Vec<f64>,
    /// clarabel's iterations.
    pub iterations: u32,
    /// Whether the polished solution replaced clarabel's.
    pub polished: bool,
}

/// A validated QP over borrowed data.
#[derive(Debug, Clone, Copy)]
pub struct DenseQp<'a> {
    hessian: &'a DMatrix<f64>,
    linear: &'a [f64],
    equalities: Option<(&'a DMatrix<f64>, &'a [f64])>,
    inequalities: Option<(&'a DMatrix<f64>, &'a [f64], &'a [f64])>,
    bounds: Option<(&'a [f64], &'a [f64])>,
}

impl<'a> DenseQp<'a> {
    /// min ½xᵀPx + qᵀx over x ∈ ℝⁿ, n = `linear.len()`; P (`hessian`) is k×k with k ≤ n.
    pub fn new(hessian: &'a DMatrix<f64>, linear: &'a [f64]) -> Result<Self, QpError> {
        let (rows, columns) = hessian.shape();
        if rows != columns || rows > linear.len() {
            return Err(QpError::Hessian { rows, columns, variables: linear.len() });
        }
        finite("the Hessian", hessian.as_slice())?;
        finite("the linear term", linear)?;
        Ok(DenseQp { hessian, linear, equalities: None, inequalities: None, bounds: None })
    }

    /// Adds the rows A x = b.
    pub fn with_equalities(mut self, matrix: &'a DMatrix<f64>, rhs: &'a [f64]) -> Result<Self, QpError> {
        self.check_columns("the equality matrix", matrix)?;
        size("the equality right-hand side", matrix.nrows(), rhs.len())?;
        finite("the equality matrix", matrix.as_slice())?;
        finite("the equality right-hand side", rhs)?;
        self.equalities = Some((matrix, rhs));
        Ok(self)
    }

    /// Adds the rows l ≤ G x ≤ u.
    pub fn with_inequalities(mut self, matrix: &'a DMatrix<f64>, lower: &'a [f64], upper: &'a [f64]) -> Result<Self, QpError> {
        self.check_columns("the inequality matrix", matrix)?;
        finite("the inequality matrix", matrix.as_slice())?;
        ranges("inequality row", matrix.nrows(), lower, upper)?;
        self.inequalities = Some((matrix, lower, upper));
        Ok(self)
    }

    /// Adds the bounds lower ≤ x ≤ upper.
    pub fn with_bounds(mut self, lower: &'a [f64], upper: &'a [f64]) -> Result<Self, QpError> {
        ranges("variable", self.linear.len(), lower, upper)?;
        self.bounds = Some((lower, upper));
        Ok(self)
    }

    fn check_columns(&self, what: &'static str, matrix: &DMatrix<f64>) -> Result<(), QpError> {
        size(what, self.linear.len(), matrix.ncols())
    }

    /// Solves with clarabel (never panics; failures are a [`QpStatus`]). When clarabel stops
    /// at its iteration limit or on a numerical failure it is run once more with the
    /// conservative settings (no equilibration, shorter steps; see `clarabel_settings`).
    pub fn solve(&self, settings: &QpSettings) -> QpSolution {
        let rows = self.rows();
        let (a, b, cones) = rows.assemble(self.linear.len());
        let p = self.upper_triangle();
        let (mut solution, mut activity) = self.run_clarabel(&p, &a, &b, &cones, &rows, clarabel_settings(settings, false));
        if matches!(solution.status, QpStatus::MaxIterations | QpStatus::Failed) {
            (solution, activity) = self.run_clarabel(&p, &a, &b, &cones, &rows, clarabel_settings(settings, true));
        }
        if solution.status.is_solved() && settings.polish {
            polish::polish(self, &mut solution, &activity);
        }
        solution
    }

    fn run_clarabel(
        &self,
        p: &CscMatrix<f64>,
        a: &CscMatrix<f64>,
        b: &[f64],
        cones: &[SupportedConeT<f64>],
        rows: &RowSet,
        settings: DefaultSettings<f64>,
    ) -> (QpSolution, Activity) {
        let mut solution = self.empty_solution();
        let mut activity = Activity { rows: vec![0.0; solution.inequality_multipliers.len()], bounds: vec![0.0; solution.x.len()] };
        let Ok(mut solver) = DefaultSolver::new(p, self.linear, a, b, cones, settings) else { return (solution, activity) };
        solver.solve();
        solution.status = status(solver.solution.status);
        solution.iterations = solver.solution.iterations;
        if solution.status.is_solved() {
            solution.x.copy_from_slice(&solver.solution.x);
            solution.objective = self.objective(&solution.x);
            rows.scatter_multipliers(&solver.solution.z, &mut solution);
            rows.mark_activity(&solver.solution.s, &solver.solution.z, &mut activity);
        }
        (solution, activity)
    }

    fn empty_solution(&self) -> QpSolution {
        let n = self.linear.len();
        QpSolution {
            status: QpStatus::Failed,
            x: vec![0.0; n],
            objective: f64::NAN,
            equality_multipliers: vec![0.0; self.equalities.map_or(0, |(a, _)| a.nrows())],
            inequality_multipliers: vec![0.0; self.inequalities.map_or(0, |(g, _, _)| g.nrows())],
            bound_multipliers: vec![0.0; n],
            iterations: 0,
            polished: false,
        }
    }

    fn objective(&self, x: &[f64]) -> f64 {
        let k = self.hessian.nrows();
        let mut value: f64 = self.linear.iter().zip(x).map(|(q, x)| q * x).sum();
        for j in 0..k {
            for i in 0..k {
                value += 0.5 * x[i] * self.hessian[(i, j)] * x[j];
            }
        }
        value
    }

    /// The upper triangle of (P + Pᵀ)/2, padded with zeros to n×n, in compressed columns.
    fn upper_triangle(&self) -> CscMatrix<f64> {
        let (k, n) = (self.hessian.nrows(), self.linear.len());
        let (mut colptr, mut rowval, mut nzval) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
        colptr.push(0);
        for j in 0..n {
            for i in 0..=j.min(k) {
                let value = if j < k { 0.5 * (self.hessian[(i, j)] + self.hessian[(j, i)]) } else { 0.0 };
                if value != 0.0 {
                    rowval.push(i);
                    nzval.push(value);
                }
            }
            colptr.push(rowval.len());
        }
        CscMatrix::new(n, n, colptr, rowval, nzval)
    }

    /// The rows in clarabel's form, A x + s = b, s in the zero cone or ℝ₊.
    fn rows(&self) -> RowSet {
        let mut rows = RowSet::default();
        if let Some((matrix, rhs)) = self.equalities {
            for (i, &value) in rhs.iter().enumerate() {
                rows.zero.push_dense(matrix, i, 1.0, value, Link { kind: Kind::Equality, index: i, sign: 1.0 });
            }
        }
        if let Some((matrix, lower, upper)) = self.inequalities {
            for i in 0..matrix.nrows() {
                rows.push_range(Kind::Inequality, i, lower[i], upper[i], |cone, sign, b, link| cone.push_dense(matrix, i, sign, b, link));
            }
        }
        if let Some((lower, upper)) = self.bounds {
            for k in 0..lower.len() {
                rows.push_range(Kind::Bound, k, lower[k], upper[k], |cone, sign, b, link| cone.push_unit(k, sign, b, link));
            }
        }
        rows
    }
}

/// clarabel's settings: verbose off, the tolerance of `settings`; `conservative` turns
/// equilibration off and shortens the steps to 0.9 of the way to the cone boundary (clarabel
/// can stall on small, well-posed QPs with its equilibration).
pub(super) fn clarabel_settings(settings: &QpSettings, conservative: bool) -> DefaultSettings<f64> {
    let defaults = DefaultSettings::default();
    DefaultSettings {
        verbose: false,
        tol_gap_abs: settings.tolerance,
        tol_gap_rel: settings.tolerance,
        tol_feas: settings.tolerance,
        max_iter: settings.max_iterations,
        equilibrate_enable: !conservative,
        max_step_fraction: if conservative { 0.9 } else { defaults.max_step_fraction },
        ..defaults
    }
}

/// clarabel's end as a [`QpStatus`].
pub(super) fn status(status: SolverStatus) -> QpStatus {
    match status {
        SolverStatus::Solved => QpStatus::Solved,
        SolverStatus::AlmostSolved => QpStatus::AlmostSolved,
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => QpStatus::Infeasible,
        SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => QpStatus::Unbounded,
        SolverStatus::MaxIterations | SolverStatus::MaxTime => QpStatus::MaxIterations,
        _ => QpStatus::Failed,
    }
}

fn size(what: &'static str, expected: usize, found: usize) -> Result<(), QpError> {
    if expected == found {
        Ok(())
    } else {
        Err(QpError::Dimension { what, expected, found })
    }
}

fn finite(what: &'static str, values: &[f64]) -> Result<(), QpError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(QpError::NotFinite { what })
    }
}

/// `count` ranges [lower, upper], each non-empty.
/// Checks that `lower` and `upper` hold `count` bounds each and that every range is non-empty.
pub(super) fn ranges(what: &'static str, count: usize, lower: &[f64], upper: &[f64]) -> Result<(), QpError> {
    size("the lower bounds", count, lower.len())?;
    size("the upper bounds", count, upper.len())?;
    for (index, (&l, &u)) in lower.iter().zip(upper).enumerate() {
        if l.is_nan() || u.is_nan() || l > u || l == f64::INFINITY || u == f64::NEG_INFINITY {
            return Err(QpError::Range { what, index, lower: l, upper: u });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    #[test]
    fn equality_constrained_minimiser_and_multiplier() {
        // min ½(x₀² + x₁²) s.t. x₀ + x₁ = 2: x = (1, 1), y = −1 (x + y·(1, 1) = 0).
        let p = DMatrix::identity(2, 2);
        let a = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let qp = DenseQp::new(&p, &[0.0, 0.0]).unwrap().with_equalities(&a, &[2.0]).unwrap();
        let solution = qp.solve(&QpSettings::default());
        assert_eq!(solution.status, QpStatus::Solved);
        assert!((solution.x[0] - 1.0).abs() < 1e-9 && (solution.x[1] - 1.0).abs() < 1e-9);
        assert!((solution.equality_multipliers[0] + 1.0).abs() < 1e-9);
        assert!((solution.objective - 1.0).abs() < 1e-9);
    }

    #[test]
    fn multiplier_signs_follow_the_active_side() {
        // min ½‖x − (3, −3)‖² s.t. −1 ≤ x₀ + 0 ≤ 1 (row), x₁ ≥ −2 (bound).
        let p = DMatrix::identity(2, 2);
        let g = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        let q = [-3.0, 3.0];
        let qp = DenseQp::new(&p, &q).unwrap().with_inequalities(&g, &[-1.0], &[1.0]).unwrap().with_bounds(&[-INF, -2.0], &[INF, INF]).unwrap();
        let solution = qp.solve(&QpSettings::default());
        assert!(solution.status.is_solved());
        assert!((solution.x[0] - 1.0).abs() < 1e-8 && (solution.x[1] + 2.0).abs() < 1e-8);
        // Upper side active: λ = 2 > 0; lower bound active: ν₁ = −1 < 0.
        assert!((solution.inequality_multipliers[0] - 2.0).abs() < 1e-7);
        assert!((solution.bound_multipliers[1] + 1.0).abs() < 1e-7);
        assert!(solution.bound_multipliers[0].abs() < 1e-7);
    }

    #[test]
    fn a_smaller_hessian_leaves_the_other_variables_linear() {
        // min ½x₀² − x₀ + x₁, 0 ≤ x₁ ≤ 5: x = (1, 0), ν₁ = −1.
        let p = DMatrix::identity(1, 1);
        let qp = DenseQp::new(&p, &[-1.0, 1.0]).unwrap().with_bounds(&[-INF, 0.0], &[INF, 5.0]).unwrap();
        let solution = qp.solve(&QpSettings::default());
        assert!(solution.status.is_solved());
        assert!((solution.x[0] - 1.0).abs() < 1e-8 && solution.x[1].abs() < 1e-8);
        assert!((solution.bound_multipliers[1] + 1.0).abs() < 1e-7);
    }

    #[test]
    fn fixed_variables_and_equal_sided_rows_are_equalities() {
        let p = DMatrix::identity(2, 2);
        let g = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let qp = DenseQp::new(&p, &[0.0, 0.0]).unwrap().with_inequalities(&g, &[3.0], &[3.0]).unwrap().with_bounds(&[1.0, -INF], &[1.0, INF]).unwrap();
        let solution = qp.solve(&QpSettings::default());
        assert!(solution.status.is_solved());
        assert!((solution.x[0] - 1.0).abs() < 1e-9 && (solution.x[1] - 2.0).abs() < 1e-9);
        // x₁ + λ = 0 → λ = −2; x₀ + λ + ν₀ = 0 → ν₀ = 1.
        assert!((solution.inequality_multipliers[0] + 2.0).abs() < 1e-8);
        assert!((solution.bound_multipliers[0] - 1.0).abs() < 1e-8);
    }

    #[test]
    fn infeasible_rows_are_a_status() {
        let p = DMatrix::identity(1, 1);
        let g = DMatrix::from_row_slice(2, 1, &[1.0, 1.0]);
        let qp = DenseQp::new(&p, &[0.0]).unwrap().with_inequalities(&g, &[2.0, -INF], &[INF, 1.0]).unwrap();
        assert_eq!(qp.solve(&QpSettings::default()).status, QpStatus::Infeasible);
    }

    #[test]
    fn building_checks_sizes_and_ranges() {
        let p = DMatrix::identity(3, 3);
        assert!(matches!(DenseQp::new(&p, &[0.0, 0.0]), Err(QpError::Hessian { .. })));
        let p = DMatrix::identity(2, 2);
        let qp = DenseQp::new(&p, &[0.0, 0.0]).unwrap();
        assert!(matches!(qp.with_bounds(&[1.0, 0.0], &[0.0, 0.0]), Err(QpError::Range { index: 0, .. })));
        assert!(matches!(qp.with_bounds(&[f64::NAN, 0.0], &[0.0, 0.0]), Err(QpError::Range { .. })));
        let g = DMatrix::zeros(1, 3);
        assert!(matches!(qp.with_inequalities(&g, &[0.0], &[1.0]), Err(QpError::Dimension { .. })));
    }
}
