//! Errors of the typed setup views; each names the file and the line (and the element where a
//! property is at fault).

use std::path::PathBuf;

use crate::io::osim::OsimError;
use crate::model::ModelError;

#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The setup file (or a file it references) cannot be read as an OpenSim document.
    #[error(transparent)]
    Document(#[from] OsimError),
    /// A property is missing or its value is not what it must be (file, line, element, expected).
    /// Boxed to keep `Result<_, SetupError>` small.
    #[error(transparent)]
    Property(Box<ModelError>),
    /// The document holds another object than the one expected, e.g. an `<InverseKinematicsTool>`
    /// passed where a `<ScaleTool>` is expected, or a set member of the wrong class.
    #[error("{}:{line}: expected <{expected}>, found <{found}>", file.display())]
    UnexpectedObject { file: PathBuf, line: usize, expected: String, found: String },
    /// An object that must be named (a task's marker or coordinate, a body to scale) has no
    /// `name` attribute.
    #[error("{}:{line}: {component}: <{class}> needs a name attribute naming its {what}", file.display())]
    Unnamed { file: PathBuf, line: usize, component: String, class: String, what: String },
    /// A table a setup names (a controls `.sto`) could not be read. Boxed as `Property`.
    #[error(transparent)]
    Table(Box<crate::io::table::TableError>),
    /// An object given by reference (`<MeasurementSet file="…"/>`) could not be read.
    #[error("{}:{line}: <{element} file={reference:?}>: {source}", file.display())]
    Reference { file: PathBuf, line: usize, element: String, reference: String, source: Box<SetupError> },
}

impl From<crate::io::table::TableError> for SetupError {
    fn from(error: crate::io::table::TableError) -> Self {
        SetupError::Table(Box::new(error))
    }
}

impl From<ModelError> for SetupError {
    fn from(error: ModelError) -> Self {
        SetupError::Property(Box::new(error))
    }
}
