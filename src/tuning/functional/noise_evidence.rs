//! The moment noise σ from the marginal likelihood ("evidence") of a linearised model under a
//! Gaussian prior. With y ≈ M(θ̂) + J(θ − θ̂), θ ~ N(c, τ²I) and noise e ~ N(0, σ²I), the
//! innovation r = y − M(θ̂) − J(c − θ̂) is N(0, σ²I + τ²JJᵀ). In the eigenbasis of τ²JJᵀ
//! (eigenvalues κ_i, z = Uᵀr) its log-likelihood is
//!
//! ℓ(v) = −½ Σ_i [ln(v + κ_i) + z_i²/(v + κ_i)],  v = σ².
//!
//! Each direction the parameters cannot reach (κ = 0) counts as a plain residual does in
//! √(RSS/(n − p)); each weakly identified one (κ ≪ σ²), where the prior keeps the fit from
//! absorbing the noise, counts nearly as much. So σ has more degrees of freedom than the
//! residuals of a fit without prior: set5's ten trials for eight rest-curve coordinates leave
//! those two.
//!
//! σ̂ is σ's posterior mean under the scale-invariant prior p(σ) ∝ 1/σ (uniform in ln v):
//! σ̂ = ∫ e^{u/2 + ℓ(eᵘ)} du / ∫ e^{ℓ(eᵘ)} du. With few degrees of freedom ℓ is skewed towards
//! large σ, and its maximum (type-II maximum likelihood) falls well below σ in a share of the
//! draws — there the prior loses its weight and the fit absorbs the noise; the mean keeps the
//! skew. Without parameters it is √(S/2)·Γ((n − 1)/2)/Γ(n/2), S = Σr².
//!
//! ∂ℓ/∂v = ½ Σ (z_i² − v − κ_i)/(v + κ_i)² is negative beyond v = max z_i², so the maxima lie
//! in (0, max z_i²]; they are found as the downward sign changes of ∂ℓ/∂v on a grid in ln v and
//! refined by false position. Without one (∂ℓ/∂v < 0 down to 1e-13·max z_i²: the data fit
//! exactly) σ̂ = 0. The integrals run over that grid and 20 above it (beyond, e^ℓ falls as
//! v^(−n/2)). Where every direction has κ > 0 (n ≤ p: four angles per direction for eight
//! coordinates), ℓ does not fall towards v = 0, the posterior is improper and σ̂ is the highest
//! maximum.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::solvers::false_position;

/// Grid of ln v below ln(max z_i²): 13 decades, searched in 0.25-wide steps.
const DECADES: f64 = 13.0;
const GRID_STEP: f64 = 0.25;
/// The refinement's tolerance in ln v (σ to 1e-10 relative).
const LOG_TOLERANCE: f64 = 2e-10;
/// The posterior mean's range above ln(max z_i²) and its trapezoid step, in ln v.
const ABOVE: f64 = 20.0;
const QUADRATURE_STEP: f64 = 0.01;
/// ℓ at the grid's floor above this (relative to the maximum): the posterior does not vanish
/// towards σ = 0, and σ̂ is the maximum.
const IMPROPER: f64 = -20.0;

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
    let likelihood = |u: f64| {
        let v = u.exp();
        -0.5 * terms.iter().map(|(k, z2)| (v + k).ln() + z2 / (v + k)).sum::<f64>()
    };
    let slope = |u: f64| {
        let v = u.exp();
        terms.iter().map(|(k, z2)| (z2 - v - k) / (v + k).powi(2)).sum::<f64>()
    };
    let high = top.ln();
    let steps = (DECADES * std::f64::consts::LN_10 / GRID_STEP).ceil() as usize;
    let grid: Vec<f64> = (0..=steps).map(|i| high - (steps - i) as f64 * GRID_STEP).collect();
    let slopes: Vec<f64> = grid.iter().map(|&u| slope(u)).collect();
    let maxima = (1..grid.len())
        .filter(|&i| slopes[i - 1] > 0.0 && slopes[i] <= 0.0)
        .filter_map(|i| false_position(slope, [grid[i - 1], grid[i]], [slopes[i - 1], slopes[i]], LOG_TOLERANCE, 200));
    let Some(mode) = maxima.max_by(|a, b| likelihood(*a).total_cmp(&likelihood(*b))) else { return 0.0 };
    let peak = likelihood(mode);
    if likelihood(grid[0]) - peak > IMPROPER {
        return (0.5 * mode).exp();
    }
    posterior_mean(|u| likelihood(u) - peak, grid[0], high + ABOVE)
}

/// ∫ e^{u/2 + ℓ(u)} du / ∫ e^{ℓ(u)} du over [low, high] (trapezoids of [`QUADRATURE_STEP`]),
/// with ℓ = `likelihood` shifted to its maximum 0 (so that e^ℓ cannot overflow).
fn posterior_mean(likelihood: impl Fn(f64) -> f64, low: f64, high: f64) -> f64 {
    let steps = ((high - low) / QUADRATURE_STEP).ceil() as usize;
    let (mut weighted, mut total) = (0.0, 0.0);
    for i in 0..=steps {
        let u = low + (high - low) * i as f64 / steps as f64;
        let weight = likelihood(u).exp() * if i == 0 || i == steps { 0.5 } else { 1.0 };
        weighted += weight * (0.5 * u).exp();
        total += weight;
    }
    weighted / total
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Without parameters (J = 0), e^ℓ = v^(−n/2)·e^(−S/2v) with S = Σr²: 1/v is Gamma(n/2, S/2)
    /// under the prior uniform in ln v, and E[σ] = √(S/2)·Γ((n − 1)/2)/Γ(n/2); n = 4 gives
    /// √(S/2)·Γ(3/2) = √(S/2)·√π/2.
    #[test]
    fn without_parameters_it_is_the_scaled_inverse_gamma_mean() {
        let r = DVector::from_vec(vec![1.0, -2.0, 0.5, 3.0]);
        let sigma = noise_by_evidence(&DMatrix::zeros(4, 0), 0.1, &r);
        approx::assert_relative_eq!(sigma, (r.norm_squared() / 2.0).sqrt() * PI.sqrt() / 2.0, max_relative = 1e-9);
    }

    /// A parameter the data fix exactly (κ ≫ σ²) takes its direction's degree of freedom, like
    /// n − p in √(RSS/(n − p)): three directions with S = 3 give √(3/2)·Γ(1)/Γ(3/2) =
    /// √(3/2)·2/√π. One the prior holds (κ → 0) leaves it: all four, S = 10003.
    #[test]
    fn strongly_identified_directions_drop_out_and_weak_ones_count() {
        let r = DVector::from_vec(vec![100.0, 1.0, -1.0, 1.0]);
        let strong = DMatrix::from_column_slice(4, 1, &[1e6, 0.0, 0.0, 0.0]);
        approx::assert_relative_eq!(noise_by_evidence(&strong, 1.0, &r), 1.5f64.sqrt() * 2.0 / PI.sqrt(), max_relative = 1e-6);
        let weak = DMatrix::from_column_slice(4, 1, &[1e-9, 0.0, 0.0, 0.0]);
        approx::assert_relative_eq!(noise_by_evidence(&weak, 1.0, &r), (r.norm_squared() / 2.0).sqrt() * PI.sqrt() / 2.0, max_relative = 1e-6);
    }

    /// Two observations, two parameters with J = I and τ = 1 (κ = 1 in both directions): ℓ does
    /// not fall towards v = 0, so σ̂ is the maximum, v + 1 = Σz²/2 = 5 for r = (3, 1): σ̂ = 2.
    #[test]
    fn without_a_free_direction_it_is_the_maximum() {
        let r = DVector::from_vec(vec![3.0, 1.0]);
        approx::assert_relative_eq!(noise_by_evidence(&DMatrix::identity(2, 2), 1.0, &r), 2.0, max_relative = 1e-9);
    }

    #[test]
    fn an_exact_fit_has_no_noise() {
        let jacobian = DMatrix::from_column_slice(3, 1, &[1.0, 2.0, 3.0]);
        let r = &jacobian * DVector::from_vec(vec![0.05]);
        assert_eq!(noise_by_evidence(&jacobian, 0.1, &r), 0.0);
        assert_eq!(noise_by_evidence(&jacobian, 0.1, &DVector::zeros(3)), 0.0);
    }
}
