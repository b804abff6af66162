//! `ModelSpec`: everything a model document says, typed, in both the 4.x and the 3.x layout.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::actuator::ActuatorSpec;
use super::body::BodySpec;
use super::constraint::ConstraintSpec;
use super::controller::ControllerSpec;
use super::coordinate::CoordinateSpec;
use super::error::ModelError;
use super::force::{is_muscle_class, ForceSpec};
use super::frame::FrameIndex;
use super::joint::JointSpec;
use super::marker::MarkerSpec;
use super::probe::ProbeSpec;
use super::reader::ComponentReader;
use super::wrap_object::WrapObjectSpec;
use crate::io::osim::{Dialect, OsimDocument};
use crate::io::xml::ElementId;

/// The typed content of a `<Model>`. Order follows the document (OpenSim's set order).
#[derive(Debug, Clone, Serialize)]
pub struct ModelSpec {
    /// The file the model was read from, for messages.
    #[serde(skip)]
    pub file: PathBuf,
    pub name: String,
    pub version: u32,
    /// m/s², in ground.
    pub gravity: [f64; 3],
    /// Bodies other than ground.
    pub bodies: Vec<BodySpec>,
    pub joints: Vec<JointSpec>,
    pub markers: Vec<MarkerSpec>,
    pub forces: Vec<ForceSpec>,
    /// The ForceSet's `CoordinateActuator`s, `PointActuator`s and `TorqueActuator`s (also in
    /// `forces`).
    pub actuators: Vec<ActuatorSpec>,
    pub constraints: Vec<ConstraintSpec>,
    pub wrap_objects: Vec<WrapObjectSpec>,
    /// The enabled controllers of the `ControllerSet` (controls files resolved against the
    /// model's directory).
    pub controllers: Vec<ControllerSpec>,
    /// The `ProbeSet`'s probes.
    pub probes: Vec<ProbeSpec>,
}

/// Name OpenSim gives the ground frame.
pub const GROUND: &str = "ground";

impl ModelSpec {
    pub fn read(document: &OsimDocument) -> Result<ModelSpec, ModelError> {
        let model = ComponentReader::new(document, document.object);
        if model.class() != "Model" {
            return Err(ModelError::NotAModel { file: document.xml.file().into(), line: model.line(), found: model.class().into() });
        }
        let dialect = document.version.dialect;
        let body_elements = body_elements(model, dialect);
        let frames = FrameIndex::new(document, &body_elements)?;
        let mut spec = ModelSpec {
            file: document.xml.file().into(),
            name: model.name(),
            version: document.version.number,
            gravity: if model.child("gravity").is_some() { model.vec3("gravity")? } else { [0.0, -9.80665, 0.0] },
            bodies: Vec::new(),
            joints: Vec::new(),
            markers: Vec::new(),
            forces: Vec::new(),
            actuators: Vec::new(),
            constraints: Vec::new(),
            wrap_objects: Vec::new(),
            controllers: Vec::new(),
            probes: Vec::new(),
        };
        for (name, element) in &body_elements {
            let body = model.at(*element);
            if let Some(set) = body.child("WrapObjectSet") {
                for w in body.listed_objects(set) {
                    spec.wrap_objects.push(WrapObjectSpec::read(body.at(w), name)?);
                }
            }
            if name == GROUND {
                continue;
            }
            spec.bodies.push(BodySpec::read(body, document.version)?);
            if dialect != Dialect::V4 {
                if let Some(joint) = body.child("Joint").and_then(|j| document.xml.children(j).first().copied()) {
                    spec.joints.push(JointSpec::read_v3(body.at(joint), name)?);
                }
            }
        }
        for joint in set_members(model, "JointSet").into_iter().chain(component_members(model, |class| class.ends_with("Joint"))) {
            spec.joints.push(JointSpec::read_v4(model.at(joint), &frames)?);
        }
        for marker in set_members(model, "MarkerSet").into_iter().chain(component_members(model, |class| class == "Marker")) {
            spec.markers.push(MarkerSpec::read(model.at(marker), dialect, &frames)?);
        }
        for force in set_members(model, "ForceSet").into_iter().chain(component_members(model, is_force_class)) {
            spec.forces.push(ForceSpec::read(model.at(force), dialect, &frames)?);
            spec.actuators.extend(ActuatorSpec::read(model.at(force))?);
        }
        for constraint in set_members(model, "ConstraintSet").into_iter().chain(component_members(model, |class| class.ends_with("Constraint"))) {
            spec.constraints.push(ConstraintSpec::read(model.at(constraint), dialect, &frames)?);
        }
        let directory = spec.file.parent().unwrap_or(Path::new("")).to_path_buf();
        for controller in set_members(model, "ControllerSet").into_iter().chain(component_members(model, |class| class.ends_with("Controller"))) {
            spec.controllers.extend(ControllerSpec::read(model.at(controller), &directory)?);
        }
        for probe in set_members(model, "ProbeSet") {
            spec.probes.push(ProbeSpec::read(model.at(probe))?);
        }
        Ok(spec)
    }

    /// Every body and offset frame of the model, for resolving the frame a component is on.
    pub fn frame_index(document: &OsimDocument) -> Result<FrameIndex, ModelError> {
        let model = ComponentReader::new(document, document.object);
        FrameIndex::new(document, &body_elements(model, document.version.dialect))
    }

    /// All coordinates, joint by joint.
    pub fn coordinates(&self) -> impl Iterator<Item = &CoordinateSpec> {
        self.joints.iter().flat_map(|joint| joint.coordinates.iter())
    }

    pub fn muscles(&self) -> impl Iterator<Item = &ForceSpec> {
        self.forces.iter().filter(|force| force.is_muscle())
    }
}

/// Ground and the bodies, named: 4.x `<Ground>` plus `BodySet` and the bodies among the model's
/// `<components>` (where `Model::addComponent` puts them, e.g. OpenSim's `ModelFactory`); 3.x
/// `BodySet` (with `ground`).
fn body_elements(model: ComponentReader, dialect: Dialect) -> Vec<(String, ElementId)> {
    let mut bodies = Vec::new();
    if dialect == Dialect::V4 {
        if let Some(ground) = model.child("Ground") {
            bodies.push((GROUND.to_string(), ground));
        }
    }
    for body in set_members(model, "BodySet").into_iter().chain(component_members(model, |class| class == "Body")) {
        bodies.push((model.at(body).name(), body));
    }
    bodies
}

/// Whether a component of this class is a force: muscles, actuators, `…Force` (e.g.
/// `CoordinateLimitForce`, `ExpressionBasedCoordinateForce`), ligaments and springs.
pub(super) fn is_force_class(class: &str) -> bool {
    is_muscle_class(class) || ["Actuator", "Force", "Ligament", "Spring"].iter().any(|suffix| class.ends_with(suffix))
}

/// The model's `<components>` of a class `class` accepts (empty without the list).
fn component_members(model: ComponentReader, class: impl Fn(&str) -> bool) -> Vec<ElementId> {
    let xml = &model.document.xml;
    model.child("components").map(|list| xml.children(list).iter().copied().filter(|&c| class(xml.tag(c))).collect()).unwrap_or_default()
}

/// Members of the model's set `<tag>` (e.g. `ForceSet`), empty when the set is absent.
fn set_members(model: ComponentReader, tag: &str) -> Vec<ElementId> {
    model.child(tag).map(|set| model.listed_objects(set)).unwrap_or_default()
}
