//! osim-tune: read, check and tune OpenSim musculoskeletal models.
//!
//! Data flows one way: [`io`] (documents and tables, lossless) → [`model`], [`setup`] (typed
//! views of model and tool documents) → [`mechanics`] (kinematics, paths, muscles) →
//! [`solvers`] (inverse kinematics) → [`tuning`] (scaling) → [`analysis`], [`validation`],
//! [`review`], [`figures`] → [`cli`] (the only place that prints). See `ARCHITECTURE.md` for the map.

pub mod analysis;
pub mod cli;
pub mod figures;
pub mod io;
pub mod mechanics;
pub mod model;
pub mod review;
pub mod setup;
pub mod solvers;
pub mod tuning;
pub mod validation;
