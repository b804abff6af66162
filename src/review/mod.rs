//! Review of model changes: a document flattened to component paths and property values, and a
//! semantic diff of two documents that ignores formatting, comments and number spelling.

mod diff;
mod flatten;

pub use diff::{diff, diff_flat, diff_within, Change, Difference, DocumentDiff, Tolerance};
pub use flatten::{flatten, flatten_for_comparison, FlatDocument, FlatEntry};
