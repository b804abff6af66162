//! CMC's `MuscleStateTrackingTask`s (opensim-core's `StateTrackingTask`, e.g. EMG-informed CMC):
//! a muscle's state, named `<muscle>.<state>`, pulled towards the column of that name in the task
//! set's `datafile` (a degree-3 GCV spline of time, as `GCVSplineSet(3, …)` builds it). The
//! error e = desired(t + T) − the state at the window's end as the force predictor left it (its
//! last run, under the upper controls — `ActuatorForceTargetFast`'s saved state). It enters the
//! fast target through OpenSim's gradient only: −2·w·e at the first generator whose name the
//! task's name contains, a linear term whose optimum is where that gradient vanishes; the value
//! gains the constant w·e² (the slow target's e², unweighted, and no gradient: its forces do not
//! change).

use std::path::{Path, PathBuf};

use super::CmcError;
use crate::analysis::signal::spline;
use crate::analysis::simulation::{Plant, SimulatedState};
use crate::io::table::StorageTable;
use crate::mechanics::Function;
use crate::setup::{CmcTaskSet, SetupPath};

/// Degree of the splines through the tracked states.
const DEGREE: usize = 3;

/// Which of a muscle's states a task tracks.
#[derive(Debug, Clone, Copy, PartialEq)]
enum MuscleState {
    Activation,
    /// The fiber length (m) or normalized tendon force.
    Second,
}

/// A state task on the plant.
pub struct StateTracking {
    weight: f64,
    /// The muscle ([`Plant::muscles`] index) and its state.
    muscle: usize,
    state: MuscleState,
    /// The generator OpenSim's gradient puts the task's term on.
    generator: Option<usize>,
    desired: Function,
}

/// What the state tasks add to a target at a predicted state.
#[derive(Debug, Clone, Default)]
pub struct StateTerms {
    /// Per generator, the gradient's linear term (1/N or 1/(N·m)).
    pub linear: Vec<f64>,
    /// Σ w·e² (the fast target's constant) and Σ e² (the slow target's).
    pub weighted: f64,
    pub unweighted: f64,
}

impl StateTracking {
    /// desired(`time`) − the tracked state's value in `state`.
    fn error(&self, state: &SimulatedState, time: f64) -> f64 {
        let value = match self.state {
            MuscleState::Activation => state.activations[self.muscle],
            MuscleState::Second => state.seconds[self.muscle].unwrap_or(f64::NAN),
        };
        self.desired.value(time) - value
    }
}

/// The terms of `tasks` at the `predicted` state at `time` (s), for `generators` generators.
pub fn state_terms(tasks: &[StateTracking], generators: usize, predicted: &SimulatedState, time: f64) -> StateTerms {
    let mut terms = StateTerms { linear: vec![0.0; generators], ..StateTerms::default() };
    for task in tasks {
        let error = task.error(predicted, time);
        terms.weighted += task.weight * error * error;
        terms.unweighted += error * error;
        if let Some(j) = task.generator {
            terms.linear[j] -= 2.0 * task.weight * error;
        }
    }
    terms
}

/// The state tasks of `set` (read from `task_file`) on `plant`, their data from the set's
/// `datafile` opened from `directory` (the setup's, as OpenSim runs from there); with the file
/// read. A task whose name is no muscle's state, a datafile that is missing or lacks a task's
/// column are errors naming them.
pub fn state_tracking(set: &CmcTaskSet, task_file: &Path, directory: &Path, plant: &Plant) -> Result<(Vec<StateTracking>, Option<PathBuf>), CmcError> {
    let Some(first) = set.state_tasks.first() else { return Ok((Vec::new(), None)) };
    let input = |what: String| CmcError::Input(format!("{}: {what}", task_file.display()));
    let written = set.datafile.as_deref().ok_or_else(|| input(format!("task {}: a MuscleStateTrackingTask tracks the task set's <datafile>, which is not given", first.name)))?;
    let file = SetupPath::resolve(written, directory).resolved;
    let read = StorageTable::read(&file)?;
    let table = read.with_repeated_times_replaced();
    let times = table.times();
    let tasks = set
        .state_tasks
        .iter()
        .map(|task| {
            let (muscle, state) = muscle_state(plant, &task.name).map_err(|what| input(format!("task {}: {what}", task.name)))?;
            let values = table.column(&task.name).ok_or_else(|| CmcError::Input(format!("{}: no column {:?} for the MuscleStateTrackingTask of that name (columns: {})", file.display(), task.name, table.labels()[1..].join(", "))))?;
            let desired = spline(DEGREE, &times, &values).map_err(|e| CmcError::Input(format!("{}: column {}: {e}", file.display(), task.name)))?;
            let generator = plant.generators.iter().position(|g| task.name.contains(g.name.as_str()));
            Ok(StateTracking { weight: task.weight, muscle, state, generator, desired })
        })
        .collect::<Result<Vec<_>, CmcError>>()?;
    Ok((tasks, Some(file)))
}

/// The muscle and state `name` (`<muscle>.<state>`, split at the first dot as OpenSim splits it)
/// names in `plant`.
fn muscle_state(plant: &Plant, name: &str) -> Result<(usize, MuscleState), String> {
    let (muscle_name, state_name) = name.split_once('.').ok_or("expected the name <muscle>.<state>, e.g. BIClong.activation")?;
    let k = plant.muscles.iter().position(|m| m.name == muscle_name).ok_or_else(|| format!("the model has no muscle {muscle_name:?}"))?;
    let activation = plant.muscles[k].activation.is_some().then_some(("activation", MuscleState::Activation));
    let second = plant.second_state(k).map(|s| (s.label(), MuscleState::Second));
    let states: Vec<(&str, MuscleState)> = activation.into_iter().chain(second).collect();
    states.iter().find(|(label, _)| *label == state_name).map(|&(_, state)| (k, state)).ok_or_else(|| {
        let names: Vec<&str> = states.iter().map(|(label, _)| *label).collect();
        format!("muscle {muscle_name} has no state {state_name:?} (its states: {})", if names.is_empty() { "none".to_string() } else { names.join(", ") })
    })
}
