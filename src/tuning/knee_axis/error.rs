//! Why a functional knee axis could not be computed. Every error names the segment, marker or
//! frame it concerns; frames are named by the trial's `Frame#` and time.

/// Bad input to the knee-axis tools. Too little motion, too few markers or too few frames are
/// errors (the axis would be meaningless); a single frame without a pose is not (it is left out
/// and reported in [`SegmentTrajectory`](super::SegmentTrajectory)).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AxisError {
    /// A cluster needs three markers to define a rigid pose.
    #[error("segment `{segment}`: the cluster has {count} marker(s); a rigid pose needs at least 3")]
    TooFewMarkers { segment: String, count: usize },
    /// The same marker listed twice in one cluster.
    #[error("segment `{segment}`: marker `{marker}` is listed twice in the cluster")]
    DuplicateMarker { segment: String, marker: String },
    /// Marker names and local coordinates of different lengths.
    #[error("segment `{segment}`: {names} marker names but {coordinates} local coordinates")]
    ClusterShape { segment: String, names: usize, coordinates: usize },
    /// The cluster's local coordinates lie on one line (or coincide): no rotation about that
    /// line can be measured.
    #[error("segment `{segment}`: the cluster markers {markers} are collinear; a rigid pose needs three markers not on one line")]
    CollinearCluster { segment: String, markers: String },
    /// A cluster marker that the trial does not have.
    #[error("segment `{segment}`: marker `{marker}` is not in the trial")]
    MarkerNotInTrial { segment: String, marker: String },
    /// No frame of the trial has every cluster marker (needed to define a cluster from a trial).
    #[error("segment `{segment}`: no frame of the trial has all cluster markers ({markers})")]
    NoCompleteFrame { segment: String, markers: String },
    /// A NaN or infinite coordinate, time or setting.
    #[error("{what}: value {value} is not finite")]
    NonFinite { what: String, value: f64 },
    /// The trial's times must increase strictly (the smoother's sampling interval comes from them).
    #[error("trial frame {frame} (t = {time} s): time does not increase from the previous frame (t = {previous} s)")]
    TimesNotIncreasing { frame: u64, time: f64, previous: f64 },
    /// Fewer usable frames than the method needs.
    #[error("{what}: {frames} usable frame(s); at least {needed} are needed")]
    TooFewFrames { what: String, frames: usize, needed: usize },
    /// The knee did not rotate enough for its axis to be identified.
    #[error("the axis is not identifiable from this trial (rotation range {:.1}° < {:.0}°; Cheze et al.)", .range.to_degrees(), .minimum.to_degrees())]
    NotIdentifiable { range: f64, minimum: f64 },
    /// A smoother or fit setting out of its domain.
    #[error("setting `{name}` = {value}: {expected}")]
    InvalidSetting { name: String, value: f64, expected: String },
    /// The Kalman smoother's rotation vector, relative to the segment's mean orientation,
    /// cannot represent rotations near 180°.
    #[error(
        "segment `{segment}`, trial frame {frame} (t = {time} s): the segment is rotated {:.1}° from its mean orientation; \
         the Kalman smoother needs less than {:.0}°",
        .angle.to_degrees(),
        .limit.to_degrees()
    )]
    RotationOutOfRange { segment: String, frame: u64, time: f64, angle: f64, limit: f64 },
    /// A covariance lost positive definiteness (badly scaled settings).
    #[error("segment `{segment}`, trial frame {frame}: the Kalman smoother's covariance is not positive definite; check the noise settings")]
    Covariance { segment: String, frame: u64 },
    /// A decomposition that did not converge (non-finite or extreme input).
    #[error("{what}: the singular value decomposition did not converge")]
    NotConverged { what: String },
    /// An axis direction that is zero or not finite.
    #[error("{what}: the axis direction {direction:?} is zero or not finite")]
    InvalidDirection { what: String, direction: [f64; 3] },
    /// A comparison plane that an axis (nearly) lies in, so the projection or intersection is
    /// undefined.
    #[error("axis comparison: {what}")]
    DegenerateComparison { what: String },
}
