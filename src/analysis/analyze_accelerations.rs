//! The accelerations OpenSim's AnalyzeTool realizes for its analyses' `_dudt` and `_acc` tables:
//! the model's forward dynamics at each row's state — every muscle pulling with its tendon force
//! at its state, every other actuator at zero control (no controller), the external loads,
//! gravity — with locks and couplers holding.

use super::reporters::AppliedAt;
use crate::mechanics::{AppliedForces, MuscleGeometry, PathScratch};

/// u̇ per row of `at` (rad/s² or m/s², [`crate::mechanics::Multibody::coordinates`] order); an
/// error names why none are found (constraints osim-tune's dynamics does not hold, a singular
/// mass matrix).
pub fn analyze_accelerations(geometry: &MuscleGeometry, at: &AppliedAt) -> Result<Vec<Vec<f64>>, String> {
    let multibody = &geometry.multibody;
    let mut kinematics = multibody.kinematics();
    let mut scratch = PathScratch::default();
    let mut accelerations = Vec::with_capacity(at.motion.len());
    for (row, &time) in at.motion.times.iter().enumerate() {
        let (q, u) = (at.motion.pose(row), &at.speeds[row]);
        multibody.realize(q, &mut kinematics);
        let mut applied = AppliedForces { loads: at.external.map(|e| e.at(time, &kinematics)).unwrap_or_default(), mobility: vec![0.0; q.len()] };
        for (generator, force) in at.generators.iter().zip(at.forces(row)) {
            generator.apply(geometry, &kinematics, q, &mut scratch, force, &mut applied);
        }
        let udot = multibody.accelerations(&kinematics, q, u, &applied.loads, &applied.mobility).map_err(|e| format!("at {time} s: {e}"))?;
        accelerations.push(udot);
    }
    Ok(accelerations)
}
