//! The estimators of functional scaling, from the model's parameters to an [`Estimate`]: the
//! thesis' method (Phase I feasible sets, hot start, Phase II; then — when every estimated
//! muscle has a reference rest fiber length — the rest-curve fit that holds those lengths
//! exactly, under the prior with noisy moments) or the Garner & Pandy baseline; with their
//! settings ([`FitSettings`]).

use serde::Serialize;

use super::error::FunctionalError;
use super::feasible_set::{feasible_sets, FeasibleSetSettings, MuscleFeasibleSet};
use super::garner_pandy::{fit_garner_pandy, GarnerPandyOptions, JointRange};
use super::hot_start::{hot_start, HotStart};
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::phase_two::{solve_phase_two, PhaseTwoSettings};
use super::rest_curve_fit::{RestCurveFit, RestCurveSettings};
use super::rest_curve_map::{fit_on_rest_curves, AppliedPrior, RestCurveProblem};
use super::trials::DynamometryData;
use crate::model::ModelSpec;

/// Default τ of the rest-curve prior: a subject's L_opt taken to lie within about ±10 % (one
/// standard deviation) of the linearly scaled model's.
pub const DEFAULT_PRIOR_SD: f64 = 0.1;

/// Which estimator runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum FitMethod {
    /// The thesis' method: Phase I feasible sets, hot start, Phase II NLP; then the rest-curve
    /// fit when [`FitSettings::rest_curve`] is set and every rest length is known.
    Functional,
    /// Garner & Pandy (2003): least squares on moments over [L̃m_min, L̃m_max].
    GarnerPandy,
}

/// Settings of [`estimate`] and of the analyses of a fit (`fit.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitSettings {
    pub method: FitMethod,
    pub feasible: FeasibleSetSettings,
    pub phase_two: PhaseTwoSettings,
    /// After Phase II, fit on the rest curves (rest fiber lengths exact); `None`: stop at Phase II.
    pub rest_curve: Option<RestCurveSettings>,
    /// τ of the rest-curve fit's Gaussian prior around the model's parameters (relative sd of
    /// L_opt), weighed against the moment noise σ; `None`: plain least squares.
    pub prior_sd: Option<f64>,
    /// σ of the moment noise, N·m; `None`: the subject file's, else estimated (from the marginal
    /// likelihood under the rest-curve prior, or without one from the residuals); 0: noise-free
    /// moments (no prior).
    pub noise_sd: Option<f64>,
    /// Propagate the noise through the fit (either method) at the 2n²+1 sigma points (n trials).
    pub sigma_points: bool,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            method: FitMethod::Functional,
            feasible: FeasibleSetSettings::default(),
            phase_two: PhaseTwoSettings::default(),
            rest_curve: Some(RestCurveSettings::default()),
            prior_sd: Some(DEFAULT_PRIOR_SD),
            noise_sd: None,
            sigma_points: false,
        }
    }
}

impl FitSettings {
    /// The defaults with the rest-curve fit's maximum a-posteriori estimate under the prior
    /// instead of the posterior mean (the CLI's `--map`).
    pub fn maximum_a_posteriori() -> FitSettings {
        FitSettings { rest_curve: Some(RestCurveSettings { posterior: None, ..RestCurveSettings::default() }), ..FitSettings::default() }
    }
}

/// The estimator's result, before the analyses.
#[derive(Debug, Clone)]
pub struct Estimate {
    pub fitted: Vec<MuscleParameters>,
    pub converged: bool,
    pub status: String,
    pub iterations: usize,
    /// Phase I's sets (empty for Garner & Pandy).
    pub feasible_sets: Vec<MuscleFeasibleSet>,
    pub hot_start: Option<HotStart>,
    pub active_constraints: Vec<String>,
    pub prior: Option<AppliedPrior>,
    /// The rest fiber lengths (m) the estimate holds, when the rest-curve fit made it.
    pub held_rest_lengths: Option<Vec<f64>>,
    /// When the estimate is the posterior mean on the rest curves: each muscle's sampled
    /// posterior sd of [L_opt, L_ts], m (`None` where the grid does not resolve it).
    pub sampled_sd: Option<Vec<Option<[f64; 2]>>>,
}

/// The estimator of `settings.method` alone, from `initial` (one per estimated muscle) on
/// `measured` (one per trial), without the input checks and analyses of a fit (`fit.rs`).
pub fn estimate(
    spec: &ModelSpec,
    knee: &KneeMomentModel,
    data: &DynamometryData,
    initial: &[MuscleParameters],
    measured: &[f64],
    settings: &FitSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<Estimate, FunctionalError> {
    match settings.method {
        FitMethod::Functional => {
            let given = settings.noise_sd.map(|sd| (sd, "given"));
            let noise = given.or(data.noise_sd.filter(|sd| *sd > 0.0).map(|sd| (sd, "subject file")));
            functional(knee, initial, &rest_references(knee, data), measured, noise, settings, progress)
        }
        FitMethod::GarnerPandy => garner_pandy(spec, knee, data, initial, measured, progress),
    }
}

/// Each estimated muscle's reference rest fiber length (m), where the subject file has one.
pub(super) fn rest_references(knee: &KneeMomentModel, data: &DynamometryData) -> Vec<Option<f64>> {
    knee.estimated_names().map(|name| data.reference_rest_fiber_length(name)).collect()
}

fn functional(
    knee: &KneeMomentModel,
    initial: &[MuscleParameters],
    rest: &[Option<f64>],
    measured: &[f64],
    noise: Option<(f64, &'static str)>,
    settings: &FitSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<Estimate, FunctionalError> {
    progress("Phase I: feasible sets");
    let sets = feasible_sets(knee, rest, initial, &settings.feasible)?;
    let start = hot_start(knee, &sets, initial, measured)?;
    progress(&format!("hot start: largest moment error {:.3} N·m; Phase II", start.max_moment_error));
    let solution = solve_phase_two(knee, &sets, &start.parameters, rest, measured, &settings.phase_two)?;
    progress(&format!("Phase II: {:?} after {} iterations, largest moment error {:.3e} N·m", solution.status, solution.iterations, solution.max_moment_error));
    let phase_two = Estimate {
        converged: solution.converged(),
        status: format!("{:?}", solution.status),
        iterations: solution.iterations,
        fitted: solution.parameters,
        feasible_sets: sets,
        hot_start: Some(start),
        active_constraints: solution.active_constraints,
        prior: None,
        held_rest_lengths: None,
        sampled_sd: None,
    };
    let Some(rest_curve) = &settings.rest_curve else { return Ok(phase_two) };
    let Some(references) = rest.iter().copied().collect::<Option<Vec<f64>>>() else {
        progress("rest-curve fit skipped: not every estimated muscle has a reference rest fiber length");
        return Ok(phase_two);
    };
    progress("rest curves: global search and refinement with the rest fiber lengths held");
    let model = knee.nominal_parameters();
    let problem = RestCurveProblem { knee, references: &references, origin: initial, measured, centre: &model, settings: rest_curve };
    let (curves, prior) = fit_on_rest_curves(&problem, &phase_two.fitted, noise, settings.prior_sd, progress)?;
    Ok(after_phase_two(phase_two, curves, prior, references))
}

/// The estimate of the rest-curve fit through `references`, keeping Phase I's records and
/// Phase II's status.
fn after_phase_two(phase_two: Estimate, curves: RestCurveFit, prior: Option<AppliedPrior>, references: Vec<f64>) -> Estimate {
    Estimate {
        prior,
        held_rest_lengths: Some(references),
        converged: curves.converged(),
        status: format!("rest curves {:?} (Phase II {})", curves.status, phase_two.status),
        iterations: phase_two.iterations + curves.iterations,
        fitted: curves.parameters,
        sampled_sd: curves.sampled_sd,
        active_constraints: Vec::new(),
        ..phase_two
    }
}

fn garner_pandy(
    spec: &ModelSpec,
    knee: &KneeMomentModel,
    data: &DynamometryData,
    initial: &[MuscleParameters],
    measured: &[f64],
    progress: &mut dyn FnMut(&str),
) -> Result<Estimate, FunctionalError> {
    progress("Garner & Pandy: least squares over [L̃m_min, L̃m_max]");
    let range = JointRange::compute(spec, data)?;
    let result = fit_garner_pandy(knee, &range, measured, initial, &GarnerPandyOptions::default())?;
    Ok(Estimate {
        fitted: result.parameters,
        converged: result.status.at_minimum(),
        status: format!("{:?}", result.status),
        iterations: result.iterations,
        feasible_sets: Vec::new(),
        hot_start: None,
        active_constraints: Vec::new(),
        prior: None,
        held_rest_lengths: None,
        sampled_sd: None,
    })
}
