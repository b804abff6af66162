//! The model extended by a named single cause (METHOD.md §8): the initial model with only that
//! cause's muscle parameter(s), or its knee joint's offset frames, set to the fitted value, for
//! the user to carry on with. Causes in the trials (an angle offset, an activation level) or in
//! the measured moments (an offset) change no model property.

use super::cause::{Cause, SingleCause};
use super::cause_axis::AxisMove;
use super::parameters::MuscleParameters;
use crate::io::osim::{format_numbers, Dialect, OsimDocument, OsimError};
use crate::mechanics::{body_fixed_xyz, Vec3};

/// What [`apply_cause`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum CauseEdit {
    /// The number of values changed.
    Changed(usize),
    /// Why the cause is no change of this model (e.g. `is in the trials, not the model`).
    NotInModel(String),
}

/// Sets `cause`'s fitted value in `document` (the model the fit started from, whose estimated
/// muscles' values are `initial`, under `/forceset`): one muscle's parameter, every group
/// member's scaled by the fitted factor, or the translations of the joint's two offset frames.
pub fn apply_cause(cause: &SingleCause, initial: &[MuscleParameters], document: &mut OsimDocument) -> Result<CauseEdit, OsimError> {
    let (parameter, changes): (_, Vec<(&str, f64)>) = match &cause.cause {
        Cause::Muscle { muscle, parameter } => (parameter, vec![(muscle.as_str(), cause.fitted)]),
        Cause::Group { muscles, parameter, .. } => {
            let members = initial.iter().filter(|p| muscles.contains(&p.name));
            (parameter, members.map(|p| (p.name.as_str(), p.get(*parameter) * cause.fitted)).collect())
        }
        Cause::AxisOffset { joint } => match &cause.axis_move {
            Some(axis_move) => return move_axis(document, joint, axis_move),
            None => return Ok(CauseEdit::NotInModel("has no fitted move".into())),
        },
        Cause::AngleOffset { .. } | Cause::Activation { .. } | Cause::MuscleActivation { .. } => return Ok(CauseEdit::NotInModel("is in the trials, not the model".into())),
        Cause::MomentOffset => return Ok(CauseEdit::NotInModel("is in the measured moments, not the model".into())),
    };
    for (muscle, value) in &changes {
        document.set_property(&format!("/forceset/{muscle}/{}", parameter.property()), &format_numbers(&[*value]))?;
    }
    Ok(CauseEdit::Changed(changes.len()))
}

/// Moves `joint`'s parent and child offset frames by `axis_move` (mm, each in its frame): each
/// frame's translation, in its body, gains R(orientation)·offset.
fn move_axis(document: &mut OsimDocument, joint: &str, axis_move: &AxisMove) -> Result<CauseEdit, OsimError> {
    if document.version.dialect != Dialect::V4 {
        return Ok(CauseEdit::NotInModel(format!("moves joint {joint}, whose frames a 3.x model does not write as offset frames; convert the model with `osim-tune convert` first")));
    }
    let mut frames = Vec::new();
    for socket in ["socket_parent_frame", "socket_child_frame"] {
        let frame = document.resolve(&format!("/jointset/{joint}/{socket}")).ok().and_then(|id| document.xml.text(id)).map(|t| t.trim().to_string());
        match frame.filter(|f| !f.contains('/') && document.resolve(&format!("/jointset/{joint}/{f}/translation")).is_ok()) {
            Some(frame) => frames.push(format!("/jointset/{joint}/{frame}")),
            None => return Ok(CauseEdit::NotInModel(format!("moves joint {joint}, whose <{socket}> is not an offset frame the joint owns"))),
        }
    }
    for (frame, offset) in frames.iter().zip([axis_move.in_parent, axis_move.in_child]) {
        let [translation, orientation] = ["translation", "orientation"].map(|p| read_vec3(document, &format!("{frame}/{p}")));
        let (Some(translation), Some(orientation)) = (translation?, orientation?) else {
            return Ok(CauseEdit::NotInModel(format!("moves joint {joint}, whose frame {frame} has no three-number translation and orientation")));
        };
        let moved = translation + body_fixed_xyz(orientation.into()) * (Vec3::from(offset) / 1000.0);
        document.set_property(&format!("{frame}/translation"), &format_numbers(moved.as_slice()))?;
    }
    Ok(CauseEdit::Changed(2))
}

/// The three numbers of the property at `path`, `None` when it holds something else.
fn read_vec3(document: &OsimDocument, path: &str) -> Result<Option<Vec3>, OsimError> {
    let id = document.resolve(path)?;
    let numbers: Option<Vec<f64>> = document.xml.text(id).and_then(|t| t.split_whitespace().map(str::parse).collect::<Result<_, _>>().ok());
    Ok(numbers.filter(|n| n.len() == 3).map(|n| Vec3::new(n[0], n[1], n[2])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn subject01() -> OsimDocument {
        OsimDocument::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/golden/scale/subject01_simbody.osim")).unwrap()
    }

    /// knee_r's axis moved 5 mm along `parent_direction` (`child_direction` in the child frame).
    fn moved_knee_axis(parent_direction: [f64; 3], child_direction: [f64; 3]) -> SingleCause {
        let axis_move = Some(AxisMove { in_parent: parent_direction.map(|c| 5.0 * c), in_child: child_direction.map(|c| 5.0 * c) });
        let cause = Cause::AxisOffset { joint: "knee_r".into() };
        SingleCause { cause, initial: 0.0, fitted: 5.0, rms_before: 1.0, rms_after: 0.0, at_minimum: true, variables: 2, axis_move, unit_noise_sd: 0.1, residuals: Vec::new() }
    }

    fn translation(document: &OsimDocument, frame: &str) -> Vec3 {
        read_vec3(document, &format!("/jointset/knee_r/{frame}/translation")).unwrap().unwrap()
    }

    #[test]
    fn an_axis_offset_moves_both_frames_along_their_own_axes() {
        let mut document = subject01();
        // The parent frame turned 90° about Z: its X is the femur's Y.
        document.set_property("/jointset/knee_r/femur_r_offset/orientation", "0 0 1.5707963267948966").unwrap();
        assert_eq!(apply_cause(&moved_knee_axis([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), &[], &mut document).unwrap(), CauseEdit::Changed(2));
        assert!((translation(&document, "femur_r_offset") - Vec3::new(0.0, 0.005, 0.0)).norm() < 1e-15);
        assert!((translation(&document, "tibia_r_offset") - Vec3::new(0.0, 0.005, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn a_joint_without_its_own_offset_frames_is_not_moved() {
        let mut document = subject01();
        document.set_property("/jointset/knee_r/socket_parent_frame", "/bodyset/femur_r").unwrap();
        let before = document.xml.serialize();
        let CauseEdit::NotInModel(reason) = apply_cause(&moved_knee_axis([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]), &[], &mut document).unwrap() else { panic!("moved") };
        assert!(reason.contains("<socket_parent_frame> is not an offset frame the joint owns"), "{reason}");
        assert_eq!(document.xml.serialize(), before);
    }
}
