//! Analyses along a motion, in the spirit of OpenSim's analyses (`MuscleAnalysis`, …).

mod muscle_analysis;

pub use muscle_analysis::MuscleAnalysis;
