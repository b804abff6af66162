//! Errors of the Scale step; each names the file and the component or marker at fault.

use std::path::PathBuf;

use crate::io::osim::OsimError;
use crate::io::table::TableError;
use crate::io::xml::EditError;
use crate::mechanics::MechanicsError;
use crate::model::ModelError;
use crate::solvers::IkError;

#[derive(Debug, thiserror::Error)]
pub enum ScaleError {
    #[error(transparent)]
    Osim(#[from] OsimError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Edit(#[from] EditError),
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error(transparent)]
    Ik(#[from] IkError),
    /// The model holds something osim-tune cannot scale as OpenSim would.
    #[error("{}:{line}: {component}: {problem}", file.display())]
    Unsupported { file: PathBuf, line: usize, component: String, problem: String },
    /// An input file or setup that cannot be used as it is (subject file, static trial, a step
    /// without its file).
    #[error("{}: {problem}", file.display())]
    Input { file: PathBuf, problem: String },
    /// A measurement cannot be taken (markers missing, no frames in the time range).
    #[error("{}: measurement {measurement:?}: {problem}", file.display())]
    Measurement { file: PathBuf, measurement: String, problem: String },
    /// A scale factor or subject mass outside what a subject can be.
    #[error("{}: {what} = {value} is not acceptable: {expected}", file.display())]
    BadValue { file: PathBuf, what: String, value: f64, expected: String },
}
