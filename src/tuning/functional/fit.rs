//! One functional-scaling run, as `osim-tune scale MODEL TRIALS/` does it: the input checks,
//! the single deficiency that best explains the initial model's error (its verdict and its gain
//! on held-out trials), the estimator
//! (`estimator.rs`) and the analyses at its estimate (`analyses.rs`).

use serde::Serialize;

use super::analyses::{analyse, attempt, AnalysisFailure, FitInputs, ParameterisationReport, Uncertainty};
use super::cause::{candidate_causes, SingleCause};
use super::cause_held_out::{held_out_gain, HeldOutGain};
use super::cause_verdict::{cause_verdict, CauseVerdict, NoiseLevel};
use super::error::FunctionalError;
use super::estimator::{estimate, FitMethod, FitSettings};
use super::feasible_set::MuscleFeasibleSet;
use super::hot_start::HotStart;
use super::knee_moment::KneeMomentModel;
use super::parameters::{MuscleParameters, Parameter};
use super::residuals::{residuals_by_direction, DirectionResiduals};
use super::rest_curve_map::AppliedPrior;
use super::sensitivity::SensitivityTable;
use super::trials::{root_mean_square, Direction, DynamometryData};
use crate::io::osim::{format_numbers, OsimDocument, OsimError};
use crate::model::ModelSpec;

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
    /// The initial and the fitted model's errors per direction.
    pub residuals: Vec<DirectionResiduals>,
    pub feasible_sets: Vec<MuscleFeasibleSet>,
    pub hot_start: Option<HotStart>,
    /// Phase II constraints active at the solution (e.g. a rest length at its tolerance).
    pub active_constraints: Vec<String>,
    /// The rest-curve fit's prior, when it was used.
    pub prior: Option<AppliedPrior>,
    /// Each candidate cause fitted alone from the initial model, best explanation first.
    pub single_causes: Vec<SingleCause>,
    /// Whether the ranking names a cause at the report's σ; `None` without single causes.
    pub cause_verdict: Option<CauseVerdict>,
    /// The best single cause's RMS on trials its fit did not see; `None` without single causes.
    pub cause_held_out: Option<HeldOutGain>,
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
        root_mean_square(self.trials.iter().map(|t| t.fitted - t.measured))
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
    progress("single causes");
    let mut unavailable = Vec::new();
    let single_causes = attempt(&mut unavailable, "single causes", candidate_causes(spec, knee, data, &initial, &measured)).unwrap_or_default();
    let held_out = |best| held_out_gain(spec, knee, data, &initial, &measured, best);
    let cause_held_out = single_causes.first().and_then(|best| attempt(&mut unavailable, "single cause held out", held_out(best)));
    let estimate = estimate(spec, knee, data, &initial, &measured, settings, progress)?;
    let moments = knee.moments(&estimate.fitted)?;
    let inputs = FitInputs { spec, knee, data, settings, measured: &measured };
    let analyses = analyse(&inputs, &estimate, &moments, progress);
    unavailable.extend(analyses.unavailable);
    let (noise, noise_source) = verdict_noise(settings, data, &analyses.uncertainty);
    let cause_verdict = cause_verdict(&single_causes, measured.len(), noise, noise_source);
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
        residuals: residuals_by_direction(knee.trials(), &measured, &initial_moments, &moments),
        trials,
        feasible_sets: estimate.feasible_sets,
        hot_start: estimate.hot_start,
        active_constraints: estimate.active_constraints,
        prior: estimate.prior,
        single_causes,
        cause_verdict,
        cause_held_out,
        sensitivity: analyses.sensitivity,
        identifiability: analyses.identifiability,
        uncertainty: analyses.uncertainty,
        unavailable,
    })
}

/// The noise the single causes are weighed against: the report's σ, except that moments the
/// subject file calls noise-free (σ = 0, not overridden) are exact.
fn verdict_noise(settings: &FitSettings, data: &DynamometryData, uncertainty: &Uncertainty) -> (NoiseLevel, &'static str) {
    if settings.noise_sd.is_none() && data.noise_sd == Some(0.0) {
        return (NoiseLevel::Exact, "subject file: noise-free; the moments' resolution");
    }
    match uncertainty.noise_level {
        NoiseLevel::Exact => (NoiseLevel::Exact, "exact fit; the moments' resolution"),
        level => (level, uncertainty.noise_source),
    }
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
                    expected: format!("an angle within the model's range of {name}, [{:.1}, {:.1}]° (the file's angles are read in the unit its header gives, as OpenSim reads them: degrees with inDegrees=yes, radians where it does not say)", low.to_degrees(), high.to_degrees()),
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
