//! Mobilizers: how a joint's coordinates place its child frame M in its parent frame F
//! (X_FM), and the partial velocities of M per unit generalized speed of each coordinate.
//!
//! OpenSim builds every joint on a Simbody mobilizer; the conventions here are Simbody's:
//! `PinJoint` turns about Z, `SliderJoint` slides along X, `UniversalJoint` turns about X then
//! the new Y, `BallJoint`/`GimbalJoint` use body-fixed X-Y-Z angles (OpenSim switches the Ball
//! from quaternions to Euler angles), `FreeJoint` adds a translation in F, `PlanarJoint` turns
//! about Z and translates in F's X-Y plane, and `CustomJoint` is Simbody's `FunctionBased`
//! mobilizer: R = R(θ₁,a₁)·R(θ₂,a₂)·R(θ₃,a₃) and p = Σ sⱼ tⱼ (in F), with θᵢ, sⱼ functions of
//! the coordinates.
//!
//! Generalized speeds are Simbody's mobilities u, the rates OpenSim's `MomentArmSolver` takes
//! generalized forces on. u = q̇ for every mobilizer except the rotations of `BallJoint` and
//! `FreeJoint`, whose u is the angular velocity of M in F expressed in F (Simbody's
//! `RBNodeBall`/`RBNodeFree`: H_FM rows (1,0,0), (0,1,0), (0,0,1)). So a moment arm about a
//! Ball or Free rotational coordinate is the torque about F's X, Y or Z axis per unit tension,
//! not −∂L/∂q (the Gimbal, same angles, has u = q̇ and gives −∂L/∂q). `EllipsoidJoint` and
//! `ScapulothoracicJoint` (`mobilizer_surface`) turn as the Ball does and glide on an ellipsoid.

use super::function::Function;
use super::mobilizer_surface::{Ellipsoid, Scapulothoracic};
use super::spatial::{body_fixed_xyz, rotation_about, Mat3, Transform, Vec3};

/// Motion of M in F per unit generalized speed of one coordinate, both expressed in F: angular
/// velocity (rad per unit speed) and velocity of M's origin (m per unit speed).
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
    /// `BallJoint`: body-fixed X-Y-Z angles, speeds = angular velocity in F.
    Ball,
    /// `GimbalJoint`: body-fixed X-Y-Z angles, speeds = the angles' rates.
    Gimbal,
    /// `FreeJoint`: the Ball's rotation and speeds, then a translation in F.
    Free,
    Planar,
    /// `CustomJoint`: three rotation axes, then three translation axes.
    Custom(Box<[TransformAxis; 6]>),
    /// `EllipsoidJoint`: the Ball's angles and speeds, gliding on an ellipsoid.
    Ellipsoid(Ellipsoid),
    /// `ScapulothoracicJoint`: an ellipsoid glide (Ball-like speeds), then winging.
    Scapulothoracic(Box<Scapulothoracic>),
}

impl Mobilizer {
    /// Number of coordinates the mobilizer takes (`None`: any, for `CustomJoint`).
    pub fn coordinate_count(&self) -> Option<usize> {
        Some(match self {
            Mobilizer::Weld => 0,
            Mobilizer::Pin | Mobilizer::Slider => 1,
            Mobilizer::Universal => 2,
            Mobilizer::Ball | Mobilizer::Gimbal | Mobilizer::Planar | Mobilizer::Ellipsoid(_) => 3,
            Mobilizer::Scapulothoracic(_) => 4,
            Mobilizer::Free => 6,
            Mobilizer::Custom(_) => return None,
        })
    }

    /// How many of the joint's first coordinates have M's angular velocity components as their
    /// speeds rather than their rates (Ball, Free and the ellipsoid glides: 3; others 0).
    pub fn angular_velocity_speeds(&self) -> usize {
        match self {
            Mobilizer::Ball | Mobilizer::Free | Mobilizer::Ellipsoid(_) | Mobilizer::Scapulothoracic(_) => 3,
            _ => 0,
        }
    }

    /// The rates q̇ of the joint's coordinates `q` moving at speeds `u`: q̇ = u but for the
    /// first three of Ball, Free and the ellipsoid glides, body-fixed X-Y-Z angles that turn at
    /// E(q)⁻¹ω for the angular velocity ω in F (Simbody's `convertAngVelInParentToBodyXYZDot`;
    /// NaN at gimbal lock, the middle angle at ±90°).
    pub fn coordinate_rates(&self, q: &[f64], u: &[f64]) -> Vec<f64> {
        let mut rates = u.to_vec();
        if self.angular_velocity_speeds() == 3 {
            let mut partials = [PartialVelocity::ZERO; 3];
            euler_xyz_rates(q, &mut partials);
            let e = Mat3::from_columns(&partials.map(|p| p.angular));
            let rotation = e.lu().solve(&Vec3::new(u[0], u[1], u[2])).unwrap_or_else(|| Vec3::repeat(f64::NAN));
            rates[..3].copy_from_slice(rotation.as_slice());
        }
        rates
    }

    /// Whether OpenSim reads the joint's reaction on its parent at the child frame's origin rather
    /// than the parent frame's: a `ScapulothoracicJoint` is an Ellipsoid and a Pin mobilizer on
    /// massless bodies and a Weld carrying the scapula, and `calcReactionOnParentExpressedInGround`
    /// asks the Weld, whose parent frame sits at the child frame.
    pub fn parent_reaction_at_child_origin(&self) -> bool {
        matches!(self, Mobilizer::Scapulothoracic(_))
    }

    /// X_FM for the joint's coordinate values `q`.
    pub fn transform(&self, q: &[f64]) -> Transform {
        let (rotation, translation) = match self {
            Mobilizer::Weld => return Transform::IDENTITY,
            Mobilizer::Ellipsoid(ellipsoid) => return ellipsoid.transform(q),
            Mobilizer::Scapulothoracic(joint) => return joint.transform(q),
            Mobilizer::Pin => (rotation_about(&Vec3::z(), q[0]), Vec3::zeros()),
            Mobilizer::Slider => (Mat3::identity(), Vec3::new(q[0], 0.0, 0.0)),
            Mobilizer::Universal => (body_fixed_xyz([q[0], q[1], 0.0]), Vec3::zeros()),
            Mobilizer::Ball | Mobilizer::Gimbal => (body_fixed_xyz([q[0], q[1], q[2]]), Vec3::zeros()),
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

    /// Fills `partials[k]` with the partial velocity of M in F per unit generalized speed of
    /// coordinate k of the joint (per unit q̇ except Ball and Free rotations, see the module).
    pub fn partial_velocities(&self, q: &[f64], partials: &mut [PartialVelocity]) {
        partials.fill(PartialVelocity::ZERO);
        match self {
            Mobilizer::Weld => {}
            Mobilizer::Pin => partials[0].angular = Vec3::z(),
            Mobilizer::Slider => partials[0].linear = Vec3::x(),
            Mobilizer::Universal | Mobilizer::Gimbal => euler_xyz_rates(q, partials),
            Mobilizer::Ball => angular_velocity_speeds(partials),
            Mobilizer::Free => {
                angular_velocity_speeds(&mut partials[..3]);
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
            Mobilizer::Ellipsoid(ellipsoid) => ellipsoid.partial_velocities(q, partials),
            Mobilizer::Scapulothoracic(joint) => joint.partial_velocities(q, partials),
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

/// Speeds that are the angular velocity in F: speed k turns about F's axis k, whatever q.
fn angular_velocity_speeds(partials: &mut [PartialVelocity]) {
    for (k, partial) in partials.iter_mut().enumerate() {
        partial.angular = Vec3::ith(k, 1.0);
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

    /// A Ball's angles turning at their rates q̇ turn M at the angular velocity u (in F):
    /// R(q + hq̇)·R(q − hq̇)ᵀ's antisymmetric part is 2h[u]× to O(h³) (an ellipsoid glide's
    /// angles likewise); a Free joint's translations move at u.
    #[test]
    fn ball_and_free_angles_turn_at_the_angular_velocity() {
        let q = [0.3, -0.7, 1.1, 0.2, -0.4, 0.5];
        let u = [2.0, -1.0, 3.0, 0.5, 2.0, -0.3];
        let rates = Mobilizer::Free.coordinate_rates(&q, &u);
        assert_eq!(rates[3..], u[3..]);
        let h = 1e-5;
        let at = |sign: f64| body_fixed_xyz([0, 1, 2].map(|k| q[k] + sign * h * rates[k]));
        let product = at(1.0) * at(-1.0).transpose();
        let turn = (product - product.transpose()) / (4.0 * h);
        let omega = Vec3::new(turn[(2, 1)], turn[(0, 2)], turn[(1, 0)]);
        assert_relative_eq!(omega, Vec3::new(u[0], u[1], u[2]), epsilon = 1e-8);
        assert_eq!(Mobilizer::Ball.coordinate_rates(&q[..3], &u[..3]), rates[..3]);
        assert_eq!(Mobilizer::Pin.coordinate_rates(&[0.4], &[1.5]), [1.5]);
        let glide = Mobilizer::Ellipsoid(Ellipsoid { radii: Vec3::new(0.03, 0.04, 0.05) });
        assert_eq!(glide.coordinate_rates(&q[..3], &u[..3]), rates[..3]);
    }

    /// Central differences of X_FM along q̇ = `qdot(k)` against the analytic partial velocity
    /// of speed k.
    fn check_partials_along(mobilizer: &Mobilizer, q: &[f64], qdot: impl Fn(usize) -> Vec<f64>) {
        let mut partials = vec![PartialVelocity::ZERO; q.len()];
        mobilizer.partial_velocities(q, &mut partials);
        let x = mobilizer.transform(q);
        let h = 1e-6;
        for (k, partial) in partials.iter().enumerate() {
            let rate = qdot(k);
            let plus: Vec<f64> = q.iter().zip(&rate).map(|(q, r)| q + h * r).collect();
            let minus: Vec<f64> = q.iter().zip(&rate).map(|(q, r)| q - h * r).collect();
            let (xp, xm) = (mobilizer.transform(&plus), mobilizer.transform(&minus));
            let rotation_rate = (xp.rotation - xm.rotation) / (2.0 * h);
            let omega = skew_vector(&(rotation_rate * x.rotation.transpose()));
            assert_relative_eq!(omega, partial.angular, epsilon = 1e-8);
            assert_relative_eq!((xp.translation - xm.translation) / (2.0 * h), partial.linear, epsilon = 1e-8);
        }
    }

    /// Mobilizers whose speeds are the coordinates' rates (u = q̇).
    fn check_partials(mobilizer: &Mobilizer, q: &[f64]) {
        check_partials_along(mobilizer, q, |k| (0..q.len()).map(|j| if j == k { 1.0 } else { 0.0 }).collect());
    }

    /// Ball and Free: rotational speed k is ω = e_k in F, i.e. q̇ = G(q)⁻¹ e_k with G the
    /// Gimbal's (Euler-rate) partials; translational speeds are q̇.
    fn check_angular_velocity_partials(mobilizer: &Mobilizer, q: &[f64]) {
        let mut gimbal = [PartialVelocity::ZERO; 3];
        Mobilizer::Gimbal.partial_velocities(&q[..3], &mut gimbal);
        let g_inverse = Mat3::from_columns(&gimbal.map(|p| p.angular)).try_inverse().unwrap();
        check_partials_along(mobilizer, q, |k| {
            let mut rate = vec![0.0; q.len()];
            if k < 3 {
                rate[..3].copy_from_slice((g_inverse * Vec3::ith(k, 1.0)).as_slice());
            } else {
                rate[k] = 1.0;
            }
            rate
        });
    }

    fn skew_vector(m: &Mat3) -> Vec3 {
        Vec3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]) / 2.0
    }

    #[test]
    fn fixed_mobilizers_have_consistent_partials() {
        check_partials(&Mobilizer::Pin, &[0.7]);
        check_partials(&Mobilizer::Slider, &[0.2]);
        check_partials(&Mobilizer::Universal, &[0.4, -1.2]);
        check_partials(&Mobilizer::Gimbal, &[0.4, -1.2, 2.5]);
        check_partials(&Mobilizer::Planar, &[0.9, 0.1, -0.2]);
        check_angular_velocity_partials(&Mobilizer::Ball, &[0.4, -1.2, 2.5]);
        check_angular_velocity_partials(&Mobilizer::Free, &[0.4, -1.2, 2.5, 0.1, 0.2, -0.3]);
    }

    #[test]
    fn ball_places_the_child_as_the_gimbal_but_turns_about_fixed_axes() {
        let q = [0.4, -1.2, 2.5];
        assert_eq!(Mobilizer::Ball.transform(&q), Mobilizer::Gimbal.transform(&q));
        let mut partials = [PartialVelocity::ZERO; 3];
        Mobilizer::Ball.partial_velocities(&q, &mut partials);
        assert_eq!(partials.map(|p| p.angular), [Vec3::x(), Vec3::y(), Vec3::z()]);
    }

    #[test]
    fn pin_turns_about_z() {
        let x = Mobilizer::Pin.transform(&[std::f64::consts::FRAC_PI_2]);
        assert_relative_eq!(x.rotation * Vec3::x(), Vec3::y(), epsilon = 1e-15);
    }
}
