//! Where a ForwardTool simulation starts: the model's default state — the default pose
//! assembled, each coordinate at its `default_speed_value`, each muscle at its
//! `default_activation` and default second state (a fiber length raised to the minimum) — or
//! the row of a states file at the start time or the closest earlier one (OpenSim does not
//! interpolate initial states; a start before the file's first row starts at that row), what
//! it lacks at the defaults; then, when asked, each muscle's second state where
//! `equilibrateMuscles` puts it.

use std::path::Path;

use super::plant::{Plant, SimulatedState};
use super::SimulationError;
use crate::analysis::analyze_states::AnalyzeStates;
use crate::analysis::muscle_states::{default_state, equilibrated};
use crate::io::table::StorageTable;
use crate::model::SecondState;
use crate::solvers::assembled_default_pose;

/// The source of the initial state.
#[derive(Debug, Clone, Copy)]
pub enum InitialSource<'a> {
    Defaults,
    /// A states file (OpenSim's state labels), read from `file`.
    File { table: &'a StorageTable, file: &'a Path },
}

/// The initial state of `plant` from `source` at `start` (s), equilibrated when `equilibrate`,
/// with the time it is at (a states file's row time).
pub fn initial_state(plant: &Plant, source: InitialSource, start: f64, equilibrate: bool) -> Result<(f64, SimulatedState), SimulationError> {
    let multibody = &plant.geometry.multibody;
    let defaults: Vec<(f64, SecondState, f64)> = plant.muscles.iter().map(|m| muscle_defaults(plant, m)).collect();
    let (start, q, u, given) = match source {
        InitialSource::Defaults => {
            let q = assembled_default_pose(multibody).map_err(|e| SimulationError::Initial(format!("the default pose cannot be assembled: {e}")))?;
            (start, q, multibody.coordinates.iter().map(|c| c.default_speed_value).collect(), Vec::new())
        }
        InitialSource::File { table, file } => {
            let labels: Vec<(String, &str)> = plant.muscles.iter().zip(&defaults).map(|(m, d)| (m.name.clone(), d.1.label())).collect();
            let states = AnalyzeStates::from_states(multibody, table, file, &labels).map_err(|e| SimulationError::Initial(e.to_string()))?;
            let row = states.times.iter().rposition(|&t| t <= start).unwrap_or(0);
            let given = states.muscle_states.iter().map(|(_, columns)| columns.each_ref().map(|c| c.as_ref().map(|c| c[row]))).collect();
            (states.times[row], states.q[row].clone(), states.u[row].clone(), given)
        }
    };
    let mut activations = Vec::new();
    let mut seconds = Vec::new();
    for (k, muscle) in plant.muscles.iter().enumerate() {
        let [activation, second]: [Option<f64>; 2] = given.get(k).copied().unwrap_or_default();
        activations.push(match muscle.activation {
            Some(_) => activation.unwrap_or(defaults[k].0),
            None => plant.control(&muscle.name, start),
        });
        seconds.push(Some(second.unwrap_or(defaults[k].2)).filter(|_| !muscle.muscle.has_rigid_tendon()));
    }
    let mut state = SimulatedState { q, u, activations, seconds };
    if equilibrate {
        equilibrate_muscles(plant, &mut state)?;
    }
    Ok((start, state))
}

/// (activation, second state's kind, its value) of `muscle` in the model's default state.
fn muscle_defaults(plant: &Plant, muscle: &crate::analysis::forward::DrivenMuscle) -> (f64, SecondState, f64) {
    let spec = plant.spec.muscles().find(|f| f.name == muscle.name).and_then(|f| f.muscle.as_ref()).expect("a driven muscle has muscle properties");
    default_state(spec, &muscle.muscle)
}

/// Each compliant muscle's second state where OpenSim's `equilibrateMuscles` puts it at
/// `state`'s activation, path length and speed.
fn equilibrate_muscles(plant: &Plant, state: &mut SimulatedState) -> Result<(), SimulationError> {
    let multibody = &plant.geometry.multibody;
    let mut kinematics = multibody.kinematics();
    let mut scratch = crate::mechanics::PathScratch::default();
    multibody.realize(&state.q, &mut kinematics);
    for (k, muscle) in plant.muscles.iter().enumerate() {
        if state.seconds[k].is_none() {
            continue;
        }
        let path = &plant.geometry.paths[muscle.path];
        let (length, speed) = path.length_and_speed(multibody, &kinematics, &state.q, &mut scratch, &path.loaded, &state.u);
        let second = equilibrated(&muscle.muscle, state.activations[k].clamp(0.0, 1.0), length, speed)
            .map_err(|e| SimulationError::Initial(format!("muscle {} cannot be equilibrated: {e}", muscle.name)))?;
        state.seconds[k] = Some(second);
    }
    Ok(())
}
