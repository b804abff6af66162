//! OpenSim's `ForceReporter`, `Actuation` and `StatesReporter` on the states an AnalyzeTool forms:
//! muscles at their [`MuscleStates`], other actuators at the controls of the model's and the
//! setup's controllers (zero without), the external loads as their `ExternalForce`s record
//! them, every coordinate's value and speed.

use super::controllers::Controllers;
use super::external_loads::ExternalLoads;
use super::analyze_tool::AnalyzeToolMotion;
use super::muscle_states::MuscleStates;
use super::static_optimization::Generator;
use super::storage;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::muscle::MuscleState;
use crate::mechanics::{Kinematics, Motion, MotionState, Multibody};
use crate::model::ModelSpec;

/// Why a reporter's table is not formed.
#[derive(Debug, thiserror::Error)]
pub enum ReporterError {
    /// The states, forces or settings it needs are not formed here (why).
    #[error("{0}")]
    NotFormed(String),
    #[error(transparent)]
    Table(#[from] TableError),
}

/// The force generators (the model's muscles and actuators that apply force, ForceSet order, then
/// those of the setup's force-set files) with the external loads, at the AnalyzeTool's rows.
#[derive(Debug, Clone)]
pub struct AppliedAt<'a> {
    pub multibody: &'a Multibody,
    pub generators: &'a [Generator],
    pub external: Option<&'a ExternalLoads>,
    /// The controls applied (summed over the sets; an actuator without one at 0).
    pub controls: &'a Controllers,
    pub muscles: &'a MuscleStates,
    /// The rows: poses, speeds (rad/s or m/s, [`Multibody::coordinates`] order).
    pub states: &'a AnalyzeToolMotion,
    /// Each generator's muscle among `muscles`, `None` for an actuator (found once).
    muscle_of: Vec<Option<usize>>,
}

impl<'a> AppliedAt<'a> {
    pub fn new(multibody: &'a Multibody, generators: &'a [Generator], external: Option<&'a ExternalLoads>, controls: &'a Controllers, muscles: &'a MuscleStates, states: &'a AnalyzeToolMotion) -> AppliedAt<'a> {
        let muscle_of = generators.iter().map(|g| g.muscle_path().and_then(|_| muscles.muscles.iter().position(|(_, m)| *m == g.name))).collect();
        AppliedAt { multibody, generators, external, controls, muscles, states, muscle_of }
    }

    /// The muscle state of generator `g` at `row`; `None` for an actuator or a muscle whose state
    /// was not evaluated.
    pub(super) fn muscle_state(&self, row: usize, g: usize) -> Option<&MuscleState> {
        self.muscle_of[g].and_then(|k| self.muscles.states[row][k].as_ref())
    }

    /// Each generator's force at `row` (N or N·m): a muscle's tendon force at its state (NaN
    /// where it was not evaluated), an actuator's actuation, control × optimal force.
    pub(super) fn forces(&self, row: usize) -> Vec<f64> {
        let time = self.states.motion.times[row];
        self.generators
            .iter()
            .enumerate()
            .map(|(g, generator)| match generator.muscle_path() {
                Some(_) => self.muscle_state(row, g).map_or(f64::NAN, |s| s.report.tendon_force),
                None => self.controls.control(&generator.name, time) * generator.unit_force(false, 0.0, 0.0),
            })
            .collect()
    }

    /// The body poses of `row`.
    fn kinematics(&self, row: usize, kinematics: &mut Kinematics) {
        self.multibody.realize(self.states.motion.pose(row), kinematics);
    }

    /// `time` and then each generator's name.
    fn labels(&self) -> Vec<String> {
        std::iter::once("time".to_string()).chain(self.generators.iter().map(|g| g.name.clone())).collect()
    }
}

/// `ForceReporter`'s `forces` table: each generator's tension or actuation (N or N·m), then the
/// external forces' records (force and torque in ground, point in its body).
pub fn force_reporter_table(at: &AppliedAt) -> Result<StorageTable, TableError> {
    let mut labels = at.labels();
    labels.extend(at.external.map(ExternalLoads::record_labels).unwrap_or_default());
    let mut kinematics = at.multibody.kinematics();
    let values = rows(&at.states.motion.times, |row| {
        let mut values = at.forces(row);
        if let Some(external) = at.external {
            at.kinematics(row, &mut kinematics);
            values.extend(external.record_values(at.states.motion.times[row], &kinematics));
        }
        values
    });
    storage("ModelForces", labels, values)
}

/// One row's actuation of the generators (`getActuation`, `getSpeed`, `getPower`).
pub(super) struct ActuationRow {
    /// As [`AppliedAt::forces`], N or N·m.
    pub forces: Vec<f64>,
    /// A muscle's path lengthening speed or an actuator's `getSpeed` (m/s or rad/s, OpenSim's
    /// quirks kept: [`crate::mechanics::Actuator::speed`]).
    pub speeds: Vec<f64>,
    /// W: −F·v for a muscle (the power it delivers), F·v for an actuator.
    pub powers: Vec<f64>,
}

/// The generators' actuation at `row`.
pub(super) fn actuation_row(at: &AppliedAt, row: usize) -> ActuationRow {
    let zeros = vec![0.0; at.multibody.coordinates.len()];
    let (motion, speeds_of) = (&at.states.motion, &at.states.speeds);
    let motions = at.multibody.body_motions(&MotionState { q: motion.pose(row), u: &speeds_of[row], udot: &zeros });
    let forces = at.forces(row);
    let speeds: Vec<f64> = (at.generators.iter().enumerate())
        .map(|(g, generator)| generator.actuator_speed(&motions, &speeds_of[row]).unwrap_or_else(|| at.muscle_state(row, g).map_or(f64::NAN, |s| s.lengthening_speed)))
        .collect();
    let powers = at.generators.iter().zip(forces.iter().zip(&speeds)).map(|(g, (f, v))| if g.muscle_path().is_some() { -f * v } else { f * v }).collect();
    ActuationRow { forces, speeds, powers }
}

/// `Actuation`'s `force`, `speed` and `power` tables of the generators ([`ActuationRow`]).
pub fn actuation_tables(at: &AppliedAt) -> Result<[StorageTable; 3], TableError> {
    let mut rows_of = [Vec::new(), Vec::new(), Vec::new()];
    for (row, &time) in at.states.motion.times.iter().enumerate() {
        let ActuationRow { forces, speeds, powers } = actuation_row(at, row);
        for (out, values) in rows_of.iter_mut().zip([forces, speeds, powers]) {
            out.push(time);
            out.extend(values);
        }
    }
    let labels = at.labels();
    let [f, v, p] = rows_of;
    Ok([storage("ActuatorForces", labels.clone(), f)?, storage("ActuatorSpeeds", labels.clone(), v)?, storage("ActuatorPowers", labels, p)?])
}

/// `StatesReporter`'s `states` table: every coordinate's `value` and `speed` (rad or m, rad/s or
/// m/s) joint by joint, then every muscle's `activation` and second state (`fiber_length` or
/// `normalized_tendon_force`), labelled by their paths as OpenSim 4 names state variables.
pub fn states_reporter_table(spec: &ModelSpec, multibody: &Multibody, states: &MuscleStates, motion: &Motion, speeds: &[Vec<f64>]) -> Result<StorageTable, TableError> {
    let coordinates = coordinate_state_paths(spec, multibody);
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
        if held.is_some_and(|v| v.second.is_some()) {
            labels.push(format!("/forceset/{name}/{}", states.second_states[k].label()));
        }
    }
    let values = rows(&motion.times, |row| {
        let q = motion.pose(row);
        let mut values: Vec<f64> = coordinates.iter().flat_map(|&(_, i)| [q[i], speeds[row][i]]).collect();
        values.extend(states.variables[row].iter().flat_map(|v| v.activation.into_iter().chain(v.second)));
        values
    });
    storage("ModelStates", labels, values)
}

/// Each coordinate's state path (`/jointset/<joint>/<coordinate>`), joint by joint as OpenSim
/// orders state variables, with its index in [`Multibody::coordinates`].
pub(super) fn coordinate_state_paths(spec: &ModelSpec, multibody: &Multibody) -> Vec<(String, usize)> {
    spec.joints
        .iter()
        .flat_map(|j| j.coordinates.iter().map(move |c| (format!("/jointset/{}/{}", j.name, c.name), c)))
        .filter_map(|(label, c)| multibody.coordinates.iter().position(|m| m.name == c.name).map(|i| (label, i)))
        .collect()
}

/// Time and `row_values(row)` for each of `times`, row after row.
fn rows(times: &[f64], mut row_values: impl FnMut(usize) -> Vec<f64>) -> Vec<f64> {
    times.iter().enumerate().flat_map(|(row, &t)| std::iter::once(t).chain(row_values(row))).collect()
}
