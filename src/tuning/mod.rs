//! Making a generic model subject-specific: linear scaling with OpenSim ScaleTool semantics.

pub mod scale;
