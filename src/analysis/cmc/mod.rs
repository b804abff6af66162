//! OpenSim's computed muscle control (`CMC`, `CMCTool`): every window the generators' forces
//! that reach the tracking tasks' desired accelerations at the window's predicted end, the
//! controls that give those forces there (the muscles' states predicted over the window), and the
//! model integrated under them. RRA runs the same controller on ideal actuators
//! ([`crate::analysis::run_rra`]).
//!
//! `desired.rs` the desired kinematics (padded, FIR-filtered, splined); `tracking.rs` the
//! windows (`Controller`); `predictor.rs` the actuator force predictor; `target.rs` the fast and
//! slow optimisation targets; `state_tasks.rs` the muscle state tracking tasks whose terms join
//! the targets; `initial_states.rs` where CMC starts a model with muscles' states;
//! `merson.rs` Simbody's Runge–Kutta–Merson step; `tool.rs` the CMCTool run whole.

mod desired;
mod initial_states;
mod merson;
mod predictor;
mod state_tasks;
mod target;
mod tool;
mod tracking;

pub use desired::DesiredKinematics;
pub use initial_states::InitialStates;
pub use target::Target;
pub use tool::{control_limits, read_tracking_inputs, run_cmc, tasks, tracked_files, CmcOutputs};
pub use tracking::{desired_state, Controller, Task, Tracking, WindowSolution};

use super::analyze_states::StatesError;

/// Why CMC (or RRA's tracking) cannot run or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum CmcError {
    #[error(transparent)]
    States(#[from] StatesError),
    /// A file or setup property CMC cannot use (the message names it).
    #[error("{0}")]
    Input(String),
    #[error("the tracking stopped at {time} s: {reason}")]
    Tracking { time: f64, reason: String },
}
