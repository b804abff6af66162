//! Wrap objects (`WrapCylinder`, `WrapEllipsoid`, `WrapSphere`, `WrapTorus`) fixed to bodies:
//! the properties every class shares and the shape of each class.

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrapObjectSpec {
    pub name: String,
    pub class: String,
    /// The body (or `ground`) the wrap object is fixed to.
    pub body: String,
    /// Whether paths wrap over it (`active`, default true).
    pub active: bool,
    /// Body-fixed X-Y-Z Euler angles (rad) of the wrap object's frame in the body.
    pub xyz_body_rotation: [f64; 3],
    /// Origin of the wrap object's frame in the body (m).
    pub translation: [f64; 3],
    /// The side paths wrap over (`+x`, `-y`, `all`, …); OpenSim's default `Unassigned` means all.
    pub quadrant: String,
    pub shape: WrapShape,
}

/// The surface of a wrap object in its own frame, centred on the origin, with OpenSim 4.6's
/// defaults for absent properties.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum WrapShape {
    /// `WrapCylinder`: axis along z; `radius` and `length` (m, default 1 each).
    Cylinder { radius: f64, length: f64 },
    /// `WrapEllipsoid`: `dimensions`, the radii along x, y, z (m, default 0.05 each).
    Ellipsoid { dimensions: [f64; 3] },
    /// `WrapSphere`: `radius` (m, default 0.05).
    Sphere { radius: f64 },
    /// `WrapTorus`: a ring of radius `outer_radius` about z (default 0.05 m), a tube of radius
    /// `inner_radius` (default 0.01 m).
    Torus { inner_radius: f64, outer_radius: f64 },
    /// A class OpenSim 4.6 does not have, such as 3.x's obstacle-set `WrapCylinderObst`.
    Other,
}

impl WrapShape {
    fn read(reader: &ComponentReader) -> Result<WrapShape, ModelError> {
        Ok(match reader.class() {
            "WrapCylinder" => WrapShape::Cylinder { radius: reader.number_or("radius", 1.0)?, length: reader.number_or("length", 1.0)? },
            "WrapEllipsoid" => {
                let dimensions = if reader.child("dimensions").is_some() { reader.vec3("dimensions")? } else { [0.05; 3] };
                WrapShape::Ellipsoid { dimensions }
            }
            "WrapSphere" => WrapShape::Sphere { radius: reader.number_or("radius", 0.05)? },
            "WrapTorus" => WrapShape::Torus { inner_radius: reader.number_or("inner_radius", 0.01)?, outer_radius: reader.number_or("outer_radius", 0.05)? },
            _ => WrapShape::Other,
        })
    }
}

impl WrapObjectSpec {
    pub fn read(reader: ComponentReader, body: &str) -> Result<WrapObjectSpec, ModelError> {
        Ok(WrapObjectSpec {
            name: reader.name(),
            class: reader.class().to_string(),
            body: body.to_string(),
            active: reader.boolean_or("active", true)?,
            xyz_body_rotation: reader.vec3_or("xyz_body_rotation", [0.0; 3])?,
            translation: reader.vec3_or("translation", [0.0; 3])?,
            quadrant: reader.optional_text("quadrant").unwrap_or_else(|| "Unassigned".into()),
            shape: WrapShape::read(&reader)?,
        })
    }
}
