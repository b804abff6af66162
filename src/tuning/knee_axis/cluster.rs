//! A segment's marker cluster: marker names and their fixed coordinates in the segment frame,
//! and the cluster's marker positions read from a trial (in metres).

use std::collections::HashSet;

use nalgebra::Vector3;

use super::segment_pose::are_collinear;
use super::AxisError;
use crate::io::table::MarkerTable;

/// The markers that move rigidly with a segment and their coordinates in the segment frame (m).
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentCluster {
    /// The segment's name (used in error messages, e.g. `femur_r`).
    pub segment: String,
    /// Marker names as in the trial.
    pub markers: Vec<String>,
    /// Each marker's position in the segment frame (m), in the order of `markers`.
    pub local: Vec<Vector3<f64>>,
}

impl SegmentCluster {
    /// A cluster from explicit segment-frame coordinates (m), e.g. a model's markers on a body in
    /// that body's frame. Needs ≥ 3 distinct, finite, non-collinear markers.
    pub fn from_local(segment: &str, markers: Vec<String>, local: Vec<Vector3<f64>>) -> Result<Self, AxisError> {
        let cluster = SegmentCluster { segment: segment.to_owned(), markers, local };
        cluster.check()?;
        Ok(cluster)
    }

    /// A cluster whose segment frame is the lab frame at the first frame of `trial` in which all
    /// `markers` are present: the local coordinates are the markers' lab positions there (m).
    pub fn from_trial(segment: &str, markers: &[String], trial: &MarkerTable) -> Result<Self, AxisError> {
        let placeholder = SegmentCluster { segment: segment.to_owned(), markers: markers.to_vec(), local: vec![Vector3::zeros(); markers.len()] };
        placeholder.check_names()?;
        let positions = placeholder.trial_positions(trial)?;
        let Some(first) = positions.iter().find(|frame| frame.iter().all(Option::is_some)) else {
            return Err(AxisError::NoCompleteFrame { segment: segment.to_owned(), markers: markers.join(", ") });
        };
        let local = first.iter().flatten().copied().collect();
        SegmentCluster::from_local(segment, markers.to_vec(), local)
    }

    /// The local coordinates' mean (segment frame, m).
    pub fn centroid(&self) -> Vector3<f64> {
        super::segment_pose::centroid(&self.local)
    }

    /// The cluster's marker positions in every frame of `trial`, in metres (whatever the
    /// trial's units), indexed `[frame][cluster marker]`; `None` where a marker is missing.
    /// Errors if a marker is not in the trial or a coordinate is not finite.
    pub fn trial_positions(&self, trial: &MarkerTable) -> Result<Vec<Vec<Option<Vector3<f64>>>>, AxisError> {
        let columns = self.trial_columns(trial)?;
        let per_meter = trial.units().per_meter();
        let mut frames = Vec::with_capacity(trial.n_frames());
        for frame in 0..trial.n_frames() {
            let mut row = Vec::with_capacity(columns.len());
            for (&column, name) in columns.iter().zip(&self.markers) {
                let position = trial.position(frame, column).map(|xyz| Vector3::from(xyz) / per_meter);
                if let Some(bad) = position.and_then(|p| p.iter().copied().find(|v| !v.is_finite())) {
                    let (number, time) = (trial.frame_numbers()[frame], trial.times()[frame]);
                    let what = format!("segment `{}`, marker `{name}`, trial frame {number} (t = {time} s)", self.segment);
                    return Err(AxisError::NonFinite { what, value: bad });
                }
                row.push(position);
            }
            frames.push(row);
        }
        Ok(frames)
    }

    /// The trial column of each cluster marker.
    fn trial_columns(&self, trial: &MarkerTable) -> Result<Vec<usize>, AxisError> {
        let missing = |marker: &String| AxisError::MarkerNotInTrial { segment: self.segment.clone(), marker: marker.clone() };
        self.markers.iter().map(|marker| trial.marker_index(marker).ok_or_else(|| missing(marker))).collect()
    }

    /// ≥ 3 distinct names, one finite local position each, not collinear.
    fn check(&self) -> Result<(), AxisError> {
        self.check_names()?;
        if self.local.len() != self.markers.len() {
            return Err(AxisError::ClusterShape { segment: self.segment.clone(), names: self.markers.len(), coordinates: self.local.len() });
        }
        for (name, position) in self.markers.iter().zip(&self.local) {
            if let Some(bad) = position.iter().copied().find(|v| !v.is_finite()) {
                return Err(AxisError::NonFinite { what: format!("segment `{}`, local position of marker `{name}`", self.segment), value: bad });
            }
        }
        if are_collinear(&self.local) {
            return Err(AxisError::CollinearCluster { segment: self.segment.clone(), markers: self.markers.join(", ") });
        }
        Ok(())
    }

    fn check_names(&self) -> Result<(), AxisError> {
        if self.markers.len() < 3 {
            return Err(AxisError::TooFewMarkers { segment: self.segment.clone(), count: self.markers.len() });
        }
        let mut seen = HashSet::new();
        if let Some(twice) = self.markers.iter().find(|name| !seen.insert(name.as_str())) {
            return Err(AxisError::DuplicateMarker { segment: self.segment.clone(), marker: twice.clone() });
        }
        Ok(())
    }
}

/// The trial's frame times (s), checked finite and strictly increasing.
pub fn checked_times(trial: &MarkerTable) -> Result<Vec<f64>, AxisError> {
    let times = trial.times();
    for (index, &time) in times.iter().enumerate() {
        let frame = trial.frame_numbers()[index];
        if !time.is_finite() {
            return Err(AxisError::NonFinite { what: format!("trial frame {frame}: time"), value: time });
        }
        if index > 0 && time <= times[index - 1] {
            return Err(AxisError::TimesNotIncreasing { frame, time, previous: times[index - 1] });
        }
    }
    Ok(times.to_vec())
}
