//! Wrap objects (`WrapCylinder`, `WrapEllipsoid`, `WrapSphere`, `WrapTorus`) fixed to bodies:
//! the properties every class shares and, for `WrapCylinder`, its radius and length.

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
    /// The shape of a `WrapCylinder`; `None` for the other classes.
    pub cylinder: Option<CylinderShape>,
}

/// A `WrapCylinder`: its axis is the z axis of the wrap object's frame, centred on the origin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CylinderShape {
    /// m (OpenSim's default 1).
    pub radius: f64,
    /// m, along z (OpenSim's default 1).
    pub length: f64,
}

impl WrapObjectSpec {
    pub fn read(reader: ComponentReader, body: &str) -> Result<WrapObjectSpec, ModelError> {
        let vec3_or_zero = |property: &str| if reader.child(property).is_some() { reader.vec3(property) } else { Ok([0.0; 3]) };
        let cylinder = if reader.class() == "WrapCylinder" {
            Some(CylinderShape { radius: reader.number_or("radius", 1.0)?, length: reader.number_or("length", 1.0)? })
        } else {
            None
        };
        Ok(WrapObjectSpec {
            name: reader.name(),
            class: reader.class().to_string(),
            body: body.to_string(),
            active: reader.boolean_or("active", true)?,
            xyz_body_rotation: vec3_or_zero("xyz_body_rotation")?,
            translation: vec3_or_zero("translation")?,
            quadrant: reader.optional_text("quadrant").unwrap_or_else(|| "Unassigned".into()),
            cylinder,
        })
    }
}
