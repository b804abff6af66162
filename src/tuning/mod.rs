//! Making a generic model subject-specific: linear scaling with OpenSim ScaleTool semantics.

pub mod functional;
pub mod knee_axis;
pub mod scale;
