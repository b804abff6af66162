//! Inverse kinematics equal to OpenSim 4.6's `InverseKinematicsTool`: per frame, the pose that
//! minimises Simbody's assembler goal, frame after frame.
//!
//! What is matched (OpenSim's `InverseKinematicsTool`, `InverseKinematicsSolver`,
//! `AssemblySolver`, `MarkersReference`; Simbody's `Assembler`, `Markers`, `QValue`):
//! - **Objective** F = Σ w_i‖x_i(q) − x̂_i‖² / (2 Σ w_i) + Σ w_j (q_j − q̂_j)² / 2: Simbody's
//!   marker goal divides by the total weight of the markers with data in the frame, then adds
//!   the coordinate goals with their own weights.
//! - **Markers in use**: the trial's markers, in column order, that have a task (every one, at
//!   weight 1, when no marker task is given) and a model marker of the same name; other tasks
//!   are ignored, as OpenSim ignores them, and listed. No marker in use is an error.
//! - **Missing markers** (empty or NaN in the trial) drop out of that frame's objective; a
//!   frame with no marker of positive weight left is an error. They count as zero error but
//!   still count in the RMS denominator, as OpenSim reports them.
//! - **Locked** coordinates stay at their `default_value`; a coordinate task on one is dropped.
//! - **Bounds**: only `clamped` coordinates are bounded, by their range.
//! - **Couplers** (`CoordinateCouplerConstraint`) hold exactly: OpenSim 4.6's tool always
//!   passes an infinite constraint weight (see [`ConstraintWeight`]); a finite weight is
//!   available for other uses and makes couplers and locks weighted goals, as Simbody does.
//! - **Links** (`PointConstraint`, `ConstantDistanceConstraint`, `PointOnLineConstraint`,
//!   `WeldConstraint`) hold exactly too, by an augmented Lagrangian (`held.rs`), or are
//!   weighted goals under a finite weight; other constraint classes are refused.
//! - **Start**: the first frame from the default pose (OpenSim's `assemble`), each later one
//!   from the previous solution (`track`). **Time range**: clipped to the trial, ends to the
//!   nearest frames.
//! - **Convergence**: far tighter than OpenSim's `accuracy` (see [`IkSettings`] and
//!   `least_squares.rs`): OpenSim's L-BFGS stops at gradients of ~1e-6, up to 0.14° from the
//!   minimum on subject01's walk; we stop at steps of 1e-10 rad or m.
//! - **Reports**: per frame, total squared error, RMS and max marker error with the worst
//!   marker (OpenSim's `_ik_marker_errors.sto` and log line), the missing markers and the
//!   iterations; the `.mot` in OpenSim's layout (degrees for rotational coordinates).
//!
//! - **Coordinate tasks** pull toward the default value, a manual value, or (`from_file`) the
//!   setup's `coordinate_file` at each frame's time through OpenSim's interpolating quintic GCV
//!   spline of each column (rotational columns converted from degrees).
//!
//! Not handled: prescribed coordinates, a clamped or locked dependent of a coupler, couplers
//! of several independent coordinates (errors say so), orientation sensors.
//!
//! - `tasks.rs`: marker and coordinate tasks and how they match a model and a trial;
//! - `coordinates.rs`: free, held and coupled coordinates, bounds, constraint weight;
//! - `frame.rs`: one frame's residuals and Jacobian;
//! - `solver.rs`: [`InverseKinematics`], the frame loop and time range;
//! - `held.rs`: links held exactly by an augmented Lagrangian;
//! - `report.rs`: per-frame errors and OpenSim's output tables;
//! - `assembly.rs`: [`assemble`], OpenSim's `Model::assemble` (the default pose of a model
//!   with constraints between bodies);
//! - `kalman.rs`: Kalman-smoothed kinematics over a whole trial (the thesis' IK, not OpenSim's).

mod assembly;
mod coordinates;
mod kalman;
mod frame;
mod held;
mod report;
mod solver;
mod tasks;

pub use assembly::{assemble, assembled_default_pose};
pub use coordinates::ConstraintWeight;
pub use kalman::{KalmanIkSettings, SmoothedKinematics};
pub use report::{IkFrame, IkSolution, MarkerErrors};
pub use solver::{IkSettings, IkWorkspace, InverseKinematics};
pub use tasks::{CoordinateTarget, CoordinateTask, CoordinateValues, IgnoredMarkerTask, IkTasks, MarkerTask, MissingFrom};
