//! Rigid transforms and the rotations OpenSim builds them from (Simbody's conventions).

use nalgebra::{Matrix3, Vector3};

pub use crate::model::{body_fixed_xyz, body_fixed_xyz_angles};
use crate::model::Offset;

pub type Vec3 = Vector3<f64>;
pub type Mat3 = Matrix3<f64>;

/// X_AB: the pose of frame B in frame A, `p_A = rotation · p_B + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub rotation: Mat3,
    /// Origin of B in A (m), expressed in A.
    pub translation: Vec3,
}

impl Transform {
    pub const IDENTITY: Transform = Transform { rotation: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), translation: Vec3::new(0.0, 0.0, 0.0) };

    /// A `PhysicalOffsetFrame` offset: body-fixed X-Y-Z rotation, then translation in the parent.
    pub fn from_offset(offset: &Offset) -> Transform {
        Transform { rotation: body_fixed_xyz(offset.orientation), translation: Vec3::from(offset.translation) }
    }

    /// X_AC = X_AB · X_BC.
    pub fn compose(&self, b_to_c: &Transform) -> Transform {
        Transform { rotation: self.rotation * b_to_c.rotation, translation: self.translation + self.rotation * b_to_c.translation }
    }

    /// A point given in B, re-expressed in A.
    pub fn apply(&self, point: &Vec3) -> Vec3 {
        self.rotation * point + self.translation
    }

    /// X_BA from X_AB.
    pub fn inverse(&self) -> Transform {
        let rotation = self.rotation.transpose();
        Transform { rotation, translation: -(rotation * self.translation) }
    }
}

/// Rotation by `angle` (rad) about the unit vector `axis`, through the quaternion
/// (cos θ/2, sin θ/2 · axis) as Simbody's `Rotation(angle, UnitVec3)` does.
pub fn rotation_about(axis: &Vec3, angle: f64) -> Mat3 {
    let (sin, cos) = (angle / 2.0).sin_cos();
    let [w, x, y, z] = [cos, sin * axis.x, sin * axis.y, sin * axis.z];
    let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
    let (wx, wy, wz, xy, xz, yz) = (w * x, w * y, w * z, x * y, x * z, y * z);
    Mat3::new(
        ww + xx - yy - zz,
        2.0 * (xy - wz),
        2.0 * (xz + wy),
        2.0 * (xy + wz),
        ww - xx + yy - zz,
        2.0 * (yz - wx),
        2.0 * (xz - wy),
        2.0 * (yz + wx),
        ww - xx - yy + zz,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn euler_angles_compose_elementary_rotations() {
        let (a, b, c) = (0.3, -1.1, 2.0);
        let expected = rotation_about(&Vec3::x(), a) * rotation_about(&Vec3::y(), b) * rotation_about(&Vec3::z(), c);
        assert_relative_eq!(body_fixed_xyz([a, b, c]), expected, epsilon = 1e-15);
    }

    #[test]
    fn euler_angles_are_recovered_from_the_matrix() {
        for angles in [[0.3, -1.1, 2.0], [-2.5, 0.4, -0.2], [0.0, 0.0, 0.0], [1.0, std::f64::consts::FRAC_PI_2, 0.0]] {
            let rotation = body_fixed_xyz(angles);
            assert_relative_eq!(body_fixed_xyz(body_fixed_xyz_angles(&rotation)), rotation, epsilon = 1e-14);
        }
    }

    #[test]
    fn rotation_about_z_turns_x_towards_y() {
        let r = rotation_about(&Vec3::z(), std::f64::consts::FRAC_PI_2);
        assert_relative_eq!(r * Vec3::x(), Vec3::y(), epsilon = 1e-15);
    }

    #[test]
    fn inverse_undoes_transform() {
        let x = Transform { rotation: body_fixed_xyz([0.1, 0.2, 0.3]), translation: Vec3::new(1.0, -2.0, 0.5) };
        let p = Vec3::new(0.3, 0.4, -0.7);
        assert_relative_eq!(x.inverse().apply(&x.apply(&p)), p, epsilon = 1e-15);
        assert_relative_eq!(x.compose(&x.inverse()).rotation, Mat3::identity(), epsilon = 1e-15);
    }
}
