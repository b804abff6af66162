//! A DeGroote–Fregly muscle at any state, as OpenSim reports it (`calcFiberVelocityInfoHelper`,
//! `calcMuscleDynamicsInfoHelper`): the fiber length from the normalized tendon force state (the
//! tendon at its slack length when rigid), the fiber velocity from the inverse force–velocity
//! curve in explicit mode — fiber damping left out there, as OpenSim — or from the path's speed
//! beside a rigid tendon.

use super::curves::DeGrooteCurves;
use super::muscle::{DeGrooteFregly2016Muscle, TendonDynamics};
use crate::mechanics::muscle::state::PennatedMotion;
use crate::mechanics::muscle::{EquilibriumStatus, FiberEquilibrium, MuscleError, MuscleState};

impl DeGrooteFregly2016Muscle {
    /// The muscle at activation `activation` (not clamped, as OpenSim's) with normalized tendon
    /// force state `normalized_tendon_force` (ignored by a rigid tendon) on a path of length
    /// `mt_length` (m) lengthening at `lengthening_speed` (m/s). A compliant tendon in implicit
    /// mode is an error: its fiber velocity comes from the tendon force's derivative, a Moco
    /// variable no state holds.
    pub fn state(&self, activation: f64, normalized_tendon_force: f64, mt_length: f64, lengthening_speed: f64) -> Result<MuscleState, MuscleError> {
        let rigid = self.ignore_tendon_compliance;
        if !rigid && self.tendon_dynamics == TendonDynamics::Implicit {
            let expected = "explicit tendon_compliance_dynamics_mode (implicit mode's fiber velocity needs the tendon force's derivative)";
            return Err(MuscleError::invalid_input(&self.name, "tendon_compliance_dynamics_mode", f64::NAN, expected));
        }
        let length = self.length_info(mt_length, normalized_tendon_force);
        let (cos, f_max) = (length.cos_pennation_angle, self.max_isometric_force);
        let active_force_length = self.curves.calc_active_force_length_multiplier(length.normalized_fiber_length);
        let passive_force_multiplier = self.curves.calc_passive_force_multiplier(length.normalized_fiber_length);
        let max_speed = self.max_contraction_velocity * self.optimal_fiber_length;
        let (force_velocity, normalized_velocity) = if rigid {
            let normalized = lengthening_speed * cos / max_speed;
            (DeGrooteCurves::calc_force_velocity_multiplier(normalized), normalized)
        } else {
            let multiplier = (normalized_tendon_force / cos - passive_force_multiplier) / (activation * active_force_length);
            (multiplier, DeGrooteCurves::calc_force_velocity_inverse_curve(multiplier))
        };
        let active = f_max * activation * active_force_length * force_velocity;
        let (elastic, damping) = (f_max * passive_force_multiplier, f_max * self.fiber_damping * normalized_velocity);
        let fiber_force = active + elastic + damping;
        let report = FiberEquilibrium {
            activation,
            mt_length,
            fiber_length: length.fiber_length,
            normalized_fiber_length: length.normalized_fiber_length,
            pennation_angle: length.sin_pennation_angle.asin(),
            cos_pennation_angle: cos,
            fiber_length_along_tendon: length.fiber_length_along_tendon,
            tendon_length: length.tendon_length,
            tendon_strain: length.normalized_tendon_length - 1.0,
            tendon_force: if rigid { fiber_force * cos } else { f_max * normalized_tendon_force },
            active_fiber_force: active,
            passive_fiber_force: elastic + damping,
            fiber_force,
            fiber_force_along_tendon: fiber_force * cos,
            active_force_length_multiplier: active_force_length,
            passive_force_multiplier,
            force_velocity_multiplier: force_velocity,
            normalized_fiber_velocity: normalized_velocity,
            status: EquilibriumStatus::Converged,
        };
        let motion = PennatedMotion::new(length.fiber_length, report.pennation_angle, normalized_velocity * max_speed, lengthening_speed);
        Ok(motion.state(report, lengthening_speed, active + damping, elastic))
    }
}
