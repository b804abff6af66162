//! Rotation helpers: rotation vectors (exp/log), the left Jacobian of SO(3), the chordal mean
//! of rotations, and the twist angle of a rotation about a given axis.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::segment_pose::nearest_rotation;

/// The rotation exp([θ]×) of rotation vector θ (rad, axis × angle).
pub fn exp(rotation_vector: &Vector3<f64>) -> Rotation3<f64> {
    Rotation3::new(*rotation_vector)
}

/// The rotation vector (rad) of `rotation`, angle in [0, π], accurate to rounding also near the
/// identity (from the quaternion by atan2, not from the trace by acos).
pub fn log(rotation: &Rotation3<f64>) -> Vector3<f64> {
    let quaternion = UnitQuaternion::from_rotation_matrix(rotation);
    let (w, v) = if quaternion.w < 0.0 { (-quaternion.w, -quaternion.imag()) } else { (quaternion.w, quaternion.imag()) };
    let sine = v.norm();
    if sine < 1e-300 {
        return 2.0 * v;
    }
    v * (2.0 * sine.atan2(w) / sine)
}

/// The left Jacobian J(θ) of SO(3): exp(θ + δ) ≈ exp(J(θ)·δ)·exp(θ) for small δ, so
/// ∂(exp(θ)·u)/∂θ = −[exp(θ)·u]× · J(θ).
/// J = I + (1 − cos φ)/φ² [θ]× + (φ − sin φ)/φ³ [θ]×², φ = ‖θ‖ (Taylor series near 0).
pub fn left_jacobian(rotation_vector: &Vector3<f64>) -> Matrix3<f64> {
    let angle = rotation_vector.norm();
    let k = rotation_vector.cross_matrix();
    let (a, b) = if angle < 1e-4 {
        let a2 = angle * angle;
        (0.5 - a2 / 24.0, 1.0 / 6.0 - a2 / 120.0)
    } else {
        ((1.0 - angle.cos()) / (angle * angle), (angle - angle.sin()) / (angle * angle * angle))
    };
    Matrix3::identity() + k * a + k * k * b
}

/// The chordal L2 mean of rotations: the rotation nearest (Frobenius) to their arithmetic mean
/// matrix. `None` for an empty set.
pub fn chordal_mean<'a>(rotations: impl IntoIterator<Item = &'a Rotation3<f64>>) -> Option<Rotation3<f64>> {
    let mut count = 0usize;
    let sum = rotations.into_iter().fold(Matrix3::zeros(), |sum, r| {
        count += 1;
        sum + r.matrix()
    });
    (count > 0).then(|| nearest_rotation(&sum))
}

/// The twist of `rotation` about the unit `axis` (rad, in (−π, π]): the angle of the rotation
/// about `axis` in its swing–twist decomposition, 2·atan2(q_v·axis, q_w).
pub fn twist_angle(rotation: &Rotation3<f64>, axis: &Vector3<f64>) -> f64 {
    let quaternion = UnitQuaternion::from_rotation_matrix(rotation);
    let angle = 2.0 * quaternion.imag().dot(axis).atan2(quaternion.w);
    if angle > std::f64::consts::PI {
        angle - 2.0 * std::f64::consts::PI
    } else if angle <= -std::f64::consts::PI {
        angle + 2.0 * std::f64::consts::PI
    } else {
        angle
    }
}

/// max − min of a sequence of angles (rad) after unwrapping jumps larger than π.
pub fn unwrapped_range(angles: impl IntoIterator<Item = f64>) -> f64 {
    let (mut previous, mut offset) = (None::<f64>, 0.0);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for angle in angles {
        if let Some(p) = previous {
            let step = angle + offset - p;
            offset -= (step / (2.0 * std::f64::consts::PI)).round() * 2.0 * std::f64::consts::PI;
        }
        let unwrapped = angle + offset;
        low = low.min(unwrapped);
        high = high.max(unwrapped);
        previous = Some(unwrapped);
    }
    if high >= low { high - low } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_inverts_exp_also_near_the_identity_and_near_half_a_turn() {
        for v in [Vector3::new(1e-9, -2e-9, 3e-10), Vector3::new(0.3, -1.2, 0.5), Vector3::new(0.0, 3.1, 0.0), Vector3::new(1e-3, 0.0, -2e-3)] {
            assert!((log(&exp(&v)) - v).norm() < 1e-15 * v.norm().max(1.0) * 10.0, "{v:?}: {:?}", log(&exp(&v)));
        }
    }

    /// ∂(exp(θ)·u)/∂θ = −[exp(θ)·u]×·J(θ), checked by central differences.
    #[test]
    fn left_jacobian_gives_the_derivative_of_a_rotated_vector() {
        let (theta, u) = (Vector3::new(0.4, -0.9, 1.3), Vector3::new(0.1, 0.2, -0.3));
        let analytic = -(exp(&theta) * u).cross_matrix() * left_jacobian(&theta);
        let step = 1e-6;
        for k in 0..3 {
            let delta = Vector3::from_fn(|i, _| if i == k { step } else { 0.0 });
            let numeric = (exp(&(theta + delta)) * u - exp(&(theta - delta)) * u) / (2.0 * step);
            assert!((numeric - analytic.column(k)).norm() < 1e-9, "{k}");
        }
    }

    #[test]
    fn twist_about_the_rotation_axis_is_the_rotation_angle_and_ranges_unwrap() {
        let axis = Vector3::new(0.2, 0.1, 1.0).normalize();
        for angle in [-3.0, -0.5, 0.0, 0.7, 3.1] {
            assert!((twist_angle(&exp(&(axis * angle)), &axis) - angle).abs() < 1e-12);
        }
        assert!((unwrapped_range([3.0, -3.0, -2.5]) - (2.0 * std::f64::consts::PI - 6.0 + 0.5 + 0.0)).abs() < 1e-12);
    }
}
