//! Review of model changes: a document flattened to component paths and property values, and a
//! semantic diff of two documents that ignores formatting, comments and number spelling.

mod diff;
mod flatten;

pub use diff::{diff, Change, Difference, DocumentDiff};
pub use flatten::{flatten, FlatDocument, FlatEntry};
