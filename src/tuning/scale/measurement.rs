//! ModelScaler's measurements: a scale factor as the mean, over marker pairs, of the
//! experimental distance (averaged over the trial frames in the time range) divided by the
//! model distance at the default pose.

use std::ops::RangeInclusive;
use std::path::Path;

use super::error::ScaleError;
use crate::io::table::MarkerTable;
use crate::mechanics::{Kinematics, Multibody};
use crate::setup::{Measurement, TimeRange};
use crate::solvers::{assembled_default_pose, IkError};

/// The two lengths of one marker pair (m).
#[derive(Debug, Clone, PartialEq)]
pub struct PairLength {
    pub markers: [String; 2],
    pub model: f64,
    /// Mean over the frames where both markers are present.
    pub experimental: f64,
    /// Frames in the time range where a marker of the pair is missing (left out of the mean).
    pub frames_missing: usize,
}

/// A measurement's scale factor and the pairs it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredFactor {
    pub measurement: String,
    pub pairs: Vec<PairLength>,
    /// Mean of experimental / model over the pairs.
    pub factor: f64,
}

/// Model markers at the default pose, for measuring distances.
pub struct DefaultPoseMarkers<'a> {
    multibody: &'a Multibody,
    kinematics: Kinematics,
}

impl<'a> DefaultPoseMarkers<'a> {
    /// At OpenSim's default state (the default values assembled, as `initSystem` leaves them).
    pub fn new(multibody: &'a Multibody) -> Result<Self, IkError> {
        let mut kinematics = multibody.kinematics();
        multibody.realize(&assembled_default_pose(multibody)?, &mut kinematics);
        Ok(DefaultPoseMarkers { multibody, kinematics })
    }

    /// Distance (m) between two model markers; `None` when either is not in the model.
    fn distance(&self, a: &str, b: &str) -> Option<f64> {
        let index = |name: &str| self.multibody.markers.iter().position(|m| m.name == name);
        let (a, b) = (index(a)?, index(b)?);
        Some((self.kinematics.marker_location(self.multibody, a) - self.kinematics.marker_location(self.multibody, b)).norm())
    }
}

/// OpenSim's `MarkerData::findFrameRange`: from the last frame at or before `start` to the first
/// frame from there at or after `end` (the whole trial when none qualifies).
pub fn frame_range(times: &[f64], range: TimeRange) -> RangeInclusive<usize> {
    let last = times.len().saturating_sub(1);
    let first = times.iter().rposition(|&t| t <= range.start).unwrap_or(0);
    let end = times[first..].iter().position(|&t| t >= range.end).map_or(last, |k| first + k);
    first..=end
}

/// Measures `measurement` on the model markers and on `trial` (in metres, read from
/// `trial_file`) over the frames of `range`.
pub fn measure(markers: &DefaultPoseMarkers, trial: &MarkerTable, trial_file: &Path, range: TimeRange, measurement: &Measurement) -> Result<MeasuredFactor, ScaleError> {
    let error = |problem: String| ScaleError::Measurement { file: trial_file.into(), measurement: measurement.name.clone(), problem };
    if measurement.marker_pairs.is_empty() {
        return Err(error("it has no marker pairs".into()));
    }
    check_range(trial.times(), range).map_err(error)?;
    let frames = frame_range(trial.times(), range);
    let mut pairs = Vec::new();
    for [a, b] in &measurement.marker_pairs {
        let model = markers.distance(a, b).ok_or_else(|| error(format!("marker {a:?} or {b:?} is not in the model's marker set")))?;
        let (ia, ib) = match (trial.marker_index(a), trial.marker_index(b)) {
            (Some(ia), Some(ib)) => (ia, ib),
            _ => return Err(error(format!("marker {a:?} or {b:?} is not in the trial"))),
        };
        let lengths: Vec<f64> = frames
            .clone()
            .filter_map(|f| Some(distance(trial.position(f, ia)?, trial.position(f, ib)?)))
            .collect();
        if lengths.is_empty() {
            return Err(error(format!("markers {a:?} and {b:?} are never both present between {} s and {} s", range.start, range.end)));
        }
        let experimental = lengths.iter().sum::<f64>() / lengths.len() as f64;
        let frames_missing = frames.clone().count() - lengths.len();
        pairs.push(PairLength { markers: [a.clone(), b.clone()], model, experimental, frames_missing });
    }
    let factor = pairs.iter().map(|p| p.experimental / p.model).sum::<f64>() / pairs.len() as f64;
    Ok(MeasuredFactor { measurement: measurement.name.clone(), pairs, factor })
}

/// A time range must overlap the trial (OpenSim would silently use its first or last frame).
pub fn check_range(times: &[f64], range: TimeRange) -> Result<(), String> {
    match (times.first(), times.last()) {
        (Some(&first), Some(&last)) if range.start <= last && range.end >= first => Ok(()),
        (Some(first), Some(last)) => Err(format!("time range {} s to {} s lies outside the trial ({first} s to {last} s)", range.start, range.end)),
        _ => Err("the trial has no frames".into()),
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_range_is_opensims() {
        let times = [0.0, 0.5, 1.0, 1.5, 2.0];
        assert_eq!(frame_range(&times, TimeRange { start: 0.7, end: 1.2 }), 1..=3);
        assert_eq!(frame_range(&times, TimeRange { start: 1.0, end: 1.5 }), 2..=3);
        assert_eq!(frame_range(&times, TimeRange { start: -1.0, end: 9.0 }), 0..=4);
    }
}
