//! The dynamics OpenSim's AnalyzeTool realizes for its analyses' `_dudt` and `_acc` tables and
//! a `JointReaction` without a forces file: the model's forward dynamics at each row's state —
//! every muscle pulling with its tendon force at its state, every other actuator at its control,
//! the external loads, gravity — with locks, couplers and links between bodies holding (the
//! links' constraint forces join the loads a joint reaction counts).

use super::reporters::AppliedAt;
use crate::mechanics::{AppliedForces, BodyLoad, MuscleGeometry, PathScratch};

/// One row's forward dynamics.
#[derive(Debug, Clone)]
pub struct RowDynamics {
    /// u̇ (rad/s² or m/s², [`crate::mechanics::Multibody::coordinates`] order).
    pub udot: Vec<f64>,
    /// The body loads applied (external loads, muscles' path forces, point and torque actuators)
    /// and the links' constraint forces.
    pub loads: Vec<BodyLoad>,
}

/// The dynamics of each row of `at`; an error names why none are found (constraints
/// osim-tune's dynamics does not hold, a singular mass matrix).
pub fn analyze_dynamics(geometry: &MuscleGeometry, at: &AppliedAt) -> Result<Vec<RowDynamics>, String> {
    let multibody = &geometry.multibody;
    let mut kinematics = multibody.kinematics();
    let mut scratch = PathScratch::default();
    let (motion, speeds) = (&at.states.motion, &at.states.speeds);
    let mut rows = Vec::with_capacity(motion.len());
    for (row, &time) in motion.times.iter().enumerate() {
        let (q, u) = (motion.pose(row), &speeds[row]);
        multibody.realize(q, &mut kinematics);
        let mut applied = AppliedForces { loads: at.external.map(|e| e.at(time, &kinematics)).unwrap_or_default(), mobility: vec![0.0; q.len()] };
        for (generator, force) in at.generators.iter().zip(at.forces(row)) {
            generator.apply(geometry, &kinematics, q, &mut scratch, force, &mut applied);
        }
        let (udot, constraint_loads) = multibody.constrained_accelerations(&kinematics, q, u, &applied.loads, &applied.mobility).map_err(|e| format!("at {time} s: {e}"))?;
        applied.loads.extend(constraint_loads);
        rows.push(RowDynamics { udot, loads: applied.loads });
    }
    Ok(rows)
}
