//! Markers: points fixed in a frame.

use serde::Serialize;

use super::error::ModelError;
use super::frame::{FrameChain, FrameIndex};
use super::reader::ComponentReader;
use crate::io::osim::Dialect;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarkerSpec {
    pub name: String,
    pub frame: FrameChain,
    /// m, in the frame.
    pub location: [f64; 3],
    /// Fixed markers are not moved by marker placement.
    pub fixed: bool,
}

impl MarkerSpec {
    pub fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<MarkerSpec, ModelError> {
        Ok(MarkerSpec {
            name: reader.name(),
            frame: attachment_frame(reader, dialect, frames)?,
            location: reader.vec3("location")?,
            fixed: reader.boolean_or("fixed", false)?,
        })
    }
}

/// The frame a point-like component hangs on: 4.x `socket_parent_frame`, 3.x `body` (or, as
/// OpenSim 4 reads a 4.x component pasted into a 3.x file, its `socket_parent_frame`).
pub fn attachment_frame(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<FrameChain, ModelError> {
    let pasted = reader.child("body").is_none() && reader.child("socket_parent_frame").is_some();
    if dialect == Dialect::V4 || pasted {
        frames.resolve(reader, &reader.text("socket_parent_frame")?, "socket_parent_frame")
    } else {
        let body = reader.text("body")?;
        Ok(FrameChain { name: body.clone(), body, offsets: Vec::new() })
    }
}
