//! OpenSim documents (`.osim` models and tool setup files): the version dialect, the root
//! object, component paths, and checked property edits on top of the lossless XML document.

mod control_set;
mod document;
mod error;
mod path;
mod property;
mod version;

pub use control_set::{bounded_control_set_document, control_set_document, ControlLimits};
pub use document::OsimDocument;
pub use error::OsimError;
pub use path::{canonical_path, child_segments, ComponentPath};
pub use property::{format_numbers, PropertyKind};
pub use version::{Dialect, DocumentVersion};
