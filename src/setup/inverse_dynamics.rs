//! `IdSetup`: an `<InverseDynamicsTool>` setup file, typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::object::{expect_class, read_document};
use super::path::{directory_of, SetupPath};
use super::property::{results_directory_or_here, name_or_empty, optional_path};
use super::time_range::TimeRange;
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An InverseDynamicsTool setup with OpenSim's defaults (`InverseDynamicsTool.cpp`,
/// `DynamicsTool.cpp`) for absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdSetup {
    /// The setup file, for messages.
    pub file: PathBuf,
    pub name: String,
    pub model_file: Option<SetupPath>,
    /// Coordinates (`.mot`/`.sto`).
    pub coordinates_file: Option<SetupPath>,
    /// The `ExternalLoads` file.
    pub external_loads_file: Option<SetupPath>,
    /// The frames solved, clipped by OpenSim to the coordinates (default −∞ to ∞).
    pub time_range: TimeRange,
    /// Model forces left out: force names, `muscles`, `actuators` or `all` (default none).
    pub forces_to_exclude: Vec<String>,
    /// Low-pass cutoff for the coordinates, Hz; negative: no filtering (default −1).
    pub lowpass_cutoff_frequency_for_coordinates: f64,
    /// The generalized forces (default `inverse_dynamics.sto`, in the results directory).
    pub output_gen_force_file: String,
    /// Where the output goes (default `./`, the setup's directory).
    pub results_directory: SetupPath,
    /// Joints whose equivalent body forces are also reported (names or `ALL`).
    pub joints_to_report_body_forces: Vec<String>,
    /// Where they go (default `body_forces_at_joints.sto`, in the results directory).
    pub output_body_forces_file: String,
}

impl IdSetup {
    /// Reads the InverseDynamicsTool setup file `path`.
    pub fn read(path: &Path) -> Result<IdSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<IdSetup, SetupError> {
        let tool = ComponentReader::new(document, document.object);
        expect_class(tool, "InverseDynamicsTool")?;
        let directory = directory_of(document.xml.file());
        let output = tool.optional_text("output_gen_force_file").filter(|f| !f.is_empty()).unwrap_or_else(|| "inverse_dynamics.sto".into());
        Ok(IdSetup {
            file: document.xml.file().into(),
            name: name_or_empty(tool),
            model_file: optional_path(tool, "model_file", &directory),
            coordinates_file: optional_path(tool, "coordinates_file", &directory),
            external_loads_file: optional_path(tool, "external_loads_file", &directory),
            time_range: TimeRange::read_or(tool, TimeRange { start: f64::NEG_INFINITY, end: f64::INFINITY })?,
            forces_to_exclude: tool.words("forces_to_exclude"),
            lowpass_cutoff_frequency_for_coordinates: tool.number_or("lowpass_cutoff_frequency_for_coordinates", -1.0)?,
            output_gen_force_file: output,
            results_directory: results_directory_or_here(tool, &directory),
            joints_to_report_body_forces: tool.words("joints_to_report_body_forces"),
            output_body_forces_file: tool.optional_text("output_body_forces_file").filter(|f| !f.is_empty()).unwrap_or_else(|| "body_forces_at_joints.sto".into()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subject01_setup_is_read_with_its_settings() {
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/subject01");
        let setup = IdSetup::read(&folder.join("subject01_Setup_InverseDynamics.xml")).unwrap();
        assert_eq!(setup.name, "subject01_walk1");
        assert_eq!(setup.coordinates_file.unwrap().resolved, folder.join("subject01_walk1_ik.mot"));
        assert_eq!(setup.external_loads_file.unwrap().resolved, folder.join("subject01_walk1_grf.xml"));
        assert_eq!((setup.time_range.start, setup.time_range.end), (0.4, 1.6));
        assert_eq!(setup.forces_to_exclude, vec!["muscles".to_string()]);
        assert_eq!(setup.lowpass_cutoff_frequency_for_coordinates, 6.0);
        assert_eq!(setup.output_gen_force_file, "InverseDynamicsOutput.sto");
        assert_eq!(setup.results_directory.resolved, folder.join("ResultsInverseDynamics"));
    }
}
