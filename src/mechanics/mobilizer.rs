//! Mobilizers: how a joint's coordinates place its child frame M in its parent frame F
//! (X_FM), and the partial velocities of M per unit rate of each coordinate.
//!
//! OpenSim builds every joint on a Simbody mobilizer; the conventions here are Simbody's:
//! `PinJoint` turns about Z, `SliderJoint` slides along X, `UniversalJoint` turns about X then
//! the new Y, `BallJoint`/`GimbalJoint` use body-fixed X-Y-Z angles, `FreeJoint` adds a
//! translation in F, `PlanarJoint` turns about Z and translates in F's X-Y plane, and
//! `CustomJoint` is Simbody's `FunctionBased` mobilizer: R = R(θ₁,a₁)·R(θ₂,a₂)·R(θ₃,a₃) and
//! p = Σ sⱼ tⱼ (in F), with θᵢ, sⱼ functions of the coordinates.

use super::function::Function;
use super::spatial::{body_fixed_xyz, rotation_about, Mat3, Transform, Vec3};

/// Motion of M in F per unit rate of one coordinate, both expressed in F: angular velocity
/// (rad per unit q) and velocity of M's origin (m per unit q).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartialVelocity {
    pub angular: Vec3,
    pub linear: Vec3,
}

impl PartialVelocity {
    const ZERO: PartialVelocity = PartialVelocity { angular: Vec3::new(0.0, 0.0, 0.0), linear: Vec3::new(0.0, 0.0, 0.0) };
}

/// One axis of a `CustomJoint`'s `SpatialTransform`: angle (rad) or displacement (m) along a
/// unit axis in F, as `function` of one of the joint's coordinates (or constant).
#[derive(Debug, Clone)]
pub struct TransformAxis {
    pub axis: Vec3,
    /// Index into the joint's coordinates; `None` for a constant function.
    pub coordinate: Option<usize>,
    pub function: Function,
}

impl TransformAxis {
    fn value(&self, q: &[f64]) -> f64 {
        self.function.value(self.coordinate.map_or(0.0, |c| q[c]))
    }

    /// (value, d value / d q) with q the axis' coordinate.
    fn value_and_slope(&self, q: &[f64]) -> (f64, f64) {
        match self.coordinate {
            Some(c) => self.function.value_and_derivative(q[c]),
            None => (self.function.value(0.0), 0.0),
        }
    }
}

/// A joint's mobilizer. Coordinate values `q` passed in are the joint's own, in the joint's
/// coordinate order (rad or m).
#[derive(Debug, Clone)]
pub enum Mobilizer {
    Weld,
    Pin,
    Slider,
    Universal,
    /// `BallJoint` and `GimbalJoint`.
    EulerXyz,
    Free,
    Planar,
    /// `CustomJoint`: three rotation axes, then three translation axes.
    Custom(Box<[TransformAxis; 6]>),
}

impl Mobilizer {
    /// Number of coordinates the mobilizer takes (`None`: any, for `CustomJoint`).
    pub fn coordinate_count(&self) -> Option<usize> {
        Some(match self {
            Mobilizer::Weld => 0,
            Mobilizer::Pin | Mobilizer::Slider => 1,
            Mobilizer::Universal => 2,
            Mobilizer::EulerXyz | Mobilizer::Planar => 3,
            Mobilizer::Free => 6,
            Mobilizer::Custom(_) => return None,
        })
    }

    /// X_FM for the joint's coordinate values `q`.
    pub fn transform(&self, q: &[f64]) -> Transform {
        let (rotation, translation) = match self {
            Mobilizer::Weld => return Transform::IDENTITY,
            Mobilizer::Pin => (rotation_about(&Vec3::z(), q[0]), Vec3::zeros()),
            Mobilizer::Slider => (Mat3::identity(), Vec3::new(q[0], 0.0, 0.0)),
            Mobilizer::Universal => (body_fixed_xyz([q[0], q[1], 0.0]), Vec3::zeros()),
            Mobilizer::EulerXyz => (body_fixed_xyz([q[0], q[1], q[2]]), Vec3::zeros()),
            Mobilizer::Free => (body_fixed_xyz([q[0], q[1], q[2]]), Vec3::new(q[3], q[4], q[5])),
            Mobilizer::Planar => (rotation_about(&Vec3::z(), q[0]), Vec3::new(q[1], q[2], 0.0)),
            Mobilizer::Custom(axes) => {
                let rotation = axes[..3].iter().fold(Mat3::identity(), |r, a| r * rotation_about(&a.axis, a.value(q)));
                let translation = axes[3..].iter().fold(Vec3::zeros(), |p, a| p + a.value(q) * a.axis);
                (rotation, translation)
            }
        };
        Transform { rotation, translation }
    }

    /// Fills `partials[k]` with the partial velocity of M in F for coordinate k of the joint.
    pub fn partial_velocities(&self, q: &[f64], partials: &mut [PartialVelocity]) {
        partials.fill(PartialVelocity::ZERO);
        match self {
            Mobilizer::Weld => {}
            Mobilizer::Pin => partials[0].angular = Vec3::z(),
            Mobilizer::Slider => partials[0].linear = Vec3::x(),
            Mobilizer::Universal | Mobilizer::EulerXyz => euler_xyz_rates(q, partials),
            Mobilizer::Free => {
                euler_xyz_rates(q, &mut partials[..3]);
                for (k, partial) in partials[3..6].iter_mut().enumerate() {
                    partial.linear[k] = 1.0;
                }
            }
            Mobilizer::Planar => {
                partials[0].angular = Vec3::z();
                partials[1].linear = Vec3::x();
                partials[2].linear = Vec3::y();
            }
            Mobilizer::Custom(axes) => custom_rates(axes, q, partials),
        }
    }
}

/// Body-fixed X-Y-Z: the k-th angle turns about axis k after the earlier turns.
fn euler_xyz_rates(q: &[f64], partials: &mut [PartialVelocity]) {
    let mut rotation = Mat3::identity();
    for (k, partial) in partials.iter_mut().enumerate() {
        let axis = Vec3::ith(k, 1.0);
        partial.angular = rotation * axis;
        rotation *= rotation_about(&axis, q[k]);
    }
}

/// Rotation i turns about Rᵢ₋₁…R₁ aᵢ; each axis adds its function's slope to its coordinate.
fn custom_rates(axes: &[TransformAxis; 6], q: &[f64], partials: &mut [PartialVelocity]) {
    let mut rotation = Mat3::identity();
    for axis in &axes[..3] {
        let (angle, slope) = axis.value_and_slope(q);
        if let Some(c) = axis.coordinate {
            partials[c].angular += slope * (rotation * axis.axis);
        }
        rotation *= rotation_about(&axis.axis, angle);
    }
    for axis in &axes[3..] {
        if let Some(c) = axis.coordinate {
            partials[c].linear += axis.value_and_slope(q).1 * axis.axis;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Central differences of X_FM against the analytic partial velocities.
    fn check_partials(mobilizer: &Mobilizer, q: &[f64]) {
        let mut partials = vec![PartialVelocity::ZERO; q.len()];
        mobilizer.partial_velocities(q, &mut partials);
        let x = mobilizer.transform(q);
        let h = 1e-6;
        for k in 0..q.len() {
            let (mut plus, mut minus) = (q.to_vec(), q.to_vec());
            plus[k] += h;
            minus[k] -= h;
            let (xp, xm) = (mobilizer.transform(&plus), mobilizer.transform(&minus));
            let rotation_rate = (xp.rotation - xm.rotation) / (2.0 * h);
            let omega = skew_vector(&(rotation_rate * x.rotation.transpose()));
            assert_relative_eq!(omega, partials[k].angular, epsilon = 1e-8);
            assert_relative_eq!((xp.translation - xm.translation) / (2.0 * h), partials[k].linear, epsilon = 1e-8);
        }
    }

    fn skew_vector(m: &Mat3) -> Vec3 {
        Vec3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]) / 2.0
    }

    #[test]
    fn fixed_mobilizers_have_consistent_partials() {
        check_partials(&Mobilizer::Pin, &[0.7]);
        check_partials(&Mobilizer::Slider, &[0.2]);
        check_partials(&Mobilizer::Universal, &[0.4, -1.2]);
        check_partials(&Mobilizer::EulerXyz, &[0.4, -1.2, 2.5]);
        check_partials(&Mobilizer::Free, &[0.4, -1.2, 2.5, 0.1, 0.2, -0.3]);
        check_partials(&Mobilizer::Planar, &[0.9, 0.1, -0.2]);
    }

    #[test]
    fn pin_turns_about_z() {
        let x = Mobilizer::Pin.transform(&[std::f64::consts::FRAC_PI_2]);
        assert_relative_eq!(x.rotation * Vec3::x(), Vec3::y(), epsilon = 1e-15);
    }
}
