//! A muscle at a given state — activation, fiber length, path length and lengthening speed —
//! with the velocities and powers OpenSim's Muscle API reports for it (`calcFiberVelocityInfo`,
//! `calcMuscleDynamicsInfo`, `getMusclePower`), as `MuscleAnalysis` and `Actuation` record them.

use serde::Serialize;

use super::FiberEquilibrium;

/// One muscle state and what OpenSim reports for it (SI units, lengthening positive).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MuscleState {
    /// Lengths, forces and multipliers at the state (fiber length raised to its minimum);
    /// `status` tells whether the fiber is held at its minimum length (`isFiberStateClamped`).
    pub report: FiberEquilibrium,
    /// dL_mt/dt, m/s.
    pub lengthening_speed: f64,
    /// dL_m/dt, m/s (0 while clamped).
    pub fiber_velocity: f64,
    /// dα/dt, rad/s.
    pub pennation_angular_velocity: f64,
    /// dL_t/dt, m/s (the path's speed while clamped).
    pub tendon_velocity: f64,
    /// W: −(F_active + F_damping) · dL_m/dt (`getFiberActivePower`).
    pub fiber_active_power: f64,
    /// W: −F_elastic · dL_m/dt, the passive fiber's conservative force (`getFiberPassivePower`).
    pub fiber_passive_power: f64,
    /// W: −F_t · dL_t/dt (`getTendonPower`).
    pub tendon_power: f64,
}

impl MuscleState {
    /// −F_t · dL_mt/dt, W (`getMusclePower`, MuscleAnalysis' `MuscleActuatorPower`).
    pub fn muscle_power(&self) -> f64 {
        -self.lengthening_speed * self.report.tendon_force
    }
}

/// The fiber's motion in a fixed-width pennation (`MuscleFixedWidthPennationModel`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PennatedMotion {
    pub fiber_velocity: f64,
    pub pennation_angular_velocity: f64,
    pub tendon_velocity: f64,
}

impl PennatedMotion {
    /// The fiber moving at `fiber_velocity` (m/s) at length `fiber_length` (m) and pennation
    /// angle `pennation_angle` (rad; 0 stays 0) on a path lengthening at `lengthening_speed`:
    /// dα/dt = −(dL_m/dt / L_m) tan α, dL_t/dt = dL_mt/dt − dL_m/dt cos α + L_m sin α dα/dt.
    pub fn new(fiber_length: f64, pennation_angle: f64, fiber_velocity: f64, lengthening_speed: f64) -> PennatedMotion {
        let pennation_angular_velocity = if pennation_angle > 0.0 { -(fiber_velocity / fiber_length) * pennation_angle.tan() } else { 0.0 };
        let (sin, cos) = pennation_angle.sin_cos();
        let tendon_velocity = lengthening_speed - fiber_velocity * cos + fiber_length * sin * pennation_angular_velocity;
        PennatedMotion { fiber_velocity, pennation_angular_velocity, tendon_velocity }
    }

    /// A fiber held at its minimum length: at rest, the tendon following the path.
    pub fn clamped(lengthening_speed: f64) -> PennatedMotion {
        PennatedMotion { fiber_velocity: 0.0, pennation_angular_velocity: 0.0, tendon_velocity: lengthening_speed }
    }

    /// The state of `report` moving so, with the powers of its active (`active_force`,
    /// damping included) and elastic (`elastic_force`) fiber forces and its tendon, N.
    pub fn state(self, report: FiberEquilibrium, lengthening_speed: f64, active_force: f64, elastic_force: f64) -> MuscleState {
        MuscleState {
            report,
            lengthening_speed,
            fiber_velocity: self.fiber_velocity,
            pennation_angular_velocity: self.pennation_angular_velocity,
            tendon_velocity: self.tendon_velocity,
            fiber_active_power: -active_force * self.fiber_velocity,
            fiber_passive_power: -elastic_force * self.fiber_velocity,
            tendon_power: -report.tendon_force * self.tendon_velocity,
        }
    }
}
