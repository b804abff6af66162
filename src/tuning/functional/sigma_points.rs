//! Propagation of measurement noise to estimated parameters by sigma points (thesis Appendix
//! 6.6, eq. 6.25–6.38, after Julier & Uhlmann).
//!
//! The n measured moments y carry Gaussian noise with covariance C_y = σ²I. In normalised
//! coordinates z = (y' − y)/σ ~ N(0, I) the 2n² + 1 sigma points are
//!
//! - ψ₀ = 0, weight w₀;
//! - ψ₁ = ±s₁ e_i (i = 1…n; 2n points), weight w₁ each;
//! - ψ₂ = ±s₂ e_i ± s₂ e_j (i < j; 2n(n − 1) points), weight w₂ each.
//!
//! **Moment matching** (odd moments vanish by symmetry):
//! Σw = w₀ + 2n w₁ + 2n(n−1) w₂ = 1; E[z_i²] = 2w₁s₁² + 4(n−1)w₂s₂² = 1;
//! E[z_i⁴] = 2w₁s₁⁴ + 4(n−1)w₂s₂⁴ = 3; E[z_i²z_j²] = 4w₂s₂⁴ = 1. Hence w₂ = 1/(4s₂⁴),
//! w₁ = (4 − n)/(2s₁⁴) and (4 − n)/s₁² + (n − 1)/s₂² = 1: one free spread. The thesis chose it
//! by minimising the error in higher moments with the points within 2σ. In closed form: the
//! sixth moments of these points are E[z_i⁴z_j²] = s₂² (Gaussian: 3) and
//! E[z_i⁶] = (4 − n)s₁² + (n − 1)s₂² (Gaussian: 15; E[z_i²z_j²z_k²] is 0 for every choice,
//! Gaussian 1). On the constraint E[z_i⁶] is largest — 9, nearest 15 — at s₁ = s₂ = √3
//! (for n > 4; for n < 4 it is smallest there, and 15 would need s₂ ≠ √3, breaking
//! E[z_i⁴z_j²] = 3), which also matches E[z_i⁴z_j²] exactly. So
//!
//! **s₁ = s₂ = √3, w₀ = (n² − 7n + 18)/18, w₁ = (4 − n)/18, w₂ = 1/36**
//!
//! for every n ≥ 1 (n = 1 gives the 3-point Gauss–Hermite rule 2/3, 1/6). Each measurement is
//! perturbed by at most √3 σ < 2σ. w₁ < 0 for n > 4 (as in the thesis' n = 5: w₀ = 4/9,
//! w₁ = −1/18, w₂ = 1/36): the weighted covariance of a strongly nonlinear fit may then be
//! indefinite; through a linear map it is exact.
//!
//! **Propagation**: the fit is evaluated at y + σψ_k for every point; the parameters' mean is
//! Σ w_k x_k and their covariance Σ w_k (x_k − x̄)(x_k − x̄)ᵀ (eq. 6.35–6.38). Fits that fail are
//! reported and left out, the remaining weights rescaled to sum 1 (the moments are then no
//! longer matched; the result says so by its failure count).
//!
//! **σ**: given, or estimated from a fit's residuals as √(RSS/(n − p)) with p the number of
//! fitted parameters ([`noise_from_residuals`]).

use nalgebra::{DMatrix, DVector};

/// Errors of sigma-point propagation (the fit's own errors are results, not these).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SigmaPointError {
    /// No measurements.
    #[error("no measurements; expected at least one")]
    NoMeasurements,
    /// The measured vector does not have the points' dimension.
    #[error("{given} measurements given; the sigma points are for {expected}")]
    Dimension { given: usize, expected: usize },
    /// σ is not a positive finite number.
    #[error("noise standard deviation {0}; expected a positive finite number")]
    NoiseLevel(f64),
    /// σ cannot be estimated: n − p ≤ 0.
    #[error("{measurements} measurements and {parameters} parameters leave no degrees of freedom to estimate the noise; expected more measurements")]
    NoDegreesOfFreedom { measurements: usize, parameters: usize },
    /// Two fits returned different numbers of parameters.
    #[error("sigma point {point}: the fit returned {given} parameters, the first successful fit {expected}")]
    ParameterCount { point: usize, given: usize, expected: usize },
}

/// The 4th-order sigma points of an n-dimensional standard normal (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaPoints {
    /// n, the number of measurements.
    pub dimension: usize,
    /// s₁ = s₂ = √3.
    pub spread: f64,
    /// w₀ of ψ₀.
    pub centre_weight: f64,
    /// w₁ of each ±s₁e_i.
    pub axis_weight: f64,
    /// w₂ of each ±s₂e_i ± s₂e_j.
    pub pair_weight: f64,
}

/// One normalised sigma point: nonzero entries `(index, value)` (none, one or two).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaPoint {
    pub entries: [(usize, f64); 2],
    /// How many of `entries` are used.
    pub nonzero: usize,
    pub weight: f64,
}

impl SigmaPoint {
    /// The point as a dense vector of `dimension` entries.
    pub fn dense(&self, dimension: usize) -> Vec<f64> {
        let mut psi = vec![0.0; dimension];
        for &(i, value) in &self.entries[..self.nonzero] {
            psi[i] = value;
        }
        psi
    }
}

impl SigmaPoints {
    /// The closed-form points for n = `dimension` measurements.
    pub fn new(dimension: usize) -> Result<SigmaPoints, SigmaPointError> {
        if dimension == 0 {
            return Err(SigmaPointError::NoMeasurements);
        }
        let n = dimension as f64;
        Ok(SigmaPoints {
            dimension,
            spread: 3f64.sqrt(),
            centre_weight: (n * n - 7.0 * n + 18.0) / 18.0,
            axis_weight: (4.0 - n) / 18.0,
            pair_weight: 1.0 / 36.0,
        })
    }

    /// 2n² + 1.
    pub fn len(&self) -> usize {
        2 * self.dimension * self.dimension + 1
    }

    /// Never: n ≥ 1.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Every point, ψ₀ first, then ±s₁e_i (i ascending, + before −), then ±s₂e_i ± s₂e_j
    /// (i < j ascending; signs ++, +−, −+, −−).
    pub fn points(&self) -> Vec<SigmaPoint> {
        let (n, s) = (self.dimension, self.spread);
        let mut points = Vec::with_capacity(self.len());
        points.push(SigmaPoint { entries: [(0, 0.0); 2], nonzero: 0, weight: self.centre_weight });
        for i in 0..n {
            for sign in [1.0, -1.0] {
                points.push(SigmaPoint { entries: [(i, sign * s), (0, 0.0)], nonzero: 1, weight: self.axis_weight });
            }
        }
        for i in 0..n {
            for j in i + 1..n {
                for (a, b) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    points.push(SigmaPoint { entries: [(i, a * s), (j, b * s)], nonzero: 2, weight: self.pair_weight });
                }
            }
        }
        points
    }
}

/// √(RSS/(n − p)): the noise standard deviation estimated from a fit's `residuals` (N·m) with
/// `parameters` fitted parameters.
pub fn noise_from_residuals(residuals: &[f64], parameters: usize) -> Result<f64, SigmaPointError> {
    let n = residuals.len();
    if n <= parameters {
        return Err(SigmaPointError::NoDegreesOfFreedom { measurements: n, parameters });
    }
    Ok((residuals.iter().map(|r| r * r).sum::<f64>() / (n - parameters) as f64).sqrt())
}

/// The parameters' statistics over the sigma points.
#[derive(Debug, Clone, PartialEq)]
pub struct NoisePropagation<E> {
    /// σ used, in the measurements' unit.
    pub noise_sd: f64,
    /// Fits attempted: 2n² + 1.
    pub evaluated: usize,
    /// (point index in [`SigmaPoints::points`] order, error) of each failed fit.
    pub failures: Vec<(usize, E)>,
    /// Parameters of each point (`None` where the fit failed), in point order.
    pub estimates: Vec<Option<Vec<f64>>>,
    /// Weighted mean x̄ (eq. 6.35); `None` when no fit succeeded or the successful weights do not
    /// sum to a positive number.
    pub mean: Option<Vec<f64>>,
    /// Weighted covariance C_x (eq. 6.36–6.38), same condition.
    pub covariance: Option<DMatrix<f64>>,
}

impl<E> NoisePropagation<E> {
    /// √diag(C_x) (negative variances, possible with negative weights, give NaN).
    pub fn standard_deviations(&self) -> Option<Vec<f64>> {
        self.covariance.as_ref().map(|c| c.diagonal().iter().map(|v| v.sqrt()).collect())
    }
}

/// Evaluates `fit` (measured values → parameters) at `measured` + σψ for every sigma point and
/// returns the weighted mean and covariance of the parameters.
pub fn propagate_noise<E>(
    points: &SigmaPoints,
    measured: &[f64],
    noise_sd: f64,
    mut fit: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
) -> Result<NoisePropagation<E>, SigmaPointError> {
    if measured.len() != points.dimension {
        return Err(SigmaPointError::Dimension { given: measured.len(), expected: points.dimension });
    }
    if !(noise_sd > 0.0 && noise_sd.is_finite()) {
        return Err(SigmaPointError::NoiseLevel(noise_sd));
    }
    let all = points.points();
    let mut perturbed = measured.to_vec();
    let mut estimates = Vec::with_capacity(all.len());
    let mut failures = Vec::new();
    let mut count: Option<usize> = None;
    for (index, point) in all.iter().enumerate() {
        perturbed.copy_from_slice(measured);
        for &(i, value) in &point.entries[..point.nonzero] {
            perturbed[i] += noise_sd * value;
        }
        match fit(&perturbed) {
            Ok(x) => {
                let expected = *count.get_or_insert(x.len());
                if x.len() != expected {
                    return Err(SigmaPointError::ParameterCount { point: index, given: x.len(), expected });
                }
                estimates.push(Some(x));
            }
            Err(error) => {
                failures.push((index, error));
                estimates.push(None);
            }
        }
    }
    let (mean, covariance) = match count {
        Some(p) => weighted_moments(&all, &estimates, p),
        None => (None, None),
    };
    Ok(NoisePropagation { noise_sd, evaluated: all.len(), failures, estimates, mean, covariance })
}

/// Mean and covariance over the successful estimates, weights rescaled to sum 1.
fn weighted_moments(points: &[SigmaPoint], estimates: &[Option<Vec<f64>>], p: usize) -> (Option<Vec<f64>>, Option<DMatrix<f64>>) {
    let total: f64 = points.iter().zip(estimates).filter(|(_, x)| x.is_some()).map(|(point, _)| point.weight).sum();
    if total.is_nan() || total <= 0.0 {
        return (None, None);
    }
    let successes =
        || points.iter().zip(estimates).filter_map(|(point, x)| x.as_ref().map(|x| (point.weight / total, DVector::from_column_slice(x))));
    let mean = successes().fold(DVector::zeros(p), |sum, (w, x)| sum + x * w);
    let covariance = successes().fold(DMatrix::zeros(p, p), |sum, (w, x)| {
        let d = x - &mean;
        sum + &d * d.transpose() * w
    });
    (Some(mean.iter().copied().collect()), Some(covariance))
}
