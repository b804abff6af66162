//! Kinematic constraints; `CoordinateCouplerConstraint` and `PointConstraint` are read in full.

use serde::Serialize;

use super::error::ModelError;
use super::frame::{FrameChain, FrameIndex};
use super::function::FunctionSpec;
use super::reader::ComponentReader;
use crate::io::osim::Dialect;

/// dependent = scale_factor · f(independent…).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CouplerSpec {
    pub independent_coordinates: Vec<String>,
    pub dependent_coordinate: String,
    pub function: FunctionSpec,
    pub scale_factor: f64,
}

/// A point fixed in each of two frames that must coincide (`PointConstraint`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointLinkSpec {
    /// `body_1`, `body_2`: 4.x sockets or 3.x body names.
    pub frames: [FrameChain; 2],
    /// `location_body_1`, `location_body_2` (m, in each frame).
    pub locations: [[f64; 3]; 2],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConstraintSpec {
    pub name: String,
    pub class: String,
    pub enforced: bool,
    pub coupler: Option<CouplerSpec>,
    pub point: Option<PointLinkSpec>,
}

impl ConstraintSpec {
    pub fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<ConstraintSpec, ModelError> {
        let coupler = if reader.class() == "CoordinateCouplerConstraint" {
            let function = reader.object_property("coupled_coordinates_function").ok_or_else(|| reader.missing("coupled_coordinates_function"))?;
            Some(CouplerSpec {
                independent_coordinates: reader.text("independent_coordinate_names")?.split_whitespace().map(String::from).collect(),
                dependent_coordinate: reader.text("dependent_coordinate_name")?,
                function: FunctionSpec::read(function)?,
                scale_factor: reader.number_or("scale_factor", 1.0)?,
            })
        } else {
            None
        };
        let point = if reader.class() == "PointConstraint" { Some(PointLinkSpec::read(reader, dialect, frames)?) } else { None };
        let enforced = reader.boolean_or("isEnforced", true)? && !reader.boolean_or("isDisabled", false)?;
        Ok(ConstraintSpec { name: reader.name(), class: reader.class().to_string(), enforced, coupler, point })
    }
}

impl PointLinkSpec {
    fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<PointLinkSpec, ModelError> {
        let frame = |k: usize| -> Result<FrameChain, ModelError> {
            if dialect == Dialect::V4 {
                let socket = format!("socket_body_{k}");
                frames.resolve(reader, &reader.text(&socket)?, &socket)
            } else {
                let body = reader.text(&format!("body_{k}"))?;
                Ok(FrameChain { name: body.clone(), body, offsets: Vec::new() })
            }
        };
        Ok(PointLinkSpec {
            frames: [frame(1)?, frame(2)?],
            locations: [reader.vec3_or("location_body_1", [0.0; 3])?, reader.vec3_or("location_body_2", [0.0; 3])?],
        })
    }
}
