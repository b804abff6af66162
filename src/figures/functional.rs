//! The figures of a functional fit: per trial set the knee moment against the knee angle —
//! measured, initial model and fitted model, both directions — and what the models get wrong
//! with the best single cause fitted, and per estimated muscle its
//! Phase I feasible set on the L_opt × L_ts plane with the regression line of eq. 6.13, the
//! initial and the fitted parameters.

use crate::tuning::functional::{Direction, FunctionalFit, IsometricTrial, MuscleFeasibleSet, MuscleParameters, TrialFit};

use super::{render, Chart, Figure, FigureError, Mark, Series, Tone};

/// Points on the drawn regression line.
const LINE_SAMPLES: usize = 60;

/// One figure per trial set (`moments_<set>.svg`): the knee moment (N·m, OpenSim's sign) against
/// the knee angle (°) of each trial, measured (dots), initial model (dashed) and fitted model
/// (solid), each direction's trials joined in the order of their angles. `trials` are the
/// fit's trials, in the order of `fit.trials`.
pub fn moment_figures(fit: &FunctionalFit, trials: &[IsometricTrial]) -> Result<Vec<Figure>, FigureError> {
    check_trials(fit, trials)?;
    sets(trials).into_iter().map(|set| set_figure(fit, trials, set)).collect()
}

fn set_figure(fit: &FunctionalFit, trials: &[IsometricTrial], set: &str) -> Result<Figure, FigureError> {
    let mut series = Vec::new();
    for (first, indices) in directions(trials, set).into_iter().enumerate().map(|(k, i)| (k == 0, i)) {
        let curve = |moment: fn(&TrialFit) -> f64| -> Vec<(f64, f64)> { indices.iter().map(|&t| (trials[t].knee_angle.to_degrees(), moment(&fit.trials[t]))).collect() };
        let label = |text: &str| if first { text.to_string() } else { String::new() };
        series.push(Series::new(label("initial model"), curve(|t| t.initial), Mark::Dashed, Tone::Initial));
        series.push(Series::new(label("fitted model"), curve(|t| t.fitted), Mark::Line, Tone::Fitted));
        series.push(Series::new(label("measured"), curve(|t| t.measured), Mark::Circles, Tone::Measured));
    }
    let chart = Chart {
        title: format!("{set}: knee moment{}", posture(trials, set)),
        x_label: "knee angle (°)".into(),
        y_label: "knee moment (N·m)".into(),
        series,
    };
    Ok(Figure { file_name: format!("moments_{}.svg", file_stem(set)), svg: render(&chart)? })
}

/// ` at hip 80°, ankle 0°` when every trial of the set has the same hip and ankle angles.
fn posture(trials: &[IsometricTrial], set: &str) -> String {
    let mut of_set = trials.iter().filter(|t| t.set == set);
    let Some(first) = of_set.next() else { return String::new() };
    let same = |a: f64, b: f64| (a - b).abs() < 1e-9;
    if !of_set.all(|t| same(t.hip_flexion, first.hip_flexion) && same(t.ankle_angle, first.ankle_angle)) {
        return String::new();
    }
    format!(" at hip {:.0}°, ankle {:.0}°", first.hip_flexion.to_degrees(), first.ankle_angle.to_degrees())
}

/// One figure per trial set (`diagnosis_<set>.svg`) of what the models get wrong, M_mod − M_meas
/// (N·m) against the knee angle (°): the initial model's (squares on a dashed line), the initial
/// model with the best single cause fitted (the report's first `single_causes`; orange) and the
/// fitted model's (solid). None when the fit ranked no cause.
pub fn diagnosis_figures(fit: &FunctionalFit, trials: &[IsometricTrial]) -> Result<Vec<Figure>, FigureError> {
    check_trials(fit, trials)?;
    let Some(best) = fit.single_causes.first().filter(|c| c.residuals.len() == trials.len()) else { return Ok(Vec::new()) };
    let title = |set: &str| format!("{set}: model − measured; best single change {} (all trials: RMS {:.2} → {:.2} N·m)", best.cause.describe(), best.rms_before, best.rms_after);
    sets(trials)
        .into_iter()
        .map(|set| {
            let mut series = Vec::new();
            for (first, indices) in directions(trials, set).into_iter().enumerate().map(|(k, i)| (k == 0, i)) {
                let label = |text: &str| if first { text.to_string() } else { String::new() };
                let curve = |residual: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> { indices.iter().map(|&t| (trials[t].knee_angle.to_degrees(), residual(t))).collect() };
                let initial = curve(&|t| fit.trials[t].initial - fit.trials[t].measured);
                series.push(Series::new("", initial.clone(), Mark::Dashed, Tone::Initial));
                series.push(Series::new(label("initial model"), initial, Mark::Squares, Tone::Initial));
                series.push(Series::new(label(&format!("with {}", best.cause.describe())), curve(&|t| best.residuals[t]), Mark::Line, Tone::Cause));
                series.push(Series::new(label("fitted model"), curve(&|t| fit.trials[t].fitted - fit.trials[t].measured), Mark::Line, Tone::Fitted));
            }
            let chart = Chart { title: title(set), x_label: "knee angle (°)".into(), y_label: "M_mod − M_meas (N·m)".into(), series };
            Ok(Figure { file_name: format!("diagnosis_{}.svg", file_stem(set)), svg: render(&chart)? })
        })
        .collect()
}

/// `trials` are as many as the fit's.
fn check_trials(fit: &FunctionalFit, trials: &[IsometricTrial]) -> Result<(), FigureError> {
    if trials.len() != fit.trials.len() {
        return Err(FigureError::Input(format!("{} trials given for a fit of {}", trials.len(), fit.trials.len())));
    }
    Ok(())
}

/// The trial sets in the order of their first trial.
fn sets(trials: &[IsometricTrial]) -> Vec<&str> {
    let mut sets: Vec<&str> = Vec::new();
    for trial in trials {
        if !sets.contains(&trial.set.as_str()) {
            sets.push(&trial.set);
        }
    }
    sets
}

/// The trials of `set` per direction that has any, extension first, each in the order of its
/// knee angles.
fn directions(trials: &[IsometricTrial], set: &str) -> Vec<Vec<usize>> {
    Direction::BOTH
        .into_iter()
        .map(|direction| {
            let mut indices: Vec<usize> = (0..trials.len()).filter(|&t| trials[t].set == set && trials[t].direction == direction).collect();
            indices.sort_by(|&a, &b| trials[a].knee_angle.total_cmp(&trials[b].knee_angle));
            indices
        })
        .filter(|indices| !indices.is_empty())
        .collect()
}

/// One figure per estimated muscle with a Phase I feasible set (`feasible_<muscle>.svg`): the
/// feasible grid points, the regression line 1/L_opt = c1·(L_ts/L_opt) + c2 over the feasible
/// ratios, the initial (square) and the fitted (triangle) L_opt and L_ts, in mm. None for a
/// fit without Phase I (Garner & Pandy).
pub fn feasible_set_figures(fit: &FunctionalFit) -> Result<Vec<Figure>, FigureError> {
    fit.feasible_sets.iter().map(|set| feasible_set_figure(fit, set)).collect()
}

fn feasible_set_figure(fit: &FunctionalFit, set: &MuscleFeasibleSet) -> Result<Figure, FigureError> {
    let millimetres = |(optimal, slack): (f64, f64)| (1e3 * optimal, 1e3 * slack);
    let parameters = |list: &[MuscleParameters]| -> Vec<(f64, f64)> {
        list.iter().filter(|p| p.name == set.muscle).map(|p| millimetres((p.optimal_fiber_length, p.tendon_slack_length))).collect()
    };
    let [low, high] = set.ratio_bounds;
    let line = (0..LINE_SAMPLES)
        .map(|i| low + (high - low) * i as f64 / (LINE_SAMPLES - 1) as f64)
        .map(|ratio| set.line.lengths(ratio, 0.0))
        .filter(|&(optimal, _)| optimal.is_finite() && optimal > 0.0)
        .map(millimetres)
        .collect();
    let chart = Chart {
        title: format!("{}: feasible set, {} of {} grid points", set.muscle, set.feasible.len(), set.evaluated),
        x_label: "optimal fiber length L_opt (mm)".into(),
        y_label: "tendon slack length L_ts (mm)".into(),
        series: vec![
            Series::new("feasible", set.feasible.iter().copied().map(millimetres).collect(), Mark::Dots, Tone::Background),
            Series::new("regression line", line, Mark::Line, Tone::Measured),
            Series::new("initial model", parameters(&fit.initial), Mark::Squares, Tone::Initial),
            Series::new("fitted model", parameters(&fit.fitted), Mark::Triangles, Tone::Fitted),
        ],
    };
    Ok(Figure { file_name: format!("feasible_{}.svg", file_stem(&set.muscle)), svg: render(&chart)? })
}

/// `name` with every character other than letters, digits, `-`, `_` and `.` replaced by `_`.
fn file_stem(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}
