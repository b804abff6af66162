//! Typed property values shared by the setup objects, on top of `ComponentReader` (whose errors
//! name the file, the line and the element).

use std::path::Path;

use super::error::SetupError;
use super::path::{is_unassigned, SetupPath};
use crate::model::ComponentReader;

/// A string property; `None` when absent, empty or `Unassigned`.
pub fn optional_string(reader: ComponentReader, property: &str) -> Option<String> {
    reader.optional_text(property).filter(|text| !is_unassigned(text))
}

/// A file property resolved against `directory`; `None` when absent, empty or `Unassigned`.
pub fn optional_path(reader: ComponentReader, property: &str, directory: &Path) -> Option<SetupPath> {
    optional_string(reader, property).map(|text| SetupPath::resolve(&text, directory))
}

/// `results_directory` resolved against `directory`; `./` (the setup's directory) when absent or
/// empty, as OpenSim's tools default it.
pub fn results_directory_or_here(reader: ComponentReader, directory: &Path) -> SetupPath {
    let written = reader.optional_text("results_directory").filter(|d| !d.is_empty()).unwrap_or_else(|| "./".into());
    SetupPath::resolve(&written, directory)
}

/// A number that must satisfy `valid` (described by `expected`), `default` when absent.
pub fn checked_number_or(
    reader: ComponentReader,
    property: &str,
    default: f64,
    valid: impl Fn(f64) -> bool,
    expected: &str,
) -> Result<f64, SetupError> {
    let value = reader.number_or(property, default)?;
    if valid(value) {
        Ok(value)
    } else {
        Err(reader.bad(property, expected, &reader.optional_text(property).unwrap_or_default()).into())
    }
}

/// A weight: a number ≥ 0, `default` when absent.
pub fn weight_or(reader: ComponentReader, property: &str, default: f64) -> Result<f64, SetupError> {
    checked_number_or(reader, property, default, |w| w >= 0.0, "a number ≥ 0")
}

/// The element's `name` attribute, required where it names what the object applies to.
pub fn required_name(reader: ComponentReader, what: &str) -> Result<String, SetupError> {
    match reader.document.xml.name(reader.element) {
        Some(name) => Ok(name.to_string()),
        None => Err(SetupError::Unnamed {
            file: reader.document.xml.file().into(),
            line: reader.line(),
            component: reader.path(),
            class: reader.class().into(),
            what: what.into(),
        }),
    }
}

/// The element's `name` attribute, empty when absent.
pub fn name_or_empty(reader: ComponentReader) -> String {
    reader.document.xml.name(reader.element).unwrap_or_default().to_string()
}
