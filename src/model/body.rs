//! Bodies: mass properties in the body frame.

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;
use super::conversion::six_significant_digits;
use crate::io::osim::DocumentVersion;

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

/// The first document version that writes a body's inertia as one `<inertia>` property.
const INERTIA_PROPERTY_VERSION: u32 = 30500;

impl BodySpec {
    /// Reads a body; before document 30500 its `inertia_xx`…`inertia_yz`, which OpenSim 4's
    /// conversion re-writes to six significant digits.
    pub fn read(reader: ComponentReader, version: DocumentVersion) -> Result<BodySpec, ModelError> {
        let inertia = if version.number >= INERTIA_PROPERTY_VERSION {
            let i = reader.numbers_or("inertia", &[0.0; 6])?;
            [i[0], i[1], i[2], i[3], i[4], i[5]]
        } else {
            // OpenSim's conversion starts from 1 1 1 0 0 0 for the elements a body leaves out.
            let mut i = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
            for (value, property) in i.iter_mut().zip(["inertia_xx", "inertia_yy", "inertia_zz", "inertia_xy", "inertia_xz", "inertia_yz"]) {
                *value = six_significant_digits(reader.number_or(property, *value)?);
            }
            i
        };
        Ok(BodySpec { name: reader.name(), mass: reader.number("mass")?, mass_center: reader.vec3_or("mass_center", [0.0; 3])?, inertia })
    }
}
