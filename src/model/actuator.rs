//! OpenSim's scalar non-muscle actuators — `CoordinateActuator`, `PointActuator`,
//! `TorqueActuator` — as a model's ForceSet or a `<ForceSet>` document (static optimisation's
//! residual and reserve actuators) describes them. Absent properties take the document's
//! `<defaults>` object of the class, which OpenSim registers as the class default while reading
//! the document, else OpenSim 4.6's class defaults.

use std::path::PathBuf;

use serde::Serialize;

use super::error::{BadProperty, ModelError};
use super::reader::{ComponentReader, PropertySources};
use crate::io::osim::OsimDocument;

/// The classes read here.
const ACTUATOR_CLASSES: &str = "CoordinateActuator, PointActuator or TorqueActuator";

/// The first document version with `appliesForce`; in older documents OpenSim reads `isDisabled`
/// as `appliesForce` negated (`Force::updateFromXMLNode`).
const APPLIES_FORCE_VERSION: u32 = 30509;

/// The first document version whose Point- and TorqueActuators are OpenSim's current ones; older
/// ones (OpenSim 1.x `Force`/`Torque`, and every document without `<OpenSimDocument>`) name their
/// bodies, point and direction the old way and point the other way
/// (`PointActuator::updateFromXMLNode`, `TorqueActuator::updateFromXMLNode`).
const CURRENT_ACTUATORS_VERSION: u32 = 10905;

/// What an actuator applies per unit actuation (1 N or 1 N·m).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum ActuatorKind {
    /// A generalized force on one coordinate (N·m or N).
    Coordinate { coordinate: String },
    /// A force along `direction` (normalised by OpenSim; in ground if `force_is_global`, else in
    /// `body`) at `point` (m; in ground if `point_is_global`, else in `body`'s frame).
    Point { body: String, point: [f64; 3], point_is_global: bool, direction: [f64; 3], force_is_global: bool },
    /// A torque about `axis` (normalised by OpenSim; in ground if `torque_is_global`, else in
    /// `body_a`'s frame) on `body_a` and its reaction on `body_b` (OpenSim's `bodyA`, `bodyB`).
    Torque { body_a: String, body_b: String, axis: [f64; 3], torque_is_global: bool },
}

/// A `ScalarActuator` of one of the three classes. Its force is actuation × the unit force of
/// `kind`, with actuation = control × `optimal_force`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ActuatorSpec {
    pub name: String,
    pub class: String,
    pub kind: ActuatorKind,
    /// N or N·m per unit control (default 1).
    pub optimal_force: f64,
    /// Control bounds (defaults −∞ and ∞).
    pub min_control: f64,
    pub max_control: f64,
    /// `appliesForce` (3.x: not `isDisabled`; default true).
    pub applies_force: bool,
    /// The file and line the actuator was read from, for messages.
    #[serde(skip)]
    pub file: PathBuf,
    #[serde(skip)]
    pub line: usize,
}

impl ActuatorSpec {
    /// The actuator a ForceSet member describes; `None` for a class that is not one of these three.
    pub fn read(reader: ComponentReader) -> Result<Option<ActuatorSpec>, ModelError> {
        let properties = PropertySources::new(reader);
        let legacy = reader.document.version.number < CURRENT_ACTUATORS_VERSION;
        // A legacy document's name of a property, when it states it.
        let named = |current: &'static str, old: &'static str| if legacy && properties.of(current).child(current).is_none() && properties.of(old).child(old).is_some() { old } else { current };
        let flipped = |v: [f64; 3]| if legacy { v.map(|x| -x) } else { v };
        let class = current_class(reader.class());
        let kind = match class {
            "CoordinateActuator" => ActuatorKind::Coordinate { coordinate: properties.reference("coordinate")? },
            "PointActuator" => ActuatorKind::Point {
                body: properties.reference(named("body", "body_B"))?,
                point: properties.vec3(named("point", "point_B"), [0.0; 3])?,
                point_is_global: properties.boolean("point_is_global", false)?,
                direction: flipped(properties.vec3(named("direction", "direction_A"), [1.0, 0.0, 0.0])?),
                force_is_global: properties.boolean("force_is_global", legacy)?,
            },
            "TorqueActuator" => ActuatorKind::Torque {
                body_a: properties.reference(named("bodyA", "body_B"))?,
                body_b: properties.reference(named("bodyB", "body_A"))?,
                axis: flipped(properties.vec3(named("axis", "direction_A"), [0.0, 0.0, 1.0])?),
                torque_is_global: properties.boolean("torque_is_global", true)?,
            },
            _ => return Ok(None),
        };
        Ok(Some(ActuatorSpec {
            name: reader.name(),
            class: class.to_string(),
            kind,
            optimal_force: properties.number("optimal_force", 1.0)?,
            min_control: properties.number("min_control", f64::NEG_INFINITY)?,
            max_control: properties.number("max_control", f64::INFINITY)?,
            applies_force: applies_force(&properties)?,
            file: reader.document.xml.file().into(),
            line: reader.line(),
        }))
    }
}

/// The current name of an actuator class: OpenSim 1.x's `GeneralizedForce`, `Force` and `Torque`
/// are read as the classes they became (`Object::renameType` in OpenSim's actuator library).
fn current_class(class: &str) -> &str {
    match class {
        "GeneralizedForce" => "CoordinateActuator",
        "Force" => "PointActuator",
        "Torque" => "TorqueActuator",
        other => other,
    }
}

/// The actuators of a `<ForceSet>` document (e.g. OpenSim's residual-actuator files; 2.x/3.x and
/// 4.x dialects; `<ActuatorSet>`, OpenSim 1.x's name that OpenSim still reads as a ForceSet), in
/// file order; a member of another class is an error naming file, line and class.
pub fn read_force_set(document: &OsimDocument) -> Result<Vec<ActuatorSpec>, ModelError> {
    let set = ComponentReader::new(document, document.object);
    if !matches!(set.class(), "ForceSet" | "ActuatorSet") {
        return Err(unexpected_class(set, "OpenSimDocument", "a <ForceSet>"));
    }
    let Some(objects) = set.child("objects") else { return Ok(Vec::new()) };
    document
        .xml
        .children(objects)
        .iter()
        .map(|&element| {
            let member = set.at(element);
            ActuatorSpec::read(member)?.ok_or_else(|| unexpected_class(member, "objects", &format!("a {ACTUATOR_CLASSES}")))
        })
        .collect()
}

/// `reader` is not of a class its container (`property`) may hold.
fn unexpected_class(reader: ComponentReader, property: &str, expected: &str) -> ModelError {
    ModelError::BadProperty(Box::new(BadProperty {
        file: reader.document.xml.file().into(),
        line: reader.line(),
        component: reader.path(),
        property: property.into(),
        expected: expected.into(),
        found: reader.class().into(),
    }))
}

/// `appliesForce`, or in documents older than 30509 also the negated `isDisabled`.
fn applies_force(properties: &PropertySources) -> Result<bool, ModelError> {
    let legacy = properties.member.document.version.number < APPLIES_FORCE_VERSION;
    for source in properties.sources() {
        if legacy && source.child("isDisabled").is_some() {
            return Ok(!source.boolean_or("isDisabled", false)?);
        }
        if source.child("appliesForce").is_some() {
            return source.boolean_or("appliesForce", true);
        }
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn document(version: u32, set: &str) -> OsimDocument {
        let text = format!("<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"{version}\">\n{set}\n</OpenSimDocument>\n");
        OsimDocument::parse(text, Path::new("actuators.xml")).unwrap()
    }

    #[test]
    fn absent_properties_take_opensims_class_defaults() {
        let set = "<ForceSet><objects>
            <CoordinateActuator name=\"c\"><coordinate>knee_angle_r</coordinate></CoordinateActuator>
            <PointActuator name=\"p\"><body>pelvis</body></PointActuator>
            <TorqueActuator name=\"t\"><bodyA>pelvis</bodyA><bodyB>ground</bodyB></TorqueActuator>
            </objects></ForceSet>";
        let actuators = read_force_set(&document(40600, set)).unwrap();
        for actuator in &actuators {
            assert_eq!((actuator.optimal_force, actuator.min_control, actuator.max_control), (1.0, f64::NEG_INFINITY, f64::INFINITY));
            assert!(actuator.applies_force);
        }
        assert_eq!(actuators[0].kind, ActuatorKind::Coordinate { coordinate: "knee_angle_r".into() });
        let point = ActuatorKind::Point { body: "pelvis".into(), point: [0.0; 3], point_is_global: false, direction: [1.0, 0.0, 0.0], force_is_global: false };
        assert_eq!(actuators[1].kind, point);
        let torque = ActuatorKind::Torque { body_a: "pelvis".into(), body_b: "ground".into(), axis: [0.0, 0.0, 1.0], torque_is_global: true };
        assert_eq!(actuators[2].kind, torque);
        assert_eq!((actuators[2].line, actuators[2].class.as_str()), (6, "TorqueActuator"));
    }

    #[test]
    fn documents_older_than_10905_name_and_point_their_actuators_the_old_way() {
        // A document without <OpenSimDocument> is 10500, as OpenSim reads opensim-core's gait2354
        // CMC actuators: the direction and axis turn round, the old names are read.
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("actuators.xml");
        std::fs::write(&file, "<ForceSet name=\"a\"><objects><PointActuator name=\"FX\"><body>pelvis</body><direction>1 0 0</direction></PointActuator>
            <TorqueActuator name=\"MX\"><body_A>ground</body_A><body_B>pelvis</body_B><direction_A>0 0 1</direction_A></TorqueActuator></objects></ForceSet>").unwrap();
        let set = read_force_set(&OsimDocument::read_object(&file).unwrap()).unwrap();
        assert!(matches!(&set[0].kind, ActuatorKind::Point { direction, force_is_global: true, .. } if *direction == [-1.0, 0.0, 0.0]), "{:?}", set[0].kind);
        assert!(matches!(&set[1].kind, ActuatorKind::Torque { body_a, body_b, axis, .. } if body_a == "pelvis" && body_b == "ground" && *axis == [0.0, 0.0, -1.0]), "{:?}", set[1].kind);
        let current = &read_force_set(&document(20302, "<ForceSet><objects><PointActuator name=\"FX\"><body>pelvis</body><direction>1 0 0</direction></PointActuator></objects></ForceSet>")).unwrap()[0];
        assert!(matches!(&current.kind, ActuatorKind::Point { direction, force_is_global: false, .. } if *direction == [1.0, 0.0, 0.0]));
    }

    #[test]
    fn opensim_1_class_names_are_read_as_the_classes_they_became() {
        // opensim-core's runningModel CMC actuators: an <ActuatorSet> of Force, Torque and
        // GeneralizedForce members with <defaults> of those classes.
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("actuators.xml");
        std::fs::write(&file, "<ActuatorSet name=\"a\"><defaults><Force name=\"default\"><optimal_force> 1000.0 </optimal_force></Force>
            <GeneralizedForce name=\"default\"><optimal_force> 300.0 </optimal_force></GeneralizedForce></defaults><objects>
            <Force name=\"FX\"><optimal_force> 1.0 </optimal_force><body_A> ground </body_A><direction_A> -1 0 0 </direction_A><body_B> pelvis </body_B><point_B> -0.07 0 0 </point_B></Force>
            <Torque name=\"MX\"><body_A> ground </body_A><direction_A> 1 0 0 </direction_A><body_B> pelvis </body_B></Torque>
            <GeneralizedForce name=\"knee\"><coordinate> knee_angle_r </coordinate></GeneralizedForce></objects></ActuatorSet>").unwrap();
        let set = read_force_set(&OsimDocument::read_object(&file).unwrap()).unwrap();
        let classes: Vec<&str> = set.iter().map(|a| a.class.as_str()).collect();
        assert_eq!(classes, ["PointActuator", "TorqueActuator", "CoordinateActuator"]);
        assert!(matches!(&set[0].kind, ActuatorKind::Point { body, point, direction, .. } if body == "pelvis" && *point == [-0.07, 0.0, 0.0] && *direction == [1.0, 0.0, 0.0]), "{:?}", set[0].kind);
        assert_eq!((set[0].optimal_force, set[2].optimal_force), (1.0, 300.0), "the member's value, else its class' <defaults>");
        assert_eq!(set[2].kind, ActuatorKind::Coordinate { coordinate: "knee_angle_r".into() });
    }

    #[test]
    fn infinite_bounds_legacy_is_disabled_and_document_defaults() {
        let set = "<ForceSet><defaults>
            <PointActuator name=\"default\"><force_is_global> true </force_is_global><optimal_force>1000</optimal_force></PointActuator>
            </defaults><objects>
            <PointActuator name=\"FX\"><isDisabled> true </isDisabled><min_control> -infinity </min_control>
              <max_control>Inf</max_control><body> pelvis </body></PointActuator>
            </objects></ForceSet>";
        let legacy = &read_force_set(&document(20302, set)).unwrap()[0];
        assert_eq!((legacy.min_control, legacy.max_control, legacy.optimal_force, legacy.applies_force), (f64::NEG_INFINITY, f64::INFINITY, 1000.0, false));
        assert!(matches!(&legacy.kind, ActuatorKind::Point { body, force_is_global: true, .. } if body == "pelvis"));
        // From 30509 on OpenSim no longer reads `isDisabled`.
        assert!(read_force_set(&document(40000, set)).unwrap()[0].applies_force);
    }

    #[test]
    fn other_members_and_missing_references_are_errors_naming_the_line() {
        let muscle = "<ForceSet><objects>\n<Thelen2003Muscle name=\"soleus_r\"/>\n</objects></ForceSet>";
        let message = read_force_set(&document(30000, muscle)).unwrap_err().to_string();
        assert!(message.starts_with("actuators.xml:4:") && message.contains("Thelen2003Muscle"), "{message}");
        let empty = "<ForceSet><objects>\n<CoordinateActuator name=\"c\"><coordinate> </coordinate></CoordinateActuator>\n</objects></ForceSet>";
        let message = read_force_set(&document(30000, empty)).unwrap_err().to_string();
        assert!(message.starts_with("actuators.xml:4:") && message.contains("<coordinate>"), "{message}");
        let message = read_force_set(&document(40000, "<Model name=\"m\"/>")).unwrap_err().to_string();
        assert!(message.contains("<ForceSet>") && message.contains("Model"), "{message}");
    }
}
