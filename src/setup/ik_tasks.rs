//! `IKTaskSet`: the markers and coordinates inverse kinematics (and marker placement) tracks,
//! with their weights.

use serde::Serialize;

use super::error::SetupError;
use super::object::set_members;
use super::property::{checked_number_or, required_name, weight_or};
use crate::model::ComponentReader;

/// The tasks of an `IKTaskSet`, each kind in document order (OpenSim's order of marker weights).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct IkTaskSet {
    pub marker_tasks: Vec<MarkerTask>,
    pub coordinate_tasks: Vec<CoordinateTask>,
}

/// `IKMarkerTask`: track the experimental marker of the same name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarkerTask {
    /// The marker, in the model and in the marker file.
    pub name: String,
    /// Whether the task is used (default true).
    pub apply: bool,
    /// Weight of the squared marker error, ≥ 0 (default 0).
    pub weight: f64,
}

/// `IKCoordinateTask`: hold a coordinate near a target value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoordinateTask {
    /// The coordinate.
    pub name: String,
    /// Whether the task is used (default true).
    pub apply: bool,
    /// Weight of the squared coordinate error, ≥ 0 (default 0).
    pub weight: f64,
    pub target: CoordinateTarget,
}

/// Where a coordinate task's target comes from (`value_type`, any letter case as in OpenSim).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum CoordinateTarget {
    /// `default_value` (OpenSim's default): the coordinate's default value in the model.
    DefaultValue,
    /// `manual_value`: `value` in the coordinate's internal unit, rad for rotational and m for
    /// translational coordinates. OpenSim uses it unconverted (only `coordinate_file` columns are
    /// converted from degrees); absent `value` is 0.
    ManualValue(f64),
    /// `from_file`: the coordinate's column of the tool's `coordinate_file`.
    FromFile,
}

impl IkTaskSet {
    /// Reads the `<IKTaskSet>` element `set`.
    pub(super) fn read(set: ComponentReader) -> Result<IkTaskSet, SetupError> {
        let mut tasks = IkTaskSet::default();
        for member in set_members(set, &["IKMarkerTask", "IKCoordinateTask"])? {
            if member.class() == "IKMarkerTask" {
                tasks.marker_tasks.push(MarkerTask::read(member)?);
            } else {
                tasks.coordinate_tasks.push(CoordinateTask::read(member)?);
            }
        }
        Ok(tasks)
    }
}

impl MarkerTask {
    fn read(task: ComponentReader) -> Result<MarkerTask, SetupError> {
        Ok(MarkerTask {
            name: required_name(task, "marker")?,
            apply: task.boolean_or("apply", true)?,
            weight: weight_or(task, "weight", 0.0)?,
        })
    }
}

impl CoordinateTask {
    fn read(task: ComponentReader) -> Result<CoordinateTask, SetupError> {
        Ok(CoordinateTask {
            name: required_name(task, "coordinate")?,
            apply: task.boolean_or("apply", true)?,
            weight: weight_or(task, "weight", 0.0)?,
            target: CoordinateTarget::read(task)?,
        })
    }
}

impl CoordinateTarget {
    fn read(task: ComponentReader) -> Result<CoordinateTarget, SetupError> {
        let value = checked_number_or(task, "value", 0.0, f64::is_finite, "a finite number")?;
        let value_type = task.optional_text("value_type").unwrap_or_else(|| "default_value".into());
        match value_type.to_ascii_lowercase().as_str() {
            "default_value" => Ok(CoordinateTarget::DefaultValue),
            "manual_value" => Ok(CoordinateTarget::ManualValue(value)),
            "from_file" => Ok(CoordinateTarget::FromFile),
            _ => Err(task.bad("value_type", "default_value, manual_value or from_file", &value_type).into()),
        }
    }
}
