//! The accelerations OpenSim's AnalyzeTool realizes for its analyses' `_dudt` and `_acc` tables:
//! the model's forward dynamics at each row's state — every muscle pulling with its tendon force
//! at its [`MuscleStates`] state, every other actuator at zero control (no controls file),
//! gravity — with locks and couplers holding.

use super::analyze_tool::AnalyzeToolMotion;
use super::muscle_states::MuscleStates;
use super::static_optimization::generators;
use crate::mechanics::{AppliedForces, MuscleGeometry, PathScratch};
use crate::model::ModelSpec;

/// u̇ per row (rad/s² or m/s², [`crate::mechanics::Multibody::coordinates`] order); an error
/// names why they are not OpenSim's (a force osim-tune cannot apply, constraints its dynamics
/// does not hold, a singular mass matrix).
pub fn analyze_accelerations(spec: &ModelSpec, geometry: &MuscleGeometry, states: &AnalyzeToolMotion, muscles: &MuscleStates) -> Result<Vec<Vec<f64>>, String> {
    let generators = generators(spec, geometry, &[], false).map_err(|e| e.to_string())?;
    let multibody = &geometry.multibody;
    let mut kinematics = multibody.kinematics();
    let mut scratch = PathScratch::default();
    let mut accelerations = Vec::with_capacity(states.motion.len());
    for (row, &time) in states.motion.times.iter().enumerate() {
        let (q, u) = (states.motion.pose(row), &states.speeds[row]);
        multibody.realize(q, &mut kinematics);
        let mut applied = AppliedForces::new(q.len());
        for generator in &generators {
            let muscle = muscles.muscles.iter().position(|(_, name)| *name == generator.name);
            let force = muscle.map_or(0.0, |k| muscles.states[row][k].map_or(f64::NAN, |s| s.report.tendon_force));
            generator.apply(geometry, &kinematics, q, &mut scratch, force, &mut applied);
        }
        let udot = multibody.accelerations(&kinematics, q, u, &applied.loads, &applied.mobility).map_err(|e| format!("at {time} s: {e}"))?;
        accelerations.push(udot);
    }
    Ok(accelerations)
}
