//! `ForwardSetup`: a `<ForwardTool>` setup file — OpenSim's forward simulation of a model from
//! an initial state under its controllers' controls — typed, with OpenSim's defaults
//! (`AbstractTool.cpp`, `ForwardTool.cpp`).

use std::path::Path;

use serde::Serialize;

use super::analyze::AnalyzeSetup;
use super::error::SetupError;
use super::object::read_document;
use super::property::checked_number_or;
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// A ForwardTool setup: the `AbstractTool` part (model, force-set files — not replacing the
/// model's forces unless asked —, results directory, time range, external loads, controllers,
/// the analyses run on the simulated states, `states_file` as the initial states,
/// `solve_for_equilibrium_for_auxiliary_states`) and the integrator's settings.
#[derive(Debug, Clone)]
pub struct ForwardSetup {
    pub tool: AnalyzeSetup,
    pub integrator: IntegratorSettings,
}

/// The integrator settings of an OpenSim tool.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IntegratorSettings {
    /// Steps allowed before the simulation gives up (default 20000).
    pub maximum_steps: usize,
    /// Largest and smallest step, s (defaults 1 and 1e-8).
    pub maximum_step_size: f64,
    pub minimum_step_size: f64,
    /// Error tolerance per state and step (default 1e-5).
    pub error_tolerance: f64,
}

impl ForwardSetup {
    /// Reads the ForwardTool setup file `path`.
    pub fn read(path: &Path) -> Result<ForwardSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<ForwardSetup, SetupError> {
        let tool = AnalyzeSetup::from_tool(document, "ForwardTool", false)?;
        let integrator = IntegratorSettings::read(ComponentReader::new(document, document.object))?;
        Ok(ForwardSetup { tool, integrator })
    }
}

impl IntegratorSettings {
    /// The integrator properties of the tool `reader` reads, with OpenSim's defaults.
    pub(super) fn read(reader: ComponentReader) -> Result<IntegratorSettings, SetupError> {
        let positive = |property: &str, default: f64| checked_number_or(reader, property, default, |v| v > 0.0, "a number > 0");
        let steps = checked_number_or(reader, "maximum_number_of_integrator_steps", 20000.0, |v| v >= 1.0 && v.fract() == 0.0, "a whole number ≥ 1")?;
        Ok(IntegratorSettings {
            maximum_steps: steps as usize,
            maximum_step_size: positive("maximum_integrator_step_size", 1.0)?,
            minimum_step_size: positive("minimum_integrator_step_size", 1e-8)?,
            error_tolerance: positive("integrator_error_tolerance", 1e-5)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(body: &str) -> Result<ForwardSetup, SetupError> {
        let xml = format!(r#"<OpenSimDocument Version="40000"><ForwardTool name="arm">{body}</ForwardTool></OpenSimDocument>"#);
        ForwardSetup::from_document(&OsimDocument::parse(xml, Path::new("/data/setup.xml")).unwrap())
    }

    #[test]
    fn opensims_defaults_are_taken() {
        let forward = setup("<model_file>arm26.osim</model_file><final_time>0.5</final_time>").unwrap();
        assert_eq!(forward.integrator, IntegratorSettings { maximum_steps: 20000, maximum_step_size: 1.0, minimum_step_size: 1e-8, error_tolerance: 1e-5 });
        assert!(!forward.tool.replace_force_set, "a ForwardTool adds its force-set files");
        assert_eq!((forward.tool.initial_time, forward.tool.final_time, forward.tool.name.as_str()), (0.0, 0.5, "arm"));
        assert_eq!(forward.tool.model_file.unwrap().resolved, Path::new("/data/arm26.osim"));
    }

    #[test]
    fn integrator_settings_are_read_and_checked() {
        let forward = setup("<maximum_number_of_integrator_steps>500</maximum_number_of_integrator_steps><integrator_error_tolerance>1e-9</integrator_error_tolerance><maximum_integrator_step_size>0.01</maximum_integrator_step_size>").unwrap();
        assert_eq!((forward.integrator.maximum_steps, forward.integrator.error_tolerance, forward.integrator.maximum_step_size), (500, 1e-9, 0.01));
        let error = setup("<integrator_error_tolerance>0</integrator_error_tolerance>").unwrap_err().to_string();
        assert!(error.contains("integrator_error_tolerance") && error.contains("> 0"), "{error}");
        assert!(setup("<maximum_number_of_integrator_steps>2.5</maximum_number_of_integrator_steps>").is_err());
    }

    #[test]
    fn another_tool_is_refused() {
        let xml = r#"<OpenSimDocument Version="40000"><AnalyzeTool name="a"/></OpenSimDocument>"#;
        let error = ForwardSetup::from_document(&OsimDocument::parse(xml.to_string(), Path::new("/data/setup.xml")).unwrap()).unwrap_err().to_string();
        assert!(error.contains("ForwardTool"), "{error}");
    }
}
