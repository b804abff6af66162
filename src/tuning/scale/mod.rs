//! Linear scaling with OpenSim ScaleTool semantics: the scale set from marker-pair measurements
//! and manual factors, the model scaled as `Model::scale` does, and markers placed as
//! `MarkerPlacer` does.

mod edits;
mod error;
mod geometry;
mod inertia;
mod marker_placer;
mod marker_set;
mod measurement;
mod model_scaler;
mod path_lengths;
mod scale_set;
mod tool;
mod trials;

pub use error::ScaleError;
pub use inertia::Inertial;
pub use marker_placer::{averaged_frame, move_markers_to_pose, place_markers, MarkerPlacement, MovedMarkers};
pub use marker_set::{marker_set_document, read_marker_set, update_marker_set, MarkerDefinition};
pub use measurement::{frame_range, measure, DefaultPoseMarkers, MeasuredFactor, PairLength};
pub use model_scaler::{reparse, scale_model, ScaledModel};
pub use path_lengths::PathRescale;
pub use scale_set::{BodyScaleFactors, ScaleSet};
pub use tool::{run_scale_tool, ScaleOutcome, LARGEST_SCALE_FACTOR};
pub use trials::{trials_setup, SubjectFile, SUBJECT_FILE};
