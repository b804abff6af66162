//! The tracked motion of femur and tibia in one trial: both segments' poses and both clusters'
//! measured marker positions, the input of both axis fits.

use nalgebra::Vector3;

use super::rotation::{twist_angle, unwrapped_range};
use super::segment_pose::SegmentPose;
use super::trajectory::track_segment;
use super::{AxisError, PoseMethod, SegmentCluster, SegmentTrajectory};
use crate::io::table::MarkerTable;

/// Femur and tibia tracked through one trial (frame indices are the trial's, from 0).
#[derive(Debug, Clone, PartialEq)]
pub struct KneeMotion {
    /// The femur cluster (its local coordinates define the femur frame).
    pub femur_cluster: SegmentCluster,
    /// The tibia cluster (its local coordinates define the tibia frame).
    pub tibia_cluster: SegmentCluster,
    /// Femur → lab pose per frame.
    pub femur: SegmentTrajectory,
    /// Tibia → lab pose per frame.
    pub tibia: SegmentTrajectory,
    /// The femur cluster markers' measured lab positions (m), `[frame][femur cluster marker]`.
    pub femur_markers: Vec<Vec<Option<Vector3<f64>>>>,
    /// The tibia cluster markers' measured lab positions (m), `[frame][tibia cluster marker]`.
    pub tibia_markers: Vec<Vec<Option<Vector3<f64>>>>,
}

impl KneeMotion {
    /// Tracks both clusters through `trial` with `method`.
    pub fn track(trial: &MarkerTable, femur: &SegmentCluster, tibia: &SegmentCluster, method: &PoseMethod) -> Result<KneeMotion, AxisError> {
        Ok(KneeMotion {
            femur_cluster: femur.clone(),
            tibia_cluster: tibia.clone(),
            femur: track_segment(femur, trial, method)?,
            tibia: track_segment(tibia, trial, method)?,
            femur_markers: femur.trial_positions(trial)?,
            tibia_markers: tibia.trial_positions(trial)?,
        })
    }

    /// Number of frames.
    pub fn n_frames(&self) -> usize {
        self.femur.frames.len()
    }

    /// The tibia frame's pose in the femur frame in `frame` (tibia → femur), if both segments
    /// have a pose there.
    pub fn relative_pose(&self, frame: usize) -> Option<SegmentPose> {
        Some(self.femur.pose(frame)?.inverse().compose(self.tibia.pose(frame)?))
    }

    /// Frames in which both segments have a pose.
    pub fn frames_with_both_poses(&self) -> Vec<usize> {
        (0..self.n_frames()).filter(|&frame| self.relative_pose(frame).is_some()).collect()
    }

    /// The visible tibia cluster markers of `frame` in the femur frame (m), as
    /// (cluster marker index, position); empty if the femur has no pose there.
    pub fn tibia_markers_in_femur(&self, frame: usize) -> Vec<(usize, Vector3<f64>)> {
        in_segment_frame(self.femur.pose(frame), &self.tibia_markers[frame])
    }

    /// The visible femur cluster markers of `frame` in the tibia frame (m), as
    /// (cluster marker index, position); empty if the tibia has no pose there.
    pub fn femur_markers_in_tibia(&self, frame: usize) -> Vec<(usize, Vector3<f64>)> {
        in_segment_frame(self.tibia.pose(frame), &self.femur_markers[frame])
    }

    /// The tibia cluster's centroid in the femur frame averaged over the frames with both poses
    /// (m); `None` if there are none.
    pub fn tibia_centroid_in_femur(&self) -> Option<Vector3<f64>> {
        let centroid = self.tibia_cluster.centroid();
        let points: Vec<Vector3<f64>> = self.frames_with_both_poses().iter().filter_map(|&f| self.relative_pose(f)).map(|p| p.to_lab(&centroid)).collect();
        (!points.is_empty()).then(|| super::segment_pose::centroid(&points))
    }

    /// The range (rad) of the tibia's rotation relative to the femur about the femur-frame unit
    /// `direction`, over `frames` (which must have both poses): the unwrapped twist of
    /// R_rel(i)·R_rel(first)ᵀ about `direction`, max − min.
    pub fn rotation_range(&self, frames: &[usize], direction: &Vector3<f64>) -> f64 {
        let relative: Vec<SegmentPose> = frames.iter().filter_map(|&f| self.relative_pose(f)).collect();
        let Some(first) = relative.first() else { return 0.0 };
        unwrapped_range(relative.iter().map(|pose| twist_angle(&(pose.rotation * first.rotation.inverse()), direction)))
    }
}


/// The visible `markers` (lab, m) in the frame of a segment at `pose`, as (marker index,
/// position); empty without a pose.
fn in_segment_frame(pose: Option<&SegmentPose>, markers: &[Option<Vector3<f64>>]) -> Vec<(usize, Vector3<f64>)> {
    let Some(pose) = pose else { return Vec::new() };
    markers.iter().enumerate().filter_map(|(marker, p)| p.map(|p| (marker, pose.to_segment(&p)))).collect()
}
