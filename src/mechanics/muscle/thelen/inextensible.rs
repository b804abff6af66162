//! The rigid-tendon active fiber force of a `Thelen2003Muscle`
//! (`calcInextensibleTendonActiveFiberForce`, `calcActiveFiberForceAlongTendon`).

use super::Thelen2003Muscle;

/// `calcActiveFiberForceAlongTendon` inverts the force–velocity relation until the velocity
/// error is below this (normalized fiber velocity) …
const FORCE_VELOCITY_TOLERANCE: f64 = 1e-6;
/// … within this many Newton steps.
const FORCE_VELOCITY_MAX_ITERATIONS: usize = 100;

impl Thelen2003Muscle {
    /// OpenSim's `calcInextensibleTendonActiveFiberForce` (N) at activation `activation`, path
    /// length `mt_length` (m) and path lengthening speed `lengthening_speed` (m/s): the tendon at
    /// L_ts, the pennation model's fiber L_m = √(h² + (L_mt − L_ts)²) (its minimum when the path
    /// is shorter; 0 N unless L_m exceeds the minimum), lengthening at
    /// `lengthening_speed` · cos α(L_m) (m/s), into [`Self::active_fiber_force_along_tendon`].
    pub fn inextensible_tendon_active_fiber_force(
        &self,
        activation: f64,
        mt_length: f64,
        lengthening_speed: f64,
    ) -> f64 {
        let pennation = self.pennation();
        let fiber_length = pennation.fiber_length(mt_length, self.tendon_slack_length());
        if fiber_length > pennation.minimum_fiber_length {
            let fiber_velocity = lengthening_speed * pennation.pennation_angle(fiber_length).cos();
            self.active_fiber_force_along_tendon(activation, fiber_length, fiber_velocity)
        } else {
            0.0
        }
    }

    /// OpenSim's `calcActiveFiberForceAlongTendon` (N): F_max a f_L f_V cos α at activation
    /// `activation` clamped to [minimum_activation, 1], fiber length `fiber_length` (m) and fiber
    /// velocity `fiber_velocity` (m/s, lengthening positive), 0 N unless the fiber is longer than
    /// its minimum. f_V is OpenSim's iterative inverse of the velocity relation
    /// ([`super::ThelenCurves::force_velocity_by_newton`], tolerance 1e-6 in normalized
    /// velocity, 100 steps), 0 for shortening faster than (0.25 + 0.75 a) v_max; NaN where that
    /// iteration fails, where OpenSim throws.
    pub fn active_fiber_force_along_tendon(
        &self,
        activation: f64,
        fiber_length: f64,
        fiber_velocity: f64,
    ) -> f64 {
        // Written so that a NaN fiber length gives 0, as OpenSim's `fiberLength > minimum` does.
        let longer_than_minimum = fiber_length > self.minimum_fiber_length();
        if !longer_than_minimum {
            return 0.0;
        }
        let a = self.clamp_activation(activation);
        let optimal_fiber_length = self.optimal_fiber_length();
        let active_force_length = self.curves().active_force_length(fiber_length / optimal_fiber_length);
        let normalized_velocity =
            fiber_velocity / (optimal_fiber_length * self.max_contraction_velocity());
        let Some(force_velocity) = self.curves().force_velocity_by_newton(
            a,
            active_force_length,
            normalized_velocity,
            FORCE_VELOCITY_TOLERANCE,
            FORCE_VELOCITY_MAX_ITERATIONS,
        ) else {
            return f64::NAN;
        };
        let cos_alpha = self.pennation().pennation_angle(fiber_length).cos();
        self.max_isometric_force() * a * active_force_length * force_velocity * cos_alpha
    }
}
