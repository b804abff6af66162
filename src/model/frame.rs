//! Frames: where a joint, marker or path point is attached, as a body plus the chain of
//! `PhysicalOffsetFrame` offsets (and `StationDefinedFrame`s, as offsets computed from their
//! stations) leading from that body to the frame.

use std::collections::HashMap;

use nalgebra::Vector3;

use serde::Serialize;

use crate::io::osim::OsimDocument;
use crate::io::xml::ElementId;

use super::error::ModelError;
use super::orientation::body_fixed_xyz;
use super::reader::ComponentReader;
use super::station_frame::station_defined_offset;

/// A fixed transform of a frame in its parent: translation (m) and body-fixed X-Y-Z Euler
/// angles (rad), OpenSim's `translation`/`orientation`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Offset {
    pub translation: [f64; 3],
    pub orientation: [f64; 3],
}

/// A frame rigidly attached to `body` (a body name, or `ground`): X_body_frame is the product of
/// `offsets` in order, the first one expressed in the body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameChain {
    /// The frame's own name: the offset frame's, or the body's when there is no offset.
    pub name: String,
    pub body: String,
    pub offsets: Vec<Offset>,
}

impl FrameChain {
    /// A point at `location` (m) in this frame, expressed in its body (m).
    pub fn point_in_body(&self, location: [f64; 3]) -> [f64; 3] {
        let point = self.offsets.iter().rev().fold(Vector3::from(location), |point, offset| {
            body_fixed_xyz(offset.orientation) * point + Vector3::from(offset.translation)
        });
        point.into()
    }
}

/// Every body and offset frame of a model keyed by OpenSim component path (`/bodyset/femur_r`,
/// `/jointset/knee_r/femur_r_offset`, `/ground`), for resolving socket paths.
pub struct FrameIndex {
    entries: HashMap<String, FrameEntry>,
}

enum FrameEntry {
    Body(String),
    Offset { element: ElementId, parent_socket: String, offset: Offset },
}

impl FrameIndex {
    /// Indexes `<Ground>`, bodies and every `PhysicalOffsetFrame` in the model.
    pub fn new(document: &OsimDocument, bodies: &[(String, ElementId)]) -> Result<Self, ModelError> {
        let mut entries = HashMap::new();
        for (name, element) in bodies {
            entries.insert(opensim_path(document, *element), FrameEntry::Body(name.clone()));
        }
        for id in document.xml.ids().filter(|&id| document.xml.tag(id) == "PhysicalOffsetFrame") {
            let reader = ComponentReader::new(document, id);
            let offset = Offset { translation: reader.vec3_or("translation", [0.0; 3])?, orientation: reader.vec3_or("orientation", [0.0; 3])? };
            let parent_socket = reader.text("socket_parent")?;
            entries.insert(opensim_path(document, id), FrameEntry::Offset { element: id, parent_socket, offset });
        }
        let mut index = FrameIndex { entries };
        index.add_station_defined_frames(document, bodies)?;
        Ok(index)
    }

    /// Every `StationDefinedFrame`, as an offset of its stations' body. Its stations may hang
    /// on another such frame, so they are placed in passes until none is left.
    fn add_station_defined_frames(&mut self, document: &OsimDocument, bodies: &[(String, ElementId)]) -> Result<(), ModelError> {
        let xml = &document.xml;
        let stations: HashMap<String, ElementId> = xml.ids().filter(|&id| xml.tag(id) == "Station").map(|id| (opensim_path(document, id), id)).collect();
        let body_paths: HashMap<&str, String> = bodies.iter().map(|(name, element)| (name.as_str(), opensim_path(document, *element))).collect();
        let mut pending: Vec<ElementId> = xml.ids().filter(|&id| xml.tag(id) == "StationDefinedFrame").collect();
        while !pending.is_empty() {
            let mut unplaced = Vec::new();
            let mut last_error = None;
            for &id in &pending {
                match station_defined_offset(ComponentReader::new(document, id), self, &stations) {
                    Ok((body, offset)) => {
                        let parent_socket = body_paths.get(body.as_str()).cloned().unwrap_or_default();
                        self.entries.insert(opensim_path(document, id), FrameEntry::Offset { element: id, parent_socket, offset });
                    }
                    Err(error) => {
                        unplaced.push(id);
                        last_error = Some(error);
                    }
                }
            }
            if unplaced.len() == pending.len() {
                return Err(last_error.expect("an unplaced frame has its error"));
            }
            pending = unplaced;
        }
        Ok(())
    }

    /// Resolves the socket path `socket` written on `owner` (relative to the owner, or absolute).
    pub fn resolve(&self, owner: ComponentReader, socket: &str, property: &str) -> Result<FrameChain, ModelError> {
        let mut offsets = Vec::new();
        let mut current = join_socket(&opensim_path(owner.document, owner.element), socket);
        let name = current.rsplit('/').next().unwrap_or_default().to_string();
        let mut current_owner = owner;
        for _ in 0..=self.entries.len() {
            match self.entries.get(&current) {
                Some(FrameEntry::Body(body)) => {
                    offsets.reverse();
                    return Ok(FrameChain { name, body: body.clone(), offsets });
                }
                Some(FrameEntry::Offset { element, parent_socket, offset }) => {
                    offsets.push(offset.clone());
                    current_owner = owner.at(*element);
                    current = join_socket(&current, parent_socket);
                }
                None => return Err(current_owner.unknown(&format!("frame in <{property}>"), socket)),
            }
        }
        Err(owner.unknown(&format!("frame in <{property}> (cyclic offsets)"), socket))
    }
}

/// The OpenSim component path of an element: the names of its named ancestors below `<Model>`,
/// a set of the model written without a name (4.0 development files) named as OpenSim names it,
/// by its class in lower case (`/bodyset/…`).
pub fn opensim_path(document: &OsimDocument, id: ElementId) -> String {
    let xml = &document.xml;
    let mut names = Vec::new();
    let mut current = Some(id);
    while let Some(element) = current.filter(|&e| e != document.object) {
        match xml.name(element) {
            Some(name) => names.push(name.to_string()),
            None if xml.parent(element) == Some(document.object) && xml.tag(element).ends_with("Set") => names.push(xml.tag(element).to_lowercase()),
            None => {}
        }
        current = xml.parent(element);
    }
    names.reverse();
    format!("/{}", names.join("/"))
}

/// Applies socket path `socket` (absolute, or relative to component `from`) with `..` steps.
pub fn join_socket(from: &str, socket: &str) -> String {
    let mut parts: Vec<&str> = if socket.starts_with('/') { Vec::new() } else { from.split('/').filter(|p| !p.is_empty()).collect() };
    for part in socket.split('/').filter(|p| !p.is_empty() && *p != ".") {
        if part == ".." {
            parts.pop();
        } else {
            parts.push(part);
        }
    }
    format!("/{}", parts.join("/"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn socket_paths_join_like_opensim() {
        assert_eq!(join_socket("/jointset/knee_r", "femur_r_offset"), "/jointset/knee_r/femur_r_offset");
        assert_eq!(join_socket("/jointset/knee_r", "/bodyset/femur_r"), "/bodyset/femur_r");
        assert_eq!(join_socket("/jointset/knee_r/femur_r_offset", "../../../bodyset/femur_r"), "/bodyset/femur_r");
        assert_eq!(join_socket("/markerset/R.ASIS", "../../ground"), "/ground");
    }
}
