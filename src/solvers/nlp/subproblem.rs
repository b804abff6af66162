//! The elastic QP subproblem of an SQP iteration at x:
//!
//! ```text
//! minimise    ½ dᵀBd + gᵀd + μ Σ (pᵢ + qᵢ)
//! subject to  c_l − c ≤ J d + p − q ≤ c_u − c
//!             x_l − x ≤ d ≤ x_u − x,   p, q ≥ 0
//! ```
//!
//! with B the (positive definite) Hessian model, g = ∇f(x) (or 0 for the feasibility QP),
//! c = c(x) and J = ∂c/∂x. The elastic variables p (raising cᵢ, present when c_l,i is finite)
//! and q (lowering it, when c_u,i is finite) make the QP feasible whatever the linearisation;
//! it is the model of the ℓ1 merit function f + μ V, so when μ exceeds the multipliers of a
//! consistent linearisation the elastic variables vanish and d is the usual SQP step.
//! The bounds on x are never relaxed: x stays inside them, and a step that (nearly) reaches a
//! bound is made to reach it exactly.

use nalgebra::{DMatrix, DVector};

use super::limits::Limits;
use crate::solvers::qp::{DenseQp, QpSettings};

/// The data of one linearisation: B, g (None: the feasibility QP), c, J at x.
pub(super) struct Linearisation<'a> {
    pub x: &'a DVector<f64>,
    pub gradient: Option<&'a DVector<f64>>,
    pub constraints: &'a DVector<f64>,
    pub jacobian: &'a DMatrix<f64>,
    pub hessian: &'a DMatrix<f64>,
}

/// A solved subproblem.
#[derive(Debug, Clone)]
pub(super) struct QpStep {
    pub d: DVector<f64>,
    /// λ of the rows (sign convention of [`NlpMultipliers`](super::NlpMultipliers)).
    pub constraint_multipliers: DVector<f64>,
    /// ν of the bounds on d.
    pub bound_multipliers: DVector<f64>,
    /// V(c + J d), the ℓ1 violation of the linearised constraints.
    pub linear_violation: f64,
    /// The penalty μ of this QP.
    pub penalty: f64,
}

/// Buffers of the subproblem, sized once per problem.
#[derive(Debug, Clone)]
pub(super) struct Subproblem {
    /// [J | E]: E holds +1 in a row's p column and −1 in its q column.
    matrix: DMatrix<f64>,
    row_lower: Vec<f64>,
    row_upper: Vec<f64>,
    variable_lower: Vec<f64>,
    variable_upper: Vec<f64>,
    linear: Vec<f64>,
    linearised: DVector<f64>,
    settings: QpSettings,
}

impl Subproblem {
    pub fn new(limits: &Limits, settings: QpSettings) -> Subproblem {
        let (n, m) = (limits.variables(), limits.constraints());
        let mut columns: Vec<(usize, f64)> = Vec::new();
        for i in 0..m {
            if limits.c_lower[i].is_finite() {
                columns.push((i, 1.0));
            }
            if limits.c_upper[i].is_finite() {
                columns.push((i, -1.0));
            }
        }
        let total = n + columns.len();
        let mut matrix = DMatrix::zeros(m, total);
        for (k, &(i, sign)) in columns.iter().enumerate() {
            matrix[(i, n + k)] = sign;
        }
        let mut variable_lower = vec![0.0; total];
        let mut variable_upper = vec![f64::INFINITY; total];
        variable_lower[..n].fill(f64::NEG_INFINITY);
        variable_upper[..n].fill(f64::INFINITY);
        Subproblem {
            matrix,
            row_lower: vec![0.0; m],
            row_upper: vec![0.0; m],
            variable_lower,
            variable_upper,
            linear: vec![0.0; total],
            linearised: DVector::zeros(m),
            settings,
        }
    }

    /// Solves the subproblem with penalty μ; `None` when clarabel fails.
    pub fn solve(&mut self, limits: &Limits, data: &Linearisation, penalty: f64) -> Option<QpStep> {
        let n = limits.variables();
        self.fill(limits, data, penalty);
        let qp = DenseQp::new(data.hessian, &self.linear)
            .and_then(|qp| qp.with_inequalities(&self.matrix, &self.row_lower, &self.row_upper))
            .and_then(|qp| qp.with_bounds(&self.variable_lower, &self.variable_upper))
            .ok()?;
        let solution = qp.solve(&self.settings);
        if !solution.status.is_solved() {
            return None;
        }
        let mut d = DVector::from_column_slice(&solution.x[..n]);
        for k in 0..n {
            d[k] = snap(d[k], self.variable_lower[k], self.variable_upper[k]);
        }
        self.linearised.copy_from(data.constraints);
        self.linearised.gemv(1.0, data.jacobian, &d, 1.0);
        Some(QpStep {
            linear_violation: limits.l1_violation(self.linearised.iter().copied()),
            d,
            constraint_multipliers: DVector::from_vec(solution.inequality_multipliers),
            bound_multipliers: DVector::from_column_slice(&solution.bound_multipliers[..n]),
            penalty,
        })
    }

    fn fill(&mut self, limits: &Limits, data: &Linearisation, penalty: f64) {
        let n = limits.variables();
        self.matrix.columns_mut(0, n).copy_from(data.jacobian);
        for (i, c) in data.constraints.iter().enumerate() {
            self.row_lower[i] = limits.c_lower[i] - c;
            self.row_upper[i] = limits.c_upper[i] - c;
        }
        for k in 0..n {
            self.variable_lower[k] = (limits.lower[k] - data.x[k]).min(0.0);
            self.variable_upper[k] = (limits.upper[k] - data.x[k]).max(0.0);
            self.linear[k] = data.gradient.map_or(0.0, |g| g[k]);
        }
        self.linear[n..].fill(penalty);
    }
}

/// A bound is taken as reached when the QP's step is within this of it (relative to
/// max(1, |distance|)); the step is then set to the bound's exact distance.
const SNAP: f64 = 1e-10;

/// The step component `d` clamped to [lower, upper] and snapped onto a bound it nearly reaches.
fn snap(d: f64, lower: f64, upper: f64) -> f64 {
    let near = |bound: f64| bound.is_finite() && (d - bound).abs() <= SNAP * bound.abs().max(1.0);
    if near(lower) {
        lower
    } else if near(upper) {
        upper
    } else {
        d.clamp(lower, upper)
    }
}
