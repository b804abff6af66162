//! What the simulation gets wrong, where and how large (METHOD.md §8): the knee moment errors
//! M_mod − M_meas of the initial and the fitted model summarised per direction — RMS, mean (its
//! sign says whether the model is too weak or too strong there) and the largest error with its
//! trial and knee angle.

use serde::Serialize;

use super::trials::{root_mean_square, Direction, IsometricTrial};

/// Error statistics of one model over some trials, N·m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorStatistics {
    pub rms: f64,
    /// Mean of M_mod − M_meas.
    pub mean: f64,
    /// The error of largest magnitude, its trial's label and knee angle (degrees).
    pub largest: f64,
    pub largest_at: String,
    pub largest_knee_angle_deg: f64,
    /// Whether the model's moments are smaller in magnitude than the measured on average (the
    /// mean error opposes the measured moments' sign).
    pub too_weak: bool,
}

/// The errors of one direction's trials.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DirectionResiduals {
    pub direction: Direction,
    pub trials: usize,
    pub initial: ErrorStatistics,
    pub fitted: ErrorStatistics,
}

/// Per direction with trials, the initial and the fitted model's errors; moments per trial in
/// `trials`' order (N·m).
pub fn residuals_by_direction(trials: &[IsometricTrial], measured: &[f64], initial: &[f64], fitted: &[f64]) -> Vec<DirectionResiduals> {
    Direction::BOTH
        .into_iter()
        .filter_map(|direction| {
            let chosen: Vec<usize> = (0..trials.len()).filter(|&t| trials[t].direction == direction).collect();
            Some(DirectionResiduals {
                direction,
                trials: chosen.len(),
                initial: statistics(trials, &chosen, measured, initial)?,
                fitted: statistics(trials, &chosen, measured, fitted)?,
            })
        })
        .collect()
}

/// `None` for no trials.
fn statistics(trials: &[IsometricTrial], chosen: &[usize], measured: &[f64], model: &[f64]) -> Option<ErrorStatistics> {
    let error = |t: usize| model[t] - measured[t];
    let worst = *chosen.iter().max_by(|&&a, &&b| error(a).abs().total_cmp(&error(b).abs()))?;
    let mean = chosen.iter().map(|&t| error(t)).sum::<f64>() / chosen.len() as f64;
    let measured_mean = chosen.iter().map(|&t| measured[t]).sum::<f64>();
    Some(ErrorStatistics {
        rms: root_mean_square(chosen.iter().map(|&t| error(t))),
        mean,
        largest: error(worst),
        largest_at: trials[worst].label(),
        largest_knee_angle_deg: trials[worst].knee_angle.to_degrees(),
        too_weak: mean * measured_mean < 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn trial(direction: Direction, number: usize, knee_deg: f64) -> IsometricTrial {
        IsometricTrial {
            file: PathBuf::from("t.mot"),
            line: number,
            set: "set5".into(),
            direction,
            number,
            knee_angle: knee_deg.to_radians(),
            hip_flexion: 0.0,
            ankle_angle: 0.0,
            moment: 0.0,
            activations: Vec::new(),
        }
    }

    #[test]
    fn a_model_short_of_the_extension_moments_is_too_weak_there() {
        let trials = [trial(Direction::Extension, 1, -90.0), trial(Direction::Extension, 2, -30.0), trial(Direction::Flexion, 1, -60.0)];
        let measured = [100.0, 80.0, -50.0];
        let initial = [90.0, 76.0, -53.0];
        let summary = residuals_by_direction(&trials, &measured, &initial, &measured);
        assert_eq!(summary.len(), 2);
        let extension = &summary[0].initial;
        assert_eq!((summary[0].trials, extension.mean, extension.largest), (2, -7.0, -10.0));
        assert!((extension.rms - (58.0f64).sqrt()).abs() < 1e-12 && extension.too_weak);
        assert_eq!((extension.largest_at.as_str(), extension.largest_knee_angle_deg.round()), ("set5 extension #1", -90.0));
        // Flexion: −53 against −50 is a stronger flexion moment.
        assert!(!summary[1].initial.too_weak);
        assert_eq!(summary[0].fitted.rms, 0.0);
    }
}
