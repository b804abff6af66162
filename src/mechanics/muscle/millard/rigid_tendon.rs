//! A Millard muscle with a rigid tendon (`ignore_tendon_compliance`) in motion, as OpenSim's
//! `calcMuscleLengthInfo`, `calcFiberVelocityInfo` and `calcMuscleDynamicsInfo` have it: the
//! fiber fills the path beside the tendon at its slack length, moves with the path
//! (dL_m/dt = dL_mt/dt · cos α), and its force along the tendon is the tendon force.

use super::muscle::{Millard2012Muscle, Position};
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;

impl Millard2012Muscle {
    /// L_m (m) beside a rigid tendon on a path of length `mt_length` (m), at least the minimum
    /// fiber length.
    pub fn rigid_tendon_fiber_length(&self, mt_length: f64) -> f64 {
        self.pennation.fiber_length(mt_length, self.tendon_slack_length).max(self.minimum_fiber_length)
    }

    /// F_t (N) at activation `activation` (clamped to [a_min, 1]) on a path of length
    /// `mt_length` (m) lengthening at `lengthening_speed` (m/s): F_max (a f_L f_V + f_PE + β ṽ)
    /// cos α, never compressive; 0 while the fiber is held at its minimum length and not
    /// lengthening; f_V = 1 at rest when the path is too short for the tendon (it buckles).
    pub fn rigid_tendon_force(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> f64 {
        let (p, norm_velocity, buckled) = self.rigid_tendon_motion(mt_length, lengthening_speed);
        if p.fiber.length <= self.minimum_fiber_length && norm_velocity <= 0.0 {
            return 0.0;
        }
        let fv = if buckled { 1.0 } else { self.curves.force_velocity.value(norm_velocity) };
        self.fiber_force(self.clamp_activation(activation), &p.fiber, fv, norm_velocity).max(0.0) * p.fiber.cos_alpha
    }

    /// The position beside a rigid tendon on a path of length `mt_length` (m), the fiber's
    /// normalized velocity dL_mt/dt cos α / (v_max L_opt) with the path lengthening at
    /// `lengthening_speed` (m/s) — 0 while the path is too short for the tendon, which then
    /// buckles (the third value).
    pub(super) fn rigid_tendon_motion(&self, mt_length: f64, lengthening_speed: f64) -> (Position, f64, bool) {
        let p = self.position(self.rigid_tendon_fiber_length(mt_length), mt_length);
        let buckled = p.tendon_length < self.tendon_slack_length - SIGNIFICANT_REAL;
        let velocity = if buckled { 0.0 } else { lengthening_speed * p.fiber.cos_alpha };
        (p, velocity / (self.optimal_fiber_length * self.max_contraction_velocity), buckled)
    }
}
