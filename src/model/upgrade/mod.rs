//! OpenSim 4's conversion of a 2.x/3.x model into its own format, as its `updateFromXMLNode`s
//! rewrite an older document while loading it: `ground` becomes `<Ground>`, joints leave their
//! bodies for a `JointSet` with offset frames, names of bodies and coordinates become socket
//! paths, display objects become attached geometry and appearances. Values the conversion
//! passes through a C++ stream keep six significant digits, as in OpenSim. The result is a 4.x
//! document (version [`UPGRADED_VERSION`]) that OpenSim 4 and every osim-tune command read as
//! OpenSim 4 reads the original.

mod body;
mod component;
mod joint;
mod values;

use std::borrow::Cow;
use std::collections::HashMap;

use crate::io::osim::{Dialect, OsimDocument};
use crate::io::xml::{raw_bytes, TreeElement};

use super::error::ModelError;
use values::Values;

/// The document version the conversion writes: OpenSim 4.0's.
pub const UPGRADED_VERSION: u32 = 40000;

/// `document` in the 4.x format: a 2.x/3.x model converted, a 4.x one borrowed as it is.
pub fn upgrade(document: &OsimDocument) -> Result<Cow<'_, OsimDocument>, ModelError> {
    if document.version.dialect == Dialect::V4 {
        return Ok(Cow::Borrowed(document));
    }
    let xml = &document.xml;
    let values = Values { file: xml.file() };
    let mut model = xml.tree(document.object);
    if model.tag != "Model" {
        return Err(ModelError::NotAModel { file: xml.file().into(), line: model.line, found: model.tag.clone() });
    }
    let upgrade = Upgrade { values, version: document.version.number, coordinate_joints: coordinate_joints(&model) };
    upgrade.model(&mut model)?;
    let mut text = format!("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"{UPGRADED_VERSION}\">\n");
    model.print(1, &mut text);
    text.push_str("</OpenSimDocument>\n");
    OsimDocument::from_bytes(raw_bytes(&text), xml.file()).map(Cow::Owned).map_err(|error| upgrade.values.unsupported(&model, &format!("the converted model does not read back: {error}")))
}

/// One conversion: the document's version and where each coordinate's joint is.
struct Upgrade<'a> {
    values: Values<'a>,
    version: u32,
    /// Joint of each coordinate (3.x: the `Joint` inside a body owns its `CoordinateSet`).
    coordinate_joints: HashMap<String, String>,
}

impl Upgrade<'_> {
    /// `Model::updateFromXMLNode` (< 30501): `ground` out of the `BodySet` as `<Ground>`, each
    /// body's joint into a `JointSet` after it; then every component's own conversion, and the
    /// model's sets named as OpenSim 4 names them (`bodyset`, `forceset`, …).
    fn model(&self, model: &mut TreeElement) -> Result<(), ModelError> {
        without_whitespace(model);
        name_components(model);
        let mut ground = None;
        let mut joints = Vec::new();
        if let Some(objects) = model.child_mut("BodySet").and_then(|set| set.child_mut("objects")) {
            let mut bodies = Vec::new();
            for mut body in objects.take_all() {
                let name = body.name().unwrap_or_default().to_string();
                if let Some(joint) = body.take("Joint").and_then(|mut holder| holder.take_all().into_iter().next()) {
                    joints.push(self.joint(joint, &name)?);
                }
                if name == "ground" {
                    ground = Some(self.ground(body)?);
                } else {
                    bodies.push(self.body(body)?);
                }
            }
            bodies.into_iter().for_each(|body| objects.push(body));
        }
        if model.child("BodySet").is_some() {
            let mut joint_objects = TreeElement::new("objects");
            joints.into_iter().for_each(|joint| joint_objects.push(joint));
            let mut joint_set = TreeElement::new("JointSet");
            joint_set.push(joint_objects);
            model.insert_after("BodySet", joint_set);
        }
        if let Some(ground) = ground {
            model.insert_before("BodySet", ground);
        }
        for child in model.elements_mut() {
            if child.tag.ends_with("Set") {
                child.set_attribute("name", &child.tag.to_lowercase());
            }
            self.components(child)?;
        }
        Ok(())
    }

    /// Each component in `element` and below, converted by its class.
    fn components(&self, element: &mut TreeElement) -> Result<(), ModelError> {
        self.component(element)?;
        for child in element.elements_mut() {
            self.components(child)?;
        }
        Ok(())
    }

    /// The socket path of a body named in a 3.x property (`ground` is `/ground`).
    pub(super) fn body_path(body: &str) -> String {
        if body == "ground" {
            "/ground".into()
        } else {
            format!("/bodyset/{body}")
        }
    }

    /// The socket path of a coordinate: `/jointset/<joint>/<coordinate>`, or its bare name when no
    /// joint has it (OpenSim's fallback).
    fn coordinate_path(&self, coordinate: &str) -> String {
        match self.coordinate_joints.get(coordinate) {
            Some(joint) => format!("/jointset/{joint}/{coordinate}"),
            None => coordinate.to_string(),
        }
    }
}

/// Every coordinate of the 3.x model's joints with its joint's name.
fn coordinate_joints(model: &TreeElement) -> HashMap<String, String> {
    let mut map = HashMap::new();
    let bodies = model.child("BodySet").and_then(|set| set.child("objects"));
    for body in bodies.into_iter().flat_map(|objects| objects.elements()) {
        for joint in body.child("Joint").into_iter().flat_map(|holder| holder.elements()) {
            let joint_name = joint.name().filter(|n| !n.is_empty()).map_or_else(|| joint.tag.to_lowercase(), str::to_string);
            let coordinates = joint.child("CoordinateSet").and_then(|set| set.child("objects"));
            for coordinate in coordinates.into_iter().flat_map(|objects| objects.elements()) {
                if let Some(name) = coordinate.name() {
                    map.insert(name.to_string(), joint_name.clone());
                }
            }
        }
    }
    map
}

/// Sets whose members are components (a `FunctionSet`'s functions or a contact force's
/// parameters are not).
const COMPONENT_SETS: [&str; 11] =
    ["BodySet", "MarkerSet", "ForceSet", "ConstraintSet", "ControllerSet", "ProbeSet", "ComponentSet", "ContactGeometrySet", "WrapObjectSet", "PathPointSet", "PathWrapSet"];

/// `Component::updateFromXMLNode` (< 30500): whitespace is no longer allowed in names, and an
/// unnamed component (e.g. a `PathWrap`) is named after its class, lowercase — the second of a
/// name `<name>_0`, the third `<name>_1`, as OpenSim renames duplicates; a body's
/// `WrapObjectSet` is `wrapobjectset`. Groups of a set are not components and keep their names.
fn name_components(element: &mut TreeElement) {
    for child in element.elements_mut() {
        without_whitespace(child);
        if child.tag == "WrapObjectSet" {
            child.set_attribute("name", "wrapobjectset");
        }
        if COMPONENT_SETS.contains(&child.tag.as_str()) {
            if let Some(objects) = child.child_mut("objects") {
                name_unnamed(objects);
            }
        }
        if child.tag != "groups" {
            name_components(child);
        }
    }
}

/// Names the unnamed members of a set's `objects` after their class.
fn name_unnamed(objects: &mut TreeElement) {
    let mut generated: HashMap<String, usize> = HashMap::new();
    for member in objects.elements_mut().filter(|m| m.name().is_none_or(str::is_empty)) {
        let base = member.tag.to_lowercase();
        let count = generated.entry(base.clone()).or_insert(0);
        let name = if *count == 0 { base } else { format!("{base}_{}", *count - 1) };
        *count += 1;
        member.set_attribute("name", &name);
    }
}

fn without_whitespace(component: &mut TreeElement) {
    if let Some(name) = component.name().filter(|n| n.contains(char::is_whitespace)) {
        let name: String = name.chars().filter(|c| !c.is_whitespace()).collect();
        component.set_attribute("name", &name);
    }
}
