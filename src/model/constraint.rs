//! Kinematic constraints: `CoordinateCouplerConstraint`, `PointConstraint`,
//! `ConstantDistanceConstraint`, `PointOnLineConstraint` and `WeldConstraint` are read in full;
//! other classes by name, class and whether they are enforced.

use serde::Serialize;

use super::error::ModelError;
use super::frame::{FrameChain, FrameIndex, Offset};
use super::function::FunctionSpec;
use super::reader::ComponentReader;
use super::conversion::six_significant_digits_each;
use crate::io::osim::Dialect;

/// dependent = scale_factor · f(independent…).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CouplerSpec {
    pub independent_coordinates: Vec<String>,
    pub dependent_coordinate: String,
    pub function: FunctionSpec,
    pub scale_factor: f64,
}

/// What a constraint other than a coupler holds between frames fixed in bodies (4.x sockets or
/// 3.x body names; points in m, in their frames).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkSpec {
    /// `PointConstraint`: `location_body_2` in `body_2` coincides with `location_body_1` in `body_1`.
    Point { frames: [FrameChain; 2], locations: [[f64; 3]; 2] },
    /// `ConstantDistanceConstraint`: the two points stay `distance` (m) apart.
    Distance { frames: [FrameChain; 2], locations: [[f64; 3]; 2], distance: f64 },
    /// `PointOnLineConstraint`: `point_on_follower` stays on the line through `point_on_line`
    /// along `direction` (a unit vector), both fixed in the line frame.
    PointOnLine { line: FrameChain, direction: [f64; 3], point_on_line: [f64; 3], follower: FrameChain, point_on_follower: [f64; 3] },
    /// `WeldConstraint`: the two frames coincide.
    Weld { frames: [FrameChain; 2] },
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConstraintSpec {
    pub name: String,
    pub class: String,
    pub enforced: bool,
    pub coupler: Option<CouplerSpec>,
    pub link: Option<LinkSpec>,
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
        let link = LinkSpec::read(reader, dialect, frames)?;
        let enforced = reader.boolean_or("isEnforced", true)? && !reader.boolean_or("isDisabled", false)?;
        Ok(ConstraintSpec { name: reader.name(), class: reader.class().to_string(), enforced, coupler, link })
    }
}

impl LinkSpec {
    /// The link of a `PointConstraint`, `ConstantDistanceConstraint`, `PointOnLineConstraint` or
    /// `WeldConstraint`; `None` for other classes.
    fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<Option<LinkSpec>, ModelError> {
        let frame = |socket: &str| -> Result<FrameChain, ModelError> {
            if dialect == Dialect::V4 {
                let property = format!("socket_{socket}");
                frames.resolve(reader, &reader.text(&property)?, &property)
            } else {
                let body = reader.text(socket)?;
                Ok(FrameChain { name: body.clone(), body, offsets: Vec::new() })
            }
        };
        let pair = || -> Result<([FrameChain; 2], [[f64; 3]; 2]), ModelError> {
            Ok(([frame("body_1")?, frame("body_2")?], [reader.vec3_or("location_body_1", [0.0; 3])?, reader.vec3_or("location_body_2", [0.0; 3])?]))
        };
        Ok(Some(match reader.class() {
            "PointConstraint" => {
                let (frames, locations) = pair()?;
                LinkSpec::Point { frames, locations }
            }
            "ConstantDistanceConstraint" => {
                let (frames, locations) = pair()?;
                let distance = reader.number("constant_distance")?;
                if !distance.is_finite() || distance < 0.0 {
                    return Err(reader.bad("constant_distance", "a distance ≥ 0 (m)", &distance.to_string()));
                }
                LinkSpec::Distance { frames, locations, distance }
            }
            "PointOnLineConstraint" => {
                let direction = nalgebra::Vector3::from(reader.vec3("line_direction_vec")?);
                if !(direction.norm() > 0.0 && direction.iter().all(|v| v.is_finite())) {
                    return Err(reader.bad("line_direction_vec", "a non-zero direction", &format!("{:?}", direction.as_slice())));
                }
                LinkSpec::PointOnLine {
                    line: frame("line_body")?,
                    direction: direction.normalize().into(),
                    point_on_line: reader.vec3_or("point_on_line", [0.0; 3])?,
                    follower: frame("follower_body")?,
                    point_on_follower: reader.vec3_or("point_on_follower", [0.0; 3])?,
                }
            }
            "WeldConstraint" => LinkSpec::Weld { frames: weld_frames(reader, dialect, frames)? },
            _ => return Ok(None),
        }))
    }
}

/// A `WeldConstraint`'s frames: 4.x sockets `frame1`, `frame2`; before, `body_1`/`body_2` with
/// `location_body_k` and `orientation_body_k` (body-fixed X-Y-Z, rad) as an offset in each, at
/// the six significant digits OpenSim's conversion keeps (`addPhysicalOffsetFrame30505_30517`
/// writes them through a C++ stream).
fn weld_frames(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<[FrameChain; 2], ModelError> {
    let frame = |k: usize| -> Result<FrameChain, ModelError> {
        if dialect == Dialect::V4 {
            let property = format!("socket_frame{k}");
            return frames.resolve(reader, &reader.text(&property)?, &property);
        }
        let body = reader.text(&format!("body_{k}"))?;
        let [translation, orientation] = [format!("location_body_{k}"), format!("orientation_body_{k}")].map(|p| reader.vec3_or(&p, [0.0; 3]).map(six_significant_digits_each));
        let offset = Offset { translation: translation?, orientation: orientation? };
        Ok(FrameChain { name: body.clone(), body, offsets: vec![offset] })
    };
    Ok([frame(1)?, frame(2)?])
}
