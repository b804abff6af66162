//! The functional knee axis (thesis ch. 4): the axis that best explains the recorded motion of
//! the tibia relative to the femur, from marker clusters on both segments.
//!
//! Pipeline: [`SegmentCluster`] (markers and their segment-frame coordinates) →
//! [`KneeMotion::track`] (segment poses per frame by [`PoseMethod::LeastSquares`] or
//! [`PoseMethod::KalmanSmoother`]) → [`fit_gal`] or [`fit_sara`] ([`AxisFit`]: the axis in both
//! segment frames) → [`compare_axes`] (the thesis' transversal/frontal angles and sagittal
//! distance). [`Axis::transepicondylar`] gives the geometric axis to compare with.
//! [`swap_knee`] rebuilds the model's knee as a `PinJoint` about a fitted axis.
//!
//! Units: metres, radians, seconds. Frames: a segment frame is the frame of its cluster's local
//! coordinates; poses map segment → lab.

mod axis;
mod axis_fit;
mod cluster;
mod compare;
mod error;
mod gal;
mod kalman;
mod knee_motion;
mod path_change;
mod rotation;
mod sara;
mod segment_pose;
mod swap;
mod trajectory;

pub use axis::Axis;
pub use axis_fit::{fit_axis, AxisFit, AxisHint, AxisMethod, MINIMUM_FRAMES, MINIMUM_ROTATION_RANGE};
pub use cluster::SegmentCluster;
pub use compare::{compare_axes, AnatomicalFrame, AxisComparison};
pub use error::AxisError;
pub use gal::fit_gal;
pub use kalman::{KalmanSettings, MAX_ROTATION_FROM_MEAN};
pub use knee_motion::KneeMotion;
pub use path_change::PathChange;
pub use sara::fit_sara;
pub use segment_pose::{are_collinear, fit_rigid, nearest_rotation, residual_rms, NoPose, SegmentPose, COLLINEAR_TOLERANCE};
pub use swap::{swap_knee, JointAxis, SwapError, SwappedKnee};
pub use trajectory::{track_segment, FramePose, PoseMethod, SegmentTrajectory};
