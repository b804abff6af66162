//! What a ForwardTool writes: `<name>_states.sto` (every state variable at every recorded time,
//! labelled by its path as OpenSim 4 names state variables — coordinates joint by joint, value
//! then speed, then each muscle's `activation` and second state), its `_states_degrees.mot`
//! twin (rotational coordinates' values and speeds in degrees) and `<name>_controls.sto` (each
//! actuator's control).

use super::plant::{Plant, SimulatedState};
use super::Simulation;
use crate::io::table::{StorageTable, TableError};
use crate::model::CoordinateUnit;

/// The states table (radians) of `simulation` of `plant`; with `in_degrees`, rotational
/// coordinates' values and speeds in degrees.
pub fn states_table(plant: &Plant, simulation: &Simulation, in_degrees: bool) -> Result<StorageTable, TableError> {
    let multibody = &plant.geometry.multibody;
    let labels = state_labels(plant);
    let values = simulation.times.iter().zip(&simulation.states).flat_map(|(time, state)| std::iter::once(*time).chain(state_values(plant, state))).collect();
    let table = StorageTable::new(plant.spec.name.as_str(), labels, values)?.with_in_degrees(false);
    if !in_degrees {
        return Ok(table);
    }
    let rotational: Vec<String> = plant.state_coordinates.iter().filter(|&&(_, c)| multibody.coordinates[c].unit == CoordinateUnit::Radian).map(|(path, _)| path.clone()).collect();
    table.to_degrees(|label| rotational.iter().any(|path| label == format!("{path}/value") || label == format!("{path}/speed")))
}

/// `time` and the state variables' labels of `plant`.
pub fn state_labels(plant: &Plant) -> Vec<String> {
    let mut labels = vec!["time".to_string()];
    for (path, _) in &plant.state_coordinates {
        labels.extend([format!("{path}/value"), format!("{path}/speed")]);
    }
    for (k, muscle) in plant.muscles.iter().enumerate() {
        if muscle.activation.is_some() {
            labels.push(format!("/forceset/{}/activation", muscle.name));
        }
        if let Some(second) = plant.second_state(k) {
            labels.push(format!("/forceset/{}/{}", muscle.name, second.label()));
        }
    }
    labels
}

/// The state variables of `state` in [`state_labels`]' order (without time).
pub fn state_values(plant: &Plant, state: &SimulatedState) -> Vec<f64> {
    let mut values: Vec<f64> = plant.state_coordinates.iter().flat_map(|&(_, c)| [state.q[c], state.u[c]]).collect();
    for (k, muscle) in plant.muscles.iter().enumerate() {
        values.extend(muscle.activation.map(|_| state.activations[k]).into_iter().chain(state.seconds[k]));
    }
    values
}

/// Each generator's control (a muscle's excitation) at every recorded time.
pub fn controls_table(plant: &Plant, simulation: &Simulation) -> Result<StorageTable, TableError> {
    let labels = std::iter::once("time".to_string()).chain(plant.generators.iter().map(|g| g.name.clone())).collect();
    let values = simulation.times.iter().flat_map(|&t| std::iter::once(t).chain(plant.generator_controls(t))).collect();
    Ok(StorageTable::new("Controls", labels, values)?.with_in_degrees(false))
}
