//! What a functional-axis fit returns, the hints that fix its sign and point, and the checks
//! shared by both methods (enough frames, enough rotation).

use nalgebra::{DMatrix, Vector3};

use super::{Axis, AxisError, KneeMotion};

/// Fewest frames a fit accepts.
pub const MINIMUM_FRAMES: usize = 5;

/// Default smallest rotation range of the tibia about the axis (20°, after Cheze et al.: no
/// accurate axis from positions less than about 25° apart).
pub const MINIMUM_ROTATION_RANGE: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// A functional axis of the knee.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisFit {
    /// The axis in the femur frame (the frame of the femur cluster's local coordinates).
    pub femur: Axis,
    /// The same axis in the tibia frame (the frame of the tibia cluster's local coordinates).
    pub tibia: Axis,
    /// RMS misfit of the method's model (m): for GaL the markers' distance from their fitted
    /// circles (tibia markers in the femur frame, femur markers in the tibia frame), for SARA
    /// the distance between the axis point carried by the femur and by the tibia.
    pub residual_rms: f64,
    /// Range of the tibia's rotation about the axis relative to the femur (rad).
    pub rotation_range: f64,
    /// Frames that entered the fit.
    pub frames_used: usize,
}

/// The two algorithms of the thesis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisMethod {
    /// Gamage & Lasenby's circle/sphere fit (a fitting technique).
    Gal,
    /// Ehrig et al.'s symmetrical axis of rotation approach (a transformation technique).
    Sara,
}

/// What fixes the fitted axis' sign and point, and how much rotation is required.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisHint {
    /// A femur-frame direction the axis direction is made to point towards (direction·lateral
    /// ≥ 0). Default +z: lateral for a right leg in OpenSim's frames (x anterior, y superior,
    /// z right).
    pub lateral: Vector3<f64>,
    /// A femur-frame point (m): the reported femur-frame axis point is the axis point nearest to
    /// it. Default (`None`): the tibia cluster's centroid in the femur frame averaged over the
    /// frames with both poses ([`KneeMotion::tibia_centroid_in_femur`]).
    pub reference_point: Option<Vector3<f64>>,
    /// Smallest accepted rotation range (rad); default [`MINIMUM_ROTATION_RANGE`].
    pub minimum_rotation_range: f64,
}

impl Default for AxisHint {
    fn default() -> Self {
        AxisHint { lateral: Vector3::z(), reference_point: None, minimum_rotation_range: MINIMUM_ROTATION_RANGE }
    }
}

impl AxisHint {
    /// The femur-frame reference point for `motion`.
    pub(super) fn reference_point(&self, motion: &KneeMotion, fallback: impl FnOnce() -> Vector3<f64>) -> Vector3<f64> {
        self.reference_point.or_else(|| motion.tibia_centroid_in_femur()).unwrap_or_else(fallback)
    }

    /// The hint values finite, the lateral direction non-zero.
    pub(super) fn check(&self) -> Result<(), AxisError> {
        if !(self.lateral.iter().all(|v| v.is_finite()) && self.lateral.norm() > 0.0) {
            return Err(AxisError::InvalidDirection { what: "axis hint `lateral`".into(), direction: self.lateral.into() });
        }
        if let Some(bad) = self.reference_point.and_then(|p| p.iter().copied().find(|v| !v.is_finite())) {
            return Err(AxisError::NonFinite { what: "axis hint `reference_point`".into(), value: bad });
        }
        if !(self.minimum_rotation_range.is_finite() && self.minimum_rotation_range >= 0.0) {
            let expected = "a finite angle ≥ 0 (rad)".into();
            return Err(AxisError::InvalidSetting { name: "minimum_rotation_range".into(), value: self.minimum_rotation_range, expected });
        }
        Ok(())
    }
}

/// Fits the knee axis of `motion` with `method`.
pub fn fit_axis(motion: &KneeMotion, method: AxisMethod, hint: &AxisHint) -> Result<AxisFit, AxisError> {
    match method {
        AxisMethod::Gal => super::gal::fit_gal(motion, hint),
        AxisMethod::Sara => super::sara::fit_sara(motion, hint),
    }
}

/// Errors unless at least [`MINIMUM_FRAMES`] frames are usable.
pub(super) fn require_frames(what: &str, frames: usize) -> Result<(), AxisError> {
    if frames < MINIMUM_FRAMES {
        return Err(AxisError::TooFewFrames { what: what.to_owned(), frames, needed: MINIMUM_FRAMES });
    }
    Ok(())
}

/// The rotation range of `motion` about the femur-frame `direction`; errors below the hint's
/// minimum.
pub(super) fn identifiable_range(motion: &KneeMotion, direction: &Vector3<f64>, hint: &AxisHint) -> Result<f64, AxisError> {
    let range = motion.rotation_range(&motion.frames_with_both_poses(), direction);
    if range < hint.minimum_rotation_range {
        return Err(AxisError::NotIdentifiable { range, minimum: hint.minimum_rotation_range });
    }
    Ok(range)
}

/// The right singular vectors of `matrix` (rows ≥ columns) in order of decreasing singular
/// value, with the singular values; `None` if the SVD does not converge.
pub(super) fn right_singular_vectors(matrix: DMatrix<f64>) -> Option<(DMatrix<f64>, Vec<f64>)> {
    let svd = nalgebra::SVD::try_new(matrix, false, true, f64::EPSILON, 10_000)?;
    Some((svd.v_t?.transpose(), svd.singular_values.iter().copied().collect()))
}
