//! Gamage & Lasenby (2002): the knee axis as the common axis of the circles that the tibia
//! markers trace in the femur frame (thesis eq. 4.1–4.2, 4.4).
//!
//! With v_i^p the position of tibia marker p in frame i, expressed in the femur frame:
//! - **orientation** n minimises Σ_p Σ_i ((v_i^p − m^p)·n)² (each marker moves in a plane
//!   ⟂ n); minimising over m^p gives m^p = mean_i v_i^p, so n is the right singular vector of
//!   the smallest singular value of the stacked centred positions;
//! - **location** m minimises Σ_p Σ_i (‖v_i^p − m‖² − (r^p)²)² (each marker stays at distance
//!   r^p from m); minimising over (r^p)² gives the linear system
//!   2 (v_i^p − v̄^p)·m = ‖v_i^p‖² − mean_i ‖v_i^p‖², whose solution is a line along n. We solve
//!   it for m = c + a·e₁ + b·e₂ with e₁, e₂ ⟂ n, so m is the axis point nearest the reference
//!   point c ([`AxisHint::reference_point`]).
//!
//! GaL needs only the femur pose; the tibia poses are used for the tibia-frame axis (the
//! femur-frame axis mapped through each frame's relative pose, averaged) and the rotation range.

use nalgebra::{DMatrix, DVector, Vector3};

use super::axis_fit::{identifiable_range, require_frames, right_singular_vectors, AxisFit, AxisHint};
use super::segment_pose::centroid;
use super::{Axis, AxisError, KneeMotion};

/// The GaL axis of `motion`. The femur-frame direction points towards `hint.lateral`; the
/// femur-frame point is the axis point nearest the hint's reference point; the tibia-frame
/// axis is that axis carried into the tibia frame (see the module doc).
pub fn fit_gal(motion: &KneeMotion, hint: &AxisHint) -> Result<AxisFit, AxisError> {
    hint.check()?;
    let (trajectories, frames_used) = marker_trajectories(motion);
    require_frames("GaL: frames with a femur pose and a visible tibia marker", frames_used)?;
    let all_samples: Vec<Vector3<f64>> = trajectories.iter().flatten().copied().collect();
    let reference = hint.reference_point(motion, || centroid(&all_samples));
    let direction = plane_normal(&trajectories)?;
    let direction = if direction.dot(&hint.lateral) < 0.0 { -direction } else { direction };
    let rotation_range = identifiable_range(motion, &direction, hint)?;
    let point = circle_centre(&trajectories, &direction, &reference).ok_or_else(|| too_few_samples(all_samples.len()))?;
    let femur = Axis::new(point, direction)?;
    let tibia = carried_to_tibia(motion, &femur)?;
    Ok(AxisFit { femur, tibia, residual_rms: circle_residual_rms(&trajectories, &femur), rotation_range, frames_used })
}

fn too_few_samples(samples: usize) -> AxisError {
    AxisError::TooFewFrames { what: "GaL: tibia marker samples spanning a plane".into(), frames: samples, needed: 3 }
}

/// Each tibia marker's positions in the femur frame (m), over the frames where the femur has a
/// pose and the marker is visible; and the number of frames that gave at least one position.
fn marker_trajectories(motion: &KneeMotion) -> (Vec<Vec<Vector3<f64>>>, usize) {
    let mut trajectories = vec![Vec::new(); motion.tibia_cluster.markers.len()];
    let mut frames = 0;
    for frame in 0..motion.n_frames() {
        let samples = motion.tibia_markers_in_femur(frame);
        frames += usize::from(!samples.is_empty());
        for (marker, position) in samples {
            trajectories[marker].push(position);
        }
    }
    (trajectories, frames)
}

/// Eq. 4.1: the unit normal n of the planes the markers move in.
fn plane_normal(trajectories: &[Vec<Vector3<f64>>]) -> Result<Vector3<f64>, AxisError> {
    let rows: Vec<Vector3<f64>> = trajectories.iter().flat_map(|samples| centred(samples)).collect();
    if rows.len() < 3 {
        return Err(too_few_samples(rows.len()));
    }
    let matrix = DMatrix::from_fn(rows.len(), 3, |i, j| rows[i][j]);
    let (vectors, _) = right_singular_vectors(matrix).ok_or_else(|| AxisError::NotConverged { what: "GaL orientation".into() })?;
    Ok(Vector3::new(vectors[(0, 2)], vectors[(1, 2)], vectors[(2, 2)]).normalize())
}

/// Eq. 4.2 restricted to the plane ⟂ n through `reference`: the axis point nearest `reference`.
fn circle_centre(trajectories: &[Vec<Vector3<f64>>], direction: &Vector3<f64>, reference: &Vector3<f64>) -> Option<Vector3<f64>> {
    let (e1, e2) = plane_basis(direction);
    let (mut rows, mut rhs) = (Vec::new(), Vec::new());
    for samples in trajectories {
        let shifted: Vec<Vector3<f64>> = samples.iter().map(|v| v - reference).collect();
        let mean_square = shifted.iter().map(|v| v.norm_squared()).sum::<f64>() / shifted.len().max(1) as f64;
        for (v, d) in shifted.iter().zip(centred(&shifted)) {
            rows.push([2.0 * d.dot(&e1), 2.0 * d.dot(&e2)]);
            rhs.push(v.norm_squared() - mean_square);
        }
    }
    if rows.len() < 2 {
        return None;
    }
    let a = DMatrix::from_fn(rows.len(), 2, |i, j| rows[i][j]);
    let solution = a.svd(true, true).solve(&DVector::from_vec(rhs), 1e-14).ok()?;
    let point = reference + e1 * solution[0] + e2 * solution[1];
    point.iter().all(|v| v.is_finite()).then_some(point)
}

/// The positions minus their mean.
fn centred(samples: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let mean = centroid(samples);
    samples.iter().map(|v| v - mean).collect()
}

/// Two unit vectors completing the unit `direction` to a right-handed orthonormal basis.
pub(super) fn plane_basis(direction: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if direction.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let e1 = direction.cross(&helper).normalize();
    (e1, direction.cross(&e1))
}

/// RMS (m) over all samples of the distance between a marker position and its fitted circle:
/// axial offset from the marker's mean plane and radial offset from its mean radius.
fn circle_residual_rms(trajectories: &[Vec<Vector3<f64>>], axis: &Axis) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for samples in trajectories.iter().filter(|s| !s.is_empty()) {
        let offsets: Vec<(f64, f64)> = samples
            .iter()
            .map(|v| {
                let relative = v - axis.point;
                let axial = relative.dot(&axis.direction);
                (axial, (relative - axis.direction * axial).norm())
            })
            .collect();
        let n = offsets.len() as f64;
        let (mean_axial, mean_radial) = offsets.iter().fold((0.0, 0.0), |(a, r), (x, y)| (a + x / n, r + y / n));
        sum += offsets.iter().map(|(a, r)| (a - mean_axial).powi(2) + (r - mean_radial).powi(2)).sum::<f64>();
        count += offsets.len();
    }
    if count == 0 { 0.0 } else { (sum / count as f64).sqrt() }
}

/// The femur-frame axis carried into the tibia frame: in every frame with both poses the axis
/// is mapped by the inverse relative pose; the directions and points are averaged.
pub(super) fn carried_to_tibia(motion: &KneeMotion, femur: &Axis) -> Result<Axis, AxisError> {
    let relative = motion.frames_with_both_poses().into_iter().filter_map(|f| motion.relative_pose(f));
    let carried: Vec<Axis> = relative.map(|pose| femur.transformed(&pose.inverse())).collect();
    if carried.is_empty() {
        return Err(AxisError::TooFewFrames { what: "frames with femur and tibia poses".into(), frames: 0, needed: 1 });
    }
    let direction: Vector3<f64> = carried.iter().map(|a| a.direction).sum();
    let points: Vec<Vector3<f64>> = carried.iter().map(|a| a.point).collect();
    Axis::new(centroid(&points), direction)
}
