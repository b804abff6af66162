//! Solvers over the compiled mechanics: bounded nonlinear least squares and what is built on
//! it. clarabel is used only here.
//!
//! - `least_squares.rs`: bounded Levenberg–Marquardt ([`LeastSquares`]);
//! - `box_qp.rs`: the box-constrained QP of a bounded step (clarabel);
//! - `power_sum.rs`: min Σ|xᵢ|ᵖ under equalities and bounds, on power cones ([`minimise_power_sum`]);
//! - `sparse_qp.rs`: a sparse QP with a diagonal Hessian over whole trajectories ([`SparseQp`]);
//! - `false_position.rs`: a bracketed scalar root without derivatives ([`false_position`]);
//! - `uncoupled_roots.rs`: OpenSim's `RootSolver`, Brent's method on every component of an
//!   uncoupled vector function at once ([`uncoupled_roots`]);
//! - `kalman_smoother.rs`: a Rauch–Tung–Striebel smoother of coordinates with a constant 4th
//!   derivative (De Groote et al. 2008);
//! - `ik/`: inverse kinematics as OpenSim 4.6 computes it ([`InverseKinematics`]);
//! - `error.rs`: [`IkError`].

mod box_qp;
mod error;
mod false_position;
pub mod kalman_smoother;
pub mod ik;
mod least_squares;
pub mod nlp;
mod power_sum;
pub mod qp;
mod sparse_qp;
mod uncoupled_roots;

pub use box_qp::BoxQpError;
pub use error::IkError;
pub use false_position::false_position;
pub use ik::{
    assemble, assembled_default_pose, ConstraintWeight, CoordinateTarget, CoordinateTask, CoordinateValues, IgnoredMarkerTask, IkFrame, IkSettings, IkSolution, IkTasks, IkWorkspace,
    InverseKinematics, KalmanIkSettings, MarkerErrors, MarkerTask, MissingFrom, SmoothedKinematics,
};
pub use power_sum::{minimise_power_sum, PowerSumSolution};
pub use sparse_qp::{SparseQp, SparseQpSolution, SparseRow};
pub use uncoupled_roots::uncoupled_roots;
pub use least_squares::{Bounds, LeastSquares, LeastSquaresOptions, LeastSquaresProblem, LeastSquaresReport, LeastSquaresStatus};
