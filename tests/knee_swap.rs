//! Swapping gait2392's knee for a PinJoint about a given axis: the tibia keeps its pose at the
//! reference angle, turns about the axis away from it, and the document changes only at the joint.

mod common;

use nalgebra::Vector3;
use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{rotation_about, Multibody, Transform};
use osim_tune::model::ModelSpec;
use osim_tune::tuning::knee_axis::{swap_knee, JointAxis, SwapError};

fn gait2392() -> OsimDocument {
    OsimDocument::read(&common::root().join("models/gait2392_millard2012muscle.osim")).unwrap()
}

/// An axis a few degrees and millimetres off the generic knee's Z axis, in the femur frame.
fn tilted_axis() -> JointAxis {
    JointAxis { point: Vector3::new(0.004, -0.41, 0.006), direction: Vector3::new(0.05, -0.03, 1.0).normalize() }
}

/// X_femur_tibia with knee_angle_r at `angle` and every other coordinate at its default.
fn tibia_in_femur(document: &OsimDocument, angle: f64) -> Transform {
    let multibody = Multibody::new(&ModelSpec::read(document).unwrap()).unwrap();
    let mut q = multibody.default_pose();
    q[multibody.coordinate_index("knee_angle_r").unwrap()] = angle;
    let mut kinematics = multibody.kinematics();
    multibody.realize(&q, &mut kinematics);
    let body = |name: &str| kinematics.bodies[multibody.body_index(name).unwrap()];
    body("femur_r").inverse().compose(&body("tibia_r"))
}

fn assert_same_pose(a: &Transform, b: &Transform, tolerance: f64) {
    for point in [Vector3::zeros(), Vector3::new(0.0, -0.4, 0.0), Vector3::new(0.05, 0.02, -0.04)] {
        let distance = (a.apply(&point) - b.apply(&point)).norm();
        assert!(distance < tolerance, "point {point:?} moved by {distance} m");
    }
}

#[test]
fn the_tibia_keeps_its_pose_at_the_reference_angle() {
    let generic = gait2392();
    for reference in [0.0, -0.6] {
        let swapped = swap_knee(&generic, "knee_r", &tilted_axis(), Some(reference)).unwrap();
        assert_same_pose(&tibia_in_femur(&generic, reference), &tibia_in_femur(&swapped.document, reference), 1e-12);
        assert!(swapped.reference_pose_error < 1e-12, "{}", swapped.reference_pose_error);
    }
}

#[test]
fn away_from_the_reference_the_tibia_turns_about_the_axis() {
    let generic = gait2392();
    let axis = tilted_axis();
    let swapped = swap_knee(&generic, "knee_r", &axis, None).unwrap();
    let reference = tibia_in_femur(&generic, 0.0);
    for angle in [-1.9, -0.8, 0.1] {
        let turn = rotation_about(&axis.direction, angle);
        let about_axis = Transform { rotation: turn, translation: axis.point - turn * axis.point };
        assert_same_pose(&about_axis.compose(&reference), &tibia_in_femur(&swapped.document, angle), 1e-12);
    }
}

#[test]
fn only_the_knee_joint_changes_in_the_document() {
    let generic = gait2392();
    let swapped = swap_knee(&generic, "knee_r", &tilted_axis(), None).unwrap();
    let text = |document: &OsimDocument| String::from_utf8(document.xml.serialize()).unwrap();
    let (before, after) = (text(&generic), text(&swapped.document));
    let start = before.find("<CustomJoint name=\"knee_r\">").unwrap();
    assert_eq!(before[..start], after[..start]);
    let end_before = start + before[start..].find("</CustomJoint>").unwrap() + "</CustomJoint>".len();
    let end_after = start + after[start..].find("</PinJoint>").unwrap() + "</PinJoint>".len();
    assert_eq!(before[end_before..], after[end_after..]);
    let joint = &after[start..end_after];
    assert!(joint.starts_with("<PinJoint name=\"knee_r\">") && !joint.contains("SpatialTransform"), "{joint}");
    assert!(joint.contains("<Coordinate name=\"knee_angle_r\">") && joint.contains("<range>-2.0943950999999998 0.17453293</range>"));
    let spec = ModelSpec::read(&swapped.document).unwrap();
    let knee = spec.joints.iter().find(|j| j.name == "knee_r").unwrap();
    assert_eq!((knee.class.as_str(), knee.parent.body.as_str(), knee.child.body.as_str()), ("PinJoint", "femur_r", "tibia_r"));
}

#[test]
fn the_knee_muscles_path_changes_are_reported() {
    let swapped = swap_knee(&gait2392(), "knee_r", &tilted_axis(), None).unwrap();
    let names: Vec<&str> = swapped.paths.iter().map(|p| p.muscle.as_str()).collect();
    for muscle in ["semimem_r", "bifemsh_r", "rect_fem_r", "vas_lat_r", "med_gas_r", "lat_gas_r", "grac_r", "sar_r", "tfl_r"] {
        assert!(names.contains(&muscle), "{muscle} missing from {names:?}");
    }
    assert!(!names.contains(&"soleus_r") && !names.contains(&"semimem_l"), "{names:?}");
    // The generic knee translates its axis by up to ~1 cm over the range; a fixed axis changes
    // the quadriceps' moment arms by millimetres, not by nothing and not by decimetres.
    let vas_lat = swapped.paths.iter().find(|p| p.muscle == "vas_lat_r").unwrap();
    assert!(vas_lat.max_moment_arm_change > 1e-4 && vas_lat.max_moment_arm_change < 0.05, "{vas_lat:?}");
}

#[test]
fn joints_that_are_not_a_one_coordinate_hinge_are_refused() {
    let generic = gait2392();
    assert!(matches!(swap_knee(&generic, "knee_x", &tilted_axis(), None), Err(SwapError::UnknownJoint { .. })));
    let error = swap_knee(&generic, "hip_r", &tilted_axis(), None).unwrap_err();
    assert!(error.to_string().contains("3 coordinate(s)"), "{error}");
    let flat = JointAxis { point: Vector3::zeros(), direction: Vector3::zeros() };
    assert!(matches!(swap_knee(&generic, "knee_r", &flat, None), Err(SwapError::BadAxis { .. })));
}

/// A 3.x model is converted to OpenSim 4's format first: its knee swapped is the knee of OpenSim
/// 4.6's own conversion of it swapped, in a 4.x document.
#[test]
fn a_3x_model_is_converted_then_swapped() {
    let legacy = OsimDocument::read(&common::fixture("legacy/pendulum_leg_v30000_digits.osim")).unwrap();
    let converted = OsimDocument::read(&common::fixture("golden/upgrade/pendulum_leg_v30000_digits.osim")).unwrap();
    let ours = swap_knee(&legacy, "knee", &tilted_axis(), None).unwrap();
    let theirs = swap_knee(&converted, "knee", &tilted_axis(), None).unwrap();
    assert_eq!(ours.document.version.number, 40000);
    assert_eq!((ours.parent_frame.clone(), ours.child_frame.clone()), (theirs.parent_frame.clone(), theirs.child_frame.clone()));
    let knee = |swapped: &OsimDocument| ModelSpec::read(swapped).unwrap().joints.into_iter().find(|j| j.name == "knee").unwrap();
    let (a, b) = (knee(&ours.document), knee(&theirs.document));
    assert_eq!((a.class.as_str(), &a.parent, &a.child), (b.class.as_str(), &b.parent, &b.child));
}
