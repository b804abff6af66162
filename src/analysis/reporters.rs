//! OpenSim's `ForceReporter`, `Actuation` and `StatesReporter` on the states an AnalyzeTool forms
//! from a coordinates file: muscles at their [`MuscleStates`], other actuators at zero control
//! (no controls file), every coordinate's value and speed.

use super::muscle_states::MuscleStates;
use super::storage;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Motion, Multibody};
use crate::model::{ActuatorKind, ModelSpec};

/// Why a reporter's table is not formed.
#[derive(Debug, thiserror::Error)]
pub enum ReporterError {
    /// A force it has no value for (the table is left out, with a note).
    #[error("{reporter}'s table, as {force} ({class}) {reason}")]
    NotReported { reporter: &'static str, force: String, class: String, reason: &'static str },
    /// The states or settings it needs are not formed here (why).
    #[error("{0}")]
    NotFormed(String),
    #[error(transparent)]
    Table(#[from] TableError),
}

/// One force a reporter records, by what it reports.
enum Recorded {
    /// Muscle k of the states.
    Muscle(usize),
    /// A scalar actuator at zero control; for a `CoordinateActuator`, its coordinate's index.
    IdleActuator(Option<usize>),
}

/// The forces that apply force, in ForceSet order, each with its record.
fn recorded(spec: &ModelSpec, multibody: &Multibody, states: &MuscleStates, reporter: &'static str) -> Result<Vec<(String, Recorded)>, ReporterError> {
    let mut forces = Vec::new();
    for force in spec.forces.iter().filter(|f| f.applies_force) {
        let not_reported = |reason| ReporterError::NotReported { reporter, force: force.name.clone(), class: force.class.clone(), reason };
        let record = if let Some(k) = states.muscles.iter().position(|(_, name)| *name == force.name) {
            Recorded::Muscle(k)
        } else if let Some(actuator) = spec.actuators.iter().find(|a| a.name == force.name) {
            Recorded::IdleActuator(match &actuator.kind {
                ActuatorKind::Coordinate { coordinate } => multibody.coordinates.iter().position(|c| &c.name == coordinate),
                _ => None,
            })
        } else {
            return Err(not_reported("has no force evaluated here"));
        };
        forces.push((force.name.clone(), record));
    }
    Ok(forces)
}

/// `ForceReporter`'s `forces` table: each force's tension or actuation (N or N·m) at `times`.
pub fn force_reporter_table(spec: &ModelSpec, multibody: &Multibody, states: &MuscleStates, times: &[f64]) -> Result<StorageTable, ReporterError> {
    let forces = recorded(spec, multibody, states, "ForceReporter")?;
    let labels = std::iter::once("time".to_string()).chain(forces.iter().map(|(n, _)| n.clone())).collect();
    let values = rows(times, |row| forces.iter().map(|(_, r)| force(states, row, r)).collect());
    Ok(storage("ModelForces", labels, values)?)
}

/// `Actuation`'s `force`, `speed` and `power` tables of the actuators (muscles and
/// `CoordinateActuator`s; speed m/s or rad/s, power W = −F·v for a muscle, F·v otherwise) at the
/// rows of `motion` with `speeds`.
pub fn actuation_tables(spec: &ModelSpec, multibody: &Multibody, states: &MuscleStates, motion: &Motion, speeds: &[Vec<f64>]) -> Result<[StorageTable; 3], ReporterError> {
    let actuators = recorded(spec, multibody, states, "Actuation")?;
    if let Some((name, _)) = actuators.iter().find(|(_, r)| matches!(r, Recorded::IdleActuator(None))) {
        let actuator = spec.actuators.iter().find(|a| &a.name == name).map_or(String::new(), |a| a.class.clone());
        return Err(ReporterError::NotReported { reporter: "Actuation", force: name.clone(), class: actuator, reason: "has no speed evaluated here" });
    }
    let speed = |row: usize, r: &Recorded| match *r {
        Recorded::Muscle(k) => states.states[row][k].map_or(f64::NAN, |s| s.lengthening_speed),
        Recorded::IdleActuator(c) => c.map_or(f64::NAN, |c| speeds[row][c]),
    };
    let power = |row: usize, r: &Recorded| match r {
        Recorded::Muscle(_) => -force(states, row, r) * speed(row, r),
        Recorded::IdleActuator(_) => force(states, row, r) * speed(row, r),
    };
    let labels: Vec<String> = std::iter::once("time".to_string()).chain(actuators.iter().map(|(n, _)| n.clone())).collect();
    let table = |name: &str, of: &dyn Fn(usize, &Recorded) -> f64| storage(name, labels.clone(), rows(&motion.times, |row| actuators.iter().map(|(_, r)| of(row, r)).collect()));
    let force_of = |row: usize, r: &Recorded| force(states, row, r);
    Ok([table("ActuatorForces", &force_of)?, table("ActuatorSpeeds", &speed)?, table("ActuatorPowers", &power)?])
}

/// `StatesReporter`'s `states` table: every coordinate's `value` and `speed` (rad or m, rad/s or
/// m/s) joint by joint, then every muscle's `activation` and `fiber_length` state, labelled by
/// their paths as OpenSim 4 names state variables.
pub fn states_reporter_table(spec: &ModelSpec, multibody: &Multibody, states: &MuscleStates, motion: &Motion, speeds: &[Vec<f64>]) -> Result<StorageTable, TableError> {
    let coordinates: Vec<(String, usize)> = spec
        .joints
        .iter()
        .flat_map(|j| j.coordinates.iter().map(move |c| (format!("/jointset/{}/{}", j.name, c.name), c)))
        .filter_map(|(label, c)| multibody.coordinates.iter().position(|m| m.name == c.name).map(|i| (label, i)))
        .collect();
    let mut labels = vec!["time".to_string()];
    for (label, _) in &coordinates {
        labels.extend([format!("{label}/value"), format!("{label}/speed")]);
    }
    let first = states.variables.first();
    for (k, (_, name)) in states.muscles.iter().enumerate() {
        let held = first.map(|v| v[k]);
        if held.is_some_and(|v| v.activation.is_some()) {
            labels.push(format!("/forceset/{name}/activation"));
        }
        if held.is_some_and(|v| v.fiber_length.is_some()) {
            labels.push(format!("/forceset/{name}/fiber_length"));
        }
    }
    let values = rows(&motion.times, |row| {
        let q = motion.pose(row);
        let mut values: Vec<f64> = coordinates.iter().flat_map(|&(_, i)| [q[i], speeds[row][i]]).collect();
        values.extend(states.variables[row].iter().flat_map(|v| v.activation.into_iter().chain(v.fiber_length)));
        values
    });
    storage("ModelStates", labels, values)
}

/// The force (N or N·m) `record` reports at `row`.
fn force(states: &MuscleStates, row: usize, record: &Recorded) -> f64 {
    match *record {
        Recorded::Muscle(k) => states.states[row][k].map_or(f64::NAN, |s| s.report.tendon_force),
        Recorded::IdleActuator(_) => 0.0,
    }
}

/// Time and `row_values(row)` for each of `times`, row after row.
fn rows(times: &[f64], row_values: impl Fn(usize) -> Vec<f64>) -> Vec<f64> {
    times.iter().enumerate().flat_map(|(row, &t)| std::iter::once(t).chain(row_values(row))).collect()
}
