//! Generalized coordinates and their motion type.

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;

/// OpenSim's `Coordinate::MotionType`: rad for rotational, m for translational; `Coupled` when the
/// coordinate drives its axes through a non-unit function (units then follow the model's intent).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionType {
    Rotational,
    Translational,
    Coupled,
}

/// What a coordinate's values measure: an angle in rad or a length in m. A coupled coordinate
/// that drives a rotation axis is an angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CoordinateUnit {
    Radian,
    Meter,
}

impl CoordinateUnit {
    pub fn symbol(self) -> &'static str {
        match self {
            CoordinateUnit::Radian => "rad",
            CoordinateUnit::Meter => "m",
        }
    }
}

/// OpenSim's default range (rad or m) of a coordinate that states none.
const DEFAULT_RANGE: [f64; 2] = [-10.0, 10.0];

/// A coordinate as written in the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CoordinateSpec {
    pub name: String,
    pub joint: String,
    pub motion_type: MotionType,
    pub unit: CoordinateUnit,
    pub default_value: f64,
    pub default_speed_value: f64,
    /// [min, max] in rad or m.
    pub range: [f64; 2],
    pub clamped: bool,
    pub locked: bool,
    pub prescribed: bool,
    /// `is_free_to_satisfy_constraints`: assembly gives the coordinate no goal (it moves as the
    /// constraints need).
    pub free_to_satisfy_constraints: bool,
}

impl CoordinateSpec {
    pub fn read(
        reader: ComponentReader,
        joint: &str,
        motion_type: MotionType,
        unit: CoordinateUnit,
    ) -> Result<CoordinateSpec, ModelError> {
        let range = reader.numbers_or("range", &DEFAULT_RANGE)?;
        if range[0] > range[1] {
            return Err(reader.bad("range", "min ≤ max", &format!("{} {}", range[0], range[1])));
        }
        Ok(CoordinateSpec {
            name: reader.name(),
            joint: joint.to_string(),
            motion_type,
            unit,
            default_value: reader.number_or("default_value", 0.0)?,
            default_speed_value: reader.number_or("default_speed_value", 0.0)?,
            range: [range[0], range[1]],
            clamped: reader.boolean_or("clamped", false)?,
            locked: reader.boolean_or("locked", false)?,
            prescribed: reader.boolean_or("prescribed", false)?,
            free_to_satisfy_constraints: reader.boolean_or("is_free_to_satisfy_constraints", false)?,
        })
    }
}

/// The motion type 3.x files state in `<motion_type>`, read as OpenSim 4 reads it: in any case
/// (`Coupled`), and a word other than the three leaves the type to the joint (`None`).
pub fn written_motion_type(reader: ComponentReader) -> Option<MotionType> {
    match reader.optional_text("motion_type")?.trim().to_ascii_lowercase().as_str() {
        "rotational" => Some(MotionType::Rotational),
        "translational" => Some(MotionType::Translational),
        "coupled" => Some(MotionType::Coupled),
        _ => None,
    }
}
