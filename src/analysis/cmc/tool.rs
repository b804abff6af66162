//! The CMCTool as a whole, and what it shares with the RRATool: the setup's inputs read (model
//! with the force-set actuators, desired kinematics, tasks, control constraints, external
//! loads), the controls' bounds, and the files of a tracked motion formed in memory —
//! `_states.sto`, `_controls.sto`, `_controls.xml`, `_pErr.sto` and the AnalyzeTool's Kinematics
//! and Actuation tables of the tracked states (`addNecessaryAnalyses`) with whatever else the
//! setup's `AnalysisSet` asks.

use std::path::{Path, PathBuf};

use super::state_tasks::state_tracking;
use super::{desired_state, CmcError, Controller, DesiredKinematics, InitialStates, Target, Task, Tracking};
use crate::analysis::analyze_tool::{analyze_tool_tables, AnalyzeModel};
use crate::analysis::controllers::Controllers;
use crate::analysis::simulation::{initial_state, state_labels, state_values, ForwardModel, InitialSource, Plant};
use crate::io::osim::{bounded_control_set_document, ControlLimits};
use crate::io::table::StorageTable;
use crate::setup::{required_input, AnalyzeSetup, CmcSetup, CmcTaskSet, ControlBounds, ControlLinear, ControlSet, KinematicsSetup, ReporterSetup, SetupPath, TrackingSetup};

/// The bound CMC gives a control whose actuator has none (`MAX_CONTROLS_FOR_RRA`).
const MAX_CONTROL: f64 = 10_000.0;
/// The least lower and upper bounds CMC gives a muscle's control (`MIN_CMC_CONTROL_VALUE`,
/// `MAX_CMC_CONTROL_VALUE`).
const MIN_MUSCLE_CONTROL: f64 = 0.02;
const MAX_MUSCLE_CONTROL: f64 = 1.0;

/// What a tracking tool reads: the model with the setup's actuators, the tasks, the control
/// constraints, the desired kinematics and the time range within them.
pub struct TrackingInputs {
    pub model: ForwardModel,
    pub task_set: CmcTaskSet,
    pub task_file: PathBuf,
    pub constraints: Option<ControlSet>,
    pub desired: DesiredKinematics,
    pub desired_file: PathBuf,
    pub range: [f64; 2],
    pub warnings: Vec<String>,
    /// Every file read.
    pub read: Vec<PathBuf>,
}

/// Reads `setup`'s inputs for `model`.
pub fn read_tracking_inputs(model: &Path, setup: &TrackingSetup) -> Result<TrackingInputs, CmcError> {
    let tool = &setup.tool;
    let input = |what: String| CmcError::Input(format!("{}: {what}", tool.file.display()));
    if setup.desired_points_file.is_some() {
        return Err(input("desired_points_file: osim-tune tracks desired kinematics (desired_kinematics_file) only".into()));
    }
    if setup.rra_controls_file.is_some() {
        return Err(input("rra_controls_file: OpenSim does not implement it (its tools stop with \"function not implemented\"); leave it empty".into()));
    }
    let existing = |property: &str, path: Option<&SetupPath>| required_input(&tool.file, property, path).map_err(CmcError::Input);
    let desired_file = existing("desired_kinematics_file", setup.desired_kinematics_file.as_ref())?;
    let task_file = existing("task_set_file", setup.task_set_file.as_ref())?;
    let forward = ForwardModel::read(model, tool).map_err(input)?;
    let mut read = forward.read.clone();
    read.extend([tool.file.clone(), desired_file.clone(), task_file.clone()]);
    let task_set = CmcTaskSet::read(&task_file)?;
    let constraints = match &setup.constraints_file {
        Some(file) => {
            let path = existing("constraints_file", Some(file))?;
            read.push(path.clone());
            Some(ControlSet::read(&path)?)
        }
        None => None,
    };
    let table = StorageTable::read(&desired_file)?;
    let mut warnings = forward.external.as_ref().map(|loads| loads.warnings.clone()).unwrap_or_default();
    let range = time_range(tool, &table, &desired_file, &mut warnings);
    let cutoff = (setup.lowpass_cutoff_frequency >= 0.0).then_some(setup.lowpass_cutoff_frequency);
    let desired = DesiredKinematics::new(&forward.geometry.multibody, &table, &desired_file, cutoff)?;
    Ok(TrackingInputs { model: forward, task_set, task_file, constraints, desired, desired_file, range, warnings, read })
}

/// The active tasks on their coordinates in `model`; a coordinate the model lacks is an error
/// naming the task.
pub fn tasks<'a>(set: &'a CmcTaskSet, model: &ForwardModel, file: &Path) -> Result<Vec<Task<'a>>, CmcError> {
    let coordinates = &model.geometry.multibody.coordinates;
    set.tasks
        .iter()
        .map(|task| {
            let coordinate = coordinates.iter().position(|c| c.name == task.coordinate);
            coordinate.map(|coordinate| Task { task, coordinate }).ok_or_else(|| CmcError::Input(format!("{}: task {}: the model has no coordinate {:?}", file.display(), task.name, task.coordinate)))
        })
        .collect()
}

/// The setup's time range within the desired kinematics' times (OpenSim moves an end that lies
/// outside them, with a warning).
fn time_range(tool: &AnalyzeSetup, table: &StorageTable, file: &Path, warnings: &mut Vec<String>) -> [f64; 2] {
    let times = table.times();
    let (first, last) = (times[0], times[times.len() - 1]);
    let range = [tool.initial_time.max(first), tool.final_time.min(last)];
    if range != [tool.initial_time, tool.final_time] {
        warnings.push(format!("{}: the time range {}–{} s is moved to {}–{} s, within the file's times", file.display(), tool.initial_time, tool.final_time, range[0], range[1]));
    }
    range
}

/// Each generator's control — its bounds and whether it steps between nodes: the constraints
/// file's control of its name (or `<name>.excitation`), which OpenSim puts in CMC's place
/// (`initializeControlSetUsingConstraints`), else its own min/max control — ±10000 where
/// unbounded; a muscle's at least 0.02 and, where under 1, raised to 1, and stepping (CMC's rules,
/// as `CMC::extendAddToSystem` has them).
pub fn control_limits(plant: &Plant, constraints: Option<&ControlSet>) -> Vec<ControlLinear> {
    plant
        .generators
        .iter()
        .map(|g| {
            constraints.and_then(|c| c.find(&g.name)).cloned().unwrap_or_else(|| {
                let [mut min, mut max] = [g.bounds[0].max(-MAX_CONTROL), g.bounds[1].min(MAX_CONTROL)];
                if g.muscle_path().is_some() {
                    (min, max) = (min.max(MIN_MUSCLE_CONTROL), max.max(MAX_MUSCLE_CONTROL));
                }
                let bounds = ControlBounds { default_min: min, default_max: max, ..ControlBounds::default() };
                ControlLinear { name: g.name.clone(), use_steps: g.muscle_path().is_some(), extrapolate: true, nodes: Vec::new(), bounds }
            })
        })
        .collect()
}

/// The files of a tracked motion.
pub struct TrackedFiles {
    /// Each file's name and text.
    pub files: Vec<(String, String)>,
    /// The Actuation's force table.
    pub actuation_force: Option<StorageTable>,
}

/// The files of the tracked motion (name, text) — states, controls (table and `ControlSet` with
/// `limits`' bounds), position errors, the AnalyzeTool's tables on the tracked states; the
/// analyses' warnings join `warnings`.
pub fn tracked_files(tool: &AnalyzeSetup, model: &ForwardModel, plant: &Plant, tracking: &Tracking, limits: &[ControlLinear], warnings: &mut Vec<String>) -> Result<TrackedFiles, CmcError> {
    let name = &tool.name;
    let rows = tracking.times.iter().zip(&tracking.states).flat_map(|(t, s)| std::iter::once(*t).chain(state_values(plant, s))).collect();
    let states = StorageTable::new(plant.spec.name.as_str(), state_labels(plant), rows)?.with_in_degrees(false);
    let states_file = tool.results_directory.resolved.join(format!("{name}_states.sto"));
    let controlled = |j: &usize| !tracking.excluded[*j];
    let styles: Vec<ControlLimits> = (0..limits.len()).filter(controlled).map(|j| ControlLimits { min: limits[j].bounds.default_min, max: limits[j].bounds.default_max, use_steps: tracking.controls.controls[j].use_steps }).collect();
    let mut files = vec![
        (format!("{name}_controls.sto"), controls_table(plant, tracking)?.to_text()),
        (format!("{name}_controls.xml"), bounded_control_set_document(&control_nodes(tracking)?, &plant.spec.name, &styles)),
        (format!("{name}_pErr.sto"), tracking.position_errors.to_text()),
    ];
    let controls = Controllers::from_control_set(tracking.controls.clone()).and(&model.controls);
    let analysed = AnalyzeModel { spec: &model.spec, geometry: &model.geometry, added: &model.added, replace: model.replace, external: model.external.as_ref(), controls: &controls };
    let tables = analyze_tool_tables(&analysed, &states, &states_file, &analyses(tool, &states_file, tracking.times[0]), name)?;
    let actuation_force = tables.files.iter().find(|(file, _)| file.ends_with("_Actuation_force.sto")).map(|(_, table)| table.clone());
    files.extend(tables.files.iter().map(|(file, table)| (file.clone(), table.to_text())));
    files.push((format!("{name}_states.sto"), states.to_text()));
    warnings.extend(tables.warnings.iter().cloned());
    Ok(TrackedFiles { files, actuation_force })
}

/// `_controls.sto`: each generator's control at the recorded times — the model's controls, CMC's
/// plus the other controllers' (an excluded generator's CMC control is 0), as OpenSim writes them.
fn controls_table(plant: &Plant, tracking: &Tracking) -> Result<StorageTable, crate::io::table::TableError> {
    let labels = std::iter::once("time".to_string()).chain(plant.generators.iter().map(|g| g.name.clone())).collect();
    let values = tracking.times.iter().flat_map(|&t| std::iter::once(t).chain(tracking.controls.controls.iter().zip(plant.generator_controls(t)).map(move |(c, other)| c.value(t) + other))).collect();
    Ok(StorageTable::new("controls", labels, values)?.with_in_degrees(false))
}

/// The controlled generators' nodes as a table (time, one column per control) for the
/// `ControlSet` document (CMC's own controls: the excluded generators' are the model's).
fn control_nodes(tracking: &Tracking) -> Result<StorageTable, crate::io::table::TableError> {
    let controls: Vec<&ControlLinear> = tracking.controls.controls.iter().zip(&tracking.excluded).filter(|(_, &excluded)| !excluded).map(|(c, _)| c).collect();
    let labels = std::iter::once("time".to_string()).chain(controls.iter().map(|c| c.name.clone())).collect();
    let values = (0..controls[0].nodes.len()).flat_map(|i| std::iter::once(controls[0].nodes[i].0).chain(controls.iter().map(move |c| c.nodes[i].1))).collect();
    StorageTable::new("controls", labels, values)
}

/// The AnalyzeTool analyses run on the tracked states: the setup's, with a Kinematics (in
/// degrees) and an Actuation added when it has none (`addNecessaryAnalyses`).
fn analyses(tool: &AnalyzeSetup, states_file: &Path, start: f64) -> AnalyzeSetup {
    let mut analyses = tool.clone();
    analyses.states_file = Some(SetupPath { written: states_file.display().to_string(), resolved: states_file.to_path_buf() });
    analyses.initial_time = start;
    let kinematics = analyses.kinematics.get_or_insert_with(|| KinematicsSetup { name: "Kinematics".into(), step_interval: 1, coordinates: vec!["all".into()], in_degrees: true });
    kinematics.in_degrees = true;
    analyses.actuation.get_or_insert_with(|| ReporterSetup { name: "Actuation".into(), step_interval: 1, include_constraint_forces: false });
    analyses
}

/// What a CMC run forms.
pub struct CmcOutputs {
    /// Each file of the results directory: its name and text.
    pub files: Vec<(String, String)>,
    /// The setup's time range within the desired kinematics' times, s, where the tracking
    /// started (0.03 s in with muscles' states) and the number of windows.
    pub range: [f64; 2],
    pub start: f64,
    pub windows: usize,
    pub warnings: Vec<String>,
    /// Every file read.
    pub read: Vec<PathBuf>,
    /// How CMC found the muscles' initial states.
    pub initial: Option<InitialStates>,
}

/// Runs the CMCTool `setup` on `model`.
pub fn run_cmc(model: &Path, setup: &CmcSetup) -> Result<CmcOutputs, CmcError> {
    let tool = &setup.tracking.tool;
    let mut inputs = read_tracking_inputs(model, &setup.tracking)?;
    check_controlled(&inputs.model, tool)?;
    let tasks = tasks(&inputs.task_set, &inputs.model, &inputs.task_file)?;
    let model = &inputs.model;
    let plant = model.plant().map_err(|e| CmcError::Input(format!("{}: {e}", tool.file.display())))?;
    let limits = control_limits(&plant, inputs.constraints.as_ref());
    let excluded = excluded_generators(&plant, &setup.actuators_to_exclude, &mut inputs.warnings);
    if excluded.iter().all(|&x| x) {
        return Err(CmcError::Input(format!("{}: actuators_to_exclude leaves CMC no actuator to control", tool.file.display())));
    }
    let target = if setup.use_fast_optimization_target { Target::Fast } else { Target::Slow };
    let directory = tool.file.parent().unwrap_or(Path::new("."));
    let (state_tasks, datafile) = state_tracking(&inputs.task_set, &inputs.task_file, directory, &plant)?;
    inputs.read.extend(datafile);
    let controller = Controller { plant: &plant, desired: &inputs.desired, tasks: &tasks, state_tasks: &state_tasks, limits: &limits, excluded: &excluded, target, window: setup.time_window };
    let start = start_state(&plant, &inputs.desired, inputs.range[0], tool.solve_for_equilibrium_for_auxiliary_states)?;
    let tracking = controller.track(start, inputs.range, &setup.tracking.integrator)?;
    let tracked = tracked_files(tool, model, &plant, &tracking, &limits, &mut inputs.warnings)?;
    Ok(CmcOutputs { files: tracked.files, range: inputs.range, start: tracking.times[0], windows: tracking.times.len() - 1, warnings: inputs.warnings, read: inputs.read, initial: tracking.initial })
}

/// Per generator, whether `names` (`actuators_to_exclude`) leave it out of CMC's control. As
/// OpenSim 4.6 (`CMCTool::getActuatorsPathsForCMC`) each name is looked up among the actuators'
/// names only — its actuator set has no groups, so a force-set group name excludes nothing —
/// and a name that matches none is reported and ignored.
fn excluded_generators(plant: &Plant, names: &[String], warnings: &mut Vec<String>) -> Vec<bool> {
    for name in names.iter().filter(|name| !plant.generators.iter().any(|g| &g.name == *name)) {
        warnings.push(format!("actuators_to_exclude: no actuator is named {name:?}; ignored (as OpenSim, which also ignores force-set group names here)"));
    }
    plant.generators.iter().map(|g| names.contains(&g.name)).collect()
}

/// The state CMC starts from at `time` (s): the desired kinematics there with the muscles'
/// states of the model's default state, equilibrated at its default pose when asked
/// (`solve_for_equilibrium_for_auxiliary_states`).
fn start_state(plant: &Plant, desired: &DesiredKinematics, time: f64, equilibrate: bool) -> Result<crate::analysis::simulation::SimulatedState, CmcError> {
    let (_, defaults) = initial_state(plant, InitialSource::Defaults, time, equilibrate).map_err(|e| CmcError::Input(e.to_string()))?;
    Ok(desired_state(plant, desired, time, &plant.muscle_states(&defaults)))
}

/// CMC has muscles or actuators to drive.
fn check_controlled(model: &ForwardModel, tool: &AnalyzeSetup) -> Result<(), CmcError> {
    if model.generators.is_empty() {
        return Err(CmcError::Input(format!("{}: no muscles or actuators to track the kinematics with", tool.file.display())));
    }
    Ok(())
}

/// The input errors of the files CMC reads (their messages name the file) and of the
/// AnalyzeTool analyses it runs on the tracked states.
macro_rules! input_error {
    ($($source:ty),*) => {$(
        impl From<$source> for CmcError {
            fn from(error: $source) -> Self {
                CmcError::Input(error.to_string())
            }
        }
    )*};
}
input_error!(crate::setup::SetupError, crate::io::table::TableError, crate::io::osim::OsimError, crate::analysis::AnalyzeToolError);
