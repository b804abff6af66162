//! Phase I of functional scaling (thesis §6.2.3, eq. 6.7–6.14): the physiologically feasible
//! set of (L_opt, L_ts) per estimated muscle on a grid around the initial values, the regression
//! line 1/L_opt ≈ c1·(L_ts/L_opt) + c2 through it, the bounds it puts on L_ts/L_opt and on the
//! deviation δ from the line, and the hot start for Phase II.
//!
//! A grid point is feasible when (1) in the muscle's agonist trials at the most flexed and the
//! most extended knee angle its static equilibrium (exact, so the slack s of eq. 6.8 is 0) has
//! a normalised fiber length in the operating range (eq. 6.9), and (2) its rest fiber length
//! (every coordinate 0, minimum activation) lies within ±`rest_tolerance` of the measured
//! reference (eq. 6.10–6.12; skipped when the subject file gives no reference). The thesis takes
//! its extreme angles at −105°/−30° (−90° for the gastrocnemii) beyond its trials; we take them
//! at the trials' own extremes, where the data say the muscle works.

use serde::Serialize;

use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::MuscleParameters;

/// Grid and acceptance settings of Phase I.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FeasibleSetSettings {
    /// The grid spans (1 ± `grid_span`) × the initial L_opt and L_ts (thesis: 0.5) …
    pub grid_span: f64,
    /// … in steps of `optimal_step` × the initial L_opt (thesis: 0.1) …
    pub optimal_step: f64,
    /// … and `slack_step` × the initial L_ts. Finer than the thesis' 0.1: the rest fiber length
    /// moves by about (ΔL_ts / L_m) per step, so a 10 % step in L_ts jumps across any realistic
    /// rest tolerance for tendon-dominated muscles.
    pub slack_step: f64,
    /// Normalised fiber lengths a working muscle may have (thesis: 0.4–1.6).
    pub operating_range: [f64; 2],
    /// Accepted deviation of the rest fiber length from its reference, relative (Δ_fl / L_ref).
    pub rest_tolerance: f64,
}

impl Default for FeasibleSetSettings {
    fn default() -> Self {
        FeasibleSetSettings { grid_span: 0.5, optimal_step: 0.1, slack_step: 0.01, operating_range: [0.4, 1.6], rest_tolerance: 0.1 }
    }
}

/// The line 1/L_opt = c1·(L_ts/L_opt) + c2 (eq. 6.13), 1/L_opt in 1/m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RegressionLine {
    pub c1: f64,
    /// 1/m.
    pub c2: f64,
}

impl RegressionLine {
    /// δ = 1/L_opt − c1·ρ − c2 (eq. 6.14), 1/m, for ρ = L_ts/L_opt.
    pub fn delta(&self, optimal_fiber_length: f64, tendon_slack_length: f64) -> f64 {
        1.0 / optimal_fiber_length - self.c1 * tendon_slack_length / optimal_fiber_length - self.c2
    }

    /// (L_opt, L_ts) in m from ρ = L_ts/L_opt and δ (1/m).
    pub fn lengths(&self, ratio: f64, delta: f64) -> (f64, f64) {
        let optimal = 1.0 / (self.c1 * ratio + self.c2 + delta);
        (optimal, ratio * optimal)
    }
}

/// One muscle's feasible set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuscleFeasibleSet {
    pub muscle: String,
    /// Grid points evaluated.
    pub evaluated: usize,
    /// (L_opt, L_ts) in m of the feasible grid points.
    pub feasible: Vec<(f64, f64)>,
    /// Points rejected by the operating range (at either extreme trial) and by the rest length.
    pub outside_operating_range: usize,
    pub outside_rest_tolerance: usize,
    pub line: RegressionLine,
    /// max |δ| over the feasible points, 1/m (at least a small floor, see [`DELTA_FLOOR`]).
    pub delta_max: f64,
    /// [min, max] of L_ts/L_opt over the feasible points.
    pub ratio_bounds: [f64; 2],
    /// Trials (indices into the model's trials) at the most flexed and most extended knee angle
    /// among the muscle's agonist trials.
    pub extreme_trials: [usize; 2],
}

/// |δ| bound used when every feasible point lies on the line, relative to 1/L_opt's scale.
pub const DELTA_FLOOR: f64 = 1e-3;

/// Phase I for every estimated muscle, around `initial` (one per estimated muscle, in order).
/// Errors when a muscle has fewer than three feasible points (no line can be fitted): the
/// message names the muscle and why the points were rejected.
pub fn feasible_sets(
    model: &KneeMomentModel,
    rest_references: &[Option<f64>],
    initial: &[MuscleParameters],
    settings: &FeasibleSetSettings,
) -> Result<Vec<MuscleFeasibleSet>, FunctionalError> {
    let mut workspace = model.estimated_muscles(initial)?;
    (0..initial.len()).map(|e| muscle_feasible_set(model, &mut workspace, e, rest_references[e], &initial[e], settings)).collect()
}

fn muscle_feasible_set(
    model: &KneeMomentModel,
    workspace: &mut EstimatedMuscles,
    e: usize,
    rest_reference: Option<f64>,
    initial: &MuscleParameters,
    settings: &FeasibleSetSettings,
) -> Result<MuscleFeasibleSet, FunctionalError> {
    let extreme_trials = extreme_trials(model, e).ok_or_else(|| FunctionalError::Parameters {
        muscle: initial.name.clone(),
        problem: "is an agonist in no trial (no activation column names it), so its operating range cannot be checked".into(),
    })?;
    let (optimal_factors, slack_factors) = (grid_factors(settings.grid_span, settings.optimal_step), grid_factors(settings.grid_span, settings.slack_step));
    let mut set = MuscleFeasibleSet {
        muscle: initial.name.clone(),
        evaluated: 0,
        feasible: Vec::new(),
        outside_operating_range: 0,
        outside_rest_tolerance: 0,
        line: RegressionLine { c1: 0.0, c2: 0.0 },
        delta_max: 0.0,
        ratio_bounds: [0.0; 2],
        extreme_trials,
    };
    let knee_index = model.estimated_knee_index(e);
    for &optimal_factor in &optimal_factors {
        for &slack_factor in &slack_factors {
            let mut candidate = initial.clone();
            candidate.optimal_fiber_length *= optimal_factor;
            candidate.tendon_slack_length *= slack_factor;
            workspace.set(model, e, &candidate)?;
            set.evaluated += 1;
            let in_range = extreme_trials.iter().all(|&t| {
                model.state(knee_index, workspace.muscle(e), t).is_ok_and(|s| within(s.normalized_fiber_length, settings.operating_range))
            });
            if !in_range {
                set.outside_operating_range += 1;
                continue;
            }
            if let Some(reference) = rest_reference {
                let rest = model.rest_state(e, workspace)?.fiber_length;
                if (rest - reference).abs() > settings.rest_tolerance * reference {
                    set.outside_rest_tolerance += 1;
                    continue;
                }
            }
            set.feasible.push((candidate.optimal_fiber_length, candidate.tendon_slack_length));
        }
    }
    workspace.set(model, e, initial)?;
    fit_line(&mut set)?;
    Ok(set)
}

/// Multipliers of an initial value: 1 − span, 1 − span + step, …, 1 + span (positive ones).
fn grid_factors(span: f64, step: f64) -> Vec<f64> {
    let steps = (2.0 * span / step).round() as usize;
    (0..=steps).map(|i| 1.0 - span + i as f64 * step).filter(|f| *f > 0.0).collect()
}

fn within(value: f64, [low, high]: [f64; 2]) -> bool {
    (low..=high).contains(&value)
}

/// The agonist trials of estimated muscle `e` at the smallest and the largest knee angle.
fn extreme_trials(model: &KneeMomentModel, e: usize) -> Option<[usize; 2]> {
    let name = &model.estimated_knee_muscle(e).name;
    let agonist: Vec<usize> = (0..model.trials().len()).filter(|&t| model.trials()[t].activation(name).is_some()).collect();
    let angle = |t: &usize| model.trials()[*t].knee_angle;
    let flexed = agonist.iter().copied().min_by(|a, b| angle(a).total_cmp(&angle(b)))?;
    let extended = agonist.iter().copied().max_by(|a, b| angle(a).total_cmp(&angle(b)))?;
    Some([flexed, extended])
}

/// Least-squares line through (ρ, 1/L_opt) of the feasible points, δ_max and the ρ bounds.
fn fit_line(set: &mut MuscleFeasibleSet) -> Result<(), FunctionalError> {
    if set.feasible.len() < 3 {
        let problem = format!(
            "Phase I found {} feasible (L_opt, L_ts) grid point(s) of {} ({} outside the operating range at the extreme trials, {} outside the rest-length tolerance); at least 3 are needed — check the initial values, the grid or the rest tolerance",
            set.feasible.len(),
            set.evaluated,
            set.outside_operating_range,
            set.outside_rest_tolerance
        );
        return Err(FunctionalError::Parameters { muscle: set.muscle.clone(), problem });
    }
    let points: Vec<(f64, f64)> = set.feasible.iter().map(|&(optimal, slack)| (slack / optimal, 1.0 / optimal)).collect();
    let n = points.len() as f64;
    let (mean_x, mean_y) = points.iter().fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x / n, sy + y / n));
    let sxx: f64 = points.iter().map(|(x, _)| (x - mean_x).powi(2)).sum();
    let sxy: f64 = points.iter().map(|(x, y)| (x - mean_x) * (y - mean_y)).sum();
    let c1 = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    set.line = RegressionLine { c1, c2: mean_y - c1 * mean_x };
    let delta_max = set.feasible.iter().map(|&(o, s)| set.line.delta(o, s).abs()).fold(0.0, f64::max);
    set.delta_max = delta_max.max(DELTA_FLOOR * mean_y);
    let ratios = points.iter().map(|(x, _)| *x);
    set.ratio_bounds = [ratios.clone().fold(f64::INFINITY, f64::min), ratios.fold(f64::NEG_INFINITY, f64::max)];
    Ok(())
}
