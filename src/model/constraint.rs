//! Kinematic constraints; `CoordinateCouplerConstraint` is read in full.

use serde::Serialize;

use super::error::ModelError;
use super::function::FunctionSpec;
use super::reader::ComponentReader;

/// dependent = scale_factor · f(independent…).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CouplerSpec {
    pub independent_coordinates: Vec<String>,
    pub dependent_coordinate: String,
    pub function: FunctionSpec,
    pub scale_factor: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConstraintSpec {
    pub name: String,
    pub class: String,
    pub enforced: bool,
    pub coupler: Option<CouplerSpec>,
}

impl ConstraintSpec {
    pub fn read(reader: ComponentReader) -> Result<ConstraintSpec, ModelError> {
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
        let enforced = reader.boolean_or("isEnforced", true)? && !reader.boolean_or("isDisabled", false)?;
        Ok(ConstraintSpec { name: reader.name(), class: reader.class().to_string(), enforced, coupler })
    }
}
