//! Errors of the XML layer; each names the file and the 1-based line.

use std::path::PathBuf;

/// The text is not a well-formed XML document.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}:{line}:{column}: malformed XML: {message}", file.display())]
pub struct XmlError {
    pub file: PathBuf,
    pub line: usize,
    pub column: usize,
    pub message: String,
}

/// An edit that cannot be applied without changing the document's structure.
#[derive(Debug, Clone, thiserror::Error)]
pub enum EditError {
    /// The element holds child elements or comments, not a plain value.
    #[error("{}:{line}: <{tag}> holds elements, not a value", file.display())]
    NotAValue { file: PathBuf, line: usize, tag: String },
    /// The edit would overlap an earlier structural edit (or vice versa).
    #[error("{}:{line}: <{tag}> overlaps an element already replaced in this edit", file.display())]
    Overlapping { file: PathBuf, line: usize, tag: String },
}
