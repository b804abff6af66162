//! Gamage & Lasenby (2002): the knee axis as the common axis of the circles that one segment's
//! markers trace in the other segment's frame (thesis eq. 4.1–4.2, 4.4), fitted both ways.
//!
//! With v_i^p the position of marker p in frame i, expressed in the other segment's frame:
//! - **orientation** n minimises Σ_p Σ_i ((v_i^p − m^p)·n)² (each marker moves in a plane
//!   ⟂ n); minimising over m^p gives m^p = mean_i v_i^p, so n is the right singular vector of
//!   the smallest singular value of the stacked centred positions;
//! - **location** m minimises Σ_p Σ_i (‖v_i^p − m‖² − (r^p)²)² (each marker stays at distance
//!   r^p from m); minimising over (r^p)² gives the linear system A m = b with rows
//!   2 (v_i^p − v̄^p)·m = ‖v_i^p‖² − mean_i ‖v_i^p‖², whose solution is a line along n. We solve
//!   it for m = c + a·e₁ + b·e₂ with e₁, e₂ ⟂ n, so m is the axis point nearest the reference
//!   point c ([`AxisHint::reference_point`]).
//!
//! The thesis fits the tibia markers in the femur frame. With clusters like real ones (markers
//! spread along the segment, little across it) that location is ill-conditioned: eq. 4.2 senses
//! m only through the markers' radial directions, which all lie within the arc the shank
//! sweeps, so the component of m along the shank's mean direction is nearly interchangeable
//! with the radii r^p, and knee-angle-dependent errors of the femur pose (soft-tissue artefact)
//! move it far. So we fit both ways — the tibia markers in the femur frame and the femur
//! markers in the tibia frame, whose weak direction, carried into the femur frame, lies along
//! the thigh instead — and combine them:
//! - orientation: n minimises the sum of both eq. 4.1 costs, the tibia-frame direction being
//!   R̄ᵀ n with R̄ the mean tibia → femur rotation (every relative rotation leaves the true axis
//!   direction fixed, so R̄ maps it exactly);
//! - location: each eq. 4.2 system, solved in the plane ⟂ its direction, gives an axis point;
//!   the tibia-frame one is carried into the femur frame (averaged over the frames' relative
//!   poses, exact for a point on the axis) and the two are combined weighted by their normal
//!   matrices AᵀA, which weights each by how well it fixes each direction.
//!
//! The tibia-frame axis is the femur-frame axis carried into the tibia frame the same way.

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Rotation3, Vector2, Vector3};

use super::axis_fit::{identifiable_range, require_frames, right_singular_vectors, AxisFit, AxisHint};
use super::segment_pose::{centroid, nearest_rotation, SegmentPose};
use super::{Axis, AxisError, KneeMotion};

/// Each marker's positions (m) in the other segment's frame, over the frames where it is
/// visible and that segment has a pose.
type Trajectories = Vec<Vec<Vector3<f64>>>;

/// The GaL axis of `motion`. The femur-frame direction points towards `hint.lateral`; the
/// femur-frame point is the axis point nearest the hint's reference point; the tibia-frame
/// axis is that axis carried into the tibia frame (see the module doc).
pub fn fit_gal(motion: &KneeMotion, hint: &AxisHint) -> Result<AxisFit, AxisError> {
    hint.check()?;
    let (tibia_in_femur, tibia_frames) = marker_trajectories(motion, motion.tibia_cluster.markers.len(), |f| motion.tibia_markers_in_femur(f));
    let (femur_in_tibia, femur_frames) = marker_trajectories(motion, motion.femur_cluster.markers.len(), |f| motion.femur_markers_in_tibia(f));
    require_frames("GaL: frames with a femur pose and a visible tibia marker", tibia_frames.len())?;
    require_frames("GaL: frames with a tibia pose and a visible femur marker", femur_frames.len())?;
    let relative: Vec<SegmentPose> = motion.frames_with_both_poses().into_iter().filter_map(|f| motion.relative_pose(f)).collect();
    let mean_rotation = mean_rotation(&relative).ok_or_else(no_relative_pose)?;
    let reference = hint.reference_point(motion, || centroid(&tibia_in_femur.concat()));
    let direction = plane_normal(&tibia_in_femur, &femur_in_tibia, &mean_rotation)?;
    let direction = if direction.dot(&hint.lateral) < 0.0 { -direction } else { direction };
    let rotation_range = identifiable_range(motion, &direction, hint)?;
    let point = combined_centre(&tibia_in_femur, &femur_in_tibia, &relative, &Plane::new(direction, reference), &mean_rotation)?;
    let femur = Axis::new(point, direction)?;
    let tibia = carried_to_tibia(&relative, &femur)?;
    let residual_rms = circle_residual_rms(&[(&tibia_in_femur, &femur), (&femur_in_tibia, &tibia)]);
    Ok(AxisFit { femur, tibia, residual_rms, rotation_range, frames_used: union_len(&tibia_frames, &femur_frames) })
}

fn too_few_samples(samples: usize) -> AxisError {
    AxisError::TooFewFrames { what: "GaL: marker samples spanning a plane".into(), frames: samples, needed: 3 }
}

fn no_relative_pose() -> AxisError {
    AxisError::TooFewFrames { what: "GaL: frames with femur and tibia poses".into(), frames: 0, needed: 1 }
}

/// The `markers` trajectories given by `samples` (a frame's visible (marker, position) pairs),
/// and the frames that gave at least one position.
fn marker_trajectories(motion: &KneeMotion, markers: usize, samples: impl Fn(usize) -> Vec<(usize, Vector3<f64>)>) -> (Trajectories, Vec<usize>) {
    let mut trajectories = vec![Vec::new(); markers];
    let mut frames = Vec::new();
    for frame in 0..motion.n_frames() {
        let positions = samples(frame);
        if !positions.is_empty() {
            frames.push(frame);
        }
        for (marker, position) in positions {
            trajectories[marker].push(position);
        }
    }
    (trajectories, frames)
}

/// The number of distinct frames in two frame lists.
fn union_len(a: &[usize], b: &[usize]) -> usize {
    let mut all = [a, b].concat();
    all.sort_unstable();
    all.dedup();
    all.len()
}

/// The rotation nearest the mean of `poses`' rotations; `None` without poses.
fn mean_rotation(poses: &[SegmentPose]) -> Option<Rotation3<f64>> {
    let sum: Matrix3<f64> = poses.iter().map(|pose| pose.rotation.matrix()).sum();
    (!poses.is_empty()).then(|| nearest_rotation(&sum))
}

/// Eq. 4.1 for both marker sets: the femur-frame unit normal n of the planes the tibia markers
/// move in (femur frame) and, rotated by `mean_rotation` (tibia → femur), of the planes the
/// femur markers move in (tibia frame).
fn plane_normal(tibia_in_femur: &Trajectories, femur_in_tibia: &Trajectories, mean_rotation: &Rotation3<f64>) -> Result<Vector3<f64>, AxisError> {
    let rotated = femur_in_tibia.iter().flat_map(|samples| centred(samples)).map(|v| mean_rotation * v);
    let rows: Vec<Vector3<f64>> = tibia_in_femur.iter().flat_map(|samples| centred(samples)).chain(rotated).collect();
    if rows.len() < 3 {
        return Err(too_few_samples(rows.len()));
    }
    let matrix = DMatrix::from_fn(rows.len(), 3, |i, j| rows[i][j]);
    let (vectors, _) = right_singular_vectors(matrix).ok_or_else(|| AxisError::NotConverged { what: "GaL orientation".into() })?;
    Ok(Vector3::new(vectors[(0, 2)], vectors[(1, 2)], vectors[(2, 2)]).normalize())
}

/// A plane through `origin` (m) ⟂ the unit `normal`, with an orthonormal basis (e₁, e₂) of it.
struct Plane {
    origin: Vector3<f64>,
    e1: Vector3<f64>,
    e2: Vector3<f64>,
}

impl Plane {
    fn new(normal: Vector3<f64>, origin: Vector3<f64>) -> Plane {
        let helper = if normal.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
        let e1 = normal.cross(&helper).normalize();
        Plane { origin, e1, e2: normal.cross(&e1) }
    }

    /// The plane through `origin` whose basis is this one's turned by `rotation`.
    fn turned(&self, rotation: &Rotation3<f64>, origin: Vector3<f64>) -> Plane {
        Plane { origin, e1: rotation * self.e1, e2: rotation * self.e2 }
    }

    /// The in-plane coordinates (m) of `point`'s projection.
    fn coordinates(&self, point: &Vector3<f64>) -> Vector2<f64> {
        let offset = point - self.origin;
        Vector2::new(offset.dot(&self.e1), offset.dot(&self.e2))
    }

    /// The point with in-plane coordinates `coordinates` (m).
    fn point(&self, coordinates: &Vector2<f64>) -> Vector3<f64> {
        self.origin + self.e1 * coordinates.x + self.e2 * coordinates.y
    }
}

/// Eq. 4.2 for both marker sets, combined: the femur-frame axis point in `plane` (⟂ the fitted
/// direction, through the reference point). The femur markers' system is solved in `plane`
/// carried into the tibia frame by the mean relative pose's rotation and the averaged reference
/// point; its point is carried back by averaging over `relative` (tibia → femur poses).
fn combined_centre(
    tibia_in_femur: &Trajectories,
    femur_in_tibia: &Trajectories,
    relative: &[SegmentPose],
    plane: &Plane,
    mean_rotation: &Rotation3<f64>,
) -> Result<Vector3<f64>, AxisError> {
    let samples = || too_few_samples(tibia_in_femur.iter().chain(femur_in_tibia).map(Vec::len).sum());
    let (forward, forward_normal) = circle_centre(tibia_in_femur, plane).ok_or_else(samples)?;
    let reference_in_tibia = centroid(&relative.iter().map(|pose| pose.to_segment(&plane.origin)).collect::<Vec<_>>());
    let tibia_plane = plane.turned(&mean_rotation.inverse(), reference_in_tibia);
    let (inverse, inverse_normal) = circle_centre(femur_in_tibia, &tibia_plane).ok_or_else(samples)?;
    let inverse = plane.coordinates(&centroid(&relative.iter().map(|pose| pose.to_lab(&tibia_plane.point(&inverse))).collect::<Vec<_>>()));
    let combined = (forward_normal + inverse_normal).try_inverse().ok_or_else(samples)? * (forward_normal * forward + inverse_normal * inverse);
    let point = plane.point(&combined);
    point.iter().all(|v| v.is_finite()).then_some(point).ok_or_else(samples)
}

/// Eq. 4.2 restricted to `plane` (⟂ the axis): the in-plane coordinates (m) of the axis point,
/// and the system's normal matrix AᵀA (m²).
fn circle_centre(trajectories: &Trajectories, plane: &Plane) -> Option<(Vector2<f64>, Matrix2<f64>)> {
    let (mut rows, mut rhs) = (Vec::new(), Vec::new());
    for samples in trajectories {
        let shifted: Vec<Vector3<f64>> = samples.iter().map(|v| v - plane.origin).collect();
        let mean_square = shifted.iter().map(|v| v.norm_squared()).sum::<f64>() / shifted.len().max(1) as f64;
        for (v, d) in shifted.iter().zip(centred(&shifted)) {
            rows.push([2.0 * d.dot(&plane.e1), 2.0 * d.dot(&plane.e2)]);
            rhs.push(v.norm_squared() - mean_square);
        }
    }
    if rows.len() < 2 {
        return None;
    }
    let a = DMatrix::from_fn(rows.len(), 2, |i, j| rows[i][j]);
    let normal = a.transpose() * &a;
    let solution = a.svd(true, true).solve(&DVector::from_vec(rhs), 1e-14).ok()?;
    Some((Vector2::new(solution[0], solution[1]), Matrix2::new(normal[(0, 0)], normal[(0, 1)], normal[(1, 0)], normal[(1, 1)])))
}

/// The positions minus their mean.
fn centred(samples: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let mean = centroid(samples);
    samples.iter().map(|v| v - mean).collect()
}

/// RMS (m) over all samples of the distance between a marker position and its fitted circle
/// about the axis of its frame: axial offset from the marker's mean plane and radial offset
/// from its mean radius.
fn circle_residual_rms(sets: &[(&Trajectories, &Axis)]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (trajectories, axis) in sets {
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
    }
    if count == 0 { 0.0 } else { (sum / count as f64).sqrt() }
}

/// The femur-frame `axis` carried into the tibia frame: mapped by the inverse of each of the
/// `relative` (tibia → femur) poses, the directions and points averaged.
fn carried_to_tibia(relative: &[SegmentPose], axis: &Axis) -> Result<Axis, AxisError> {
    let carried: Vec<Axis> = relative.iter().map(|pose| axis.transformed(&pose.inverse())).collect();
    let direction: Vector3<f64> = carried.iter().map(|a| a.direction).sum();
    let points: Vec<Vector3<f64>> = carried.iter().map(|a| a.point).collect();
    Axis::new(centroid(&points), direction)
}
