//! What inverse kinematics tracks: marker tasks (a weight per marker) and coordinate tasks (a
//! weight and a target per coordinate), and how they are matched with a model and a trial the
//! way OpenSim 4.6's `InverseKinematicsTool` matches them.

use std::path::{Path, PathBuf};

use crate::io::table::{MarkerTable, StorageTable};
use crate::mechanics::{Function, Motion, Multibody, Vec3};
use crate::model::FunctionSpec;
use crate::setup::{CoordinateTarget as SetupTarget, IkTaskSet};
use crate::solvers::IkError;

/// A tracked marker: OpenSim's `IKMarkerTask` with `apply = true`.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerTask {
    pub name: String,
    /// ≥ 0; 0 keeps the marker in the error report but out of the objective (as Simbody).
    pub weight: f64,
}

/// The value a coordinate task pulls its coordinate towards (OpenSim's `value_type`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CoordinateTarget {
    /// The coordinate's `default_value` in the model (`default_value`).
    DefaultValue,
    /// This value, rad or m (`manual_value`).
    Value(f64),
    /// The coordinate's column of the [`CoordinateValues`] at each frame's time (`from_file`).
    FromFile,
}

/// A tool's `coordinate_file`: coordinate values over time, which OpenSim fits column by column
/// with an interpolating quintic `GCVSpline` (`GCVSplineSet(5, …)`) after converting rotational
/// columns from degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateValues {
    pub file: PathBuf,
    pub table: StorageTable,
}

impl CoordinateValues {
    /// The table at `file` (`.mot`/`.sto`).
    pub fn read(file: &Path) -> Result<CoordinateValues, IkError> {
        let table = StorageTable::read(file)?;
        Ok(CoordinateValues { file: file.into(), table })
    }

    /// The table a setup's `coordinate_file` names, if it names one.
    pub fn read_setup_file(file: Option<&crate::setup::SetupPath>) -> Result<Option<CoordinateValues>, IkError> {
        file.map(|path| CoordinateValues::read(&path.resolved)).transpose()
    }
}

/// OpenSim's `IKCoordinateTask` with `apply = true`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateTask {
    pub name: String,
    /// ≥ 0; 0 drops the task (Simbody skips goals of weight 0).
    pub weight: f64,
    pub target: CoordinateTarget,
}

/// The tasks of an inverse kinematics run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IkTasks {
    /// Empty: every trial marker the model has, weight 1 (OpenSim's rule when a task set lists
    /// no marker task). Otherwise only these markers; a name listed twice takes its first
    /// weight.
    pub markers: Vec<MarkerTask>,
    pub coordinates: Vec<CoordinateTask>,
    /// The values `from_file` tasks follow.
    pub coordinate_values: Option<CoordinateValues>,
}

impl IkTasks {
    /// Every trial marker the model has, weight 1; no coordinate task.
    pub fn every_marker() -> IkTasks {
        IkTasks::default()
    }

    /// The applied tasks of a setup's `IKTaskSet` (read from `setup_file`), `from_file` tasks
    /// following `coordinate_values` (the setup's `coordinate_file`, an error when it names
    /// none, as OpenSim's).
    pub fn from_task_set(tasks: &IkTaskSet, setup_file: &Path, coordinate_values: Option<CoordinateValues>) -> Result<IkTasks, IkError> {
        let markers = tasks.marker_tasks.iter().filter(|t| t.apply).map(|t| MarkerTask { name: t.name.clone(), weight: t.weight }).collect();
        let mut coordinates = Vec::new();
        for task in tasks.coordinate_tasks.iter().filter(|t| t.apply) {
            let target = match task.target {
                SetupTarget::DefaultValue => CoordinateTarget::DefaultValue,
                SetupTarget::ManualValue(value) => CoordinateTarget::Value(value),
                SetupTarget::FromFile if coordinate_values.is_some() => CoordinateTarget::FromFile,
                SetupTarget::FromFile => {
                    let problem = format!("IKCoordinateTask {} has value_type from_file, but the setup names no coordinate_file", task.name);
                    return Err(IkError::Setup { file: setup_file.into(), problem });
                }
            };
            coordinates.push(CoordinateTask { name: task.name.clone(), weight: task.weight, target });
        }
        Ok(IkTasks { markers, coordinates, coordinate_values })
    }
}

/// Where a marker task's marker is missing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MissingFrom {
    Model,
    Trial,
    ModelAndTrial,
}

/// A marker task that cannot be tracked; OpenSim ignores such tasks silently.
#[derive(Debug, Clone, PartialEq)]
pub struct IgnoredMarkerTask {
    pub name: String,
    pub missing_from: MissingFrom,
}

/// A marker in use: in the trial, in the model, and tasked (or every marker, by default).
#[derive(Debug, Clone)]
pub(super) struct TrackedMarker {
    pub name: String,
    /// Index of the trial column.
    pub trial_column: usize,
    pub body: usize,
    /// m, in the body frame.
    pub location: Vec3,
    pub weight: f64,
}

/// A coordinate task resolved against the model.
#[derive(Debug, Clone)]
pub(super) struct TrackedCoordinate {
    pub coordinate: usize,
    pub weight: f64,
    /// rad or m.
    pub target: f64,
    /// For a `from_file` task: the target over time (s), overriding `target`.
    pub trajectory: Option<Function>,
}

impl TrackedCoordinate {
    /// The target at time `time` (s), rad or m.
    pub fn target_at(&self, time: f64) -> f64 {
        self.trajectory.as_ref().map_or(self.target, |f| f.value(time))
    }
}

/// The markers in use in trial column order (OpenSim's `MarkersReference` order: the order of
/// the error report and of "worst marker" ties), and the tasks that cannot be used.
pub(super) fn resolve_markers(
    multibody: &Multibody,
    trial: &MarkerTable,
    trial_file: &Path,
    tasks: &[MarkerTask],
) -> Result<(Vec<TrackedMarker>, Vec<IgnoredMarkerTask>), IkError> {
    for task in tasks {
        check_weight(&task.name, task.weight)?;
    }
    let in_model = |name: &str| multibody.markers.iter().position(|m| m.name == name);
    let mut tracked = Vec::new();
    for (column, name) in trial.marker_names().iter().enumerate() {
        let weight = if tasks.is_empty() { Some(1.0) } else { tasks.iter().find(|t| &t.name == name).map(|t| t.weight) };
        if let (Some(weight), Some(marker)) = (weight, in_model(name)) {
            let marker = &multibody.markers[marker];
            tracked.push(TrackedMarker { name: name.clone(), trial_column: column, body: marker.body, location: marker.location, weight });
        }
    }
    let mut ignored = Vec::new();
    for task in tasks {
        let missing_from = match (in_model(&task.name).is_some(), trial.marker_index(&task.name).is_some()) {
            (true, true) => continue,
            (false, true) => MissingFrom::Model,
            (true, false) => MissingFrom::Trial,
            (false, false) => MissingFrom::ModelAndTrial,
        };
        if !ignored.iter().any(|i: &IgnoredMarkerTask| i.name == task.name) {
            ignored.push(IgnoredMarkerTask { name: task.name.clone(), missing_from });
        }
    }
    if tracked.is_empty() {
        let list = |names: Vec<&str>| abbreviated(&names);
        return Err(IkError::NoMarkers {
            model: multibody.file.clone(),
            trial: trial_file.into(),
            model_markers: list(multibody.markers.iter().map(|m| m.name.as_str()).collect()),
            trial_markers: list(trial.marker_names().iter().map(String::as_str).collect()),
        });
    }
    Ok((tracked, ignored))
}

/// Coordinate tasks by coordinate index; tasks of weight 0 are dropped (a weight-0 goal does
/// nothing in Simbody's assembler). Tasks on locked coordinates are kept here; the caller
/// decides (OpenSim locks such a coordinate in the assembler and drops the task).
pub(super) fn resolve_coordinates(multibody: &Multibody, tasks: &IkTasks) -> Result<Vec<TrackedCoordinate>, IkError> {
    let mut tracked = Vec::new();
    let mut trajectories = None;
    for task in &tasks.coordinates {
        check_weight(&task.name, task.weight)?;
        let coordinate = multibody
            .coordinate_index(&task.name)
            .ok_or_else(|| IkError::UnknownCoordinate { model: multibody.file.clone(), name: task.name.clone() })?;
        let (target, trajectory) = match task.target {
            CoordinateTarget::DefaultValue => (multibody.coordinates[coordinate].default_value, None),
            CoordinateTarget::Value(value) => (value, None),
            CoordinateTarget::FromFile => {
                let values = tasks.coordinate_values.as_ref().ok_or_else(|| IkError::Setup {
                    file: multibody.file.clone(),
                    problem: format!("coordinate task {} is from_file, but no coordinate file was given", task.name),
                })?;
                let motion = match &trajectories {
                    Some(motion) => motion,
                    None => trajectories.insert(coordinate_motion(multibody, values)?),
                };
                (f64::NAN, Some(coordinate_trajectory(motion, values, multibody, coordinate)?))
            }
        };
        if task.weight > 0.0 {
            tracked.push(TrackedCoordinate { coordinate, weight: task.weight, target, trajectory });
        }
    }
    Ok(tracked)
}

/// The coordinate file's columns on `multibody`'s coordinates, rotations in rad.
fn coordinate_motion(multibody: &Multibody, values: &CoordinateValues) -> Result<Motion, IkError> {
    Motion::from_table(&values.table, &values.file, multibody, true).map_err(|e| IkError::Setup { file: values.file.clone(), problem: e.to_string() })
}

/// OpenSim's `GCVSplineSet(5, …)` column of `coordinate`: an interpolating quintic spline of
/// its values over the file's times.
fn coordinate_trajectory(motion: &Motion, values: &CoordinateValues, multibody: &Multibody, coordinate: usize) -> Result<Function, IkError> {
    let name = &multibody.coordinates[coordinate].name;
    let problem = |problem: String| IkError::Setup { file: values.file.clone(), problem };
    if motion.defaulted.contains(name) {
        return Err(problem(format!("no column for coordinate {name}, which a from_file coordinate task follows")));
    }
    if motion.len() < 6 {
        return Err(problem(format!("{} rows; a quintic spline through coordinate {name} needs at least 6", motion.len())));
    }
    if let Some(k) = motion.times.windows(2).position(|t| t[1].partial_cmp(&t[0]) != Some(std::cmp::Ordering::Greater)) {
        return Err(problem(format!("times must increase; row {} ({} s) follows {} s", k + 2, motion.times[k + 1], motion.times[k])));
    }
    let y: Vec<f64> = (0..motion.len()).map(|i| motion.pose(i)[coordinate]).collect();
    if let Some(k) = y.iter().position(|v| !v.is_finite()) {
        return Err(problem(format!("coordinate {name} is {} at row {} ({} s); a from_file task needs finite values", y[k], k + 1, motion.times[k])));
    }
    Ok(Function::new(&FunctionSpec::GCVSpline { degree: 5, error_variance: 0.0, x: motion.times.clone(), y }))
}

fn check_weight(name: &str, weight: f64) -> Result<(), IkError> {
    if weight.is_finite() && weight >= 0.0 {
        Ok(())
    } else {
        Err(IkError::InvalidWeight { name: name.to_string(), weight })
    }
}

/// The first few names, then how many more.
fn abbreviated(names: &[&str]) -> String {
    if names.is_empty() {
        return "none".to_string();
    }
    let shown = names.iter().take(8).copied().collect::<Vec<_>>().join(", ");
    if names.len() > 8 {
        format!("{shown}, … ({} more)", names.len() - 8)
    } else {
        shown
    }
}
