//! The moment noise σ by the marginal likelihood ("evidence", type-II maximum likelihood) of a
//! linearised model under a Gaussian prior. With y ≈ M(θ̂) + J(θ − θ̂), θ ~ N(c, τ²I) and
//! noise e ~ N(0, σ²I), the innovation r = y − M(θ̂) − J(c − θ̂) is N(0, σ²I + τ²JJᵀ). In the
//! eigenbasis of τ²JJᵀ (eigenvalues κ_i, z = Uᵀr) its log-likelihood is
//!
//! ℓ(v) = −½ Σ_i [ln(v + κ_i) + z_i²/(v + κ_i)],  v = σ²,
//!
//! and σ̂² is its largest maximum over v ≥ 0. Each direction the parameters cannot reach
//! (κ = 0) counts as a plain residual does in √(RSS/(n − p)); each weakly identified one
//! (κ ≪ σ²), where the prior keeps the fit from absorbing the noise, counts nearly as much. So
//! σ̂ has more degrees of freedom than the residuals of a fit without prior: set5's ten trials
//! for eight rest-curve coordinates leave those two.
//!
//! ∂ℓ/∂v = ½ Σ (z_i² − v − κ_i)/(v + κ_i)² is negative beyond v = max z_i², so the maxima lie
//! in (0, max z_i²]; they are found as the downward sign changes of ∂ℓ/∂v on a grid in ln v and
//! refined by false position. With no such change (∂ℓ/∂v < 0 down to 1e-13·max z_i²: the data
//! fit exactly) σ̂ = 0.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::solvers::false_position;

/// Grid of ln v below ln(max z_i²): 13 decades in 0.25-wide steps.
const DECADES: f64 = 13.0;
const GRID_STEP: f64 = 0.25;
/// The refinement's tolerance in ln v (σ to 1e-10 relative).
const LOG_TOLERANCE: f64 = 2e-10;

/// σ̂ ≥ 0 (the unit of `innovation`) for the innovation r (observations), Jacobian J
/// (observations × parameters) and prior sd τ = `prior_sd` (the parameters' unit).
pub fn noise_by_evidence(jacobian: &DMatrix<f64>, prior_sd: f64, innovation: &DVector<f64>) -> f64 {
    let covariance = jacobian * jacobian.transpose() * (prior_sd * prior_sd);
    let eigen = SymmetricEigen::new(covariance);
    let z = eigen.eigenvectors.tr_mul(innovation);
    let terms: Vec<(f64, f64)> = eigen.eigenvalues.iter().map(|k| k.max(0.0)).zip(z.iter().map(|z| z * z)).collect();
    let top = terms.iter().map(|(_, z2)| *z2).fold(0.0, f64::max);
    if !(top > 0.0 && top.is_finite()) {
        return 0.0;
    }
    let slope = |u: f64| {
        let v = u.exp();
        terms.iter().map(|(k, z2)| (z2 - v - k) / (v + k).powi(2)).sum::<f64>()
    };
    let likelihood = |u: f64| {
        let v = u.exp();
        -0.5 * terms.iter().map(|(k, z2)| (v + k).ln() + z2 / (v + k)).sum::<f64>()
    };
    let high = top.ln();
    let steps = (DECADES * std::f64::consts::LN_10 / GRID_STEP).ceil() as usize;
    let grid: Vec<f64> = (0..=steps).map(|i| high - (steps - i) as f64 * GRID_STEP).collect();
    let slopes: Vec<f64> = grid.iter().map(|&u| slope(u)).collect();
    let maxima = (1..grid.len())
        .filter(|&i| slopes[i - 1] > 0.0 && slopes[i] <= 0.0)
        .filter_map(|i| false_position(slope, [grid[i - 1], grid[i]], [slopes[i - 1], slopes[i]], LOG_TOLERANCE, 200));
    maxima.max_by(|a, b| likelihood(*a).total_cmp(&likelihood(*b))).map_or(0.0, |u| (0.5 * u).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without parameters (J = 0) the estimate is the root mean square: ℓ = −½ n ln v − ½ Σr²/v.
    #[test]
    fn without_parameters_it_is_the_root_mean_square() {
        let r = DVector::from_vec(vec![1.0, -2.0, 0.5, 3.0]);
        let sigma = noise_by_evidence(&DMatrix::zeros(4, 0), 0.1, &r);
        approx::assert_relative_eq!(sigma, (r.norm_squared() / 4.0).sqrt(), max_relative = 1e-9);
    }

    /// A parameter the data fix exactly (κ ≫ σ²) takes its direction's degree of freedom, like
    /// n − p in √(RSS/(n − p)); one the prior holds (κ → 0) leaves it.
    #[test]
    fn strongly_identified_directions_drop_out_and_weak_ones_count() {
        let r = DVector::from_vec(vec![100.0, 1.0, -1.0, 1.0]);
        let strong = DMatrix::from_column_slice(4, 1, &[1e6, 0.0, 0.0, 0.0]);
        approx::assert_relative_eq!(noise_by_evidence(&strong, 1.0, &r), 1.0, max_relative = 1e-6);
        let weak = DMatrix::from_column_slice(4, 1, &[1e-9, 0.0, 0.0, 0.0]);
        approx::assert_relative_eq!(noise_by_evidence(&weak, 1.0, &r), (r.norm_squared() / 4.0).sqrt(), max_relative = 1e-6);
    }

    #[test]
    fn an_exact_fit_has_no_noise() {
        let jacobian = DMatrix::from_column_slice(3, 1, &[1.0, 2.0, 3.0]);
        let r = &jacobian * DVector::from_vec(vec![0.05]);
        assert_eq!(noise_by_evidence(&jacobian, 0.1, &r), 0.0);
        assert_eq!(noise_by_evidence(&jacobian, 0.1, &DVector::zeros(3)), 0.0);
    }
}
