//! OpenSim 4.6's `equilibrateMuscles` for a Millard muscle, step by step: the static branch of
//! `estimateMuscleFiberState` (Newton with step halving from a tendon at 1.01 L_ts, tolerance
//! max(1e-8 F_max, 10·SignificantReal), 200 iterations), then the fiber velocity the state
//! implies. The result carries OpenSim's own residual (|F_m cos α − F_t| up to 1e-8 F_max and a
//! small fiber velocity), so it reproduces OpenSim's reported numbers, not the exact balance.

use super::muscle::{Millard2012Muscle, Position};
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;
use crate::mechanics::muscle::root::sign;
use crate::mechanics::muscle::{check_inputs, FiberEquilibrium, MuscleError};

const MAX_ITERATIONS: usize = 200;

impl Millard2012Muscle {
    /// The muscle state OpenSim reports after `equilibrateMuscles` at activation `activation`
    /// and path length `mt_length` with the path at rest.
    pub fn opensim_equilibrium(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<FiberEquilibrium, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        let a = self.clamp_activation(activation);
        if self.ignore_tendon_compliance {
            let fiber_length = self
                .pennation
                .fiber_length(mt_length, self.tendon_slack_length)
                .max(self.minimum_fiber_length);
            return Ok(self.report(a, mt_length, &self.position(fiber_length, mt_length), 0.0, true));
        }
        let p = self.estimate_fiber_state(a, mt_length)?;
        let velocity = self.norm_fiber_velocity(a, &p, mt_length)?;
        Ok(self.report(a, mt_length, &p, velocity, false))
    }

    /// `estimateMuscleFiberState` with `staticSolution`: the position at the fiber length the
    /// iteration ends at (never below the minimum fiber length).
    fn estimate_fiber_state(&self, a: f64, mt_length: f64) -> Result<Position, MuscleError> {
        let f = self.max_isometric_force;
        let tolerance = (1e-8 * f).max(SIGNIFICANT_REAL * 10.0);
        let start = self
            .pennation
            .fiber_length(mt_length, self.tendon_slack_length * 1.01);
        let mut lce = start.max(self.minimum_fiber_length);
        let error_at = |lce: f64| {
            let p = self.position(lce, mt_length);
            let fiber_force = self.fiber_force(a, &p.fiber, 1.0, 0.0);
            (
                fiber_force * p.fiber.cos_alpha - p.tendon_force_length * f,
                p,
                fiber_force,
            )
        };
        let (mut error, mut p, mut fiber_force) = error_at(lce);
        let (mut error_prev, mut lce_prev) = (error, lce);
        let mut iterations = 0;
        while error.abs() > tolerance && iterations < MAX_ITERATIONS {
            let slope = self.d_residual(a, &p, fiber_force);
            let mut h = 1.0;
            while error.abs() >= error_prev.abs() {
                let delta = -h * error_prev / slope;
                if delta.abs() > SIGNIFICANT_REAL {
                    lce = lce_prev + delta;
                } else {
                    lce = lce_prev - sign(delta) * f64::EPSILON.sqrt();
                    h = 0.0;
                }
                lce = lce.max(self.minimum_fiber_length);
                (error, p, fiber_force) = error_at(lce);
                if h <= f64::EPSILON.sqrt() {
                    break;
                }
                h *= 0.5;
            }
            (error_prev, lce_prev) = (error, lce);
            iterations += 1;
        }
        if error.abs() < tolerance || lce <= self.minimum_fiber_length {
            return Ok(p);
        }
        Err(MuscleError::NotConverged {
            muscle: self.name.clone(),
            activation: a,
            mt_length,
            iterations,
            residual: error,
        })
    }
}
