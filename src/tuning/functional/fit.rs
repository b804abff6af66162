//! One functional-scaling run, as `osim-tune scale MODEL TRIALS/` does it: the input checks,
//! the single parameter that best explains the initial model's error, the fit (Phase I, hot
//! start and Phase II, then — when every estimated muscle has a reference rest fiber length —
//! the rest-curve fit that holds those lengths exactly; or the Garner & Pandy baseline), and the
//! analyses at the estimate (`analyses.rs`).

use serde::Serialize;

use super::analyses::{analyse, attempt, AnalysisFailure, FitInputs, ParameterisationReport, Uncertainty};
use super::cause::{single_causes, SingleCause};
use super::error::FunctionalError;
use super::feasible_set::{feasible_sets, FeasibleSetSettings, MuscleFeasibleSet};
use super::garner_pandy::{fit_garner_pandy, GarnerPandyOptions, JointRange};
use super::hot_start::{hot_start, HotStart};
use super::knee_moment::KneeMomentModel;
use super::parameters::{MuscleParameters, Parameter};
use super::phase_two::{solve_phase_two, PhaseTwoSettings};
use super::rest_curve_fit::{RestCurveFit, RestCurveSettings};
use super::rest_curve_map::{fit_on_rest_curves, AppliedPrior, RestCurveProblem};
use super::sensitivity::SensitivityTable;
use super::trials::{DynamometryData, Direction};
use crate::io::osim::{format_numbers, OsimDocument, OsimError};
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

/// Settings of [`fit`].
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

/// The outcome of one fit and its analyses.
#[derive(Debug, Clone, Serialize)]
pub struct FunctionalFit {
    pub method: FitMethod,
    pub initial: Vec<MuscleParameters>,
    pub fitted: Vec<MuscleParameters>,
    /// Whether the solver met its convergence test; a fit that did not is reported, not used.
    pub converged: bool,
    /// The solver's own status word.
    pub solver_status: String,
    pub iterations: usize,
    /// Per trial: label, measured, initial-model and fitted-model moment (N·m).
    pub trials: Vec<TrialFit>,
    pub feasible_sets: Vec<MuscleFeasibleSet>,
    pub hot_start: Option<HotStart>,
    /// Phase II constraints active at the solution (e.g. a rest length at its tolerance).
    pub active_constraints: Vec<String>,
    /// The rest-curve fit's prior, when it was used.
    pub prior: Option<AppliedPrior>,
    /// Each single parameter fitted alone from the initial model, best explanation first.
    pub single_causes: Vec<SingleCause>,
    /// `None` when unavailable (see `unavailable`).
    pub sensitivity: Option<SensitivityTable>,
    pub identifiability: Vec<ParameterisationReport>,
    pub uncertainty: Uncertainty,
    /// The analyses that could not be computed, and why (the fit stands).
    pub unavailable: Vec<AnalysisFailure>,
}

/// One trial's moments.
#[derive(Debug, Clone, Serialize)]
pub struct TrialFit {
    pub trial: String,
    pub measured: f64,
    pub initial: f64,
    pub fitted: f64,
}

impl FunctionalFit {
    pub fn max_moment_error(&self) -> f64 {
        self.trials.iter().map(|t| (t.fitted - t.measured).abs()).fold(0.0, f64::max)
    }

    pub fn rms_moment_error(&self) -> f64 {
        (self.trials.iter().map(|t| (t.fitted - t.measured).powi(2)).sum::<f64>() / self.trials.len().max(1) as f64).sqrt()
    }

    /// Writes the fitted L_opt and L_ts into `document` (the model the fit started from, muscles
    /// under `/forceset`); values equal to the model's stay as written. Returns the number of
    /// values changed.
    pub fn apply(&self, document: &mut OsimDocument) -> Result<usize, OsimError> {
        let mut changed = 0;
        for (fitted, initial) in self.fitted.iter().zip(&self.initial) {
            for parameter in [Parameter::OptimalFiberLength, Parameter::TendonSlackLength] {
                if fitted.get(parameter) != initial.get(parameter) {
                    let path = format!("/forceset/{}/{}", fitted.name, parameter.property());
                    document.set_property(&path, &format_numbers(&[fitted.get(parameter)]))?;
                    changed += 1;
                }
            }
        }
        Ok(changed)
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
/// `measured` (one per trial), without the input checks and analyses of [`fit`].
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

/// Checks the trials against the model, fits and analyses. `progress` hears each stage.
pub fn fit(
    spec: &ModelSpec,
    knee: &KneeMomentModel,
    data: &DynamometryData,
    settings: &FitSettings,
    progress: &mut dyn FnMut(&str),
) -> Result<FunctionalFit, FunctionalError> {
    check_coordinate_ranges(spec, data)?;
    check_observations(knee, data)?;
    let initial = knee.nominal_parameters();
    let measured = data.measured_moments();
    let initial_moments = knee.moments(&initial)?;
    check_sign_convention(data, &measured, &initial_moments)?;
    let rest = rest_references(knee, data);
    progress("single causes");
    let mut unavailable = Vec::new();
    let single_causes = attempt(&mut unavailable, "single causes", single_causes(knee, &initial, &measured)).unwrap_or_default();
    let estimate = estimate(spec, knee, data, &initial, &measured, settings, progress)?;
    let moments = knee.moments(&estimate.fitted)?;
    let inputs = FitInputs { spec, knee, data, settings, rest: &rest, measured: &measured };
    let analyses = analyse(&inputs, &estimate, &moments, progress);
    unavailable.extend(analyses.unavailable);
    let trials = knee
        .trials()
        .iter()
        .enumerate()
        .map(|(t, trial)| TrialFit { trial: trial.label(), measured: measured[t], initial: initial_moments[t], fitted: moments[t] })
        .collect();
    Ok(FunctionalFit {
        method: settings.method,
        initial,
        fitted: estimate.fitted,
        converged: estimate.converged,
        solver_status: estimate.status,
        iterations: estimate.iterations,
        trials,
        feasible_sets: estimate.feasible_sets,
        hot_start: estimate.hot_start,
        active_constraints: estimate.active_constraints,
        prior: estimate.prior,
        single_causes,
        sensitivity: analyses.sensitivity,
        identifiability: analyses.identifiability,
        uncertainty: analyses.uncertainty,
        unavailable,
    })
}

fn rest_references(knee: &KneeMomentModel, data: &DynamometryData) -> Vec<Option<f64>> {
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

/// Every trial angle within its model coordinate's range.
fn check_coordinate_ranges(spec: &ModelSpec, data: &DynamometryData) -> Result<(), FunctionalError> {
    for trial in &data.trials {
        let angles = [(&data.columns.knee_angle, trial.knee_angle), (&data.columns.hip_flexion, trial.hip_flexion), (&data.columns.ankle_angle, trial.ankle_angle)];
        for (name, value) in angles {
            let Some(coordinate) = spec.coordinates().find(|c| &c.name == name) else { continue };
            let [low, high] = coordinate.range;
            if !(low - 1e-9..=high + 1e-9).contains(&value) {
                return Err(FunctionalError::TrialValue {
                    file: trial.file.clone(),
                    line: trial.line,
                    column: name.clone(),
                    value: value.to_degrees(),
                    expected: format!("an angle within the model's range of {name}, [{:.1}, {:.1}]°", low.to_degrees(), high.to_degrees()),
                });
            }
        }
    }
    Ok(())
}

/// Per direction, distinct knee angles plus known rest lengths must reach the agonists'
/// parameter count (2 each); otherwise those parameters are not identifiable.
fn check_observations(knee: &KneeMomentModel, data: &DynamometryData) -> Result<(), FunctionalError> {
    let estimated: Vec<&str> = knee.estimated_names().collect();
    for direction in [Direction::Extension, Direction::Flexion] {
        let agonists: Vec<&String> = data.agonists(direction).iter().filter(|a| estimated.contains(&a.as_str())).collect();
        let mut angles: Vec<f64> = data.trials.iter().filter(|t| t.direction == direction).map(|t| t.knee_angle).collect();
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let rest = agonists.iter().filter(|a| data.reference_rest_fiber_length(a).is_some()).count();
        let (observations, parameters) = (angles.len() + rest, 2 * agonists.len());
        if observations < parameters {
            let names: Vec<String> = agonists.iter().map(|a| format!("{a} (L_opt, L_ts)")).collect();
            return Err(FunctionalError::NotIdentifiable {
                folder: data.folder.clone(),
                direction: direction.key(),
                observations,
                parameters,
                unidentifiable: names.join(", "),
            });
        }
    }
    Ok(())
}

/// The measured moments must have the model's sign: Σ M_meas·M_model > 0 over the trials of
/// each direction. Opposite signs in both directions mean the other sign convention.
fn check_sign_convention(data: &DynamometryData, measured: &[f64], model: &[f64]) -> Result<(), FunctionalError> {
    let agreement = |direction: Direction| -> f64 {
        data.trials.iter().enumerate().filter(|(_, t)| t.direction == direction).map(|(k, _)| measured[k] * model[k]).sum()
    };
    if agreement(Direction::Extension) < 0.0 && agreement(Direction::Flexion) < 0.0 {
        return Err(FunctionalError::SignConvention { folder: data.folder.clone(), column: data.columns.moment.clone(), coordinate: data.columns.knee_angle.clone() });
    }
    Ok(())
}
