//! The pose of a segment in the lab and the least-squares rigid fit (Söderkvist & Wedin 1993,
//! the Kabsch solution by SVD) that finds it from marker positions.

use nalgebra::{Matrix3, Rotation3, Vector3};

/// The pose of a segment frame in the lab: a point `p` given in the segment frame is at
/// `rotation * p + translation` in the lab (both in metres). `rotation` maps segment-frame
/// vectors to lab vectors (a proper rotation, det = +1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentPose {
    /// Segment → lab rotation.
    pub rotation: Rotation3<f64>,
    /// The segment frame's origin in the lab (m).
    pub translation: Vector3<f64>,
}

impl SegmentPose {
    /// The identity pose (segment frame = lab frame).
    pub fn identity() -> Self {
        SegmentPose { rotation: Rotation3::identity(), translation: Vector3::zeros() }
    }

    /// A segment-frame point (m) in the lab.
    pub fn to_lab(&self, point: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * point + self.translation
    }

    /// A lab point (m) in the segment frame.
    pub fn to_segment(&self, point: &Vector3<f64>) -> Vector3<f64> {
        self.rotation.inverse() * (point - self.translation)
    }

    /// The inverse pose: the lab frame's pose in the segment frame.
    pub fn inverse(&self) -> SegmentPose {
        let rotation = self.rotation.inverse();
        SegmentPose { rotation, translation: -(rotation * self.translation) }
    }

    /// `self ∘ inner`: if `inner` is frame B's pose in frame A and `self` is A's pose in the lab,
    /// the result is B's pose in the lab.
    pub fn compose(&self, inner: &SegmentPose) -> SegmentPose {
        SegmentPose { rotation: self.rotation * inner.rotation, translation: self.to_lab(&inner.translation) }
    }
}

/// Why a set of marker positions does not define a rigid pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoPose {
    /// Fewer than three markers visible in the frame.
    TooFewMarkers { visible: usize },
    /// The visible markers' local coordinates lie on one line.
    Collinear { visible: usize },
}

/// Relative size below which the second principal extent of a point set counts as zero
/// (the points are collinear): σ₂ < `COLLINEAR_TOLERANCE` · σ₁ of the centred coordinates.
pub const COLLINEAR_TOLERANCE: f64 = 1e-6;

/// True if the points lie on one line (or coincide), judged by the singular values of their
/// centred coordinates (see [`COLLINEAR_TOLERANCE`]).
pub fn are_collinear(points: &[Vector3<f64>]) -> bool {
    if points.len() < 3 {
        return true;
    }
    let centroid = centroid(points);
    let scatter = points.iter().fold(Matrix3::zeros(), |sum, p| sum + (p - centroid) * (p - centroid).transpose());
    let mut extents = scatter.symmetric_eigenvalues().map(|v| v.max(0.0).sqrt());
    extents.as_mut_slice().sort_by(|a, b| b.total_cmp(a));
    extents[0] == 0.0 || extents[1] < COLLINEAR_TOLERANCE * extents[0]
}

/// The mean of the points (the zero vector for none).
pub fn centroid(points: &[Vector3<f64>]) -> Vector3<f64> {
    if points.is_empty() {
        return Vector3::zeros();
    }
    points.iter().sum::<Vector3<f64>>() / points.len() as f64
}

/// The rigid pose that moves the `local` points (segment frame, m) closest, in the
/// least-squares sense, to the `lab` points (same order, m): minimises Σ‖R·local + t − lab‖²
/// over proper rotations R (det = +1) and translations t. Needs ≥ 3 non-collinear local points.
pub fn fit_rigid(local: &[Vector3<f64>], lab: &[Vector3<f64>]) -> Result<SegmentPose, NoPose> {
    let visible = local.len().min(lab.len());
    if visible < 3 {
        return Err(NoPose::TooFewMarkers { visible });
    }
    if are_collinear(&local[..visible]) {
        return Err(NoPose::Collinear { visible });
    }
    let (local_centroid, lab_centroid) = (centroid(&local[..visible]), centroid(&lab[..visible]));
    let covariance = local.iter().zip(lab).fold(Matrix3::zeros(), |sum, (l, p)| sum + (p - lab_centroid) * (l - local_centroid).transpose());
    let rotation = nearest_rotation(&covariance);
    Ok(SegmentPose { rotation, translation: lab_centroid - rotation * local_centroid })
}

/// The proper rotation R maximising trace(Rᵀ·M) (the polar factor of M with det = +1), by SVD:
/// R = U·diag(1, 1, det(U·Vᵀ))·Vᵀ.
pub fn nearest_rotation(matrix: &Matrix3<f64>) -> Rotation3<f64> {
    let svd = matrix.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else { return Rotation3::identity() };
    let sign = (u * v_t).determinant().signum();
    let correction = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, if sign < 0.0 { -1.0 } else { 1.0 }));
    Rotation3::from_matrix_unchecked(u * correction * v_t)
}

/// Root mean square of ‖pose·local − lab‖ over the point pairs (m); 0 for none.
pub fn residual_rms(pose: &SegmentPose, local: &[Vector3<f64>], lab: &[Vector3<f64>]) -> f64 {
    if local.is_empty() {
        return 0.0;
    }
    let sum: f64 = local.iter().zip(lab).map(|(l, p)| (pose.to_lab(l) - p).norm_squared()).sum();
    (sum / local.len() as f64).sqrt()
}
