//! Joints: the frames they connect, their coordinates and, for `CustomJoint`, the
//! `SpatialTransform` of three rotations and three translations.

use serde::Serialize;

use super::conversion::six_significant_digits_each;
use super::coordinate::{written_motion_type, CoordinateSpec, CoordinateUnit, MotionType};
use super::error::ModelError;
use super::frame::{FrameChain, FrameIndex, Offset};
use super::function::FunctionSpec;
use super::reader::ComponentReader;

/// One of the six axes of a `SpatialTransform` (rotation1–3, translation1–3).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransformAxisSpec {
    pub name: String,
    /// Names of the coordinates the function takes (usually one, none for a constant).
    pub coordinates: Vec<String>,
    /// Unit axis in the parent frame.
    pub axis: [f64; 3],
    /// Angle (rad) or displacement (m) along the axis; `None` means zero.
    pub function: Option<FunctionSpec>,
}

/// A joint as written in the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointSpec {
    pub name: String,
    /// OpenSim class, e.g. `CustomJoint`, `PinJoint`.
    pub class: String,
    pub parent: FrameChain,
    pub child: FrameChain,
    pub coordinates: Vec<CoordinateSpec>,
    /// Six axes for `CustomJoint`, empty for the other classes.
    pub spatial_transform: Vec<TransformAxisSpec>,
    /// The surface an `EllipsoidJoint` or `ScapulothoracicJoint` glides on; `None` for the others.
    pub surface: Option<JointSurface>,
}

impl JointSpec {
    /// Reads a 4.x joint, resolving its sockets through `frames`.
    pub fn read_v4(reader: ComponentReader, frames: &FrameIndex) -> Result<JointSpec, ModelError> {
        let parent = frames.resolve(reader, &reader.text("socket_parent_frame")?, "socket_parent_frame")?;
        let child = frames.resolve(reader, &reader.text("socket_child_frame")?, "socket_child_frame")?;
        let coordinate_elements = reader.child("coordinates").map(|c| reader.listed_objects(c)).unwrap_or_default();
        Self::assemble(reader, parent, child, coordinate_elements)
    }

    /// Reads a 3.x joint nested in `<Body name=child_body><Joint>`; its offsets as OpenSim 4's
    /// conversion to offset frames re-writes them, to six significant digits.
    pub fn read_v3(reader: ComponentReader, child_body: &str) -> Result<JointSpec, ModelError> {
        if reader.boolean_or("reverse", false)? {
            let expected = "false: OpenSim 4 turns a reversed joint into one from its child body to its parent, a tree osim-tune does not build";
            return Err(reader.bad("reverse", expected, "true"));
        }
        let parent_body = reader.text("parent_body")?;
        // OpenSim's 3.x conversion always adds offset frames named `<body>_offset`.
        let parent = FrameChain {
            name: format!("{parent_body}_offset"),
            body: parent_body,
            offsets: vec![converted_offset(reader, "location_in_parent", "orientation_in_parent")?],
        };
        let child = FrameChain {
            name: format!("{child_body}_offset"),
            body: child_body.to_string(),
            offsets: vec![converted_offset(reader, "location", "orientation")?],
        };
        let coordinate_elements = reader.child("CoordinateSet").map(|c| reader.listed_objects(c)).unwrap_or_default();
        Self::assemble(reader, parent, child, coordinate_elements)
    }

    fn assemble(
        reader: ComponentReader,
        parent: FrameChain,
        child: FrameChain,
        coordinate_elements: Vec<crate::io::xml::ElementId>,
    ) -> Result<JointSpec, ModelError> {
        let name = reader.name();
        let spatial_transform = read_spatial_transform(reader)?;
        let fixed_types = class_motion_types(reader.class());
        let mut coordinates = Vec::new();
        for (index, &element) in coordinate_elements.iter().enumerate() {
            let coordinate = reader.at(element);
            let motion_type = match (written_motion_type(coordinate), &fixed_types) {
                (Some(written), _) => written,
                (None, Some(types)) => *types.get(index).ok_or_else(|| coordinate.bad("coordinates", &format!("at most {} coordinates for {}", types.len(), reader.class()), &coordinate_elements.len().to_string()))?,
                (None, None) => transform_motion_type(&coordinate.name(), &spatial_transform),
            };
            let unit = coordinate_unit(&coordinate.name(), motion_type, &spatial_transform);
            coordinates.push(CoordinateSpec::read(coordinate, &name, motion_type, unit)?);
        }
        let surface = JointSurface::read(reader)?;
        Ok(JointSpec { name, class: reader.class().to_string(), parent, child, coordinates, spatial_transform, surface })
    }
}

/// The shape properties of the joint classes that glide on an ellipsoid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum JointSurface {
    /// `EllipsoidJoint`: `radii_x_y_z` (m) along the parent frame's axes.
    Ellipsoid { radii: [f64; 3] },
    /// `ScapulothoracicJoint`: `thoracic_ellipsoid_radii_x_y_z` (m, along the parent frame's axes),
    /// `scapula_winging_axis_origin` (m, x and y in the scapula's frame on the ellipsoid) and
    /// `scapula_winging_axis_direction` (rad from that frame's y axis, counterclockwise).
    Scapulothoracic { radii: [f64; 3], winging_origin: [f64; 2], winging_direction: f64 },
}

impl JointSurface {
    /// The surface of a joint of the reader's class (OpenSim's radii default to NaN: required).
    fn read(reader: ComponentReader) -> Result<Option<JointSurface>, ModelError> {
        Ok(match reader.class() {
            "EllipsoidJoint" => Some(JointSurface::Ellipsoid { radii: positive_radii(reader, "radii_x_y_z")? }),
            "ScapulothoracicJoint" => {
                let origin = reader.numbers_or("scapula_winging_axis_origin", &[0.0, 0.0])?;
                Some(JointSurface::Scapulothoracic {
                    radii: positive_radii(reader, "thoracic_ellipsoid_radii_x_y_z")?,
                    winging_origin: [origin[0], origin[1]],
                    winging_direction: reader.number_or("scapula_winging_axis_direction", 0.0)?,
                })
            }
            _ => None,
        })
    }
}

/// Three positive radii (m).
fn positive_radii(reader: ComponentReader, property: &str) -> Result<[f64; 3], ModelError> {
    let radii = reader.vec3(property)?;
    if radii.iter().all(|r| *r > 0.0 && r.is_finite()) { Ok(radii) } else { Err(reader.bad(property, "three positive radii (m)", &format!("{radii:?}"))) }
}

/// A 3.x joint's offset as OpenSim 4 converts it to a `PhysicalOffsetFrame`.
fn converted_offset(reader: ComponentReader, translation: &str, orientation: &str) -> Result<Offset, ModelError> {
    Ok(Offset { translation: six_significant_digits_each(reader.vec3(translation)?), orientation: six_significant_digits_each(reader.vec3(orientation)?) })
}

fn read_spatial_transform(reader: ComponentReader) -> Result<Vec<TransformAxisSpec>, ModelError> {
    let Some(transform) = reader.child("SpatialTransform") else { return Ok(Vec::new()) };
    let axes = reader.listed_objects(transform);
    let mut spatial_transform = Vec::with_capacity(6);
    for &element in axes.iter().filter(|&&e| reader.document.xml.tag(e) == "TransformAxis") {
        let axis = reader.at(element);
        spatial_transform.push(TransformAxisSpec {
            name: axis.name(),
            coordinates: axis.words("coordinates"),
            axis: axis.vec3_or("axis", [1.0, 0.0, 0.0])?,
            function: axis.object_property("function").map(FunctionSpec::read).transpose()?,
        });
    }
    if spatial_transform.len() != 6 {
        return Err(reader.bad("SpatialTransform", "6 TransformAxis elements", &spatial_transform.len().to_string()));
    }
    Ok(spatial_transform)
}

/// Coordinate motion types fixed by the joint class, in coordinate order.
fn class_motion_types(class: &str) -> Option<Vec<MotionType>> {
    use MotionType::{Rotational as R, Translational as T};
    Some(match class {
        "PinJoint" => vec![R],
        "SliderJoint" => vec![T],
        "UniversalJoint" => vec![R, R],
        "BallJoint" | "GimbalJoint" | "EllipsoidJoint" => vec![R, R, R],
        "FreeJoint" => vec![R, R, R, T, T, T],
        "ScapulothoracicJoint" => vec![R, R, R, R],
        "PlanarJoint" => vec![R, T, T],
        "WeldJoint" => vec![],
        _ => return None,
    })
}

/// OpenSim's rule for `CustomJoint`: an axis driven through `LinearFunction` with slope ±1 makes
/// the coordinate rotational (axes 0–2) or translational (3–5); any other function makes it
/// coupled unless a pure axis has already typed it. Later pure axes win.
fn transform_motion_type(coordinate: &str, axes: &[TransformAxisSpec]) -> MotionType {
    let mut motion_type = None;
    for (index, axis) in axes.iter().enumerate() {
        if !axis.coordinates.iter().any(|c| c == coordinate) {
            continue;
        }
        match &axis.function {
            Some(function) if function.is_unit_linear() => {
                motion_type = Some(if index < 3 { MotionType::Rotational } else { MotionType::Translational });
            }
            Some(_) => motion_type = motion_type.or(Some(MotionType::Coupled)),
            None => {}
        }
    }
    motion_type.unwrap_or(MotionType::Coupled)
}

/// Angle for rotational coordinates and coupled ones that drive a rotation axis, else length.
fn coordinate_unit(coordinate: &str, motion_type: MotionType, axes: &[TransformAxisSpec]) -> CoordinateUnit {
    let drives_rotation = axes.iter().take(3).any(|axis| axis.coordinates.iter().any(|c| c == coordinate));
    match motion_type {
        MotionType::Rotational => CoordinateUnit::Radian,
        MotionType::Translational => CoordinateUnit::Meter,
        MotionType::Coupled if drives_rotation => CoordinateUnit::Radian,
        MotionType::Coupled => CoordinateUnit::Meter,
    }
}
