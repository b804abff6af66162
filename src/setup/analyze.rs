//! `AnalyzeSetup`: an `<AnalyzeTool>` setup file with a `StaticOptimization` analysis, typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::object::{expect_class, read_document};
use super::path::{directory_of, SetupPath};
use super::property::{results_directory_or_here, checked_number_or, name_or_empty, optional_path, words};
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An AnalyzeTool setup with OpenSim's defaults (`AbstractTool.cpp`, `AnalyzeTool.cpp`) for
/// absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalyzeSetup {
    /// The setup file, for messages.
    pub file: PathBuf,
    pub name: String,
    pub model_file: Option<SetupPath>,
    /// `ForceSet` files added to (or, with `replace_force_set`, replacing) the model's forces.
    pub force_set_files: Vec<SetupPath>,
    /// Default true, as OpenSim's.
    pub replace_force_set: bool,
    /// Where the results go (default `./`).
    pub results_directory: SetupPath,
    /// s (default 0).
    pub initial_time: f64,
    /// s (default 1).
    pub final_time: f64,
    pub coordinates_file: Option<SetupPath>,
    /// A states or speeds file, which osim-tune does not read (refused by the command).
    pub states_or_speeds_file: Option<SetupPath>,
    pub external_loads_file: Option<SetupPath>,
    /// Hz; negative: no filtering (default −1).
    pub lowpass_cutoff_frequency_for_coordinates: f64,
    /// The `StaticOptimization` analysis, if the set has one that is on.
    pub static_optimization: Option<StaticOptimizationSetup>,
    /// Classes of the other analyses in the set (not run by osim-tune).
    pub other_analyses: Vec<String>,
}

/// OpenSim's `StaticOptimization` analysis properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StaticOptimizationSetup {
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Default true; false (coordinate actuators for every coordinate) is refused by the command.
    pub use_model_force_set: bool,
    /// The exponent p of Σ|a|ᵖ (default 2).
    pub activation_exponent: f64,
    /// Muscle forces from the force–length–velocity curves (default true), else F_max.
    pub use_muscle_physiology: bool,
}

impl AnalyzeSetup {
    /// Reads the AnalyzeTool setup file `path`.
    pub fn read(path: &Path) -> Result<AnalyzeSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<AnalyzeSetup, SetupError> {
        let tool = ComponentReader::new(document, document.object);
        expect_class(tool, "AnalyzeTool")?;
        let directory = directory_of(document.xml.file());
        let (static_optimization, other_analyses) = analyses(tool)?;
        Ok(AnalyzeSetup {
            file: document.xml.file().into(),
            name: name_or_empty(tool),
            model_file: optional_path(tool, "model_file", &directory),
            force_set_files: words(tool, "force_set_files").iter().map(|f| SetupPath::resolve(f, &directory)).collect(),
            replace_force_set: tool.boolean_or("replace_force_set", true)?,
            results_directory: results_directory_or_here(tool, &directory),
            initial_time: tool.number_or("initial_time", 0.0)?,
            final_time: tool.number_or("final_time", 1.0)?,
            coordinates_file: optional_path(tool, "coordinates_file", &directory),
            states_or_speeds_file: optional_path(tool, "states_file", &directory).or_else(|| optional_path(tool, "speeds_file", &directory)),
            external_loads_file: optional_path(tool, "external_loads_file", &directory),
            lowpass_cutoff_frequency_for_coordinates: tool.number_or("lowpass_cutoff_frequency_for_coordinates", -1.0)?,
            static_optimization,
            other_analyses,
        })
    }
}

/// The `StaticOptimization` that is on, and the classes of the other analyses.
fn analyses(tool: ComponentReader) -> Result<(Option<StaticOptimizationSetup>, Vec<String>), SetupError> {
    let Some(set) = tool.child("AnalysisSet") else { return Ok((None, Vec::new())) };
    let mut static_optimization = None;
    let mut others = Vec::new();
    for element in tool.at(set).listed_objects(set) {
        let analysis = tool.at(element);
        if !analysis.boolean_or("on", true)? {
            continue;
        }
        if analysis.class() == "StaticOptimization" && static_optimization.is_none() {
            static_optimization = Some(StaticOptimizationSetup {
                step_interval: checked_number_or(analysis, "step_interval", 1.0, |n| n >= 1.0 && n.fract() == 0.0, "a whole number ≥ 1")? as usize,
                use_model_force_set: analysis.boolean_or("use_model_force_set", true)?,
                activation_exponent: checked_number_or(analysis, "activation_exponent", 2.0, |p| p >= 1.0, "a number ≥ 1")?,
                use_muscle_physiology: analysis.boolean_or("use_muscle_physiology", true)?,
            });
        } else {
            others.push(analysis.class().to_string());
        }
    }
    Ok((static_optimization, others))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subject01_static_optimization_setup_is_read() {
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/subject01");
        let setup = AnalyzeSetup::read(&folder.join("setup_static_optimization.xml")).unwrap();
        assert!(!setup.replace_force_set);
        assert_eq!(setup.force_set_files.len(), 1);
        let so = setup.static_optimization.unwrap();
        assert_eq!((so.step_interval, so.activation_exponent, so.use_muscle_physiology), (10, 2.0, true));
        assert_eq!((setup.initial_time, setup.final_time), (0.5, 2.0));
    }
}
