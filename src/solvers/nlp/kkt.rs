//! The KKT measures of the convergence test (see [`NlpSettings`](super::NlpSettings)).

use nalgebra::{DMatrix, DVector};

use super::limits::Limits;

/// Scaled KKT measures at one iterate with one set of multipliers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Kkt {
    /// ‖∇f + Jᵀλ + ν‖∞ / max(1, ‖∇f‖∞).
    pub stationarity: f64,
    /// max |multiplier|·(distance from the side its sign names) / max(1, ‖∇f‖∞).
    pub complementarity: f64,
    /// Largest constraint violation.
    pub violation: f64,
}

impl Kkt {
    pub fn error(&self) -> f64 {
        self.stationarity.max(self.complementarity)
    }
}

/// The measures at x (with c = c(x), J = ∂c/∂x, g = ∇f) for multipliers λ (rows) and ν (bounds).
pub(super) fn measure(
    limits: &Limits,
    x: &DVector<f64>,
    gradient: &DVector<f64>,
    constraints: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    lambda: &DVector<f64>,
    nu: &DVector<f64>,
) -> Kkt {
    let scale = gradient.amax().max(1.0);
    let mut residual = gradient + nu;
    residual.gemv_tr(1.0, jacobian, lambda, 1.0);
    let rows = lambda.iter().zip(constraints).zip(limits.c_lower.iter().zip(&limits.c_upper));
    let row_gaps = rows.map(|((&l, &c), (&lo, &up))| gap_product(l, c, lo, up));
    let bounds = nu.iter().zip(x).zip(limits.lower.iter().zip(&limits.upper));
    let bound_gaps = bounds.map(|((&v, &x), (&lo, &up))| gap_product(v, x, lo, up));
    Kkt {
        stationarity: residual.amax() / scale,
        complementarity: row_gaps.chain(bound_gaps).fold(0.0, f64::max) / scale,
        violation: limits.max_violation(constraints.as_slice()),
    }
}

/// |multiplier|·|distance of the value from the side the multiplier's sign names| (0 for an
/// equality or a side that does not exist).
fn gap_product(multiplier: f64, value: f64, lower: f64, upper: f64) -> f64 {
    let side = if lower == upper {
        return 0.0;
    } else if multiplier > 0.0 {
        upper
    } else {
        lower
    };
    if side.is_finite() {
        multiplier.abs() * (side - value).abs()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complementarity_uses_the_side_the_multiplier_names() {
        assert_eq!(gap_product(2.0, 0.5, 0.0, 1.0), 1.0);
        assert_eq!(gap_product(-2.0, 0.5, 0.0, 1.0), 1.0);
        assert_eq!(gap_product(-2.0, 0.25, 0.0, f64::INFINITY), 0.5);
        assert_eq!(gap_product(3.0, 0.25, 0.0, 0.0), 0.0);
        assert_eq!(gap_product(3.0, 0.25, 0.0, f64::INFINITY), 0.0);
    }

    #[test]
    fn measures_of_a_kkt_point() {
        // min x₀ + x₁ s.t. x₀ + x₁ ≥ 1 (λ = −1), x₀ ≥ 0: stationarity 1 + λ + ν = 0.
        let limits = Limits { lower: vec![0.0, f64::NEG_INFINITY], upper: vec![f64::INFINITY; 2], c_lower: vec![1.0], c_upper: vec![f64::INFINITY] };
        let x = DVector::from_vec(vec![0.25, 0.75]);
        let gradient = DVector::from_vec(vec![1.0, 1.0]);
        let constraints = DVector::from_vec(vec![1.0]);
        let jacobian = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let kkt = measure(&limits, &x, &gradient, &constraints, &jacobian, &DVector::from_vec(vec![-1.0]), &DVector::zeros(2));
        assert_eq!((kkt.stationarity, kkt.complementarity, kkt.violation), (0.0, 0.0, 0.0));
        let kkt = measure(&limits, &x, &gradient, &DVector::from_vec(vec![0.9]), &jacobian, &DVector::from_vec(vec![-0.5]), &DVector::zeros(2));
        assert_eq!(kkt.stationarity, 0.5);
        assert!((kkt.complementarity - 0.05).abs() < 1e-15 && (kkt.violation - 0.1).abs() < 1e-15);
    }
}
