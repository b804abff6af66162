//! Accuracy studies of functional scaling (issue 6, thesis §6.2.4) on a dynamometry subject
//! whose true parameters are known: the thesis' 81 initial-guess combinations on noise-free
//! moments, and repeated fits to moments with Gaussian noise, for our method and for Garner &
//! Pandy. Used by `cargo xtask validate` (full) and the tests (a slice). A public subject's
//! truth is read from its `ground_truth.json` ([`GroundTruth`]); [`model_with`] makes the
//! thesis' protocol, in which the model is the truth.

use std::path::Path;

use rayon::prelude::*;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal};

use crate::model::ModelSpec;
use crate::tuning::functional::{
    candidate_causes, cause_verdict, estimate, root_mean_square, Cause, CauseVerdict, Direction, DynamometryData, FitSettings, FunctionalError, IsometricTrial, KneeMomentModel,
    MuscleParameters, NoiseLevel, SingleCause,
};

/// A public dynamometry subject's `ground_truth.json`: the parameters and the noise-free
/// moments its data were generated with.
pub struct GroundTruth(serde_json::Value);

impl GroundTruth {
    /// Reads `folder/ground_truth.json`.
    pub fn read(folder: &Path) -> std::io::Result<GroundTruth> {
        let text = std::fs::read_to_string(folder.join("ground_truth.json"))?;
        Ok(GroundTruth(serde_json::from_str(&text)?))
    }

    /// `nominal` with each muscle's true L_opt and L_ts (`true_parameters`); `None` when the
    /// file lacks one.
    pub fn parameters(&self, nominal: &[MuscleParameters]) -> Option<Vec<MuscleParameters>> {
        nominal
            .iter()
            .map(|p| {
                let t = &self.0["true_parameters"][&p.name];
                let (optimal_fiber_length, tendon_slack_length) = (t["optimal_fiber_length"].as_f64()?, t["tendon_slack_length"].as_f64()?);
                Some(MuscleParameters { optimal_fiber_length, tendon_slack_length, ..p.clone() })
            })
            .collect()
    }

    /// Each trial's noise-free knee moment (`knee_moment_true_Nm`), N·m; `None` when the file
    /// lacks one.
    pub fn noise_free_moments(&self, trials: &[IsometricTrial]) -> Option<Vec<f64>> {
        trials
            .iter()
            .map(|trial| {
                let direction = if trial.direction == Direction::Extension { "extension" } else { "flexion" };
                self.0["trial_sets"][&trial.set][direction]["knee_moment_true_Nm"][trial.number.checked_sub(1)?].as_f64()
            })
            .collect()
    }
}

/// A subject: model, trials and the truth the data were generated with.
pub struct StudySubject<'a> {
    pub spec: &'a ModelSpec,
    pub knee: &'a KneeMomentModel,
    pub data: &'a DynamometryData,
    /// One per estimated muscle, in order.
    pub truth: &'a [MuscleParameters],
}

/// `spec` with each muscle of `parameters` set to its five values: a model whose parameters are
/// the truth, as in the thesis' studies (§6.2.4: "the generic values as reported by \[32\] were
/// chosen as ground truth value"), where the model a fit starts from and its prior's centre are
/// the truth.
pub fn model_with(spec: &ModelSpec, parameters: &[MuscleParameters]) -> ModelSpec {
    let mut model = spec.clone();
    for force in &mut model.forces {
        if let (Some(p), Some(muscle)) = (parameters.iter().find(|p| p.name == force.name), &force.muscle) {
            force.muscle = Some(p.apply_to(muscle));
        }
    }
    model
}

/// Relative errors (fitted/true − 1) of one fit, per muscle [L_opt, L_ts].
pub type FitErrors = Vec<[f64; 2]>;

/// The outcome of a series of fits.
#[derive(Debug, Clone, Default)]
pub struct StudyResult {
    /// One entry per fit that returned parameters.
    pub errors: Vec<FitErrors>,
    /// Fits that did not converge (their parameters are still in `errors`).
    pub not_converged: usize,
    /// Fits that failed outright, with the first message.
    pub failed: usize,
    pub first_failure: Option<String>,
}

/// Per-muscle statistics of a [`StudyResult`]: [L_opt, L_ts] each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MuscleStatistics {
    pub mean: [f64; 2],
    pub sd: [f64; 2],
    pub max_abs: [f64; 2],
    /// Share of fits within 1 % and within 2 % of the truth.
    pub within_1: [f64; 2],
    pub within_2: [f64; 2],
}

impl StudyResult {
    /// Statistics of muscle `e` over the fits.
    pub fn statistics(&self, e: usize) -> MuscleStatistics {
        let n = self.errors.len().max(1) as f64;
        let column = |i: usize| self.errors.iter().map(move |f| f[e][i]);
        let mean = [0, 1].map(|i| column(i).sum::<f64>() / n);
        let sd = [0, 1].map(|i| (column(i).map(|v| (v - mean[i]).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt());
        let max_abs = [0, 1].map(|i| column(i).fold(0.0, |m, v| f64::max(m, v.abs())));
        let share = |limit: f64| [0, 1].map(|i| column(i).filter(|v| v.abs() <= limit).count() as f64 / n);
        MuscleStatistics { mean, sd, max_abs, within_1: share(0.01), within_2: share(0.02) }
    }

    fn record(&mut self, outcome: Result<(FitErrors, bool), FunctionalError>) {
        match outcome {
            Ok((errors, converged)) => {
                self.errors.push(errors);
                self.not_converged += usize::from(!converged);
            }
            Err(error) => {
                self.failed += 1;
                self.first_failure.get_or_insert_with(|| error.to_string());
            }
        }
    }
}

/// The thesis' initial guesses: per muscle group (the extension and the flexion agonists) each
/// muscle takes one of [truth, (75 % L_opt, 125 % L_ts), (125 % L_opt, 75 % L_ts)] — 3⁴ = 81
/// combinations for groups of four, the same digits for both groups — and every value gets
/// ±5 % uniform jitter (seeded).
pub fn thesis_initial_guesses(truth: &[MuscleParameters], data: &DynamometryData, seed: u64) -> Vec<Vec<MuscleParameters>> {
    const FACTORS: [(f64, f64); 3] = [(1.0, 1.0), (0.75, 1.25), (1.25, 0.75)];
    let position = |name: &str| {
        [Direction::Extension, Direction::Flexion].iter().find_map(|&d| data.agonists(d).iter().filter(|a| truth.iter().any(|t| &t.name == *a)).position(|a| a == name))
    };
    let digits: Vec<usize> = truth.iter().map(|t| position(&t.name).unwrap_or(0)).collect();
    let combinations = 3usize.pow(digits.iter().map(|d| d + 1).max().unwrap_or(1) as u32);
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    (0..combinations)
        .map(|c| {
            truth
                .iter()
                .zip(&digits)
                .map(|(p, &digit)| {
                    let (optimal, slack) = FACTORS[(c / 3usize.pow(digit as u32)) % 3];
                    let mut guess = p.clone();
                    guess.optimal_fiber_length *= optimal * (1.0 + rng.random_range(-0.05..=0.05));
                    guess.tendon_slack_length *= slack * (1.0 + rng.random_range(-0.05..=0.05));
                    guess
                })
                .collect()
        })
        .collect()
}

/// The hidden effect of the test: a seeded draw of one estimated muscle whose L_ts is
/// changed by ±(2–6) %. Returns its index and the changed parameters.
pub fn hidden_slack_change(nominal: &[MuscleParameters], seed: u64) -> (usize, Vec<MuscleParameters>) {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let hidden = rng.random_range(0..nominal.len());
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let mut changed = nominal.to_vec();
    changed[hidden].tendon_slack_length *= 1.0 + sign * rng.random_range(0.02..0.06);
    (hidden, changed)
}

/// What a hidden-effect subject's `ground_truth.json` (`oracle/gen_hidden_changes.py`) says was
/// hidden: the cause and its true value in the cause's unit (a muscle parameter's value, a
/// group's factor, the axis offset in mm, the offset to add to the recorded angles in degrees,
/// the activation factor). `None` when it says nothing of the kind.
pub fn hidden_cause(truth: &serde_json::Value) -> Option<(Cause, f64)> {
    let parameter = || {
        let property = truth["hidden_parameter"].as_str()?;
        crate::tuning::functional::Parameter::ALL.into_iter().find(|p| p.property() == property)
    };
    if let Some(muscle) = truth["hidden_muscle"].as_str() {
        let parameter = parameter()?;
        let value = truth["true_parameters"][muscle][parameter.property()].as_f64()?;
        return Some((Cause::Muscle { muscle: muscle.to_string(), parameter }, value));
    }
    if let Some(group) = truth["hidden_group"].as_str() {
        let muscles = truth["hidden_group_muscles"].as_array()?.iter().map(|m| m.as_str().map(String::from)).collect::<Option<Vec<_>>>()?;
        return Some((Cause::Group { group: group.to_string(), muscles, parameter: parameter()? }, truth["factor"].as_f64()?));
    }
    if let Some(joint) = truth["hidden_joint"].as_str() {
        let [x, y, z] = hidden_axis_offset(truth)?;
        return Some((Cause::AxisOffset { joint: joint.to_string() }, (x * x + y * y + z * z).sqrt()));
    }
    if let Some(coordinate) = truth["hidden_coordinate"].as_str() {
        return Some((Cause::AngleOffset { coordinate: coordinate.to_string() }, -truth["recorded_minus_true_deg"].as_f64()?));
    }
    if let Some(offset) = truth["hidden_moment_offset_Nm"].as_f64() {
        return Some((Cause::MomentOffset, offset));
    }
    if let Some(muscle) = truth["hidden_activation_muscle"].as_str() {
        return Some((Cause::MuscleActivation { muscle: muscle.to_string() }, truth["activation_factor"].as_f64()?));
    }
    let direction = match truth["hidden_activation_direction"].as_str()? {
        "both" => None,
        key => Some(Direction::BOTH.into_iter().find(|d| d.key() == key)?),
    };
    Some((Cause::Activation { direction }, truth["activation_factor"].as_f64()?))
}

/// The hidden axis move in the joint's parent frame, mm.
pub fn hidden_axis_offset(truth: &serde_json::Value) -> Option<[f64; 3]> {
    let offset = truth["axis_offset_in_parent_mm"].as_array()?.iter().map(|c| c.as_f64()).collect::<Option<Vec<_>>>()?;
    offset.try_into().ok()
}

/// How far the best candidate `best` recovers a hidden value `truth` (an axis move:
/// `axis_offset`, mm in the parent frame) as a fraction of what moments with noise σ =
/// `noise_sd` (N·m) allow (≤ 1 passes): three of the fit's own standard errors
/// ([`SingleCause::standard_error`]), and never less than L_ts 1 % (issue 6's goal), L_opt and
/// F_max 5 % (less sensitive), α_opt 1°, a group's factor the same fractions, an axis move 2 mm
/// (the distance between the fitted and the true offset), an angle offset 0.5°, an activation
/// factor 0.02, a moment offset 2 N·m. An axis cause without a fitted move or without
/// `axis_offset` is infinitely off.
pub fn hidden_value_error(best: &SingleCause, truth: f64, axis_offset: Option<[f64; 3]>, noise_sd: f64) -> f64 {
    use crate::tuning::functional::Parameter;
    let (fitted, spread) = (best.fitted, 3.0 * best.standard_error(noise_sd));
    let off = |allowed: f64| (fitted - truth).abs() / allowed.max(spread);
    if let (Some(fitted), Some(truth)) = (&best.axis_move, axis_offset) {
        return fitted.in_parent.iter().zip(truth).map(|(f, t)| (f - t).powi(2)).sum::<f64>().sqrt() / spread.max(2.0);
    }
    match &best.cause {
        Cause::Muscle { parameter: Parameter::TendonSlackLength, .. } => off(0.01 * truth.abs()),
        Cause::Muscle { parameter: Parameter::PennationAngleAtOptimal, .. } => off(1f64.to_radians()),
        Cause::Muscle { .. } => off(0.05 * truth.abs()),
        Cause::Group { parameter: Parameter::TendonSlackLength, .. } => off(0.01),
        Cause::Group { .. } => off(0.05),
        Cause::AxisOffset { .. } => f64::INFINITY,
        Cause::AngleOffset { .. } => off(0.5),
        Cause::MomentOffset => off(2.0),
        Cause::Activation { .. } | Cause::MuscleActivation { .. } => off(0.02),
    }
}

/// Every candidate cause of `data`'s moments from the model's values (`spec`, whose knee-moment
/// model is `knee`), and their verdict at the subject file's σ (0: noise-free; absent: unknown).
/// `None` for the verdict with fewer than two candidates.
pub fn single_cause_verdict(spec: &ModelSpec, knee: &KneeMomentModel, data: &DynamometryData) -> Result<(Vec<SingleCause>, Option<CauseVerdict>), FunctionalError> {
    let measured = data.measured_moments();
    let causes = candidate_causes(spec, knee, data, &knee.nominal_parameters(), &measured)?;
    let noise = match data.noise_sd {
        Some(sd) if sd > 0.0 => NoiseLevel::Estimated(sd),
        Some(_) => NoiseLevel::Exact,
        None => NoiseLevel::Unknown,
    };
    let verdict = cause_verdict(&causes, measured.len(), noise, "subject file");
    Ok((causes, verdict))
}

/// One fit from `initial` on `measured`: relative errors against the truth and convergence.
pub fn fit_errors(subject: &StudySubject, initial: &[MuscleParameters], measured: &[f64], settings: &FitSettings) -> Result<(FitErrors, bool), FunctionalError> {
    let result = estimate(subject.spec, subject.knee, subject.data, initial, measured, settings, &mut |_| {})?;
    Ok((relative_errors(&result.fitted, subject.truth), result.converged))
}

/// The posterior mean's errors in units of its sampled posterior sd, L_opt and L_ts pooled.
#[derive(Debug, Default)]
pub struct Calibration {
    /// (fitted − true)/sd, L_opt's and L_ts's of each muscle in turn.
    pub z: Vec<f64>,
    /// Muscle fits without a sampled sd (left out).
    pub unsampled: usize,
}

impl Calibration {
    /// Adds one fit's errors against `truth`, in units of `sampled` (per muscle [L_opt, L_ts],
    /// m; `None` where it has none).
    pub fn add(&mut self, fitted: &[MuscleParameters], truth: &[MuscleParameters], sampled: Option<&[Option<[f64; 2]>]>) {
        for (e, (fit, true_value)) in fitted.iter().zip(truth).enumerate() {
            let Some(sd) = sampled.and_then(|s| s[e]) else {
                self.unsampled += 1;
                continue;
            };
            self.z.push((fit.optimal_fiber_length - true_value.optimal_fiber_length) / sd[0]);
            self.z.push((fit.tendon_slack_length - true_value.tendon_slack_length) / sd[1]);
        }
    }

    /// RMS of z (1 when calibrated).
    pub fn rms(&self) -> f64 {
        root_mean_square(self.z.iter().copied())
    }

    /// The share of |z| > 2 (4.6 % for normal errors).
    pub fn beyond_two(&self) -> f64 {
        self.z.iter().filter(|z| z.abs() > 2.0).count() as f64 / self.z.len().max(1) as f64
    }
}

/// fitted/true − 1 per muscle, [L_opt, L_ts].
pub fn relative_errors(fitted: &[MuscleParameters], truth: &[MuscleParameters]) -> FitErrors {
    fitted
        .iter()
        .zip(truth)
        .map(|(f, t)| [f.optimal_fiber_length / t.optimal_fiber_length - 1.0, f.tendon_slack_length / t.tendon_slack_length - 1.0])
        .collect()
}

/// Fits from each of `guesses` to the subject's own (noise-free) moments.
pub fn initial_guess_study(subject: &StudySubject, guesses: &[Vec<MuscleParameters>], settings: &FitSettings) -> StudyResult {
    let measured = subject.data.measured_moments();
    let fits: Vec<_> = guesses.par_iter().map(|guess| fit_errors(subject, guess, &measured, settings)).collect();
    let mut result = StudyResult::default();
    fits.into_iter().for_each(|fit| result.record(fit));
    result
}

/// Fits from the truth to the subject's moments plus N(0, σ²) noise, `draws` times (seeded).
pub fn noise_study(subject: &StudySubject, noise_sd: f64, draws: usize, seed: u64, settings: &FitSettings) -> StudyResult {
    let measured = subject.data.measured_moments();
    let normal = Normal::new(0.0, noise_sd).expect("a finite, non-negative σ");
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let draws: Vec<Vec<f64>> = (0..draws).map(|_| measured.iter().map(|m| m + normal.sample(&mut rng)).collect()).collect();
    let fits: Vec<_> = draws.par_iter().map(|noisy| fit_errors(subject, subject.truth, noisy, settings)).collect();
    let mut result = StudyResult::default();
    fits.into_iter().for_each(|fit| result.record(fit));
    result
}
