//! The RRATool as a whole: its setup's inputs read (model with the force-set actuators, desired
//! kinematics, tasks, control constraints, external loads), the mass-center adjustment, the
//! tracking, and every file RRA writes formed in memory — `_states.sto`, `_controls.sto`,
//! `_controls.xml`, `_pErr.sto`, the AnalyzeTool's Kinematics and Actuation tables of the tracked
//! states (`RRATool::addNecessaryAnalyses`) and whatever else its `AnalysisSet` asks,
//! `_avgResiduals.txt` and the adjusted model (only the adjusted body's `mass_center` edited).

use std::path::{Path, PathBuf};

use super::{average_residuals, mass_adjustment, time_average, MassAdjustment, ResidualReductionError, Residuals, RESIDUALS};
use crate::analysis::cmc::{control_limits, desired_state, read_tracking_inputs, tasks, tracked_files, Controller, DesiredKinematics, Target};
use crate::analysis::simulation::ForwardModel;
use crate::io::osim::{format_numbers, OsimDocument};
use crate::io::table::StorageTable;
use crate::setup::{AnalyzeSetup, RraSetup};

/// RRA's window (s).
const WINDOW: f64 = 0.001;

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
    let tool = &setup.tracking.tool;
    let input = |what: String| ResidualReductionError::Input(format!("{}: {what}", tool.file.display()));
    let mut inputs = read_tracking_inputs(model, &setup.tracking)?;
    check_actuated(&inputs.model, tool).map_err(input)?;
    let tasks = tasks(&inputs.task_set, &inputs.model, &inputs.task_file)?;
    if let Some(task) = inputs.task_set.state_tasks.first() {
        return Err(input(format!("{}: MuscleStateTrackingTask {}: RRA drives no muscles", inputs.task_file.display(), task.name)));
    }
    let range = inputs.range;
    let adjustment = if setup.adjust_com_to_reduce_residuals { Some(adjust_mass_center(setup, &inputs.model, &inputs.desired, range, &inputs.desired_file)?) } else { None };
    let tracked_model = adjustment.as_ref().map_or(&inputs.model, |a| &a.model);
    let plant = tracked_model.plant().map_err(|e| input(e.to_string()))?;
    let limits = control_limits(&plant, inputs.constraints.as_ref());
    let excluded = vec![false; plant.generators.len()];
    let controller = Controller { plant: &plant, desired: &inputs.desired, tasks: &tasks, state_tasks: &[], limits: &limits, excluded: &excluded, target: Target::Slow, window: WINDOW };
    let tracking = controller.track(desired_state(&plant, &inputs.desired, range[0], &[]), range, &setup.tracking.integrator)?;
    let tracked = tracked_files(tool, tracked_model, &plant, &tracking, &limits, &mut inputs.warnings)?;
    let final_residuals = tracked.actuation_force.as_ref().map_or([0.0; 6], actuation_residuals);
    let mut files = tracked.files;
    files.push((format!("{}_avgResiduals.txt", tool.name), average_residuals_text(&final_residuals)));
    let adjusted_model = adjustment.as_ref().map(|a| adjusted_model_text(model, &a.adjustment).map(|text| (adjusted_model_file(setup), text))).transpose()?;
    Ok(RraOutputs { files, adjusted_model, adjustment, final_residuals, range, windows: tracking.times.len() - 1, warnings: inputs.warnings, read: inputs.read })
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

/// RRA's first pass: the average residuals over the adjustment's time range, the mass-center
/// move, the adjusted model and its average residuals.
fn adjust_mass_center(setup: &RraSetup, inputs: &ForwardModel, desired: &DesiredKinematics, range: [f64; 2], file: &Path) -> Result<Adjusted, ResidualReductionError> {
    let body = setup.adjusted_com_body.as_deref().ok_or_else(|| ResidualReductionError::Input(format!("{}: adjust_com_to_reduce_residuals is true but adjusted_com_body is not set", setup.tracking.tool.file.display())))?;
    let range = setup.com_adjustment_time_range.unwrap_or(range);
    let averages = |model: &ForwardModel| average_residuals(&model.geometry, &model.generators, model.external.as_ref(), &mut desired.states.clone(), range, file);
    let before = averages(inputs)?;
    let adjustment = mass_adjustment(&inputs.spec, body, inputs.spec.gravity, &before)?;
    let model = inputs.with_mass_center(body, adjustment.mass_center[1]).map_err(ResidualReductionError::Input)?;
    let after = averages(&model)?;
    Ok(Adjusted { model, adjustment, before, after })
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
    setup.output_model_file.as_ref().map_or_else(|| setup.tracking.tool.file.parent().unwrap_or(Path::new(".")).join("adjusted_model.osim"), |f| f.resolved.clone())
}

/// `model`'s text with only the adjusted body's `mass_center` changed.
fn adjusted_model_text(model: &Path, adjustment: &MassAdjustment) -> Result<String, ResidualReductionError> {
    let mut document = OsimDocument::read(model)?;
    document.set_property(&format!("/bodyset/{}/mass_center", adjustment.body), &format_numbers(&adjustment.mass_center[1]))?;
    String::from_utf8(document.xml.serialize()).map_err(|e| ResidualReductionError::Input(format!("{}: the model is not UTF-8 text: {e}", model.display())))
}
