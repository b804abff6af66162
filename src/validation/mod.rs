//! Agreement with OpenSim: comparisons of our mechanics against golden tables that OpenSim 4.6
//! produced, used by the conformance tests and `cargo xtask validate`.

mod geometry;
mod golden;

pub use geometry::{compare_geometry, GeometryComparison, Worst};
pub use golden::{GoldenError, GoldenPoses, GoldenTable};
