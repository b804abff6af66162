//! Analyses along a motion, in the spirit of OpenSim's analyses (`MuscleAnalysis`, …).

mod activation;
mod fiber_analysis;
mod muscle_analysis;

pub use activation::{ActivationError, Activations};
pub use fiber_analysis::{hill_muscles, FiberAnalysis, FiberAnalysisError};
pub use muscle_analysis::MuscleAnalysis;
