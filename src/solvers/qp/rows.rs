//! The QP's rows in clarabel's form, A x + s = b with s in the zero cone (equalities) or ℝ₊
//! (one row per finite side), and the way back from clarabel's duals to the multipliers.

use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;
use nalgebra::DMatrix;

use super::QpSolution;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Equality,
    Inequality,
    Bound,
}

/// Where a clarabel row's dual goes: `sign · z` is added to the multiplier `index` of `kind`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Link {
    pub kind: Kind,
    pub index: usize,
    pub sign: f64,
}

/// The rows of one cone as triplets.
#[derive(Debug, Default)]
pub(super) struct ConeRows {
    rows: Vec<usize>,
    columns: Vec<usize>,
    values: Vec<f64>,
    b: Vec<f64>,
    links: Vec<Link>,
}

impl ConeRows {
    /// The row `sign · matrix[i, :] x (+ s) = b`, zeros skipped.
    pub fn push_dense(&mut self, matrix: &DMatrix<f64>, i: usize, sign: f64, b: f64, link: Link) {
        let row = self.b.len();
        for j in 0..matrix.ncols() {
            let value = matrix[(i, j)];
            if value != 0.0 {
                self.rows.push(row);
                self.columns.push(j);
                self.values.push(sign * value);
            }
        }
        self.b.push(b);
        self.links.push(link);
    }

    /// The row `sign · x_k (+ s) = b`.
    pub fn push_unit(&mut self, k: usize, sign: f64, b: f64, link: Link) {
        self.rows.push(self.b.len());
        self.columns.push(k);
        self.values.push(sign);
        self.b.push(b);
        self.links.push(link);
    }
}

/// The active side of each inequality row and bound: +1 upper, −1 lower, 0 none (equal sides
/// are equalities, not marked).
#[derive(Debug, Clone)]
pub(super) struct Activity {
    pub rows: Vec<f64>,
    pub bounds: Vec<f64>,
}

/// Zero-cone rows (equalities) and nonnegative-cone rows (one per finite side).
#[derive(Debug, Default)]
pub(super) struct RowSet {
    pub zero: ConeRows,
    pub nonnegative: ConeRows,
}

impl RowSet {
    /// l ≤ row ≤ u as an equality when l = u, else as up to two one-sided rows.
    pub fn push_range(&mut self, kind: Kind, index: usize, lower: f64, upper: f64, mut push: impl FnMut(&mut ConeRows, f64, f64, Link)) {
        if lower == upper {
            push(&mut self.zero, 1.0, upper, Link { kind, index, sign: 1.0 });
            return;
        }
        if upper.is_finite() {
            push(&mut self.nonnegative, 1.0, upper, Link { kind, index, sign: 1.0 });
        }
        if lower.is_finite() {
            push(&mut self.nonnegative, -1.0, -lower, Link { kind, index, sign: -1.0 });
        }
    }

    pub fn assemble(&self, n: usize) -> (CscMatrix<f64>, Vec<f64>, Vec<SupportedConeT<f64>>) {
        let (zero, nonnegative) = (&self.zero, &self.nonnegative);
        let offset = zero.b.len();
        let rows: Vec<usize> = zero.rows.iter().copied().chain(nonnegative.rows.iter().map(|r| r + offset)).collect();
        let columns: Vec<usize> = zero.columns.iter().chain(&nonnegative.columns).copied().collect();
        let values: Vec<f64> = zero.values.iter().chain(&nonnegative.values).copied().collect();
        let b: Vec<f64> = zero.b.iter().chain(&nonnegative.b).copied().collect();
        let a = CscMatrix::new_from_triplets(b.len(), n, rows, columns, values);
        let mut cones = Vec::with_capacity(2);
        if offset > 0 {
            cones.push(SupportedConeT::ZeroConeT(offset));
        }
        if !nonnegative.b.is_empty() {
            cones.push(SupportedConeT::NonnegativeConeT(nonnegative.b.len()));
        }
        (a, b, cones)
    }

    /// The side of each inequality row and bound that clarabel takes as active: slack s below
    /// its dual z (near an interior point solution s·z ≈ 0, so one of them is small).
    pub fn mark_activity(&self, s: &[f64], z: &[f64], activity: &mut Activity) {
        let offset = self.zero.b.len();
        for (k, link) in self.nonnegative.links.iter().enumerate() {
            if s[offset + k] < z[offset + k] {
                let target = if link.kind == Kind::Bound { &mut activity.bounds } else { &mut activity.rows };
                target[link.index] = link.sign;
            }
        }
    }

    pub fn scatter_multipliers(&self, z: &[f64], solution: &mut QpSolution) {
        for (link, z) in self.zero.links.iter().chain(&self.nonnegative.links).zip(z) {
            let target = match link.kind {
                Kind::Equality => &mut solution.equality_multipliers,
                Kind::Inequality => &mut solution.inequality_multipliers,
                Kind::Bound => &mut solution.bound_multipliers,
            };
            target[link.index] += link.sign * z;
        }
    }
}
