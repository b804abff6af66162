//! An axis (a directed line) in a segment frame, its transforms between frames, and the
//! transepicondylar axis through two epicondyle markers.

use nalgebra::Vector3;

use super::segment_pose::SegmentPose;
use super::{AxisError, SegmentTrajectory};
use crate::io::table::MarkerTable;

/// A line: a point on it and a unit direction, both in one frame (stated where an `Axis` is
/// returned). The point is one chosen point of the line (the rules are given with each fit);
/// the direction's sign follows the convention of whatever produced it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// A point on the axis (m).
    pub point: Vector3<f64>,
    /// Unit direction.
    pub direction: Vector3<f64>,
}

impl Axis {
    /// The axis through `point` along `direction` (normalised). Errors for a zero or
    /// non-finite direction or a non-finite point.
    pub fn new(point: Vector3<f64>, direction: Vector3<f64>) -> Result<Axis, AxisError> {
        let norm = direction.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(AxisError::InvalidDirection { what: "axis".into(), direction: direction.into() });
        }
        if let Some(bad) = point.iter().copied().find(|v| !v.is_finite()) {
            return Err(AxisError::NonFinite { what: "axis point".into(), value: bad });
        }
        Ok(Axis { point, direction: direction / norm })
    }

    /// The axis through two points (m), directed from `medial` to `lateral`, with its point
    /// midway between them. Errors if the points coincide.
    pub fn through_points(lateral: Vector3<f64>, medial: Vector3<f64>) -> Result<Axis, AxisError> {
        Axis::new((lateral + medial) * 0.5, lateral - medial)
    }

    /// The transepicondylar axis in the femur frame: each epicondyle marker's trial positions
    /// are expressed in the femur frame in every frame where the femur has a pose and the marker
    /// is visible, and averaged; the axis runs through the two averages, directed medial →
    /// lateral, with its point at their midpoint.
    pub fn transepicondylar(femur: &SegmentTrajectory, lateral: &str, medial: &str, trial: &MarkerTable) -> Result<Axis, AxisError> {
        let average = |marker: &str| average_in_segment(femur, marker, trial);
        Axis::through_points(average(lateral)?, average(medial)?)
    }

    /// This axis, given in a frame whose pose in frame B is `pose`, expressed in frame B (for
    /// `pose` a segment → lab pose: the axis in the lab).
    pub fn transformed(&self, pose: &SegmentPose) -> Axis {
        Axis { point: pose.to_lab(&self.point), direction: pose.rotation * self.direction }
    }

    /// This axis, given in the segment frame, in the lab at segment pose `pose`.
    pub fn in_lab(&self, pose: &SegmentPose) -> Axis {
        self.transformed(pose)
    }

    /// This axis, given in the lab, in the frame of the segment at pose `pose`.
    pub fn in_segment(&self, pose: &SegmentPose) -> Axis {
        self.transformed(&pose.inverse())
    }

    /// The same line with the opposite direction.
    pub fn reversed(&self) -> Axis {
        Axis { point: self.point, direction: -self.direction }
    }

    /// The point of the line nearest to `point` (m).
    pub fn nearest_point(&self, point: &Vector3<f64>) -> Vector3<f64> {
        self.point + self.direction * (point - self.point).dot(&self.direction)
    }

    /// Distance (m) from `point` to the line.
    pub fn distance_to(&self, point: &Vector3<f64>) -> f64 {
        (point - self.nearest_point(point)).norm()
    }

    /// The same line with its point moved to the point nearest `point`.
    pub fn through_nearest(&self, point: &Vector3<f64>) -> Axis {
        Axis { point: self.nearest_point(point), direction: self.direction }
    }

    /// The same line with its direction flipped if needed so that direction·`hint` ≥ 0.
    pub fn oriented_towards(&self, hint: &Vector3<f64>) -> Axis {
        if self.direction.dot(hint) < 0.0 { self.reversed() } else { *self }
    }

    /// The angle (rad, in [0, π/2]) between the two lines, independent of direction signs.
    pub fn angle_to(&self, other: &Axis) -> f64 {
        let cross = self.direction.cross(&other.direction).norm();
        cross.atan2(self.direction.dot(&other.direction).abs())
    }
}

/// The mean position (m) in the segment frame of `marker`'s trial positions, over the frames
/// where the segment has a pose and the marker is visible.
fn average_in_segment(segment: &SegmentTrajectory, marker: &str, trial: &MarkerTable) -> Result<Vector3<f64>, AxisError> {
    let column = trial.marker_index(marker).ok_or_else(|| AxisError::MarkerNotInTrial { segment: segment.segment.clone(), marker: marker.to_owned() })?;
    let per_meter = trial.units().per_meter();
    let (mut sum, mut count) = (Vector3::zeros(), 0usize);
    for frame in 0..trial.n_frames().min(segment.frames.len()) {
        let (Some(pose), Some(xyz)) = (segment.pose(frame), trial.position(frame, column)) else { continue };
        let lab = Vector3::from(xyz) / per_meter;
        if let Some(bad) = lab.iter().copied().find(|v| !v.is_finite()) {
            let what = format!("marker `{marker}`, trial frame {} (t = {} s)", trial.frame_numbers()[frame], trial.times()[frame]);
            return Err(AxisError::NonFinite { what, value: bad });
        }
        sum += pose.to_segment(&lab);
        count += 1;
    }
    if count == 0 {
        let what = format!("segment `{}`: marker `{marker}` visible with a segment pose", segment.segment);
        return Err(AxisError::TooFewFrames { what, frames: 0, needed: 1 });
    }
    Ok(sum / count as f64)
}
