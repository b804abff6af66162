//! Errors of muscle construction and equilibrium.

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum MuscleError {
    #[error(
        "muscle '{muscle}': {property} = {value} is outside the range OpenSim accepts: {expected}"
    )]
    InvalidParameter {
        muscle: String,
        property: String,
        value: f64,
        expected: String,
    },
    #[error("muscle '{muscle}': {what} = {value} is not valid: expected {expected}")]
    InvalidInput {
        muscle: String,
        what: String,
        value: f64,
        expected: String,
    },
    #[error("muscle '{muscle}': no equilibrium at activation {activation} and path length {mt_length} m: {reason}")]
    Infeasible {
        muscle: String,
        activation: f64,
        mt_length: f64,
        reason: String,
    },
    #[error(
        "muscle '{muscle}': equilibrium at activation {activation} and path length {mt_length} m did not converge \
         in {iterations} iterations (force residual {residual} N)"
    )]
    NotConverged {
        muscle: String,
        activation: f64,
        mt_length: f64,
        iterations: usize,
        residual: f64,
    },
    #[error("muscle '{muscle}': class {class} has no muscle mechanics in osim-tune (supported: {supported})", supported = crate::model::MUSCLE_CLASSES.join(", "))]
    Unsupported { muscle: String, class: String },
}

impl MuscleError {
    /// The first (property, value) that is not a finite number > 0 (NaN fails), as an
    /// `InvalidParameter` expecting `expected`.
    pub fn require_positive(muscle: &str, values: &[(&str, f64)], expected: &str) -> Result<(), MuscleError> {
        match values.iter().find(|(_, value)| !(*value > 0.0 && value.is_finite())) {
            Some(&(property, value)) => Err(MuscleError::invalid_parameter(muscle, property, value, expected)),
            None => Ok(()),
        }
    }

    pub fn invalid_parameter(
        muscle: &str,
        property: &str,
        value: f64,
        expected: &str,
    ) -> MuscleError {
        MuscleError::InvalidParameter {
            muscle: muscle.into(),
            property: property.into(),
            value,
            expected: expected.into(),
        }
    }

    pub fn invalid_input(muscle: &str, what: &str, value: f64, expected: &str) -> MuscleError {
        MuscleError::InvalidInput {
            muscle: muscle.into(),
            what: what.into(),
            value,
            expected: expected.into(),
        }
    }
}
