//! An OpenSim document: XML with a known version and one root object.

use std::path::Path;

use super::error::OsimError;
use super::path::{canonical_path, resolve_segment, ComponentPath, SegmentMatch};
use super::property::PropertyKind;
use super::version::{Dialect, DocumentVersion};
use crate::io::xml::{Document, ElementId};

/// `<OpenSimDocument Version="…">` with its object (`<Model>`, `<ScaleTool>`, …).
#[derive(Debug, Clone)]
pub struct OsimDocument {
    pub xml: Document,
    pub version: DocumentVersion,
    /// The object element: `<Model>` in a `.osim` file, the tool in a setup file.
    pub object: ElementId,
}

/// The version OpenSim gives a document whose root is the object itself.
const BARE_DOCUMENT_VERSION: u32 = 10500;

impl OsimDocument {
    /// Reads and checks `path`.
    pub fn read(path: &Path) -> Result<Self, OsimError> {
        Self::from_xml(Document::read(path)?)
    }

    /// Reads `path`: `<OpenSimDocument Version="…">` around the object, or the object as the
    /// root element (no `<OpenSimDocument>`, as written before OpenSim 1.6 and in some task and
    /// actuator files, e.g. an `<ActuatorSet>`), which OpenSim reads as version 10500.
    pub fn read_object(path: &Path) -> Result<Self, OsimError> {
        match Self::read(path) {
            Err(OsimError::NotOpenSim { .. }) => {
                let xml = Document::read(path)?;
                let object = xml.root();
                Ok(OsimDocument { xml, version: DocumentVersion { number: BARE_DOCUMENT_VERSION, dialect: Dialect::V2 }, object })
            }
            read => read,
        }
    }

    /// Parses `source`; `file` names it in messages.
    pub fn parse(source: String, file: &Path) -> Result<Self, OsimError> {
        Self::from_xml(Document::parse(source, file)?)
    }

    /// Parses a file's bytes (see [`Document::from_bytes`]); `file` names it in messages.
    pub fn from_bytes(bytes: Vec<u8>, file: &Path) -> Result<Self, OsimError> {
        Self::from_xml(Document::from_bytes(bytes, file)?)
    }

    fn from_xml(xml: Document) -> Result<Self, OsimError> {
        let root = xml.root();
        let file = xml.file().to_path_buf();
        if xml.tag(root) != "OpenSimDocument" {
            return Err(OsimError::NotOpenSim { file, line: xml.line(root), found: xml.tag(root).to_string() });
        }
        let version_text = xml.attribute(root, "Version").unwrap_or("(missing)").to_string();
        let version = version_text
            .trim()
            .parse()
            .ok()
            .and_then(DocumentVersion::from_number)
            .ok_or_else(|| OsimError::UnsupportedVersion { file: file.clone(), line: xml.line(root), version: version_text })?;
        let object = *xml.children(root).first().ok_or(OsimError::NoObject { file, line: xml.line(root) })?;
        Ok(OsimDocument { xml, version, object })
    }

    /// The class of the object, e.g. `Model` or `ScaleTool`.
    pub fn object_class(&self) -> &str {
        self.xml.tag(self.object)
    }

    /// The element a component path names, below the object.
    pub fn resolve(&self, path: &str) -> Result<ElementId, OsimError> {
        let parsed = ComponentPath::parse(path);
        let mut current = self.object;
        for segment in &parsed.segments {
            current = match resolve_segment(&self.xml, current, segment) {
                SegmentMatch::One(id) => id,
                SegmentMatch::None => {
                    let reached = canonical_path(&self.xml, self.object, current);
                    let reason = format!("{reached} has no child {:?}", segment.0);
                    return Err(OsimError::UnknownPath { file: self.xml.file().into(), path: path.into(), reason });
                }
                SegmentMatch::Many(found) => {
                    let candidates = found.iter().map(|&id| self.path_of(id)).collect();
                    return Err(OsimError::AmbiguousPath { file: self.xml.file().into(), path: path.into(), candidates });
                }
            };
        }
        Ok(current)
    }

    /// The canonical component path of an element.
    pub fn path_of(&self, id: ElementId) -> String {
        canonical_path(&self.xml, self.object, id)
    }

    /// Sets the property at `path` to `value`, checking that it is a property (not a component)
    /// and that the new value has the kind of the old one.
    pub fn set_property(&mut self, path: &str, value: &str) -> Result<(), OsimError> {
        let id = self.resolve(path)?;
        let line = self.xml.line(id);
        let bad_value = |expected: String| OsimError::BadValue {
            file: self.xml.file().into(),
            line,
            path: path.into(),
            expected,
            value: value.into(),
        };
        let Some(old) = self.xml.text(id) else {
            return Err(bad_value(format!("a property, but <{}> is a component", self.xml.tag(id))));
        };
        let kind = PropertyKind::of(&old);
        if !kind.accepts(value) {
            return Err(bad_value(kind.describe()));
        }
        self.xml.set_text(id, value)?;
        Ok(())
    }
}
