//! Errors of the solvers; each names the file (model or trial) and what was expected.

use std::path::PathBuf;

use crate::io::table::TableError;
use crate::mechanics::MechanicsError;

/// Why inverse kinematics could not be set up or run. Non-convergence of a frame is not an
/// error: it is the frame's [`LeastSquaresStatus`](super::LeastSquaresStatus).
#[derive(Debug, thiserror::Error)]
pub enum IkError {
    /// The model could not be compiled for kinematics.
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    /// A coordinate file that cannot be read (the error names it).
    #[error(transparent)]
    Table(#[from] TableError),
    /// A coordinate task names no coordinate of the model (OpenSim throws too).
    #[error("{}: coordinate task {name:?}: the model has no coordinate of that name", model.display())]
    UnknownCoordinate { model: PathBuf, name: String },
    /// A task weight that is negative or not finite.
    #[error("task {name:?}: weight {weight} is not a finite number ≥ 0")]
    InvalidWeight { name: String, weight: f64 },
    /// No marker both has a task and is in the model and the trial (OpenSim: "Marker data does
    /// not correspond to any model markers").
    #[error("{}: no marker of the trial {} has a task and a model marker of the same name (model markers: {model_markers}; trial markers: {trial_markers})", model.display(), trial.display())]
    NoMarkers { model: PathBuf, trial: PathBuf, model_markers: String, trial_markers: String },
    /// The trial has no frames.
    #[error("{}: the trial has no frames", trial.display())]
    EmptyTrial { trial: PathBuf },
    /// The requested time range does not overlap the trial.
    #[error("{}: time range {start}–{end} s does not overlap the trial's frames at {first}–{last} s", trial.display())]
    TimeRange { trial: PathBuf, start: f64, end: f64, first: f64, last: f64 },
    /// A frame in which no marker with a positive weight has data.
    #[error("{}: frame {frame} (t = {time} s): none of the tracked markers with a positive weight has data in this frame", trial.display())]
    NoUsableMarkers { trial: PathBuf, frame: usize, time: f64 },
    /// The model uses something the solver does not handle.
    #[error("{}: {component}: {what} is not supported by inverse kinematics", model.display())]
    Unsupported { model: PathBuf, component: String, what: String },
    /// A frame index past the trial's end.
    #[error("{}: frame {frame} does not exist (the trial has {frames} frames)", trial.display())]
    NoFrame { trial: PathBuf, frame: usize, frames: usize },
    /// A start pose of the wrong length.
    #[error("a pose needs {expected} coordinate values, got {found}")]
    PoseLength { expected: usize, found: usize },
    /// A constraint between bodies the solver could not close (after its augmented-Lagrangian
    /// rounds); `constraint` is `name (class)`.
    #[error("{}: frame {frame} (t = {time} s): constraint {constraint} still has an error of {error:e} (m, or rad for a weld's orientation) after {rounds} rounds", trial.display())]
    LinkNotMet { trial: PathBuf, frame: usize, time: f64, constraint: String, error: f64, rounds: usize },
    /// Assembly could not close a constraint between bodies; `constraint` is `name (class)`.
    #[error("{}: the model does not assemble: constraint {constraint} keeps an error of {error:e} (m, or rad for a weld's orientation) after {rounds} rounds", model.display())]
    NotAssembled { model: PathBuf, constraint: String, error: f64, rounds: usize },
    /// A setup or its coordinate file that inverse kinematics cannot use.
    #[error("{}: {problem}", file.display())]
    Setup { file: PathBuf, problem: String },
    /// The Kalman smoother cannot run.
    #[error("Kalman smoothing: {problem}")]
    Smoother { problem: String },
}
