//! The objective of one frame as least-squares residuals, equal to Simbody's assembler goal:
//!
//! F(q) = Σ_i w_i ‖x_i(q) − x̂_i‖² / (2 Σ_i w_i) + Σ_j w_j (q_j − q̂_j)² / 2 [+ Σ_k w_c e_k² / 2]
//!
//! over the markers i with data in the frame (Simbody's `Markers` goal divides by the total
//! weight of those markers), the coordinate tasks j and, with a finite constraint weight w_c,
//! the constraint errors e_k. Residuals: √(w_i/W)·(x_i − x̂_i) (three each, zero for a marker
//! without data), √w_j·(q_j − q̂_j), √w_c·e_k, so F = ½‖r‖². The errors of the links between
//! bodies ([`BodyLink`]: point, distance, point-on-line and weld constraints) enter as
//! √w_ℓ·(e + s) with the [`LinkTerms`]' weight and shifts: an augmented Lagrangian when the
//! solver holds them exactly.

use nalgebra::DMatrix;

use super::coordinates::{CoordinateMap, PoseDerivatives};
use super::tasks::{TrackedCoordinate, TrackedMarker};
use crate::mechanics::{BodyLink, CoordinateAxis, Kinematics, Mobilizer, Multibody, RateTerm, Vec3};
use crate::solvers::least_squares::LeastSquaresProblem;

/// What the residuals of every frame share: the compiled model and tasks.
#[derive(Debug, Clone)]
pub(super) struct FrameModel<'m> {
    pub multibody: &'m Multibody,
    pub markers: Vec<TrackedMarker>,
    pub coordinates: Vec<TrackedCoordinate>,
    /// Per tracked marker: the coordinates that move it and are not held.
    pub marker_coordinates: Vec<Vec<usize>>,
    /// Per link, per end: the coordinates that move its body and are not held.
    pub link_coordinates: Vec<[Vec<usize>; 2]>,
}

impl FrameModel<'_> {
    pub fn residual_count(&self, map: &CoordinateMap) -> usize {
        3 * self.markers.len() + self.coordinates.len() + map.soft_couplers.len() + map.soft_locks.len() + link_rows(self.multibody)
    }
}

/// How the links enter a frame's residuals: √weight·(e + shift) per link error e (m, or the
/// weld's dimensionless orientation errors); weight 0 leaves them out.
#[derive(Debug, Clone, Copy)]
pub(super) struct LinkTerms<'a> {
    pub root_weight: f64,
    /// Per link error, in [`link_errors`] order (empty: none).
    pub shifts: &'a [f64],
}

impl LinkTerms<'_> {
    pub const NONE: LinkTerms<'static> = LinkTerms { root_weight: 0.0, shifts: &[] };
}

/// The coordinates that move `body` and are not held.
pub(super) fn moving_coordinates(multibody: &Multibody, map: &CoordinateMap, body: usize) -> Vec<usize> {
    (0..multibody.coordinates.len()).filter(|&c| !map.is_held(c) && multibody.is_moved_by(body, multibody.coordinate_joint(c))).collect()
}

/// How many errors the links have.
pub(super) fn link_rows(multibody: &Multibody) -> usize {
    multibody.links.iter().map(BodyLink::rows).sum()
}

/// Buffers reused from frame to frame.
#[derive(Debug, Clone)]
pub(super) struct FrameScratch {
    pub kinematics: Kinematics,
    pub q: Vec<f64>,
    /// ∂p/∂q axes per coordinate (Ball and Free rotations converted to angle rates).
    axes: Vec<CoordinateAxis>,
    derivatives: PoseDerivatives,
}

impl FrameScratch {
    pub fn new(multibody: &Multibody) -> FrameScratch {
        let kinematics = multibody.kinematics();
        let axes = kinematics.axes.clone();
        FrameScratch { kinematics, q: multibody.default_pose(), axes, derivatives: PoseDerivatives::default() }
    }
}

/// One frame's residuals: observed marker positions and their per-frame scales.
pub(super) struct FrameObjective<'a, 'm> {
    pub model: &'a FrameModel<'m>,
    pub map: &'a CoordinateMap,
    pub scratch: &'a mut FrameScratch,
    /// Per tracked marker: the observation (m, ground), `None` when missing in the frame.
    pub observed: &'a [Option<Vec3>],
    /// Per tracked marker: √(w_i / W), 0 without data.
    pub scales: &'a [f64],
    /// Per coordinate task: its target in this frame (rad or m).
    pub targets: &'a [f64],
    pub links: LinkTerms<'a>,
}

impl LeastSquaresProblem for FrameObjective<'_, '_> {
    fn variable_count(&self) -> usize {
        self.map.variable_count()
    }

    fn residual_count(&self) -> usize {
        self.model.residual_count(self.map)
    }

    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
        let multibody = self.model.multibody;
        let scratch = &mut *self.scratch;
        self.map.pose(multibody, x, &mut scratch.q);
        multibody.realize(&scratch.q, &mut scratch.kinematics);
        let mut row = 0;
        for (i, marker) in self.model.markers.iter().enumerate() {
            let location = scratch.kinematics.bodies[marker.body].apply(&marker.location);
            let error = match self.observed[i] {
                Some(observed) if self.scales[i] > 0.0 => self.scales[i] * (location - observed),
                _ => Vec3::zeros(),
            };
            residuals[row..row + 3].copy_from_slice(error.as_slice());
            row += 3;
        }
        for (task, target) in self.model.coordinates.iter().zip(self.targets) {
            residuals[row] = task.weight.sqrt() * (scratch.q[task.coordinate] - target);
            row += 1;
        }
        let root_weight = self.map.root_weight;
        for &k in &self.map.soft_couplers {
            let coupler = &multibody.couplers[k];
            residuals[row] = root_weight * (coupler.dependent_value(&scratch.q) - scratch.q[coupler.dependent]);
            row += 1;
        }
        for &c in &self.map.soft_locks {
            residuals[row] = root_weight * (scratch.q[c] - multibody.coordinates[c].default_value);
            row += 1;
        }
        for (k, error) in multibody.link_errors(&scratch.kinematics).into_iter().enumerate() {
            let shift = self.links.shifts.get(k).copied().unwrap_or(0.0);
            residuals[row] = self.links.root_weight * (error + shift);
            row += 1;
        }
        if let Some(jacobian) = jacobian {
            self.fill_jacobian(jacobian);
        }
    }
}

impl FrameObjective<'_, '_> {
    /// ∂r/∂x at the pose of the last `evaluate`.
    fn fill_jacobian(&mut self, jacobian: &mut DMatrix<f64>) {
        let multibody = self.model.multibody;
        let scratch = &mut *self.scratch;
        self.map.derivatives(multibody, &scratch.q, &mut scratch.derivatives);
        let derivatives = &scratch.derivatives;
        angle_rate_axes(multibody, &scratch.kinematics, &scratch.q, &mut scratch.axes);
        jacobian.fill(0.0);
        let map = self.map;
        for (i, marker) in self.model.markers.iter().enumerate() {
            let scale = self.scales[i];
            if scale == 0.0 || self.observed[i].is_none() {
                continue;
            }
            let location = scratch.kinematics.bodies[marker.body].apply(&marker.location);
            add_point_partials(jacobian, 3 * i, &location, scale, &self.model.marker_coordinates[i], &scratch.axes, derivatives);
        }
        let mut row = 3 * self.model.markers.len();
        for task in &self.model.coordinates {
            for &(k, coefficient) in derivatives.of(task.coordinate) {
                jacobian[(row, k)] += task.weight.sqrt() * coefficient;
            }
            row += 1;
        }
        for &k in &map.soft_couplers {
            let coupler = &multibody.couplers[k];
            let slope = coupler.slope(&scratch.q);
            for &(x, coefficient) in derivatives.of(coupler.independent) {
                jacobian[(row, x)] += map.root_weight * slope * coefficient;
            }
            for &(x, coefficient) in derivatives.of(coupler.dependent) {
                jacobian[(row, x)] -= map.root_weight * coefficient;
            }
            row += 1;
        }
        for &c in &map.soft_locks {
            for &(x, coefficient) in derivatives.of(c) {
                jacobian[(row, x)] += map.root_weight * coefficient;
            }
            row += 1;
        }
        for (link, coordinates) in multibody.links.iter().zip(&self.model.link_coordinates) {
            for link_row in 0..link.rows() {
                for (term, moving) in link.rate_terms(&scratch.kinematics, link_row).iter().zip(coordinates) {
                    add_rate_partials(jacobian, row, term, self.links.root_weight, moving, &scratch.axes, derivatives);
                }
                row += 1;
            }
        }
    }
}

/// Adds factor·∂x/∂(free values) of a point at `location` (ground), moved by `coordinates`, to
/// the three rows from `row`.
fn add_point_partials(jacobian: &mut DMatrix<f64>, row: usize, location: &Vec3, factor: f64, coordinates: &[usize], axes: &[CoordinateAxis], derivatives: &PoseDerivatives) {
    for &c in coordinates {
        let axis = &axes[c];
        let partial = factor * (axis.angular.cross(&(location - axis.origin)) + axis.linear);
        for &(k, coefficient) in derivatives.of(c) {
            for a in 0..3 {
                jacobian[(row + a, k)] += coefficient * partial[a];
            }
        }
    }
}

/// Adds factor·∂e/∂(free values) of a link error's share `term`, its body moved by
/// `coordinates`, to row `row`.
fn add_rate_partials(jacobian: &mut DMatrix<f64>, row: usize, term: &RateTerm, factor: f64, coordinates: &[usize], axes: &[CoordinateAxis], derivatives: &PoseDerivatives) {
    for &c in coordinates {
        let axis = &axes[c];
        let velocity = axis.angular.cross(&(term.point - axis.origin)) + axis.linear;
        let partial = factor * (term.linear.dot(&velocity) + term.angular.dot(&axis.angular));
        for &(k, coefficient) in derivatives.of(c) {
            jacobian[(row, k)] += coefficient * partial;
        }
    }
}

/// The motion axes per unit q̇ of every coordinate: [`Kinematics::axes`], except that a joint's
/// speeds that are M's angular velocity (`BallJoint`, `FreeJoint`, the ellipsoid glides) are
/// turned into rates of its body-fixed X-Y-Z angles, the q's Simbody's assembler varies:
/// u = G(q)·q̇ with G the angles' rate partials, so the axis of q̇ⱼ is Σₖ (axis of uₖ)·Gₖⱼ.
fn angle_rate_axes(multibody: &Multibody, kinematics: &Kinematics, q: &[f64], axes: &mut [CoordinateAxis]) {
    axes.copy_from_slice(&kinematics.axes);
    for joint in &multibody.joints {
        if joint.mobilizer.angular_velocity_speeds() == 0 {
            continue;
        }
        let angles: Vec<f64> = joint.coordinates[..3].iter().map(|&c| q[c]).collect();
        let mut partials = [crate::mechanics::PartialVelocity { angular: Vec3::zeros(), linear: Vec3::zeros() }; 3];
        Mobilizer::Gimbal.partial_velocities(&angles, &mut partials);
        for (j, partial) in partials.iter().enumerate() {
            let axis = &mut axes[joint.coordinates[j]];
            axis.angular = Vec3::zeros();
            axis.linear = Vec3::zeros();
            for k in 0..3 {
                let speed_axis = &kinematics.axes[joint.coordinates[k]];
                axis.angular += speed_axis.angular * partial.angular[k];
                axis.linear += speed_axis.linear * partial.angular[k];
            }
        }
    }
}
