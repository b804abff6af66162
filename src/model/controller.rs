//! Controllers as model and setup files write them: a `PrescribedController` (a function of
//! time per actuator, or a controls file), a `ControlSetController` (a controls file), and any
//! other class by name, for the tools that cannot apply it to refuse it.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::ModelError;
use super::function::FunctionSpec;
use super::reader::ComponentReader;

/// An enabled controller.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum ControllerSpec {
    PrescribedController(PrescribedControllerSpec),
    /// Its controls file, resolved against the directory of the file naming it.
    ControlSetController { name: String, controls_file: Option<PathBuf> },
    /// A class osim-tune does not apply (e.g. `ToyReflexController`), or a controller whose
    /// functions it cannot read (`reason`).
    Unsupported { class: String, name: String, reason: String },
}

/// A `PrescribedController`: the i-th control function drives the i-th actuator.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PrescribedControllerSpec {
    pub name: String,
    /// Actuator names or absolute paths (`socket_actuators`, before 4.6 `actuator_list`); `ALL`
    /// (any case) for every actuator of the model in its order.
    pub actuators: Vec<String>,
    /// `ControlFunctions`, in order.
    pub functions: Vec<FunctionSpec>,
    /// A table with a column per actuator (name or path) not given a function; resolved against
    /// the directory of the file naming it.
    pub controls_file: Option<PathBuf>,
    /// How the file's columns become functions: 0 piecewise constant, n = 1, 3, 5, 7 an
    /// interpolating GCV spline of degree n (default 1).
    pub interpolation_method: usize,
}

impl ControllerSpec {
    /// The controller `reader` points at, `None` when it is disabled (`enabled` false, 3.x
    /// `isDisabled` true); `directory` resolves its controls file.
    pub fn read(reader: ComponentReader, directory: &Path) -> Result<Option<ControllerSpec>, ModelError> {
        if !reader.boolean_or("enabled", true)? || reader.boolean_or("isDisabled", false)? {
            return Ok(None);
        }
        let name = reader.name();
        let controls_file = reader.optional_text("controls_file").map(|f| f.trim().to_string()).filter(|f| !f.is_empty()).map(|f| directory.join(f));
        let controller = match reader.class() {
            "ControlSetController" => ControllerSpec::ControlSetController { name, controls_file },
            "PrescribedController" => match prescribed(reader, name.clone(), controls_file) {
                Ok(prescribed) => ControllerSpec::PrescribedController(prescribed),
                Err(error) => ControllerSpec::Unsupported { class: reader.class().into(), name, reason: error.to_string() },
            },
            class => ControllerSpec::Unsupported { class: class.into(), name, reason: "osim-tune applies PrescribedControllers and ControlSetControllers".into() },
        };
        Ok(Some(controller))
    }

    /// `<class> <name>`, for messages.
    pub fn description(&self) -> String {
        let (class, name) = match self {
            ControllerSpec::PrescribedController(p) => ("PrescribedController", p.name.as_str()),
            ControllerSpec::ControlSetController { name, .. } => ("ControlSetController", name.as_str()),
            ControllerSpec::Unsupported { class, name, .. } => (class.as_str(), name.as_str()),
        };
        if name.is_empty() { class.to_string() } else { format!("{class} {name}") }
    }
}

/// A `PrescribedController`'s actuators, functions and file.
fn prescribed(reader: ComponentReader, name: String, controls_file: Option<PathBuf>) -> Result<PrescribedControllerSpec, ModelError> {
    let list = reader.optional_text("socket_actuators").or_else(|| reader.optional_text("actuator_list")).unwrap_or_default();
    let mut functions = Vec::new();
    if let Some(set) = reader.object_property("ControlFunctions") {
        for function in set.listed_objects(set.element) {
            functions.push(FunctionSpec::read(set.at(function))?);
        }
    }
    let method = reader.number_or("interpolation_method", 1.0)?;
    if ![0.0, 1.0, 3.0, 5.0, 7.0].contains(&method) {
        return Err(reader.bad("interpolation_method", "0 (piecewise constant) or a GCV spline degree 1, 3, 5 or 7", &method.to_string()));
    }
    Ok(PrescribedControllerSpec { name, actuators: list.split_whitespace().map(String::from).collect(), functions, controls_file, interpolation_method: method as usize })
}
