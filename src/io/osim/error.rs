//! Errors of OpenSim documents; each names the file and the line or component.

use std::path::PathBuf;

use crate::io::xml::{EditError, XmlError};

#[derive(Debug, thiserror::Error)]
pub enum OsimError {
    #[error(transparent)]
    Xml(#[from] XmlError),
    #[error(transparent)]
    Edit(#[from] EditError),
    /// The root element is not `<OpenSimDocument>`.
    #[error("{}:{line}: expected the root element <OpenSimDocument Version=\"…\">, found <{found}>", file.display())]
    NotOpenSim { file: PathBuf, line: usize, found: String },
    /// The `Version` attribute is missing, not a number, or not a dialect we read.
    #[error("{}:{line}: unsupported OpenSim document version {version:?}; expected 20000–29999 (2.x setup files), 30000–30499 (3.x) or 30517–49999 (4.x; 30500–30516 are OpenSim 4.0 development formats: open and save the file in OpenSim 4)", file.display())]
    UnsupportedVersion { file: PathBuf, line: usize, version: String },
    /// `<OpenSimDocument>` holds no object (model or tool).
    #[error("{}:{line}: <OpenSimDocument> holds no object (expected e.g. <Model>)", file.display())]
    NoObject { file: PathBuf, line: usize },
    /// A component path names nothing in the document.
    #[error("{}: no component or property at {path}: {reason}", file.display())]
    UnknownPath { file: PathBuf, path: String, reason: String },
    /// A component path names more than one element.
    #[error("{}: {path} is ambiguous; it matches {}", file.display(), candidates.join(", "))]
    AmbiguousPath { file: PathBuf, path: String, candidates: Vec<String> },
    /// A new property value does not have the kind of the old one.
    #[error("{}:{line}: {path}: expected {expected}, got {value:?}", file.display())]
    BadValue { file: PathBuf, line: usize, path: String, expected: String, value: String },
}
