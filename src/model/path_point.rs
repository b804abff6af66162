//! Points of a muscle's `GeometryPath`: fixed, conditional (active only in a coordinate range)
//! and moving (location functions of coordinates).

use serde::Serialize;

use super::error::ModelError;
use super::frame::{FrameChain, FrameIndex};
use super::function::FunctionSpec;
use super::marker::attachment_frame;
use super::reader::ComponentReader;
use crate::io::osim::Dialect;

/// One coordinate of a `MovingPathPoint`: location (m) along a frame axis as a function of a
/// coordinate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MovingComponent {
    pub coordinate: String,
    pub function: FunctionSpec,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "class")]
pub enum PathPointKind {
    PathPoint { location: [f64; 3] },
    /// Active while `range[0] ≤ coordinate ≤ range[1]` (rad or m).
    ConditionalPathPoint { location: [f64; 3], coordinate: String, range: [f64; 2] },
    /// x, y, z locations in the frame, each a function of a coordinate.
    MovingPathPoint { x: MovingComponent, y: MovingComponent, z: MovingComponent },
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathPointSpec {
    pub name: String,
    pub frame: FrameChain,
    pub kind: PathPointKind,
}

impl PathPointSpec {
    pub fn read(reader: ComponentReader, dialect: Dialect, frames: &FrameIndex) -> Result<PathPointSpec, ModelError> {
        let kind = match reader.class() {
            "PathPoint" => PathPointKind::PathPoint { location: reader.vec3("location")? },
            "ConditionalPathPoint" => {
                let range = reader.numbers("range", Some(2))?;
                PathPointKind::ConditionalPathPoint {
                    location: reader.vec3("location")?,
                    coordinate: coordinate_reference(reader, "coordinate")?,
                    range: [range[0], range[1]],
                }
            }
            "MovingPathPoint" => PathPointKind::MovingPathPoint {
                x: moving_component(reader, "x")?,
                y: moving_component(reader, "y")?,
                z: moving_component(reader, "z")?,
            },
            other => return Err(reader.bad("PathPointSet", "PathPoint, ConditionalPathPoint or MovingPathPoint", other)),
        };
        Ok(PathPointSpec { name: reader.name(), frame: attachment_frame(reader, dialect, frames)?, kind })
    }
}

fn moving_component(reader: ComponentReader, axis: &str) -> Result<MovingComponent, ModelError> {
    let property = format!("{axis}_location");
    let function = reader.object_property(&property).ok_or_else(|| reader.missing(&property))?;
    Ok(MovingComponent { coordinate: coordinate_reference(reader, &format!("{axis}_coordinate"))?, function: FunctionSpec::read(function)? })
}

/// A coordinate named by a 4.x socket (`socket_<property>`, a path whose last segment is the
/// coordinate's name) or a 3.x property holding the name.
fn coordinate_reference(reader: ComponentReader, property: &str) -> Result<String, ModelError> {
    let socket = format!("socket_{property}");
    let text = reader.optional_text(&socket).or_else(|| reader.optional_text(property)).ok_or_else(|| reader.missing(&socket))?;
    Ok(text.rsplit('/').next().unwrap_or_default().to_string())
}
