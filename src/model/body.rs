//! Bodies: mass properties in the body frame.

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;
use crate::io::osim::Dialect;

/// A rigid body as written in the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodySpec {
    pub name: String,
    /// kg.
    pub mass: f64,
    /// m, in the body frame.
    pub mass_center: [f64; 3],
    /// kg·m² about the mass center: [xx, yy, zz, xy, xz, yz].
    pub inertia: [f64; 6],
}

impl BodySpec {
    pub fn read(reader: ComponentReader, dialect: Dialect) -> Result<BodySpec, ModelError> {
        let inertia = if dialect == Dialect::V4 {
            let i = reader.numbers_or("inertia", &[0.0; 6])?;
            [i[0], i[1], i[2], i[3], i[4], i[5]]
        } else {
            let mut i = [0.0; 6];
            for (value, property) in i.iter_mut().zip(["inertia_xx", "inertia_yy", "inertia_zz", "inertia_xy", "inertia_xz", "inertia_yz"]) {
                *value = reader.number(property)?;
            }
            i
        };
        Ok(BodySpec { name: reader.name(), mass: reader.number("mass")?, mass_center: reader.vec3_or("mass_center", [0.0; 3])?, inertia })
    }
}
