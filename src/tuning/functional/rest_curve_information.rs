//! Identifiability and uncertainty on the rest curves: with every estimated muscle's rest fiber
//! length held, as the rest-curve fit holds it (thesis table 6.4's "+Fl", taken as exact), each
//! muscle keeps one parameter, its curve coordinate s (`rest_curve.rs`; ln of L_opt's ratio on
//! the unclamped branch). For the n coordinates:
//!
//! - J = ∂M/∂s (N·m), central differences of the muscle's contribution with step
//!   [`COORDINATE_STEP`] (one-sided on the branch s lies on when the clamp corner is nearer);
//! - F = JᵀJ/σ² ([`FisherInformation`], labels s): the Cramér–Rao bound √(F⁻¹)_ii binds every
//!   unbiased estimator;
//! - with the fit's Gaussian prior s − c ~ N(0, τ²I), the posterior covariance is
//!   (F + I/τ²)⁻¹, the MAP estimate's uncertainty, and to first order the prior moves the
//!   estimate by (F + I/τ²)⁻¹(c − s)/τ² (its bias when the truth is at s).
//!
//! Bounds on L_opt and L_ts follow through the curve's tangent: sd(L) = |dL/ds|·sd(s), and a
//! move Δs changes L by (dL/ds)·Δs. The same linearisation gives σ of the moment noise by the
//! marginal likelihood under the prior (`noise_evidence.rs`).

use nalgebra::{DMatrix, DVector};

use super::error::FunctionalError;
use super::identifiability::{FisherInformation, ParameterLabel, TransformedParameter, DEFAULT_RANK_TOLERANCE};
use super::knee_moment::KneeMomentModel;
use super::noise_evidence::noise_by_evidence;
use super::parameters::MuscleParameters;
use super::rest_curve::RestCurve;

/// The parameterisation's name in reports.
pub const REST_CURVE_PARAMETERISATION: &str = "[s] on the rest curves";

/// Difference step in s (relative in L_opt): truncation ~1e-8 relative, rounding ~1e-11 N·m/h.
pub const COORDINATE_STEP: f64 = 1e-4;

/// The Fisher information of the rest-curve coordinates at some parameters.
#[derive(Debug, Clone)]
pub struct RestCurveInformation {
    /// F of the n coordinates (labels s, scale 1).
    pub fisher: FisherInformation,
    /// Per muscle (dL_opt/ds, dL_ts/ds) at the parameters, m.
    pub tangents: Vec<[f64; 2]>,
    /// The curves, s = 0 at the parameters' L_opt (their coordinates are the labels' values).
    curves: Vec<RestCurve>,
}

impl RestCurveInformation {
    /// At `parameters` (one per estimated muscle, each on its curve through `references`, m) for
    /// the trial moments of `knee` with noise σ = `noise_sd` N·m.
    pub fn new(knee: &KneeMomentModel, parameters: &[MuscleParameters], references: &[f64], noise_sd: f64) -> Result<RestCurveInformation, FunctionalError> {
        if references.len() != parameters.len() {
            return Err(FunctionalError::all_muscles(format!("{} rest lengths for {} muscles; expected one per estimated muscle", references.len(), parameters.len())));
        }
        let mut workspace = knee.estimated_muscles(parameters)?;
        let trials = knee.trials().len();
        let mut jacobian = DMatrix::zeros(trials, parameters.len());
        let (mut curves, mut tangents, mut labels) = (Vec::new(), Vec::new(), Vec::new());
        for (e, p) in parameters.iter().enumerate() {
            let curve = RestCurve::new(knee, &mut workspace, e, references[e], p)?;
            let s = curve.coordinate_of(p);
            let [low, high] = stencil(&curve, s);
            let mut slack = p.tendon_slack_length;
            let (mut plus, mut minus) = (vec![0.0; trials], vec![0.0; trials]);
            let unavailable = || FunctionalError::Parameters { muscle: p.name.clone(), problem: format!("the rest curve has no equilibrium in every trial within {COORDINATE_STEP} of s = {s:.6}") };
            let above = curve.contributions(knee, &mut workspace, high, &mut slack, &mut plus).ok_or_else(unavailable)?;
            let below = curve.contributions(knee, &mut workspace, low, &mut slack, &mut minus).ok_or_else(unavailable)?;
            let width = high - low;
            jacobian.column_mut(e).iter_mut().zip(plus.iter().zip(&minus)).for_each(|(j, (a, b))| *j = (a - b) / width);
            tangents.push([(above.optimal_fiber_length - below.optimal_fiber_length) / width, (above.tendon_slack_length - below.tendon_slack_length) / width]);
            labels.push(ParameterLabel { muscle: p.name.clone(), parameter: TransformedParameter::RestCurveCoordinate, value: s, scale: 1.0 });
            workspace.set(knee, e, p)?;
            curves.push(curve);
        }
        let fisher = FisherInformation::from_jacobian(REST_CURVE_PARAMETERISATION, jacobian, labels, noise_sd, DEFAULT_RANK_TOLERANCE)?;
        Ok(RestCurveInformation { fisher, tangents, curves })
    }

    /// The Cramér–Rao standard deviations per muscle [L_opt, L_ts], m; `None` where the moments
    /// do not identify the coordinate.
    pub fn cramer_rao(&self) -> Vec<[Option<f64>; 2]> {
        self.fisher.standard_deviations.iter().zip(&self.tangents).map(|(sd, t)| t.map(|d| sd.map(|sd| d.abs() * sd))).collect()
    }

    /// The posterior standard deviations per muscle [L_opt, L_ts], m, under a prior of sd τ =
    /// `prior_sd` in s against moment noise σ = `noise_sd` N·m (Laplace: linearised here).
    pub fn posterior(&self, prior_sd: f64, noise_sd: f64) -> Result<Vec<[f64; 2]>, FunctionalError> {
        let covariance = self.posterior_covariance(prior_sd, noise_sd)?;
        Ok(self.tangents.iter().enumerate().map(|(e, t)| t.map(|d| d.abs() * covariance[(e, e)].sqrt())).collect())
    }

    /// The first-order move of the estimate by a prior of sd τ centred at `centre`'s
    /// coordinates, per muscle [ΔL_opt, ΔL_ts], m; σ = `noise_sd` N·m.
    pub fn prior_pull(&self, prior_sd: f64, noise_sd: f64, centre: &[MuscleParameters]) -> Result<Vec<[f64; 2]>, FunctionalError> {
        let shift = self.posterior_covariance(prior_sd, noise_sd)? * self.offset(centre) / (prior_sd * prior_sd);
        Ok(self.tangents.iter().zip(shift.iter()).map(|(t, ds)| t.map(|d| d * ds)).collect())
    }

    /// σ of the moment noise, N·m, from the marginal likelihood of the moments under a prior of
    /// sd τ = `prior_sd` in s centred at `centre`'s coordinates, linearised here (its posterior
    /// mean, `noise_evidence.rs`); `residuals` are M − M_meas at these parameters, one per trial.
    /// 0 when the moments fit exactly.
    pub fn noise_by_evidence(&self, residuals: &[f64], prior_sd: f64, centre: &[MuscleParameters]) -> f64 {
        let jacobian = &self.fisher.jacobian;
        let innovation = -DVector::from_column_slice(residuals) - jacobian * self.offset(centre);
        noise_by_evidence(jacobian, prior_sd, &innovation)
    }

    /// c − s: `centre`'s coordinates on the curves minus these.
    fn offset(&self, centre: &[MuscleParameters]) -> DVector<f64> {
        DVector::from_iterator(self.curves.len(), self.curves.iter().zip(centre).zip(&self.fisher.labels).map(|((c, p), label)| c.coordinate_of(p) - label.value))
    }

    /// (JᵀJ/σ² + I/τ²)⁻¹.
    fn posterior_covariance(&self, prior_sd: f64, noise_sd: f64) -> Result<DMatrix<f64>, FunctionalError> {
        if !(prior_sd > 0.0 && prior_sd.is_finite() && noise_sd > 0.0 && noise_sd.is_finite()) {
            return Err(FunctionalError::all_muscles(format!("prior τ = {prior_sd}, σ = {noise_sd} N·m; expected positive finite numbers")));
        }
        let j = &self.fisher.jacobian;
        let information = j.tr_mul(j) / (noise_sd * noise_sd) + DMatrix::identity(j.ncols(), j.ncols()) / (prior_sd * prior_sd);
        let cholesky = information.cholesky().ok_or_else(|| FunctionalError::all_muscles("the posterior information is not positive definite"))?;
        Ok(cholesky.inverse())
    }
}

/// The difference points around s: central, or one-sided on s's branch when the clamp corner
/// lies within a step.
fn stencil(curve: &RestCurve, s: f64) -> [f64; 2] {
    match curve.clamp() {
        Some((corner, _)) if (s - corner).abs() < COORDINATE_STEP => {
            if s >= corner { [s, s + COORDINATE_STEP] } else { [s - COORDINATE_STEP, s] }
        }
        _ => [s - COORDINATE_STEP, s + COORDINATE_STEP],
    }
}
