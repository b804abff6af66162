//! `postScale` of path-based forces: a muscle's `optimal_fiber_length` and
//! `tendon_slack_length` (a ligament's or path spring's `resting_length`) times the ratio of its
//! path length after and before scaling, both at the model's default pose.

use super::edits::{scaled_number_edit, Edit};
use super::error::ScaleError;
use crate::io::osim::OsimDocument;
use crate::mechanics::{GeometryPath, Multibody, PathScratch};
use crate::model::{ComponentReader, ForceSpec, ModelSpec};
use crate::solvers::assembled_default_pose;

/// Classes derived from OpenSim's `ActivationFiberLengthMuscle` (and DeGroote–Fregly), whose
/// `extendPostScale` rescales both lengths.
const FIBER_LENGTH_MUSCLES: [&str; 7] = [
    "Millard2012EquilibriumMuscle",
    "Millard2012AccelerationMuscle",
    "Thelen2003Muscle",
    "DeGrooteFregly2016Muscle",
    "Schutte1993Muscle_Deprecated",
    "Delp1990Muscle_Deprecated",
    "Thelen2003Muscle_Deprecated",
];

/// Classes whose `extendPostScale` rescales `resting_length`.
const RESTING_LENGTH_FORCES: [&str; 2] = ["Ligament", "PathSpring"];

/// One force's path length at the default pose before and after scaling (m).
#[derive(Debug, Clone, PartialEq)]
pub struct PathRescale {
    pub force: String,
    pub length_before: f64,
    pub length_after: f64,
}

impl PathRescale {
    pub fn ratio(&self) -> f64 {
        self.length_after / self.length_before
    }
}

/// Path lengths at the default state (assembled) of the forces OpenSim rescales, by name, in
/// ForceSet order.
pub fn default_pose_lengths(model: &ModelSpec) -> Result<Vec<(String, f64)>, ScaleError> {
    let multibody = Multibody::new(model)?;
    let mut kinematics = multibody.kinematics();
    let q = assembled_default_pose(&multibody)?;
    multibody.realize(&q, &mut kinematics);
    let mut scratch = PathScratch::default();
    let mut lengths = Vec::new();
    for force in model.forces.iter().filter(|f| rescaled(f)) {
        let path = GeometryPath::new(&multibody, model, force)?;
        if !path.ignored_wraps.is_empty() {
            let objects = path.ignored_wraps.join(", ");
            let problem = format!("{}: its path wraps over {objects}, among which one of a class OpenSim 4.6 does not have, which osim-tune does not wrap over, so it cannot rescale its lengths", force.name);
            return Err(ScaleError::Input { file: model.file.clone(), problem });
        }
        lengths.push((force.name.clone(), path.length(&kinematics, &q, &mut scratch)));
    }
    Ok(lengths)
}

fn rescaled(force: &ForceSpec) -> bool {
    FIBER_LENGTH_MUSCLES.contains(&force.class.as_str()) || RESTING_LENGTH_FORCES.contains(&force.class.as_str())
}

/// The edits rescaling each force of `model` (read from `document`) by its length ratio.
pub fn rescale_edits(document: &OsimDocument, model: &ModelSpec, before: &[(String, f64)], after: &[(String, f64)]) -> Result<(Vec<Edit>, Vec<PathRescale>), ScaleError> {
    let mut edits = Vec::new();
    let mut report = Vec::new();
    for (force, ((name, length_before), (_, length_after))) in model.forces.iter().filter(|f| rescaled(f)).zip(before.iter().zip(after)) {
        if *length_before <= 0.0 {
            continue;
        }
        if *length_after <= 0.0 {
            let problem = format!(
                "{name}: its path is {length_after} m long at the default pose after scaling ({length_before} m before), so its lengths would be rescaled to negative values; OpenSim's ScaleTool fails on this model too"
            );
            return Err(ScaleError::Input { file: model.file.clone(), problem });
        }
        let rescale = PathRescale { force: name.clone(), length_before: *length_before, length_after: *length_after };
        let reader = ComponentReader::new(document, force.element);
        let properties: &[&str] = if RESTING_LENGTH_FORCES.contains(&force.class.as_str()) { &["resting_length"] } else { &["optimal_fiber_length", "tendon_slack_length"] };
        for property in properties {
            edits.extend(scaled_number_edit(reader, property, rescale.ratio())?);
        }
        report.push(rescale);
    }
    Ok((edits, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path whose scaled length is not positive (OpenSim's far side of a WrapSphere can make
    /// it so) is refused, naming the muscle, rather than given a negative L_opt.
    #[test]
    fn a_path_not_positive_after_scaling_is_refused() {
        let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/models/leg6dof9musc.osim");
        let document = OsimDocument::read(&file).unwrap();
        let model = ModelSpec::read(&document).unwrap();
        let before = default_pose_lengths(&model).unwrap();
        let mut after = before.clone();
        assert!(rescale_edits(&document, &model, &before, &after).is_ok());
        after[1].1 = -0.01;
        let message = rescale_edits(&document, &model, &before, &after).unwrap_err().to_string();
        assert!(message.contains("leg6dof9musc.osim") && message.contains(&before[1].0) && message.contains("-0.01 m"), "{message}");
    }
}
