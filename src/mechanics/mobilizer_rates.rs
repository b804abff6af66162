//! X_FM in motion: a mobilizer's transform with its first and second time derivatives for given
//! generalized speeds u and their rates u̇ (Simbody's, see `mobilizer`: u = q̇ but for the
//! rotations of `BallJoint` and `FreeJoint`, whose u is the angular velocity of M in F, in F).

use super::mobilizer::{Mobilizer, TransformAxis};
use super::motion_rates::{product_rates, rotation_rates, TransformRates};
use super::spatial::{body_fixed_xyz, rotation_about, Mat3, Transform, Vec3};

impl Mobilizer {
    /// X_FM, Ẋ_FM and Ẍ_FM for the joint's coordinates `q`, speeds `u` and accelerations `udot`
    /// (the joint's own, in its coordinate order; rad, m, per s and per s²).
    pub fn transform_rates(&self, q: &[f64], u: &[f64], udot: &[f64]) -> TransformRates {
        let still = [Vec3::zeros(); 3];
        let unturned = [Mat3::identity(), Mat3::zeros(), Mat3::zeros()];
        match self {
            Mobilizer::Weld => TransformRates::fixed(Transform::IDENTITY),
            Mobilizer::Pin => TransformRates::new(turn(&Vec3::z(), [q[0], u[0], udot[0]]), still),
            Mobilizer::Slider => TransformRates::new(unturned, [q[0], u[0], udot[0]].map(|s| s * Vec3::x())),
            Mobilizer::Universal => TransformRates::new(euler_xyz_rates(2, q, u, udot), still),
            Mobilizer::Gimbal => TransformRates::new(euler_xyz_rates(3, q, u, udot), still),
            Mobilizer::Ball => TransformRates::new(angular_velocity_rates(q, u, udot), still),
            Mobilizer::Free => {
                let translation = [&q[3..6], &u[3..6], &udot[3..6]].map(Vec3::from_column_slice);
                TransformRates::new(angular_velocity_rates(q, u, udot), translation)
            }
            Mobilizer::Planar => {
                let translation = [q, u, udot].map(|v| Vec3::new(v[1], v[2], 0.0));
                TransformRates::new(turn(&Vec3::z(), [q[0], u[0], udot[0]]), translation)
            }
            Mobilizer::Custom(axes) => custom_rates(axes, q, u, udot),
            Mobilizer::Ellipsoid(ellipsoid) => ellipsoid.transform_rates(q, u, udot),
            Mobilizer::Scapulothoracic(joint) => joint.transform_rates(q, u, udot),
        }
    }
}

/// Simbody's `FunctionBased` mobilizer: R = R(θ₁,a₁)·R(θ₂,a₂)·R(θ₃,a₃), ω = Σ Wᵢ·θ̇ᵢ with
/// W = [a₁, R₁a₂, R₁R₂a₃], and α = Σ Wᵢ·θ̈ᵢ + Ẇ₂·θ̇₂ + Ẇ₃·θ̇₃ where Simbody takes Ẇ₂ = ω₁ × W₂ with
/// ω₁ the angular velocity of the joint's first speed alone and Ẇ₃ = ω₂ × W₃ with ω₂ that of
/// every speed but the third (`FunctionBasedImpl::buildHdot`). That is the exact rate when
/// rotation k is driven by the joint's k-th coordinate (every gait2392 joint); when one
/// coordinate drives several rotations (Rajagopal2016's walker knee) it is not, and OpenSim's
/// inverse dynamics is off the exact by up to about 1e-3 N·m there. We follow Simbody, so the
/// forces agree with OpenSim's. Translations p = Σ sⱼ·tⱼ are differentiated exactly.
fn custom_rates(axes: &[TransformAxis; 6], q: &[f64], u: &[f64], udot: &[f64]) -> TransformRates {
    let angles = [0, 1, 2].map(|i| axis_rates(&axes[i], q, u, udot));
    let first = rotation_about(&axes[0].axis, angles[0][0]);
    let second = first * rotation_about(&axes[1].axis, angles[1][0]);
    let rotation = second * rotation_about(&axes[2].axis, angles[2][0]);
    let w = [axes[0].axis, first * axes[1].axis, second * axes[2].axis];
    let omega_of = |speed: &dyn Fn(usize) -> bool| -> Vec3 {
        (0..3).filter_map(|i| axes[i].coordinate.filter(|&c| speed(c)).map(|c| w[i] * axes[i].function.derivative(q[c]) * u[c])).sum()
    };
    let omega: Vec3 = (0..3).map(|i| w[i] * angles[i][1]).sum();
    let (omega_1, omega_2) = (omega_of(&|c| c == 0), omega_of(&|c| c != 2));
    let alpha: Vec3 = (0..3).map(|i| w[i] * angles[i][2]).sum::<Vec3>() + omega_1.cross(&w[1]) * angles[1][1] + omega_2.cross(&w[2]) * angles[2][1];
    let rate = omega.cross_matrix() * rotation;
    let translation = axes[3..].iter().fold([Vec3::zeros(); 3], |p, a| {
        let s = axis_rates(a, q, u, udot);
        [p[0] + s[0] * a.axis, p[1] + s[1] * a.axis, p[2] + s[2] * a.axis]
    });
    TransformRates::new([rotation, rate, alpha.cross_matrix() * rotation + omega.cross_matrix() * rate], translation)
}

/// R(θ) about the unit `axis` with its rates, from [θ, θ̇, θ̈].
fn turn(axis: &Vec3, angle: [f64; 3]) -> [Mat3; 3] {
    rotation_rates(rotation_about(axis, angle[0]), axis, angle[1], angle[2])
}

/// Body-fixed X-Y(-Z) angles with u = q̇: the first `n` turns about x, y, z.
fn euler_xyz_rates(n: usize, q: &[f64], u: &[f64], udot: &[f64]) -> [Mat3; 3] {
    (0..n).fold([Mat3::identity(), Mat3::zeros(), Mat3::zeros()], |r, k| product_rates(&r, &turn(&Vec3::ith(k, 1.0), [q[k], u[k], udot[k]])))
}

/// Body-fixed X-Y-Z angles `q[..3]` with u = ω in F: Ṙ = U·R, R̈ = U̇·R + U·Ṙ with U, U̇ the cross-product matrices of u, u̇.
fn angular_velocity_rates(q: &[f64], u: &[f64], udot: &[f64]) -> [Mat3; 3] {
    let rotation = body_fixed_xyz([q[0], q[1], q[2]]);
    let (omega, alpha) = (Vec3::from_column_slice(&u[..3]).cross_matrix(), Vec3::from_column_slice(&udot[..3]).cross_matrix());
    let rate = omega * rotation;
    [rotation, rate, alpha * rotation + omega * rate]
}

/// A `CustomJoint` axis' value v = f(q) with v̇ = f′·u and v̈ = f″·u² + f′·u̇ (constant without a
/// coordinate).
fn axis_rates(axis: &TransformAxis, q: &[f64], u: &[f64], udot: &[f64]) -> [f64; 3] {
    match axis.coordinate {
        Some(c) => {
            let (slope, curvature) = (axis.function.derivative(q[c]), axis.function.second_derivative(q[c]));
            [axis.function.value(q[c]), slope * u[c], curvature * u[c] * u[c] + slope * udot[c]]
        }
        None => [axis.function.value(0.0), 0.0, 0.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::mobilizer::PartialVelocity;
    use approx::assert_relative_eq;

    /// Every mobilizer's velocity equals Σ partial velocity · u, and its acceleration the central
    /// difference of that velocity along the motion (q̇ = u, for rate-speed mobilizers).
    fn check(mobilizer: &Mobilizer, q: &[f64]) {
        let u: Vec<f64> = (0..q.len()).map(|k| 0.7 - 0.3 * k as f64).collect();
        let rates = mobilizer.transform_rates(q, &u, &vec![0.0; q.len()]);
        let mut partials = vec![PartialVelocity { angular: Vec3::zeros(), linear: Vec3::zeros() }; q.len()];
        mobilizer.partial_velocities(q, &mut partials);
        let omega: Vec3 = partials.iter().zip(&u).map(|(p, u)| p.angular * *u).sum();
        let velocity: Vec3 = partials.iter().zip(&u).map(|(p, u)| p.linear * *u).sum();
        assert_relative_eq!(rates.angular_velocity(), omega, epsilon = 1e-14);
        assert_relative_eq!(rates.translation_rate, velocity, epsilon = 1e-14);
        let h = 1e-5;
        let at = |sign: f64| {
            let moved: Vec<f64> = q.iter().zip(&u).map(|(q, u)| q + sign * h * u).collect();
            mobilizer.transform_rates(&moved, &u, &vec![0.0; q.len()])
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        assert_relative_eq!(rates.rotation_acceleration, (plus.rotation_rate - minus.rotation_rate) / (2.0 * h), epsilon = 1e-8);
        assert_relative_eq!(rates.translation_acceleration, (plus.translation_rate - minus.translation_rate) / (2.0 * h), epsilon = 1e-8);
    }

    fn custom() -> Mobilizer {
        use crate::mechanics::function::Function;
        use crate::model::FunctionSpec;
        let spline = FunctionSpec::SimmSpline { x: vec![-2.0, -1.0, 0.0, 1.0, 2.0], y: vec![0.01, -0.02, 0.0, 0.03, 0.01] };
        let axis = |axis: [f64; 3], coordinate: Option<usize>, spec: &FunctionSpec| TransformAxis { axis: Vec3::from(axis).normalize(), coordinate, function: Function::new(spec) };
        let linear = FunctionSpec::LinearFunction { slope: 0.5, intercept: 0.1 };
        let identity = FunctionSpec::LinearFunction { slope: 1.0, intercept: 0.0 };
        let constant = FunctionSpec::Constant { value: 0.2 };
        Mobilizer::Custom(Box::new([
            axis([0.3, 0.9, 0.1], Some(0), &identity),
            axis([1.0, 0.0, 0.0], Some(1), &linear),
            axis([0.0, 0.0, 1.0], None, &constant),
            axis([1.0, 0.0, 0.0], Some(0), &spline),
            axis([0.0, 1.0, 0.0], Some(0), &spline),
            axis([0.0, 0.0, 1.0], None, &constant),
        ]))
    }

    #[test]
    fn rate_speed_mobilizers_move_as_their_partials_say() {
        check(&Mobilizer::Pin, &[0.7]);
        check(&Mobilizer::Slider, &[0.2]);
        check(&Mobilizer::Universal, &[0.4, -1.2]);
        check(&Mobilizer::Gimbal, &[0.4, -1.2, 2.5]);
        check(&Mobilizer::Planar, &[0.9, 0.1, -0.2]);
        check(&custom(), &[0.6, -0.4]);
    }

    #[test]
    fn ball_speeds_are_the_angular_velocity_and_accelerations_its_rate() {
        let (q, u, udot) = ([0.4, -1.2, 2.5], [0.3, -0.8, 1.1], [2.0, 0.5, -1.5]);
        let rates = Mobilizer::Ball.transform_rates(&q, &u, &udot);
        assert_relative_eq!(rates.angular_velocity(), Vec3::from(u), epsilon = 1e-14);
        assert_relative_eq!(rates.angular_acceleration(), Vec3::from(udot), epsilon = 1e-14);
        let free = Mobilizer::Free.transform_rates(&[q, [0.1, 0.2, 0.3]].concat(), &[u, [1.0, 2.0, 3.0]].concat(), &[udot, [4.0, 5.0, 6.0]].concat());
        assert_eq!(free.translation_acceleration, Vec3::new(4.0, 5.0, 6.0));
        assert_relative_eq!(free.angular_acceleration(), Vec3::from(udot), epsilon = 1e-14);
    }
}
