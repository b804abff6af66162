//! Inverse kinematics equal to OpenSim 4.6's `InverseKinematicsTool`: per frame, the pose that
//! minimises Simbody's assembler goal — weighted marker distances (divided by the total weight
//! of the markers with data) plus weighted coordinate-task errors — with locked coordinates
//! held, clamped coordinates bounded by their range and couplers exact.
//!
//! - `tasks.rs`: marker and coordinate tasks and how they match a model and a trial;
//! - `coordinates.rs`: free, held and coupled coordinates, bounds, constraint weight;
//! - `frame.rs`: one frame's residuals and Jacobian;
//! - `solver.rs`: [`InverseKinematics`], the frame loop and time range;
//! - `report.rs`: per-frame errors and OpenSim's output tables.

mod coordinates;
mod frame;
mod report;
mod solver;
mod tasks;

pub use coordinates::ConstraintWeight;
pub use report::{IkFrame, IkSolution, MarkerErrors};
pub use solver::{IkSettings, IkWorkspace, InverseKinematics};
pub use tasks::{CoordinateTarget, CoordinateTask, IgnoredMarkerTask, IkTasks, MarkerTask, MissingFrom};
