//! Lossless XML: a read-only element tree over the original text plus value edits that are
//! spliced into that text on output, so an unchanged document writes back byte-identical and an
//! edit changes only the bytes of the values it touches.

mod document;
mod error;
mod parse;
mod text;
mod tree;

pub use document::{Attribute, Document, Element, ElementId};
pub use error::{EditError, XmlError};
pub use text::{escape_attribute, raw_bytes};
pub use tree::{Node, TreeElement};
