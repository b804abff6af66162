//! Ehrig et al. (2007), the symmetrical axis of rotation approach (SARA; thesis eq. 4.3, 4.5):
//! a point fixed in both segments, minimise Σ_i ‖R_i^f m^f + t_i^f − (R_i^t m^t + t_i^t)‖² over
//! (m^f, m^t), the point in the femur and in the tibia frame.
//!
//! In matrix form A x = b with rows [R_i^f  −R_i^t] and b_i = t_i^t − t_i^f. For a hinge every
//! point of the axis is a solution, so A has a (near-)null right singular vector (n^f, n^t):
//! the axis direction in the femur and in the tibia frame. We take the least-squares solution
//! without that direction (truncated SVD) and then move along it to the axis point nearest the
//! femur-frame reference point ([`AxisHint::reference_point`]).

use nalgebra::{DMatrix, DVector, Vector3};

use super::axis_fit::{identifiable_range, require_frames, right_singular_vectors, AxisFit, AxisHint};
use super::segment_pose::SegmentPose;
use super::{Axis, AxisError, KneeMotion};

/// The SARA axis of `motion`, in both segment frames. The femur-frame direction points towards
/// `hint.lateral` and the tibia-frame direction is the same physical direction; the points are
/// the same physical point, nearest the hint's reference point in the femur frame.
pub fn fit_sara(motion: &KneeMotion, hint: &AxisHint) -> Result<AxisFit, AxisError> {
    hint.check()?;
    let frames = motion.frames_with_both_poses();
    require_frames("SARA: frames with femur and tibia poses", frames.len())?;
    let poses: Vec<(SegmentPose, SegmentPose)> = frames.iter().filter_map(|&f| Some((*motion.femur.pose(f)?, *motion.tibia.pose(f)?))).collect();
    let (a, b) = linear_system(&poses);
    let not_converged = || AxisError::NotConverged { what: "SARA".into() };
    let (vectors, singular_values) = right_singular_vectors(a.clone()).ok_or_else(not_converged)?;
    let null = vectors.column(5).into_owned();
    let (femur_direction, tibia_direction) = (null.fixed_rows::<3>(0).into_owned(), null.fixed_rows::<3>(3).into_owned());
    let sign = if femur_direction.dot(&hint.lateral) < 0.0 { -1.0 } else { 1.0 };
    let femur_direction = Axis::new(Vector3::zeros(), femur_direction * sign)?.direction;
    let tibia_direction = Axis::new(Vector3::zeros(), tibia_direction * sign)?.direction;
    let rotation_range = identifiable_range(motion, &femur_direction, hint)?;

    let mut solution = truncated_solution(&a, &b, &vectors, &singular_values);
    let reference = hint.reference_point(motion, || solution.fixed_rows::<3>(0).into_owned());
    let along = null.fixed_rows::<3>(0).into_owned();
    solution += &null * ((reference - solution.fixed_rows::<3>(0)).dot(&along) / along.norm_squared());
    let (femur_point, tibia_point) = (solution.fixed_rows::<3>(0).into_owned(), solution.fixed_rows::<3>(3).into_owned());
    Ok(AxisFit {
        femur: Axis::new(femur_point, femur_direction)?,
        tibia: Axis::new(tibia_point, tibia_direction)?,
        residual_rms: point_residual_rms(&poses, &femur_point, &tibia_point),
        rotation_range,
        frames_used: poses.len(),
    })
}

/// A (3N × 6) and b (3N) of eq. 4.3 for the (femur, tibia) poses of N frames.
fn linear_system(poses: &[(SegmentPose, SegmentPose)]) -> (DMatrix<f64>, DVector<f64>) {
    let mut a = DMatrix::zeros(3 * poses.len(), 6);
    let mut b = DVector::zeros(3 * poses.len());
    for (i, (femur, tibia)) in poses.iter().enumerate() {
        a.view_mut((3 * i, 0), (3, 3)).copy_from(femur.rotation.matrix());
        a.view_mut((3 * i, 3), (3, 3)).copy_from(&(-tibia.rotation.matrix()));
        b.rows_mut(3 * i, 3).copy_from(&(tibia.translation - femur.translation));
    }
    (a, b)
}

/// x = Σ_{k<6} v_k (u_k·b)/σ_k over the five largest singular values, with u_k = A v_k / σ_k.
fn truncated_solution(a: &DMatrix<f64>, b: &DVector<f64>, vectors: &DMatrix<f64>, singular_values: &[f64]) -> DVector<f64> {
    let mut x = DVector::zeros(6);
    for k in 0..5 {
        let sigma = singular_values[k];
        if sigma <= f64::EPSILON * singular_values[0] {
            continue;
        }
        let v = vectors.column(k);
        x += v * ((a * v).dot(b) / (sigma * sigma));
    }
    x
}

/// RMS over frames of ‖R^f m^f + t^f − (R^t m^t + t^t)‖ (m).
fn point_residual_rms(poses: &[(SegmentPose, SegmentPose)], femur_point: &Vector3<f64>, tibia_point: &Vector3<f64>) -> f64 {
    let sum: f64 = poses.iter().map(|(f, t)| (f.to_lab(femur_point) - t.to_lab(tibia_point)).norm_squared()).sum();
    (sum / poses.len().max(1) as f64).sqrt()
}
