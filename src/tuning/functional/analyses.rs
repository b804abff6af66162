//! The analyses every functional fit reports at its estimate (`fit.rs`): sensitivity classes
//! (eq. 3.3–3.4), the Fisher identifiability of [L_opt, L_ts], [L_ts/L_opt, δ] (when Phase I
//! gave the lines), [L̃m_min, L̃m_max] and, when the fit held the rest lengths, the rest-curve
//! coordinates (thesis table 6.4), and the parameters' uncertainty (Cramér–Rao bounds, the
//! posterior with the prior, optionally the sigma-point propagation of Appendix 6.6) at the
//! moment noise σ (given, the subject file's, the prior's, else from the residuals).
//!
//! An analysis that cannot be computed at the estimate is reported as unavailable, with the
//! reason, and the fit stands: e.g. a Garner & Pandy fit that ends on the edge of its
//! parameterisation's domain (L_ts → 0), where a difference step of the Fisher information
//! leaves the domain.

use serde::Serialize;

use super::error::FunctionalError;
use super::estimator::{rest_references, Estimate, FitMethod, FitSettings};
use super::garner_pandy::{fit_garner_pandy, GarnerPandyOptions, JointRange};
use super::identifiability::{fisher_information, FisherCriteria, FisherInformation, FisherOptions, Identifiability, Parameterisation, GARNER_PANDY_PARAMETERS};
use super::knee_moment::KneeMomentModel;
use super::phase_two::solve_phase_two;
use super::rest_curve_fit::{fit_rest_curves, RestCurvePrior, RestCurveSettings};
use super::rest_curve_information::RestCurveInformation;
use super::rest_curve_map::AppliedPrior;
use super::sensitivity::{SensitivityTable, DEFAULT_RELATIVE_STEP};
use super::cause_verdict::NoiseLevel;
use super::sigma_points::{noise_from_residuals, propagate_noise, SigmaPoints};
use super::trials::DynamometryData;
use crate::model::ModelSpec;

/// What the analyses found at one estimate.
#[derive(Debug, Clone)]
pub struct Analyses {
    /// `None` when unavailable.
    pub sensitivity: Option<SensitivityTable>,
    /// The parameterisations whose Fisher information could be computed.
    pub identifiability: Vec<ParameterisationReport>,
    pub uncertainty: Uncertainty,
    pub unavailable: Vec<AnalysisFailure>,
}

/// An analysis that could not be computed at the estimate, and why; the fit stands.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalysisFailure {
    /// e.g. "sensitivity" or "[L̃m_min, L̃m_max]".
    pub analysis: String,
    pub reason: String,
}

/// `result`'s value, or `None` with the failure of `analysis` noted in `unavailable`.
pub(super) fn attempt<T>(unavailable: &mut Vec<AnalysisFailure>, analysis: &str, result: Result<T, FunctionalError>) -> Option<T> {
    result.map_err(|e| unavailable.push(AnalysisFailure { analysis: analysis.to_string(), reason: e.to_string() })).ok()
}

/// What a fit ran on: the model, its knee moments, the trials, the settings and the measured
/// moments (N·m, one per trial).
pub struct FitInputs<'a> {
    pub spec: &'a ModelSpec,
    pub knee: &'a KneeMomentModel,
    pub data: &'a DynamometryData,
    pub settings: &'a FitSettings,
    pub measured: &'a [f64],
}

/// The analyses at `estimate` of `inputs`, whose moments are `moments` (N·m, one per trial).
/// `progress` hears the stages.
pub fn analyse(inputs: &FitInputs, estimate: &Estimate, moments: &[f64], progress: &mut dyn FnMut(&str)) -> Analyses {
    let FitInputs { knee, data, settings, measured, .. } = *inputs;
    let mut unavailable = Vec::new();
    progress("sensitivity and identifiability");
    let sensitivity = attempt(&mut unavailable, "sensitivity", SensitivityTable::compute(knee, &estimate.fitted, DEFAULT_RELATIVE_STEP));
    let residuals: Vec<f64> = moments.iter().zip(measured).map(|(m, y)| m - y).collect();
    let (noise_sd, noise_source, noise_level) = noise(settings, data, estimate.prior, &residuals, 2 * estimate.fitted.len());
    let options = FisherOptions::new(noise_sd);
    let hill = attempt(&mut unavailable, Parameterisation::Hill.name(), fisher_information(knee, &estimate.fitted, &Parameterisation::Hill, &options));
    let cramer_rao = hill.as_ref().map(|f| f.standard_deviations.chunks(2).map(|c| [c[0], c[1]]).collect());
    let mut fishers: Vec<FisherInformation> = hill.into_iter().collect();
    fishers.extend(other_parameterisations(inputs, estimate, &options, &mut unavailable));
    let mut identifiability: Vec<ParameterisationReport> = fishers.iter().map(ParameterisationReport::of).collect();
    let on_curves = estimate
        .held_rest_lengths
        .as_ref()
        .and_then(|references| attempt(&mut unavailable, "rest-curve information", RestCurveInformation::new(knee, &estimate.fitted, references, noise_sd)));
    identifiability.extend(on_curves.as_ref().map(|information| ParameterisationReport::of(&information.fisher)));
    let rest_curve = on_curves.and_then(|information| {
        attempt(&mut unavailable, "rest-curve uncertainty", RestCurveUncertainty::of(&information, estimate.prior, estimate.sampled_sd.as_deref()))
    });
    let sigma_points = settings.sigma_points.then(|| attempt(&mut unavailable, "sigma points", sigma_point_spread(inputs, estimate, noise_sd, progress))).flatten();
    let uncertainty = Uncertainty { noise_sd, noise_source, noise_level, cramer_rao, rest_curve, sigma_points };
    Analyses { sensitivity, identifiability, uncertainty, unavailable }
}

/// The Fisher information of one parameterisation at the fit (thesis table 6.4).
#[derive(Debug, Clone, Serialize)]
pub struct ParameterisationReport {
    /// e.g. "[L_opt, L_ts]".
    pub parameterisation: &'static str,
    /// D- and E-criteria of F in the parameters' units and relative to their values.
    pub absolute: FisherCriteria,
    pub relative: FisherCriteria,
    pub identifiability: Identifiability,
}

impl ParameterisationReport {
    fn of(fisher: &FisherInformation) -> ParameterisationReport {
        ParameterisationReport {
            parameterisation: fisher.parameterisation,
            absolute: fisher.absolute,
            relative: fisher.relative,
            identifiability: fisher.identifiability.clone(),
        }
    }
}

/// Standard deviations of the fitted (L_opt, L_ts), m.
#[derive(Debug, Clone, Serialize)]
pub struct Uncertainty {
    /// σ of the moment noise used, N·m.
    pub noise_sd: f64,
    /// Where σ came from: "given", "subject file", "marginal likelihood" (under the rest-curve
    /// prior) or "residuals".
    pub noise_source: &'static str,
    /// σ as a noise estimate ([`NoiseLevel::Estimated`]), or a nominal scale of an exact fit
    /// or of a fit without degrees of freedom.
    #[serde(skip)]
    pub noise_level: NoiseLevel,
    /// Cramér–Rao bound per muscle [sd L_opt, sd L_ts]; `None` where not identifiable (the
    /// whole list when the Fisher information is unavailable).
    pub cramer_rao: Option<Vec<[Option<f64>; 2]>>,
    /// With the rest fiber lengths held, when the rest-curve fit made the estimate.
    pub rest_curve: Option<RestCurveUncertainty>,
    /// Sigma-point propagation per muscle [sd L_opt, sd L_ts], when run.
    pub sigma_points: Option<Vec<[f64; 2]>>,
}

/// Standard deviations of the fitted (L_opt, L_ts) along the rest curves, m (one parameter per
/// muscle: its curve coordinate).
#[derive(Debug, Clone, Serialize)]
pub struct RestCurveUncertainty {
    /// Cramér–Rao bound from the moments alone (any unbiased estimator), at the report's σ;
    /// `None` where not identifiable.
    pub cramer_rao: Vec<[Option<f64>; 2]>,
    /// Posterior sd with the fit's prior, at the prior's σ, when it had one: of the posterior
    /// mean from its Gibbs samples; of the MAP fit, and of a coordinate the sampling grid does
    /// not resolve, the Laplace approximation (linearised at the estimate).
    pub posterior: Option<Vec<[f64; 2]>>,
    /// Per muscle, how its posterior sd was found: [`SAMPLED`] or [`LAPLACE`].
    pub posterior_method: Option<Vec<&'static str>>,
}

/// A posterior sd from the Gibbs samples.
pub const SAMPLED: &str = "sampled";
/// A posterior sd of the Laplace approximation.
pub const LAPLACE: &str = "Laplace";

impl RestCurveUncertainty {
    /// `sampled`: each muscle's sampled posterior sd of [L_opt, L_ts], where there is one.
    fn of(information: &RestCurveInformation, prior: Option<AppliedPrior>, sampled: Option<&[Option<[f64; 2]>]>) -> Result<RestCurveUncertainty, FunctionalError> {
        let cramer_rao = information.cramer_rao();
        let Some(prior) = prior else { return Ok(RestCurveUncertainty { cramer_rao, posterior: None, posterior_method: None }) };
        let laplace = information.posterior(prior.coordinate_sd, prior.noise_sd)?;
        let per_muscle = laplace.into_iter().enumerate().map(|(e, sd)| match sampled.and_then(|s| s[e]) {
            Some(sampled) => (sampled, SAMPLED),
            None => (sd, LAPLACE),
        });
        let (posterior, methods) = per_muscle.unzip();
        Ok(RestCurveUncertainty { cramer_rao, posterior: Some(posterior), posterior_method: Some(methods) })
    }
}

/// The source of σ when the fit is exact: a nominal 1 N·m scales the criteria.
const EXACT_FIT_NOMINAL: &str = "nominal (exact fit: 1 N·m)";
/// The source of σ when the fit has no degrees of freedom left to estimate it.
const NO_DEGREES_NOMINAL: &str = "nominal (no more trials than parameters: 1 N·m)";

/// σ: given, else the subject file's (when positive), else the prior's (the fit's own
/// estimate), else √(RSS/(n − p)) of the fit (when the fit is exact or has no degrees of
/// freedom, a nominal 1 N·m scales the criteria, and the source says why), its source and
/// what it is ([`NoiseLevel`]).
fn noise(settings: &FitSettings, data: &DynamometryData, prior: Option<AppliedPrior>, residuals: &[f64], parameters: usize) -> (f64, &'static str, NoiseLevel) {
    let (sd, source) = if let Some(sd) = settings.noise_sd.filter(|sd| *sd > 0.0) {
        (sd, "given")
    } else if let Some(sd) = data.noise_sd.filter(|sd| *sd > 0.0) {
        (sd, "subject file")
    } else if let Some(prior) = prior {
        (prior.noise_sd, prior.noise_source)
    } else {
        match noise_from_residuals(residuals, parameters) {
            Ok(sd) if sd > 1e-6 => (sd, "residuals"),
            Ok(_) => return (1.0, EXACT_FIT_NOMINAL, NoiseLevel::Exact),
            Err(_) => return (1.0, NO_DEGREES_NOMINAL, NoiseLevel::Unknown),
        }
    };
    (sd, source, NoiseLevel::Estimated(sd))
}

/// The Fisher information at the fit of [L_ts/L_opt, δ] (when Phase I gave the lines) and
/// [L̃m_min, L̃m_max], each where it can be computed.
fn other_parameterisations(inputs: &FitInputs, estimate: &Estimate, options: &FisherOptions, unavailable: &mut Vec<AnalysisFailure>) -> Vec<FisherInformation> {
    let FitInputs { spec, knee, data, .. } = *inputs;
    let lines: Vec<(f64, f64)> = estimate.feasible_sets.iter().map(|s| (s.line.c1, s.line.c2)).collect();
    let mut all = Vec::new();
    if !lines.is_empty() {
        let parameterisation = Parameterisation::SlackRatioDelta(&lines);
        all.extend(attempt(unavailable, parameterisation.name(), fisher_information(knee, &estimate.fitted, &parameterisation, options)));
    }
    let garner_pandy = JointRange::compute(spec, data).and_then(|range| fisher_information(knee, &estimate.fitted, &Parameterisation::GarnerPandy(&range), options));
    all.extend(attempt(unavailable, GARNER_PANDY_PARAMETERS, garner_pandy));
    all
}

/// The fit re-solved from itself at each sigma point of the moments (Garner & Pandy's for its
/// fit; the rest-curve fit without its global search, with the fit's prior if it had one, when
/// it made the fit; else Phase II); sd of (L_opt, L_ts).
fn sigma_point_spread(inputs: &FitInputs, estimate: &Estimate, noise_sd: f64, progress: &mut dyn FnMut(&str)) -> Result<Vec<[f64; 2]>, FunctionalError> {
    let FitInputs { knee, data, settings, measured, .. } = *inputs;
    let rest = &rest_references(knee, data);
    let points = SigmaPoints::new(measured.len()).map_err(|e| FunctionalError::all_muscles(e.to_string()))?;
    let range = match settings.method {
        FitMethod::GarnerPandy => Some(JointRange::compute(inputs.spec, inputs.data)?),
        FitMethod::Functional => None,
    };
    let references: Option<Vec<f64>> = rest.iter().copied().collect();
    let local = settings.rest_curve.map(|s| RestCurveSettings { global_search: false, ..s });
    let model = knee.nominal_parameters();
    let prior = estimate.prior.map(|applied| RestCurvePrior { model: &model, coordinate_sd: applied.coordinate_sd, noise_sd });
    progress(&format!("sigma points: {} refits at σ = {noise_sd:.3} N·m", points.len()));
    let refit = |perturbed: &[f64]| -> Result<Vec<f64>, FunctionalError> {
        let parameters = match (&range, &references, &local) {
            (Some(range), _, _) => fit_garner_pandy(knee, range, perturbed, &estimate.fitted, &GarnerPandyOptions::default())?.parameters,
            (None, Some(references), Some(local)) => fit_rest_curves(knee, references, &estimate.fitted, perturbed, std::slice::from_ref(&estimate.fitted), prior, local)?.parameters,
            _ => solve_phase_two(knee, &estimate.feasible_sets, &estimate.fitted, rest, perturbed, &settings.phase_two)?.parameters,
        };
        Ok(parameters.iter().flat_map(|p| [p.optimal_fiber_length, p.tendon_slack_length]).collect())
    };
    let propagation = propagate_noise(&points, measured, noise_sd, refit).map_err(|e| FunctionalError::all_muscles(e.to_string()))?;
    let sd = propagation
        .standard_deviations()
        .ok_or_else(|| FunctionalError::all_muscles(format!("every one of the {} sigma-point fits failed", propagation.evaluated)))?;
    Ok(sd.chunks(2).map(|c| [c[0], c[1]]).collect())
}

