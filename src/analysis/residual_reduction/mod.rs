//! OpenSim's residual reduction algorithm (`RRATool`): with the model's forces replaced by
//! residual actuators on the pelvis (FX, FY, FZ, MX, MY, MZ) and a coordinate actuator per joint,
//! (1) the average residuals of inverse dynamics along the desired kinematics move a body's mass
//! center to cancel the average MX and MZ and recommend mass changes for FY (`averages`), then
//! (2) CMC tracks the desired kinematics with the actuators on the adjusted model (`tracking`),
//! giving kinematics consistent with its dynamics and the residuals that keep them; the
//! tracked states then feed the AnalyzeTool's Kinematics and Actuation (what RRA writes), and
//! the Actuation's residual forces are averaged again.

mod averages;
mod tool;

use std::path::PathBuf;

use averages::{average_residuals, mass_adjustment, time_average};
pub use averages::{MassAdjustment, Residuals, RESIDUALS};
pub use tool::{run_rra, Adjusted, RraOutputs};

use super::analyze_states::StatesError;
use super::cmc::CmcError;

/// Why RRA cannot run or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum ResidualReductionError {
    #[error(transparent)]
    States(#[from] StatesError),
    #[error("{}: no row lies in the time range {}–{} s", file.display(), range[0], range[1])]
    NoRows { file: PathBuf, range: [f64; 2] },
    #[error("inverse dynamics for the average residuals has no solution at {time} s: {reason}")]
    InverseDynamics { time: f64, reason: String },
    #[error("the model has no body {0:?} to adjust")]
    NoBody(String),
    #[error("{0} has no weight to adjust its mass center by")]
    Weightless(String),
    /// A file or setup property RRA cannot use (the message names it).
    #[error("{0}")]
    Input(String),
    #[error(transparent)]
    Cmc(#[from] CmcError),
}

/// The model file RRA reads again to write the adjusted model (the message names it).
impl From<crate::io::osim::OsimError> for ResidualReductionError {
    fn from(error: crate::io::osim::OsimError) -> Self {
        ResidualReductionError::Input(error.to_string())
    }
}
