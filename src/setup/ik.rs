//! `IkSetup`: an `<InverseKinematicsTool>` setup file (3.x and 4.x dialects), typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::ik_tasks::IkTaskSet;
use super::object::{expect_class, read_document, read_object};
use super::path::{directory_of, is_unassigned, SetupPath};
use super::property::{checked_number_or, name_or_empty, optional_path, weight_or};
use super::time_range::TimeRange;
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An InverseKinematicsTool setup with OpenSim's defaults (`InverseKinematicsToolBase.h`,
/// `InverseKinematicsTool.cpp`, `Tool.h`) for absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkSetup {
    /// The setup file, for messages.
    pub file: PathBuf,
    /// The directory relative file names resolve against (the setup file's).
    pub directory: PathBuf,
    /// The document's `Version` (10500 when the file has no `<OpenSimDocument>`).
    pub version: u32,
    /// The trial's name; OpenSim prefixes the error and marker-location files with it.
    pub name: String,
    /// The model. (OpenSim 4.6 opens it before changing into the setup's directory, so there it
    /// is relative to the working directory; we resolve it like every other name.)
    pub model_file: Option<SetupPath>,
    /// `IKTaskSet` (default empty).
    pub tasks: IkTaskSet,
    /// The marker trajectories (`.trc`).
    pub marker_file: Option<SetupPath>,
    /// Coordinate values (`.mot`/`.sto`, degrees converted by OpenSim) for `from_file` tasks.
    pub coordinate_file: Option<SetupPath>,
    /// The frames solved, clipped by OpenSim to the marker data (default −∞ to ∞).
    pub time_range: TimeRange,
    /// Convergence tolerance of the IK solver, > 0 (default 1e-5).
    pub accuracy: f64,
    /// Weight of the constraint errors, ≥ 0; ∞ (the default) enforces constraints exactly.
    pub constraint_weight: f64,
    /// The solved coordinates (`.mot`, degrees).
    pub output_motion_file: Option<SetupPath>,
    /// Write `<name>_ik_marker_errors.sto` (default true).
    pub report_errors: bool,
    /// Write `<name>_ik_model_marker_locations.sto` (default false).
    pub report_marker_locations: bool,
    /// Where the reports go (default `./`, the setup's directory); `None` when written empty or
    /// `Unassigned`.
    pub results_directory: Option<SetupPath>,
}

impl IkSetup {
    /// Reads the InverseKinematicsTool setup file `path`.
    pub fn read(path: &Path) -> Result<IkSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The InverseKinematicsTool of `document`; a task set given by reference is read from its file.
    pub fn from_document(document: &OsimDocument) -> Result<IkSetup, SetupError> {
        let tool = ComponentReader::new(document, document.object);
        expect_class(tool, "InverseKinematicsTool")?;
        let directory = directory_of(document.xml.file());
        Ok(IkSetup {
            file: document.xml.file().into(),
            version: document.version.number,
            name: name_or_empty(tool),
            model_file: optional_path(tool, "model_file", &directory),
            tasks: read_object(tool, "IKTaskSet", &directory, IkTaskSet::read)?.unwrap_or_default(),
            marker_file: optional_path(tool, "marker_file", &directory),
            coordinate_file: optional_path(tool, "coordinate_file", &directory),
            time_range: TimeRange::read_or(tool, TimeRange { start: f64::NEG_INFINITY, end: f64::INFINITY })?,
            accuracy: checked_number_or(tool, "accuracy", 1e-5, |a| a > 0.0, "a number > 0")?,
            constraint_weight: weight_or(tool, "constraint_weight", f64::INFINITY)?,
            output_motion_file: optional_path(tool, "output_motion_file", &directory),
            report_errors: tool.boolean_or("report_errors", true)?,
            report_marker_locations: tool.boolean_or("report_marker_locations", false)?,
            results_directory: results_directory(tool, &directory),
            directory,
        })
    }
}

/// `results_directory`: `./` when absent (OpenSim's `Tool` default).
fn results_directory(tool: ComponentReader, directory: &Path) -> Option<SetupPath> {
    let written = tool.optional_text("results_directory").unwrap_or_else(|| "./".into());
    (!is_unassigned(&written)).then(|| SetupPath::resolve(&written, directory))
}
