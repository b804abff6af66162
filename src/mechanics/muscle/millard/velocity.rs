//! Millard fiber velocity from the force balance at a given fiber length
//! (`calcFiberVelocityInfo`): the damped model solves a f_L f_V(ṽ) + f_PE + β ṽ = f_T / cos α
//! for ṽ by Newton's method; the classic model inverts f_V directly.

use super::muscle::{Millard2012Muscle, Position};
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;
use crate::mechanics::muscle::state::PennatedMotion;
use crate::mechanics::muscle::{check_compliant_tendon, check_inputs, EquilibriumStatus, MuscleError, MuscleState};

/// Newton steps of the damped velocity solve (`calcDampedNormFiberVelocity`).
const MAX_VELOCITY_ITERATIONS: usize = 20;

impl Millard2012Muscle {
    /// Normalised fiber velocity ṽ = dL_m/dt / (v_max L_opt) balancing fiber and tendon at
    /// position `p` (path length `mt_length`), activation `a` (already clamped).
    pub(super) fn norm_fiber_velocity(
        &self,
        a: f64,
        p: &Position,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        if self.fiber_damping > 0.0 {
            return self.damped_norm_fiber_velocity(a, p, mt_length);
        }
        let (fal, fpe, fse, cos_alpha) =
            (p.fiber.active_force_length, p.fiber.fiber_force_length, p.tendon_force_length, p.fiber.cos_alpha);
        let singular = [
            (cos_alpha, "cos of the pennation angle"),
            (a, "activation"),
            (fal, "active force-length multiplier"),
        ];
        if let Some((value, what)) = singular.iter().find(|(v, _)| *v <= SIGNIFICANT_REAL) {
            return Err(MuscleError::invalid_input(
                &self.name,
                what,
                *value,
                "a positive value (the undamped model is singular at 0)",
            ));
        }
        let fv = (fse / cos_alpha - fpe) / (a * fal);
        Ok(self.curves.force_velocity_inverse.value(fv))
    }

    /// `calcDampedNormFiberVelocity`: Newton on F_m(ṽ) cos α − F_t, tolerance 1e-10 F_max.
    fn damped_norm_fiber_velocity(&self, a: f64, p: &Position, mt_length: f64) -> Result<f64, MuscleError> {
        let f = self.max_isometric_force;
        let (fal, fpe, fse, cos_alpha) =
            (p.fiber.active_force_length, p.fiber.fiber_force_length, p.tendon_force_length, p.fiber.cos_alpha);
        let tolerance = (1e-10 * f).max(SIGNIFICANT_REAL * 100.0);
        let fv_undamped = (fse / cos_alpha.max(0.01) - fpe) / (a.max(0.01) * fal.max(0.01));
        let mut v = self.curves.force_velocity_inverse.value(fv_undamped).clamp(-1.0, 1.0);
        let mut error = 1e10;
        for _ in 0..MAX_VELOCITY_ITERATIONS {
            let (fv, d_fv) = self.curves.force_velocity.value_and_derivative(v);
            error = self.fiber_force(a, &p.fiber, fv, v) * cos_alpha - fse * f;
            if error.abs() <= tolerance {
                return Ok(v);
            }
            let d_error = f * (a * fal * d_fv + self.fiber_damping) * cos_alpha;
            if d_error.abs() <= SIGNIFICANT_REAL {
                break;
            }
            v += -error / d_error;
        }
        Err(MuscleError::NotConverged {
            muscle: self.name.clone(),
            activation: a,
            mt_length,
            iterations: MAX_VELOCITY_ITERATIONS,
            residual: error,
        })
    }

    /// dL_m/dt (m/s) of forward simulation at activation `activation`, fiber length
    /// `fiber_length` and path length `mt_length` (path not moving), as OpenSim's
    /// `getFiberVelocity`; 0 while the fiber is held at its minimum length.
    pub fn fiber_velocity(
        &self,
        activation: f64,
        fiber_length: f64,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        check_compliant_tendon(&self.name, self.ignore_tendon_compliance)?;
        Ok(self.state(activation, fiber_length, mt_length, 0.0)?.fiber_velocity)
    }

    /// The muscle at activation `activation` ∈ [0, 1] (clamped) on a path of length
    /// `mt_length` (m) lengthening at `lengthening_speed` (m/s), the fiber at its state
    /// `fiber_length` (m, > 0; a rigid tendon's fiber follows the path instead), as OpenSim
    /// reports it (`calcFiberVelocityInfo`, `calcMuscleDynamicsInfo`): a compliant fiber at the
    /// velocity that balances the tendon, a rigid tendon's at the path's (at rest while the
    /// tendon is slack). A fiber at its minimum length and not lengthening is held: at rest,
    /// no fiber force.
    pub fn state(&self, activation: f64, fiber_length: f64, mt_length: f64, lengthening_speed: f64) -> Result<MuscleState, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        let a = self.clamp_activation(activation);
        let (p, norm_velocity) = if self.ignore_tendon_compliance {
            let (p, norm_velocity, _) = self.rigid_tendon_motion(mt_length, lengthening_speed);
            (p, norm_velocity)
        } else {
            if !(fiber_length > 0.0 && fiber_length.is_finite()) {
                return Err(MuscleError::invalid_input(&self.name, "fiber length", fiber_length, "a positive length in m"));
            }
            let p = self.position(fiber_length.max(self.minimum_fiber_length), mt_length);
            (p, self.norm_fiber_velocity(a, &p, mt_length)?)
        };
        let mut report = self.report(a, mt_length, &p, norm_velocity, self.ignore_tendon_compliance);
        let f = self.max_isometric_force;
        if report.status == EquilibriumStatus::ClampedAtMinimumFiberLength {
            return Ok(PennatedMotion::clamped(lengthening_speed).state(report, lengthening_speed, 0.0, 0.0));
        }
        if self.ignore_tendon_compliance && report.fiber_force < 0.0 {
            // A rigid tendon cannot push: the damping takes up the rest (OpenSim's p2Fm).
            report.passive_fiber_force = -report.active_fiber_force;
            (report.fiber_force, report.fiber_force_along_tendon, report.tendon_force) = (0.0, 0.0, 0.0);
        }
        let elastic = f * p.fiber.fiber_force_length;
        let damping = report.passive_fiber_force - elastic;
        let velocity = report.normalized_fiber_velocity * self.optimal_fiber_length * self.max_contraction_velocity;
        let mut motion = PennatedMotion::new(p.fiber.length, report.pennation_angle, velocity, lengthening_speed);
        if self.ignore_tendon_compliance {
            motion.tendon_velocity = 0.0;
        }
        Ok(motion.state(report, lengthening_speed, report.active_fiber_force + damping, elastic))
    }
}
