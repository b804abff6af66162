//! The model extended by a named single cause (METHOD.md §8): the initial model with only that
//! cause's muscle parameter(s) set to the fitted value, for the user to carry on with. Causes in
//! the trials (an angle offset, an activation level) change no model property.

use super::cause::{Cause, SingleCause};
use super::parameters::MuscleParameters;
use crate::io::osim::{format_numbers, OsimDocument, OsimError};

/// Sets `cause`'s fitted value in `document` (the model the fit started from, whose estimated
/// muscles' values are `initial`, under `/forceset`): one muscle's parameter, or every group
/// member's scaled by the fitted factor. Returns the number of values changed, or `None` for a
/// cause that is not a model property.
pub fn apply_cause(cause: &SingleCause, initial: &[MuscleParameters], document: &mut OsimDocument) -> Result<Option<usize>, OsimError> {
    let (parameter, changes): (_, Vec<(&str, f64)>) = match &cause.cause {
        Cause::Muscle { muscle, parameter } => (parameter, vec![(muscle.as_str(), cause.fitted)]),
        Cause::Group { muscles, parameter, .. } => {
            let members = initial.iter().filter(|p| muscles.contains(&p.name));
            (parameter, members.map(|p| (p.name.as_str(), p.get(*parameter) * cause.fitted)).collect())
        }
        Cause::AngleOffset { .. } | Cause::Activation { .. } => return Ok(None),
    };
    for (muscle, value) in &changes {
        document.set_property(&format!("/forceset/{muscle}/{}", parameter.property()), &format_numbers(&[*value]))?;
    }
    Ok(Some(changes.len()))
}
