//! A moving frame: a transform with its first and second time derivatives, and the rules that
//! compose them. Inverse dynamics reads body velocities and accelerations from these.

use super::spatial::{Mat3, Transform, Vec3};

/// X_AB(t) and its time derivatives at one instant: p_A = R·p_B + p, so a point fixed in B moves
/// in A with velocity Ṙ·p_B + ṗ and acceleration R̈·p_B + p̈ (m/s, m/s²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransformRates {
    pub transform: Transform,
    /// Ṙ (1/s).
    pub rotation_rate: Mat3,
    /// R̈ (1/s²).
    pub rotation_acceleration: Mat3,
    /// ṗ, the velocity of B's origin in A (m/s).
    pub translation_rate: Vec3,
    /// p̈ (m/s²).
    pub translation_acceleration: Vec3,
}

impl TransformRates {
    /// A transform that does not move.
    pub fn fixed(transform: Transform) -> TransformRates {
        TransformRates { transform, rotation_rate: Mat3::zeros(), rotation_acceleration: Mat3::zeros(), translation_rate: Vec3::zeros(), translation_acceleration: Vec3::zeros() }
    }

    /// A rotation R (with Ṙ, R̈) and a translation p (with ṗ, p̈), composed as X = (R, p).
    pub fn new(rotation: [Mat3; 3], translation: [Vec3; 3]) -> TransformRates {
        TransformRates {
            transform: Transform { rotation: rotation[0], translation: translation[0] },
            rotation_rate: rotation[1],
            rotation_acceleration: rotation[2],
            translation_rate: translation[1],
            translation_acceleration: translation[2],
        }
    }

    /// X_AC = X_AB · X_BC, differentiated by the product rule.
    pub fn compose(&self, b_to_c: &TransformRates) -> TransformRates {
        let (r1, r1d, r1dd) = (self.transform.rotation, self.rotation_rate, self.rotation_acceleration);
        let (r2, r2d, r2dd) = (b_to_c.transform.rotation, b_to_c.rotation_rate, b_to_c.rotation_acceleration);
        let (p2, p2d, p2dd) = (b_to_c.transform.translation, b_to_c.translation_rate, b_to_c.translation_acceleration);
        TransformRates {
            transform: self.transform.compose(&b_to_c.transform),
            rotation_rate: r1d * r2 + r1 * r2d,
            rotation_acceleration: r1dd * r2 + 2.0 * r1d * r2d + r1 * r2dd,
            translation_rate: self.translation_rate + r1d * p2 + r1 * p2d,
            translation_acceleration: self.translation_acceleration + r1dd * p2 + 2.0 * (r1d * p2d) + r1 * p2dd,
        }
    }

    /// X_AC = X_AB · X_BC with X_BC fixed.
    pub fn then_fixed(&self, b_to_c: &Transform) -> TransformRates {
        TransformRates {
            transform: self.transform.compose(b_to_c),
            rotation_rate: self.rotation_rate * b_to_c.rotation,
            rotation_acceleration: self.rotation_acceleration * b_to_c.rotation,
            translation_rate: self.translation_rate + self.rotation_rate * b_to_c.translation,
            translation_acceleration: self.translation_acceleration + self.rotation_acceleration * b_to_c.translation,
        }
    }

    /// ω of B in A, expressed in A (rad/s): Ṙ·Rᵀ = ω×, the cross-product matrix of ω.
    pub fn angular_velocity(&self) -> Vec3 {
        axial(&(self.rotation_rate * self.transform.rotation.transpose()))
    }

    /// α = ω̇ of B in A, expressed in A (rad/s²): the skew part of R̈·Rᵀ (Ṙ·Ṙᵀ is symmetric).
    pub fn angular_acceleration(&self) -> Vec3 {
        axial(&(self.rotation_acceleration * self.transform.rotation.transpose()))
    }

    /// Velocity in A of the point `point` fixed in B (given in B), m/s.
    pub fn point_velocity(&self, point: &Vec3) -> Vec3 {
        self.rotation_rate * point + self.translation_rate
    }

    /// Acceleration in A of the point `point` fixed in B (given in B), m/s².
    pub fn point_acceleration(&self, point: &Vec3) -> Vec3 {
        self.rotation_acceleration * point + self.translation_acceleration
    }
}

/// R(θ) about the unit `axis` a, with the given θ̇ (`rate`) and θ̈ (`acceleration`): Ṙ = θ̇·K·R
/// and R̈ = (θ̈·K + θ̇²·K²)·R, K the cross-product matrix of a.
pub fn rotation_rates(rotation: Mat3, axis: &Vec3, rate: f64, acceleration: f64) -> [Mat3; 3] {
    let k = axis.cross_matrix();
    [rotation, rate * k * rotation, (acceleration * k + rate * rate * k * k) * rotation]
}

/// R = Rᵢ·Rⱼ with both rotating: the rates of the product.
pub fn product_rates(a: &[Mat3; 3], b: &[Mat3; 3]) -> [Mat3; 3] {
    [a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2]]
}

/// ω from its cross-product matrix: the skew part of `m`.
fn axial(m: &Mat3) -> Vec3 {
    Vec3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::spatial::{body_fixed_xyz, rotation_about};
    use approx::assert_relative_eq;

    /// X(t): a rotation about a tilted axis by θ(t) = 0.3 + 1.1t + 0.9t², then a translation
    /// (t, t², 2t) of the origin.
    fn moving(t: f64) -> Transform {
        let axis = Vec3::new(0.2, 0.9, -0.4).normalize();
        Transform { rotation: body_fixed_xyz([0.1, -0.2, 0.3]) * rotation_about(&axis, 0.3 + 1.1 * t + 0.9 * t * t), translation: Vec3::new(t, t * t, 2.0 * t) }
    }

    fn moving_rates() -> TransformRates {
        let axis = Vec3::new(0.2, 0.9, -0.4).normalize();
        let base = TransformRates::fixed(Transform { rotation: body_fixed_xyz([0.1, -0.2, 0.3]), translation: Vec3::zeros() });
        let turn = rotation_rates(rotation_about(&axis, 0.3), &axis, 1.1, 1.8);
        let rotation = [base.transform.rotation * turn[0], base.transform.rotation * turn[1], base.transform.rotation * turn[2]];
        TransformRates::new(rotation, [Vec3::zeros(), Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 2.0, 0.0)])
    }

    #[test]
    fn rates_match_central_differences_of_the_motion() {
        let h = 1e-4;
        let x = moving_rates();
        let (plus, zero, minus) = (moving(h), moving(0.0), moving(-h));
        assert_relative_eq!(x.transform.rotation, zero.rotation, epsilon = 1e-15);
        assert_relative_eq!(x.rotation_rate, (plus.rotation - minus.rotation) / (2.0 * h), epsilon = 1e-7);
        assert_relative_eq!(x.rotation_acceleration, (plus.rotation - 2.0 * zero.rotation + minus.rotation) / (h * h), epsilon = 1e-6);
    }

    #[test]
    fn composition_follows_the_product_rule() {
        let h = 1e-4;
        let offset = Transform { rotation: body_fixed_xyz([0.5, 0.1, -0.7]), translation: Vec3::new(0.3, -0.1, 0.2) };
        let composed = moving_rates().compose(&moving_rates()).then_fixed(&offset);
        let at = |t: f64| moving(t).compose(&moving(t)).compose(&offset);
        let (plus, zero, minus) = (at(h), at(0.0), at(-h));
        let point = Vec3::new(0.4, 0.5, -0.6);
        let acceleration = (plus.apply(&point) - 2.0 * zero.apply(&point) + minus.apply(&point)) / (h * h);
        assert_relative_eq!(composed.point_acceleration(&point), acceleration, epsilon = 1e-6);
        let omega = axial(&((plus.rotation - minus.rotation) / (2.0 * h) * zero.rotation.transpose()));
        assert_relative_eq!(composed.angular_velocity(), omega, epsilon = 1e-7);
    }
}
