//! Forces, muscles among them, with their geometry paths.

use serde::Serialize;

use super::error::ModelError;
use super::frame::FrameIndex;
use super::muscle::MuscleSpec;
use super::path_point::PathPointSpec;
use super::reader::ComponentReader;
use crate::io::osim::Dialect;
use crate::io::xml::ElementId;

/// A wrap object a path may wrap over, with the point range it applies to.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathWrapSpec {
    pub wrap_object: String,
    pub method: String,
    /// `range`: the first and last path points (1-based, among all points of the path, active
    /// or not) between which the path may wrap; a value below 1 means the first (last) point.
    pub range: [i32; 2],
}

/// A force element; muscles carry a path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceSpec {
    pub name: String,
    pub class: String,
    /// Element of the force in the document, for reading further properties and for edits.
    #[serde(skip)]
    pub element: ElementId,
    pub path_points: Vec<PathPointSpec>,
    pub path_wraps: Vec<PathWrapSpec>,
    /// Hill-muscle properties when the class is one osim-tune evaluates.
    pub muscle: Option<MuscleSpec>,
    /// `appliesForce` (4.x) or not `isDisabled` (2.x/3.x); default true.
    pub applies_force: bool,
    /// An actuator's `min_control` and `max_control` as written (`None` when absent, or when a
    /// 2.x/3.x muscle's are 0 and 1, which OpenSim 4 drops).
    pub controls: [Option<f64>; 2],
}

impl ForceSpec {
    pub fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<ForceSpec, ModelError> {
        let path = reader.object_property("path").or_else(|| reader.child("GeometryPath").map(|g| reader.at(g)));
        let (mut path_points, mut path_wraps) = (Vec::new(), Vec::new());
        if let Some(path) = path.filter(|p| p.class() == "GeometryPath") {
            if let Some(set) = path.child("PathPointSet") {
                for element in path.listed_objects(set) {
                    path_points.push(PathPointSpec::read(path.at(element), dialect, frames)?);
                }
            }
            if let Some(set) = path.child("PathWrapSet") {
                for element in path.listed_objects(set) {
                    let wrap = path.at(element);
                    path_wraps.push(PathWrapSpec {
                        wrap_object: wrap.text("wrap_object")?,
                        method: wrap.optional_text("method").unwrap_or_else(|| "hybrid".into()),
                        range: read_range(wrap)?,
                    });
                }
            }
        }
        let muscle = MuscleSpec::read(reader)?;
        let applies_force = if dialect == Dialect::V4 { reader.boolean_or("appliesForce", true)? } else { !reader.boolean_or("isDisabled", false)? };
        let dropped = |property: &str, value: f64| dialect != Dialect::V4 && is_muscle_class(reader.class()) && DROPPED_MUSCLE_CONTROLS.contains(&(property, value));
        let control = |property: &str| reader.child(property).map(|_| reader.number(property)).transpose().map(|v| v.filter(|&v| !dropped(property, v)));
        let controls = [control("min_control")?, control("max_control")?];
        Ok(ForceSpec { name: reader.name(), class: reader.class().to_string(), element: reader.element, path_points, path_wraps, muscle, applies_force, controls })
    }

    /// Whether the class is a muscle (`Thelen2003Muscle`, `Millard2012EquilibriumMuscle`,
    /// `DeGrooteFregly2016Muscle`, `RigidTendonMuscle`, the deprecated Schutte/Delp muscles, …).
    pub fn is_muscle(&self) -> bool {
        is_muscle_class(&self.class)
    }
}

/// The control bounds OpenSim 4 drops from a pre-4.0 muscle, so the muscle's own defaults hold
/// (`Muscle::updateFromXMLNode`, < 30513): a `min_control` of 0 and a `max_control` of 1.
pub(super) const DROPPED_MUSCLE_CONTROLS: [(&str, f64); 2] = [("min_control", 0.0), ("max_control", 1.0)];

/// Whether an element class is a muscle: its name ends in `Muscle` (or `Muscle_Deprecated`), so
/// `Bhargava2004SmoothedMuscleMetabolics` or `MuscleActivationDynamics` are not.
pub fn is_muscle_class(class: &str) -> bool {
    class.trim_end_matches("_Deprecated").ends_with("Muscle")
}

/// A `PathWrap`'s `range` (OpenSim's default `-1 -1`: the whole path).
fn read_range(wrap: ComponentReader) -> Result<[i32; 2], ModelError> {
    if wrap.child("range").is_none() {
        return Ok([-1, -1]);
    }
    let text = wrap.text("range")?;
    let values: Vec<i32> = text.split_whitespace().filter_map(|t| t.parse().ok()).collect();
    match values[..] {
        [first, last] if text.split_whitespace().count() == 2 => Ok([first, last]),
        _ => Err(wrap.bad("range", "2 integers", &text)),
    }
}

#[cfg(test)]
mod tests {
    use super::is_muscle_class;

    /// Moco's `Bhargava2004SmoothedMuscleMetabolics` sits among a model's components beside its
    /// muscles; it is no muscle (it has no path) and must not be read as one.
    #[test]
    fn muscles_are_the_classes_named_muscle() {
        for class in ["Millard2012EquilibriumMuscle", "Thelen2003Muscle", "RigidTendonMuscle", "Schutte1993Muscle_Deprecated"] {
            assert!(is_muscle_class(class), "{class}");
        }
        for class in ["Bhargava2004SmoothedMuscleMetabolics", "MuscleActivationDynamics", "McKibbenActuator", "PathSpring"] {
            assert!(!is_muscle_class(class), "{class}");
        }
    }
}
