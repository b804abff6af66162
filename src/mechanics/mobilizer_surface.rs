//! Mobilizers that glide on an ellipsoid.
//!
//! Simbody's `Ellipsoid` mobilizer (OpenSim's `EllipsoidJoint`): M turns in F by body-fixed
//! X-Y-Z angles q and its origin sits at p = D·n, D the diagonal of the radii and n = R·ẑ, M's z
//! axis — a point on the surface, though not the one whose normal is n (Simbody's choice). Its
//! speeds are M's angular velocity in F, as a `BallJoint`'s.
//!
//! OpenSim's `ScapulothoracicJoint` chains that mobilizer, turned a quarter turn about F's z
//! (its radii swapped x↔y so that they stay along the parent's axes) and turned back on the
//! scapula side, with a pin about the winging axis:
//! X_FM = Z·E(q₀, q₁, q₂)·Z⁻¹·W·R_z(q₃)·W⁻¹, W the winging axis' frame (its z axis the axis).

use super::mobilizer::PartialVelocity;
use super::motion_rates::{rotation_rates, TransformRates};
use super::spatial::{body_fixed_xyz, rotation_about, Mat3, Transform, Vec3};

/// Simbody's `Ellipsoid` mobilizer with semi-axes `radii` (m) along F's x, y, z.
#[derive(Debug, Clone, PartialEq)]
pub struct Ellipsoid {
    pub radii: Vec3,
}

impl Ellipsoid {
    /// X_FM for the angles `q[..3]` (rad).
    pub fn transform(&self, q: &[f64]) -> Transform {
        let rotation = body_fixed_xyz([q[0], q[1], q[2]]);
        Transform { rotation, translation: self.radii.component_mul(&rotation.column(2).into_owned()) }
    }

    /// Speed k turns M about F's axis k and moves its origin by D·(e_k × n).
    pub fn partial_velocities(&self, q: &[f64], partials: &mut [PartialVelocity]) {
        let normal = body_fixed_xyz([q[0], q[1], q[2]]).column(2).into_owned();
        for (k, partial) in partials.iter_mut().take(3).enumerate() {
            let axis = Vec3::ith(k, 1.0);
            *partial = PartialVelocity { angular: axis, linear: self.radii.component_mul(&axis.cross(&normal)) };
        }
    }

    /// X_FM with its rates for angular velocity u (in F) and its rate u̇: ṗ = D·(ω × n),
    /// p̈ = D·(α × n + ω × ṅ).
    pub fn transform_rates(&self, q: &[f64], u: &[f64], udot: &[f64]) -> TransformRates {
        let rotation = body_fixed_xyz([q[0], q[1], q[2]]);
        let (omega, alpha) = (Vec3::from_column_slice(&u[..3]), Vec3::from_column_slice(&udot[..3]));
        let rate = omega.cross_matrix() * rotation;
        let turned = [rotation, rate, alpha.cross_matrix() * rotation + omega.cross_matrix() * rate];
        let normal = rotation.column(2).into_owned();
        let normal_rate = omega.cross(&normal);
        let normal_acceleration = alpha.cross(&normal) + omega.cross(&normal_rate);
        TransformRates::new(turned, [normal, normal_rate, normal_acceleration].map(|n| self.radii.component_mul(&n)))
    }
}

/// OpenSim's `ScapulothoracicJoint`: abduction, elevation and upward rotation on the thoracic
/// ellipsoid (speeds: angular velocity in the quarter-turned frame), then winging (rad).
#[derive(Debug, Clone, PartialEq)]
pub struct Scapulothoracic {
    ellipsoid: Ellipsoid,
    /// Z: a quarter turn about F's z.
    quarter_turn: Transform,
    /// Z⁻¹·W: from the ellipsoid's moving frame, turned back, to the winging axis' frame W (in
    /// the scapula's frame on the ellipsoid, z along the axis).
    to_winging: Transform,
    /// W⁻¹.
    from_winging: Transform,
}

impl Scapulothoracic {
    /// From the thoracic ellipsoid's radii (m, along F's axes) and the winging axis' origin (m,
    /// x and y on the ellipsoid's scapula frame) and direction (rad from its y axis).
    pub fn new(radii: [f64; 3], winging_origin: [f64; 2], winging_direction: f64) -> Scapulothoracic {
        let (sin, cos) = winging_direction.sin_cos();
        let rotation = Mat3::from_columns(&[Vec3::z(), Vec3::new(cos, sin, 0.0), Vec3::new(-sin, cos, 0.0)]);
        let winging = Transform { rotation, translation: Vec3::new(winging_origin[0], winging_origin[1], 0.0) };
        let quarter_turn = Transform { rotation: rotation_about(&Vec3::z(), std::f64::consts::FRAC_PI_2), translation: Vec3::zeros() };
        Scapulothoracic {
            ellipsoid: Ellipsoid { radii: Vec3::new(radii[1], radii[0], radii[2]) },
            quarter_turn,
            to_winging: quarter_turn.inverse().compose(&winging),
            from_winging: winging.inverse(),
        }
    }

    /// X_FM for `q` = [abduction, elevation, upward rotation, winging] (rad).
    pub fn transform(&self, q: &[f64]) -> Transform {
        let pin = Transform { rotation: rotation_about(&Vec3::z(), q[3]), translation: Vec3::zeros() };
        self.quarter_turn.compose(&self.ellipsoid.transform(q)).compose(&self.to_winging).compose(&pin).compose(&self.from_winging)
    }

    /// The chain's rates: Z·E·(Z⁻¹·W)·R_z(q₃)·W⁻¹ by the product rule (winging speed = q̇₃).
    pub fn transform_rates(&self, q: &[f64], u: &[f64], udot: &[f64]) -> TransformRates {
        let pin = TransformRates::new(rotation_rates(rotation_about(&Vec3::z(), q[3]), &Vec3::z(), u[3], udot[3]), [Vec3::zeros(); 3]);
        TransformRates::fixed(self.quarter_turn)
            .compose(&self.ellipsoid.transform_rates(q, u, udot))
            .then_fixed(&self.to_winging)
            .compose(&pin)
            .then_fixed(&self.from_winging)
    }

    /// The motion of M per unit speed k: the chain's rates at u = e_k.
    pub fn partial_velocities(&self, q: &[f64], partials: &mut [PartialVelocity]) {
        let still = [0.0; 4];
        for (k, partial) in partials.iter_mut().take(4).enumerate() {
            let mut u = [0.0; 4];
            u[k] = 1.0;
            let rates = self.transform_rates(q, &u, &still);
            *partial = PartialVelocity { angular: rates.angular_velocity(), linear: rates.translation_rate };
        }
    }
}
