//! Errors of the typed model view; each names the file, the line and the component.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The document's object is not a `<Model>`.
    #[error("{}:{line}: expected a <Model>, found <{found}>", file.display())]
    NotAModel { file: PathBuf, line: usize, found: String },
    /// A property OpenSim requires is absent.
    #[error("{}:{line}: {component}: missing <{property}>", file.display())]
    MissingProperty { file: PathBuf, line: usize, component: String, property: String },
    /// A property's text is not what it must be (boxed: the largest variant).
    #[error(transparent)]
    BadProperty(Box<BadProperty>),
    /// A reference (socket, body name, coordinate name) names nothing in the model.
    #[error("{}:{line}: {component}: {what} {target:?} does not exist in the model", file.display())]
    UnknownReference { file: PathBuf, line: usize, component: String, what: String, target: String },
    /// A part of an older model OpenSim 4's format cannot hold as osim-tune converts it.
    #[error("{}:{line}: {component}: {problem}", file.display())]
    Unsupported { file: PathBuf, line: usize, component: String, problem: String },
}

/// A property's text is not what it must be.
#[derive(Debug, thiserror::Error)]
#[error("{}:{line}: {component}: <{property}> must be {expected}, found {found:?}", file.display())]
pub struct BadProperty {
    pub file: PathBuf,
    pub line: usize,
    pub component: String,
    pub property: String,
    pub expected: String,
    pub found: String,
}
