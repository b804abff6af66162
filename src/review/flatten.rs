//! A document as an ordered list of components and property values keyed by canonical path.

use std::collections::HashMap;

use crate::io::osim::OsimDocument;
use crate::io::xml::ElementId;

/// One addressable element.
#[derive(Debug, Clone, PartialEq)]
pub enum FlatEntry {
    /// An element holding other elements; `class` is its tag.
    Component { class: String },
    /// A value element (or an attribute other than `name`, keyed `path@attribute`).
    Property { value: String },
}

/// Entries in document order with an index by path.
#[derive(Debug, Clone, Default)]
pub struct FlatDocument {
    pub entries: Vec<(String, FlatEntry)>,
    index: HashMap<String, usize>,
}

impl FlatDocument {
    pub fn get(&self, path: &str) -> Option<&FlatEntry> {
        self.index.get(path).map(|&i| &self.entries[i].1)
    }

    /// The same entries under paths mapped by `rename` (e.g. to match components a newer
    /// OpenSim writes under another name).
    pub fn renamed(self, rename: impl Fn(&str) -> String) -> FlatDocument {
        let mut flat = FlatDocument::default();
        for (path, entry) in self.entries {
            flat.push(rename(&path), entry);
        }
        flat
    }

    fn push(&mut self, path: String, entry: FlatEntry) {
        self.index.insert(path.clone(), self.entries.len());
        self.entries.push((path, entry));
    }
}

/// The document version from which OpenSim names a force's `GeometryPath` `path`
/// (`Force::updateFromXMLNode`: older ones are renamed so when read).
const PATH_RENAMED_VERSION: u32 = 40500;

/// [`flatten`] of `document` as OpenSim reads it for comparison with a document of version
/// `other_version`: a 4.x document older than 40500 compared with a newer one has its forces'
/// `GeometryPath`s under the name OpenSim ≥ 4.5 gives them, `path`. Also returns how many were
/// renamed.
pub fn flatten_for_comparison(document: &OsimDocument, other_version: u32) -> (FlatDocument, usize) {
    let flat = flatten(document);
    let older = document.version.dialect == crate::io::osim::Dialect::V4 && document.version.number < PATH_RENAMED_VERSION && other_version >= PATH_RENAMED_VERSION;
    if !older {
        return (flat, 0);
    }
    let paths: Vec<String> = flat.entries.iter().filter(|(path, entry)| matches!(entry, FlatEntry::Component { class } if class == "GeometryPath") && !path.ends_with("/path")).map(|(path, _)| path.clone()).collect();
    if paths.is_empty() {
        return (flat, 0);
    }
    let rename = |path: &str| {
        for old in &paths {
            if let Some(rest) = path.strip_prefix(old.as_str()).filter(|rest| rest.is_empty() || rest.starts_with(['/', '@'])) {
                let parent = &old[..old.rfind('/').unwrap_or(0)];
                return format!("{parent}/path{rest}");
            }
        }
        path.to_string()
    };
    let count = paths.len();
    (flat.renamed(rename), count)
}

/// Flattens the object of `document` (the `<Model>` or tool) with canonical paths.
pub fn flatten(document: &OsimDocument) -> FlatDocument {
    let mut flat = FlatDocument::default();
    visit(document, document.object, "", &mut flat);
    flat
}

fn visit(document: &OsimDocument, id: ElementId, path: &str, flat: &mut FlatDocument) {
    let xml = &document.xml;
    for attribute in &xml.element(id).attributes {
        if attribute.name != "name" {
            flat.push(format!("{path}@{}", attribute.name), FlatEntry::Property { value: attribute.value.clone() });
        }
    }
    for (child, segment) in crate::io::osim::child_segments(xml, id) {
        let child_path = format!("{path}/{segment}");
        match xml.text(child) {
            Some(value) if xml.element(child).attributes.is_empty() => {
                flat.push(child_path, FlatEntry::Property { value: value.into_owned() });
            }
            _ => {
                flat.push(child_path.clone(), FlatEntry::Component { class: xml.tag(child).to_string() });
                visit(document, child, &child_path, flat);
            }
        }
    }
}
