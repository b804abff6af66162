//! Errors compiling a model view into mechanics; each names the file and the component.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum MechanicsError {
    /// The model is inconsistent (a reference to nothing, a cycle, a degenerate axis).
    #[error("{}: {component}: {problem}", file.display())]
    Invalid { file: PathBuf, component: String, problem: String },
    /// The model uses something osim-tune does not compute.
    #[error("{}: {component}: {what} is not supported", file.display())]
    Unsupported { file: PathBuf, component: String, what: String },
}
