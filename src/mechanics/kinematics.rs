//! Forward kinematics: body poses in ground and the point Jacobian columns of every generalized
//! speed, for a pose given as coordinate values.

use super::mobilizer::PartialVelocity;
use super::multibody::{Multibody, GROUND_INDEX};
use super::spatial::{Transform, Vec3};

/// How one coordinate's generalized speed u moves the bodies it carries, in ground: a point p
/// fixed in such a body moves by ∂ṗ/∂u = angular × (p − origin) + linear. u = q̇ (so this is
/// ∂p/∂q) except for `BallJoint`/`FreeJoint` rotations (see `mobilizer`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinateAxis {
    /// rad per unit u.
    pub angular: Vec3,
    /// Velocity of `origin` per unit u.
    pub linear: Vec3,
    /// The joint's child frame origin, m.
    pub origin: Vec3,
}

/// Results of [`Multibody::realize`], reused between poses (no allocation per pose).
#[derive(Debug, Clone)]
pub struct Kinematics {
    /// X_GB per body (ground first).
    pub bodies: Vec<Transform>,
    /// Per coordinate.
    pub axes: Vec<CoordinateAxis>,
}

impl Kinematics {
    /// ∂ṗ/∂u for the point `point` (in ground) fixed in `body`, u = the speed of `coordinate`.
    pub fn point_partial(&self, multibody: &Multibody, body: usize, point: &Vec3, coordinate: usize) -> Vec3 {
        let joint = multibody.coordinate_joint(coordinate);
        if !multibody.is_moved_by(body, joint) {
            return Vec3::zeros();
        }
        let axis = &self.axes[coordinate];
        axis.angular.cross(&(point - axis.origin)) + axis.linear
    }

    /// A marker's location in ground (m).
    pub fn marker_location(&self, multibody: &Multibody, marker: usize) -> Vec3 {
        let marker = &multibody.markers[marker];
        self.bodies[marker.body].apply(&marker.location)
    }
}

impl Multibody {
    /// Buffers for [`Multibody::realize`].
    pub fn kinematics(&self) -> Kinematics {
        let zero = CoordinateAxis { angular: Vec3::zeros(), linear: Vec3::zeros(), origin: Vec3::zeros() };
        Kinematics { bodies: vec![Transform::IDENTITY; self.bodies.len()], axes: vec![zero; self.coordinates.len()] }
    }

    /// Places every body for coordinate values `q` (rad or m, [`Multibody::coordinates`] order),
    /// as given: values are neither clamped to ranges nor checked against locks.
    ///
    /// # Panics
    /// If `q` does not hold one value per coordinate.
    pub fn realize(&self, q: &[f64], kinematics: &mut Kinematics) {
        assert_eq!(q.len(), self.coordinates.len(), "one value per coordinate");
        kinematics.bodies[GROUND_INDEX] = Transform::IDENTITY;
        let mut local = [0.0; 6];
        let mut partials = [PartialVelocity { angular: Vec3::zeros(), linear: Vec3::zeros() }; 6];
        for joint in &self.joints {
            let n = joint.coordinates.len();
            for (value, &c) in local.iter_mut().zip(&joint.coordinates) {
                *value = q[c];
            }
            let parent_frame = kinematics.bodies[joint.parent].compose(&joint.parent_frame);
            let child_frame = parent_frame.compose(&joint.mobilizer.transform(&local[..n]));
            kinematics.bodies[joint.child] = child_frame.compose(&joint.child_body);
            joint.mobilizer.partial_velocities(&local[..n], &mut partials[..n]);
            for (partial, &c) in partials.iter().zip(&joint.coordinates) {
                kinematics.axes[c] = CoordinateAxis {
                    angular: parent_frame.rotation * partial.angular,
                    linear: parent_frame.rotation * partial.linear,
                    origin: child_frame.translation,
                };
            }
        }
    }
}
