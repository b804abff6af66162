//! A segment's pose in every frame of a trial, by per-frame least squares or by Kalman smoothing.

use nalgebra::Vector3;

use super::cluster::checked_times;
use super::kalman::{smooth_segment, KalmanSettings};
use super::segment_pose::{fit_rigid, residual_rms, NoPose, SegmentPose};
use super::{AxisError, SegmentCluster};
use crate::io::table::MarkerTable;

/// How segment poses are estimated from the cluster markers.
#[derive(Debug, Clone, PartialEq)]
pub enum PoseMethod {
    /// Each frame on its own: the least-squares rigid fit of the visible markers
    /// ([`fit_rigid`](super::fit_rigid)); frames with fewer than three visible (or collinear)
    /// markers have no pose.
    LeastSquares,
    /// The whole trial at once: a Rauch–Tung–Striebel smoother with a constant-fourth-derivative
    /// process model and the marker positions as measurements (De Groote et al. 2008, as in the
    /// thesis). Every frame gets a pose, also frames with missing markers.
    KalmanSmoother(KalmanSettings),
}

/// A segment's estimated pose in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FramePose {
    /// Segment → lab pose.
    pub pose: SegmentPose,
    /// RMS distance (m) between the visible markers and their positions predicted by `pose`
    /// (0 when no marker is visible).
    pub residual_rms: f64,
    /// Number of cluster markers visible in the frame.
    pub visible: usize,
}

/// A segment's pose in every frame of a trial (one entry per trial frame, in order).
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentTrajectory {
    /// The segment's name.
    pub segment: String,
    /// Frame times (s), as in the trial.
    pub times: Vec<f64>,
    /// The trial's `Frame#` of each frame.
    pub frame_numbers: Vec<u64>,
    /// The pose of each frame, or why the frame has none.
    pub frames: Vec<Result<FramePose, NoPose>>,
}

impl SegmentTrajectory {
    /// The pose in frame index `frame` (from 0), if it has one.
    pub fn pose(&self, frame: usize) -> Option<&SegmentPose> {
        self.frames.get(frame)?.as_ref().ok().map(|f| &f.pose)
    }

    /// Number of frames with a pose.
    pub fn posed_frames(&self) -> usize {
        self.frames.iter().filter(|f| f.is_ok()).count()
    }

    /// Frame indices (from 0) without a pose and why.
    pub fn gaps(&self) -> impl Iterator<Item = (usize, NoPose)> + '_ {
        self.frames.iter().enumerate().filter_map(|(i, f)| f.as_ref().err().map(|&why| (i, why)))
    }
}

/// The poses of `cluster`'s segment in every frame of `trial` by `method`.
pub fn track_segment(cluster: &SegmentCluster, trial: &MarkerTable, method: &PoseMethod) -> Result<SegmentTrajectory, AxisError> {
    let times = checked_times(trial)?;
    let positions = cluster.trial_positions(trial)?;
    let frames = match method {
        PoseMethod::LeastSquares => least_squares_poses(cluster, &positions),
        PoseMethod::KalmanSmoother(settings) => {
            let initial = least_squares_poses(cluster, &positions);
            let context = FrameContext { segment: &cluster.segment, frame_numbers: trial.frame_numbers(), times: &times };
            let poses = smooth_segment(cluster, &positions, &initial, settings, &context)?;
            poses.into_iter().zip(&positions).map(|(pose, observed)| Ok(frame_pose(cluster, pose, observed))).collect()
        }
    };
    Ok(SegmentTrajectory { segment: cluster.segment.clone(), times, frame_numbers: trial.frame_numbers().to_vec(), frames })
}

/// What error messages need to name a frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct FrameContext<'a> {
    pub segment: &'a str,
    pub frame_numbers: &'a [u64],
    pub times: &'a [f64],
}

/// Per-frame least-squares poses of the visible markers.
fn least_squares_poses(cluster: &SegmentCluster, positions: &[Vec<Option<Vector3<f64>>>]) -> Vec<Result<FramePose, NoPose>> {
    positions
        .iter()
        .map(|observed| {
            let (local, lab) = visible_pairs(cluster, observed);
            fit_rigid(&local, &lab).map(|pose| FramePose { pose, residual_rms: residual_rms(&pose, &local, &lab), visible: local.len() })
        })
        .collect()
}

/// `pose` with its residual against the markers observed in that frame.
fn frame_pose(cluster: &SegmentCluster, pose: SegmentPose, observed: &[Option<Vector3<f64>>]) -> FramePose {
    let (local, lab) = visible_pairs(cluster, observed);
    FramePose { pose, residual_rms: residual_rms(&pose, &local, &lab), visible: local.len() }
}

/// The local and lab positions of the markers visible in one frame.
pub(super) fn visible_pairs(cluster: &SegmentCluster, observed: &[Option<Vector3<f64>>]) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    cluster.local.iter().zip(observed).filter_map(|(l, p)| p.map(|p| (*l, p))).unzip()
}
