//! The RRATool as a whole: its setup's inputs read (model with the force-set actuators, desired
//! kinematics, tasks, control constraints, external loads), the mass-center adjustment, the
//! tracking, and every file RRA writes formed in memory — `_states.sto`, `_controls.sto`,
//! `_controls.xml`, `_pErr.sto`, the AnalyzeTool's Kinematics and Actuation tables of the tracked
//! states (`RRATool::addNecessaryAnalyses`) and whatever else its `AnalysisSet` asks,
//! `_avgResiduals.txt` and the adjusted model (only the adjusted body's `mass_center` edited).

use std::path::{Path, PathBuf};

use super::{average_residuals, mass_adjustment, time_average, track, DesiredKinematics, MassAdjustment, ResidualReductionError, Residuals, Task, Tracking, RESIDUALS};
use crate::analysis::analyze_tool::{analyze_tool_tables, AnalyzeModel};
use crate::analysis::controllers::Controllers;
use crate::analysis::simulation::{state_labels, state_values, ForwardModel, Plant};
use crate::io::osim::{bounded_control_set_document, format_numbers, OsimDocument};
use crate::io::table::StorageTable;
use crate::setup::{required_input, AnalyzeSetup, CmcTaskSet, ControlBounds, ControlLinear, ControlSet, KinematicsSetup, ReporterSetup, RraSetup, SetupPath};

/// The bound CMC gives a control whose actuator has none (`MAX_CONTROLS_FOR_RRA`).
const MAX_CONTROL: f64 = 10_000.0;

/// What an RRA run forms.
pub struct RraOutputs {
    /// Each file of the results directory: its name and text.
    pub files: Vec<(String, String)>,
    /// The adjusted model's path and text (with `adjust_com_to_reduce_residuals`).
    pub adjusted_model: Option<(PathBuf, String)>,
    pub adjustment: Option<Adjusted>,
    /// The Actuation's residuals averaged over the tracked motion.
    pub final_residuals: Residuals,
    /// The setup's time range within the desired kinematics' times, s (tracked to one window
    /// short of its end), and the number of windows.
    pub range: [f64; 2],
    pub windows: usize,
    pub warnings: Vec<String>,
    /// Every file read.
    pub read: Vec<PathBuf>,
}

/// The mass-center adjustment: the adjusted model, the move and the average residuals before and
/// after it.
pub struct Adjusted {
    pub model: ForwardModel,
    pub adjustment: MassAdjustment,
    pub before: Residuals,
    pub after: Residuals,
}

/// Runs the RRATool `setup` on `model`.
pub fn run_rra(model: &Path, setup: &RraSetup) -> Result<RraOutputs, ResidualReductionError> {
    let tool = &setup.tool;
    let input = |what: String| ResidualReductionError::Input(format!("{}: {what}", tool.file.display()));
    if setup.desired_points_file.is_some() {
        return Err(input("desired_points_file: osim-tune's RRA tracks desired kinematics (desired_kinematics_file) only".into()));
    }
    let desired_file = existing(setup, "desired_kinematics_file", setup.desired_kinematics_file.as_ref())?;
    let task_file = existing(setup, "task_set_file", setup.task_set_file.as_ref())?;
    let inputs = ForwardModel::read(model, tool).map_err(input)?;
    check_actuated(&inputs, tool).map_err(input)?;
    let mut read = inputs.read.clone();
    read.extend([tool.file.clone(), desired_file.clone(), task_file.clone()]);
    let task_set = CmcTaskSet::read(&task_file)?;
    let tasks = tasks(&task_set, &inputs, &task_file)?;
    let constraints = match &setup.constraints_file {
        Some(file) => {
            let path = existing(setup, "constraints_file", Some(file))?;
            read.push(path.clone());
            Some(ControlSet::read(&path)?)
        }
        None => None,
    };
    let table = StorageTable::read(&desired_file)?;
    let mut warnings = Vec::new();
    let range = time_range(tool, &table, &desired_file, &mut warnings);
    let cutoff = (setup.lowpass_cutoff_frequency >= 0.0).then_some(setup.lowpass_cutoff_frequency);
    let desired = DesiredKinematics::new(&inputs.geometry.multibody, &table, &desired_file, cutoff)?;
    let adjustment = if setup.adjust_com_to_reduce_residuals { Some(adjust_mass_center(setup, &inputs, &desired, range, &desired_file)?) } else { None };
    let tracked_model = adjustment.as_ref().map_or(&inputs, |a| &a.model);
    let plant = tracked_model.plant().map_err(|e| input(e.to_string()))?;
    let limits = control_limits(&plant, constraints.as_ref());
    let tracking = track(&plant, &desired, &tasks, &limits, range, &setup.integrator)?;
    let (files, final_residuals) = tracked_files(tool, tracked_model, &plant, &tracking, &limits, &mut warnings)?;
    let adjusted_model = adjustment.as_ref().map(|a| adjusted_model_text(model, &a.adjustment).map(|text| (adjusted_model_file(setup), text))).transpose()?;
    Ok(RraOutputs { files, adjusted_model, adjustment, final_residuals, range, windows: tracking.times.len() - 1, warnings, read })
}

/// The files of the tracked motion (name, text) — states, controls (table and `ControlSet` with
/// `limits`' bounds), position errors, the AnalyzeTool's tables on the tracked states, the
/// average residuals — and those residuals; the analyses' warnings join `warnings`.
fn tracked_files(tool: &AnalyzeSetup, model: &ForwardModel, plant: &Plant, tracking: &Tracking, limits: &[ControlLinear], warnings: &mut Vec<String>) -> Result<(Vec<(String, String)>, Residuals), ResidualReductionError> {
    let name = &tool.name;
    let rows = tracking.times.iter().zip(&tracking.states).flat_map(|(t, s)| std::iter::once(*t).chain(state_values(plant, s))).collect();
    let states = StorageTable::new(plant.spec.name.as_str(), state_labels(plant), rows)?.with_in_degrees(false);
    let states_file = tool.results_directory.resolved.join(format!("{name}_states.sto"));
    let bounds: Vec<(f64, f64)> = limits.iter().map(|l| (l.bounds.default_min, l.bounds.default_max)).collect();
    let mut files = vec![
        (format!("{name}_controls.sto"), controls_table(plant, tracking)?.to_text()),
        (format!("{name}_controls.xml"), bounded_control_set_document(&control_nodes(tracking)?, &plant.spec.name, &bounds)),
        (format!("{name}_pErr.sto"), tracking.position_errors.to_text()),
    ];
    let controls = Controllers::from_control_set(tracking.controls.clone());
    let analysed = AnalyzeModel { spec: &model.spec, geometry: &model.geometry, added: &model.added, replace: model.replace, external: model.external.as_ref(), controls: &controls };
    let start = tracking.times[0];
    let tables = analyze_tool_tables(&analysed, &states, &states_file, &analyses(tool, &states_file, start), name)?;
    let residuals = tables.files.iter().find(|(file, _)| file.ends_with("_Actuation_force.sto")).map_or([0.0; 6], |(_, table)| actuation_residuals(table));
    files.extend(tables.files.iter().map(|(file, table)| (file.clone(), table.to_text())));
    files.push((format!("{name}_states.sto"), states.to_text()));
    files.push((format!("{name}_avgResiduals.txt"), average_residuals_text(&residuals)));
    warnings.extend(tables.warnings.iter().cloned());
    Ok((files, residuals))
}

/// The file a setup's `property` names, which must exist.
fn existing(setup: &RraSetup, property: &str, path: Option<&SetupPath>) -> Result<PathBuf, ResidualReductionError> {
    required_input(&setup.tool.file, property, path).map_err(ResidualReductionError::Input)
}

/// The active tasks on their coordinates; a coordinate the model lacks is an error naming the
/// task.
fn tasks<'a>(set: &'a CmcTaskSet, inputs: &ForwardModel, file: &Path) -> Result<Vec<Task<'a>>, ResidualReductionError> {
    let coordinates = &inputs.geometry.multibody.coordinates;
    set.tasks
        .iter()
        .map(|task| {
            let coordinate = coordinates.iter().position(|c| c.name == task.coordinate);
            coordinate.map(|coordinate| Task { task, coordinate }).ok_or_else(|| ResidualReductionError::Input(format!("{}: task {}: the model has no coordinate {:?}", file.display(), task.name, task.coordinate)))
        })
        .collect()
}

/// RRA drives ideal actuators only, by its own controller.
fn check_actuated(inputs: &ForwardModel, tool: &AnalyzeSetup) -> Result<(), String> {
    if let Some(muscle) = inputs.generators.iter().find(|g| g.muscle_path().is_some()) {
        return Err(format!("muscle {} acts: osim-tune's RRA drives ideal actuators only (replace the model's forces by the setup's force_set_files, replace_force_set true)", muscle.name));
    }
    if !inputs.spec.controllers.is_empty() || !tool.controllers.is_empty() {
        return Err("controllers besides RRA's own are not supported (the model's or the setup's ControllerSet)".into());
    }
    if inputs.generators.is_empty() {
        return Err("no actuators to track the kinematics with (force_set_files)".into());
    }
    Ok(())
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

/// RRA's first pass: the average residuals over the adjustment's time range, the mass-center
/// move, the adjusted model and its average residuals.
fn adjust_mass_center(setup: &RraSetup, inputs: &ForwardModel, desired: &DesiredKinematics, range: [f64; 2], file: &Path) -> Result<Adjusted, ResidualReductionError> {
    let body = setup.adjusted_com_body.as_deref().ok_or_else(|| ResidualReductionError::Input(format!("{}: adjust_com_to_reduce_residuals is true but adjusted_com_body is not set", setup.tool.file.display())))?;
    let range = setup.com_adjustment_time_range.unwrap_or(range);
    let averages = |model: &ForwardModel| average_residuals(&model.geometry, &model.generators, model.external.as_ref(), &mut desired.states.clone(), range, file);
    let before = averages(inputs)?;
    let adjustment = mass_adjustment(&inputs.spec, body, inputs.spec.gravity, &before)?;
    let model = inputs.with_mass_center(body, adjustment.mass_center[1]).map_err(ResidualReductionError::Input)?;
    let after = averages(&model)?;
    Ok(Adjusted { model, adjustment, before, after })
}

/// Each generator's control bounds: the constraints file's control of its name (or
/// `<name>.excitation`), else its actuator's min/max control (±10000 where unbounded).
fn control_limits(plant: &Plant, constraints: Option<&ControlSet>) -> Vec<ControlLinear> {
    plant
        .generators
        .iter()
        .map(|g| {
            constraints.and_then(|c| c.find(&g.name)).cloned().unwrap_or_else(|| {
                let bounds = ControlBounds { default_min: g.bounds[0].max(-MAX_CONTROL), default_max: g.bounds[1].min(MAX_CONTROL), ..ControlBounds::default() };
                ControlLinear { name: g.name.clone(), use_steps: false, extrapolate: true, nodes: Vec::new(), bounds }
            })
        })
        .collect()
}

/// `_controls.sto`: each actuator's control at the recorded times.
fn controls_table(plant: &Plant, tracking: &Tracking) -> Result<StorageTable, crate::io::table::TableError> {
    let labels = std::iter::once("time".to_string()).chain(plant.generators.iter().map(|g| g.name.clone())).collect();
    let values = tracking.times.iter().flat_map(|&t| std::iter::once(t).chain(tracking.controls.controls.iter().map(move |c| c.value(t)))).collect();
    Ok(StorageTable::new("controls", labels, values)?.with_in_degrees(false))
}

/// The controls' nodes as a table (time, one column per control) for the `ControlSet` document.
fn control_nodes(tracking: &Tracking) -> Result<StorageTable, crate::io::table::TableError> {
    let controls = &tracking.controls.controls;
    let labels = std::iter::once("time".to_string()).chain(controls.iter().map(|c| c.name.clone())).collect();
    let values = (0..controls[0].nodes.len()).flat_map(|i| std::iter::once(controls[0].nodes[i].0).chain(controls.iter().map(move |c| c.nodes[i].1))).collect();
    StorageTable::new("controls", labels, values)
}

/// The AnalyzeTool analyses run on the tracked states: the setup's, with a Kinematics (in
/// degrees) and an Actuation added when it has none (`RRATool::addNecessaryAnalyses`).
fn analyses(tool: &AnalyzeSetup, states_file: &Path, start: f64) -> AnalyzeSetup {
    let mut analyses = tool.clone();
    analyses.states_file = Some(SetupPath { written: states_file.display().to_string(), resolved: states_file.to_path_buf() });
    analyses.initial_time = start;
    let kinematics = analyses.kinematics.get_or_insert_with(|| KinematicsSetup { name: "Kinematics".into(), step_interval: 1, coordinates: vec!["all".into()], in_degrees: true });
    kinematics.in_degrees = true;
    analyses.actuation.get_or_insert_with(|| ReporterSetup { name: "Actuation".into(), step_interval: 1, include_constraint_forces: false });
    analyses
}

/// The time averages of the residual actuators' columns of an Actuation force table.
fn actuation_residuals(table: &StorageTable) -> Residuals {
    let columns = RESIDUALS.map(|name| table.column_index(name));
    let samples: Vec<(f64, Residuals)> = table.rows().map(|row| (row[0], columns.map(|c| c.map_or(0.0, |c| row[c])))).collect();
    time_average(&samples)
}

/// `<name>_avgResiduals.txt` as OpenSim writes it.
fn average_residuals_text(residuals: &Residuals) -> String {
    let mut text = String::from("Average Residuals:\n\n");
    for (name, value) in RESIDUALS.iter().zip(residuals) {
        text.push_str(&format!("{name} average = {value}\n"));
    }
    text
}

/// The setup's `output_model_file`, else `adjusted_model.osim` beside the setup (OpenSim's).
fn adjusted_model_file(setup: &RraSetup) -> PathBuf {
    setup.output_model_file.as_ref().map_or_else(|| setup.tool.file.parent().unwrap_or(Path::new(".")).join("adjusted_model.osim"), |f| f.resolved.clone())
}

/// `model`'s text with only the adjusted body's `mass_center` changed.
fn adjusted_model_text(model: &Path, adjustment: &MassAdjustment) -> Result<String, ResidualReductionError> {
    let mut document = OsimDocument::read(model)?;
    document.set_property(&format!("/bodyset/{}/mass_center", adjustment.body), &format_numbers(&adjustment.mass_center[1]))?;
    String::from_utf8(document.xml.serialize()).map_err(|e| ResidualReductionError::Input(format!("{}: the model is not UTF-8 text: {e}", model.display())))
}
