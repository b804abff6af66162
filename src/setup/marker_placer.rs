//! `MarkerPlacer`: how the ScaleTool moves the model's markers onto a static trial.

use std::path::Path;

use serde::Serialize;

use super::error::SetupError;
use super::ik_tasks::IkTaskSet;
use super::object::read_object;
use super::path::SetupPath;
use super::property::optional_path;
use super::time_range::TimeRange;
use crate::model::ComponentReader;

/// The `MarkerPlacer` of a ScaleTool setup, with OpenSim's defaults (`MarkerPlacer.cpp`) for
/// absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarkerPlacer {
    /// Whether markers are placed (default true).
    pub apply: bool,
    /// `IKTaskSet`: weights of the static-pose IK (default empty).
    pub ik_tasks: IkTaskSet,
    /// The static trial (`.trc`).
    pub marker_file: Option<SetupPath>,
    /// Coordinate values (`.mot`/`.sto`, degrees converted by OpenSim) for `from_file` tasks.
    pub coordinate_file: Option<SetupPath>,
    /// The frames of `marker_file` averaged into the static pose (default −1 to −1).
    pub time_range: TimeRange,
    /// The solved static pose.
    pub output_motion_file: Option<SetupPath>,
    /// The scaled model with placed markers.
    pub output_model_file: Option<SetupPath>,
    /// The placed markers as a `MarkerSet`.
    pub output_marker_file: Option<SetupPath>,
    /// Largest movement of a marker allowed while averaging, in the unit of `marker_file`
    /// (usually mm); negative: no limit (default −1).
    pub max_marker_movement: f64,
}

impl MarkerPlacer {
    /// Reads a `<MarkerPlacer>`; its `IKTaskSet` may be given by `file` relative to `directory`.
    pub(super) fn read(placer: ComponentReader, directory: &Path) -> Result<MarkerPlacer, SetupError> {
        Ok(MarkerPlacer {
            apply: placer.boolean_or("apply", true)?,
            ik_tasks: read_object(placer, "IKTaskSet", directory, IkTaskSet::read)?.unwrap_or_default(),
            marker_file: optional_path(placer, "marker_file", directory),
            coordinate_file: optional_path(placer, "coordinate_file", directory),
            time_range: TimeRange::read_or(placer, TimeRange { start: -1.0, end: -1.0 })?,
            output_motion_file: optional_path(placer, "output_motion_file", directory),
            output_model_file: optional_path(placer, "output_model_file", directory),
            output_marker_file: optional_path(placer, "output_marker_file", directory),
            max_marker_movement: placer.number_or("max_marker_movement", -1.0)?,
        })
    }
}
