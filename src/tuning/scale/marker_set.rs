//! OpenSim's `GenericModelMaker` marker step (`Model::updateMarkerSet`): the markers of a
//! marker-set file replace the model's markers of the same name and are appended to its
//! `MarkerSet`, written in the model's 4.x form.

use std::path::Path;

use super::edits::indent_unit;
use super::error::ScaleError;
use crate::io::osim::{Dialect, OsimDocument};
use crate::io::xml::{escape_attribute, ElementId};
use crate::model::{ComponentReader, ModelSpec};

/// A marker as a marker-set file gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerDefinition {
    pub name: String,
    /// Socket path of the frame (`/bodyset/<body>` for a 3.x `<body>`).
    pub parent_frame: String,
    /// m, in that frame.
    pub location: [f64; 3],
    pub fixed: bool,
}

/// Reads the markers of a `<MarkerSet>` document (3.x `<body>` or 4.x `socket_parent_frame`).
pub fn read_marker_set(path: &Path) -> Result<Vec<MarkerDefinition>, ScaleError> {
    let document = OsimDocument::read(path)?;
    let set = ComponentReader::new(&document, document.object);
    if set.class() != "MarkerSet" {
        return Err(unsupported(&document, document.object, &format!("expected a <MarkerSet>, found <{}>", set.class())));
    }
    let mut markers = Vec::new();
    for element in set.listed_objects(document.object) {
        let marker = set.at(element);
        let parent_frame = match document.version.dialect {
            Dialect::V4 => marker.text("socket_parent_frame")?,
            _ => match marker.text("body")?.as_str() {
                "ground" => "/ground".to_string(),
                body => format!("/bodyset/{body}"),
            },
        };
        markers.push(MarkerDefinition { name: marker.name(), parent_frame, location: marker.vec3("location")?, fixed: marker.boolean_or("fixed", false)? });
    }
    Ok(markers)
}

/// `model` with `markers` merged into its `MarkerSet`; every marker frame must exist.
pub fn update_marker_set(model: &OsimDocument, markers: &[MarkerDefinition]) -> Result<OsimDocument, ScaleError> {
    let xml = &model.xml;
    let set = xml.children(model.object).iter().copied().find(|&c| xml.tag(c) == "MarkerSet");
    let Some(set) = set else { return Err(unsupported(model, model.object, "the model has no <MarkerSet> to add markers to")) };
    let Some(objects) = xml.child(set, "objects") else { return Err(unsupported(model, set, "its <MarkerSet> has no <objects>")) };
    check_frames(model, markers)?;
    let indentation = xml.indentation(objects);
    let unit = indent_unit(indentation);
    let inner = format!("{indentation}{unit}");
    let mut text = String::from("<objects>");
    for &kept in xml.children(objects).iter().filter(|&&m| !markers.iter().any(|d| xml.name(m) == Some(d.name.as_str()))) {
        text.push_str(&format!("\n{inner}{}", xml.element_source(kept)));
    }
    for marker in markers {
        text.push_str(&format!("\n{inner}{}", marker_element(marker, &inner, unit)));
    }
    text.push_str(&format!("\n{indentation}</objects>"));
    let mut updated = model.clone();
    updated.xml.replace_element(objects, &text)?;
    super::reparse(&updated)
}

/// The markers of `model` (4.x) as a `MarkerSet` document of their own, as OpenSim's
/// `Model::writeMarkerFile` writes the MarkerPlacer's `output_marker_file`: the model's
/// `<MarkerSet>` as written there (edits applied), one level deep (an empty set without one).
pub fn marker_set_document(model: &OsimDocument) -> Result<String, ScaleError> {
    let model = super::reparse(model)?;
    let xml = &model.xml;
    let set = xml.children(model.object).iter().copied().find(|&c| xml.tag(c) == "MarkerSet");
    let body = match set {
        Some(set) => {
            let indentation = xml.indentation(set);
            let unit = indent_unit(indentation);
            xml.element_source(set).replace(&format!("\n{indentation}"), &format!("\n{unit}"))
        }
        None => "<MarkerSet name=\"markerset\">\n\t\t<objects />\n\t\t<groups />\n\t</MarkerSet>".to_string(),
    };
    Ok(format!("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"{}\">\n\t{body}\n</OpenSimDocument>\n", model.version.number))
}

/// A 4.x `<Marker>` element; `indentation` is that of its start tag.
fn marker_element(marker: &MarkerDefinition, indentation: &str, unit: &str) -> String {
    let [x, y, z] = marker.location;
    let property = |tag: &str, value: String| format!("\n{indentation}{unit}<{tag}>{value}</{tag}>");
    format!(
        "<Marker name=\"{}\">{}{}{}\n{indentation}</Marker>",
        escape_attribute(&marker.name),
        property("socket_parent_frame", escape_attribute(&marker.parent_frame).into_owned()),
        property("location", format!("{x} {y} {z}")),
        property("fixed", marker.fixed.to_string())
    )
}

/// Every marker's frame must be a frame of the model.
fn check_frames(model: &OsimDocument, markers: &[MarkerDefinition]) -> Result<(), ScaleError> {
    let frames = ModelSpec::frame_index(model)?;
    let owner = ComponentReader::new(model, model.object);
    for marker in markers {
        frames.resolve(owner, &marker.parent_frame, &format!("socket_parent_frame of marker {}", marker.name))?;
    }
    Ok(())
}

fn unsupported(document: &OsimDocument, element: ElementId, problem: &str) -> ScaleError {
    ScaleError::Unsupported { file: document.xml.file().into(), line: document.xml.line(element), component: document.path_of(element), problem: problem.into() }
}
