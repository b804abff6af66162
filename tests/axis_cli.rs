//! `osim-tune axis` end to end: a synthetic flexion trial with a known axis (marker clusters
//! from the trial), a hinge model moved about a known axis (clusters from the model, knee
//! swapped), and a trial with too little rotation.

mod common;

use std::path::Path;

use common::osim_tune;
use nalgebra::Vector3;
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{LengthUnit, MarkerTable, TrcHeader};
use osim_tune::mechanics::Multibody;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::knee_axis::{swap_knee, Axis, JointAxis};
use osim_tune::validation::knee_axis::{synthetic_knee, Condition, SyntheticKneeSettings};
use serde_json::Value;

const SCALED_MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";

fn vector(value: &Value) -> Vector3<f64> {
    let numbers: Vec<f64> = value.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    Vector3::from_column_slice(&numbers)
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Angle (rad, sign-free) and distance (m) of `axis` from the line of `truth` at its point.
fn errors(truth: &Axis, axis: &Value) -> (f64, f64) {
    let (point, direction) = (vector(&axis["point"]), vector(&axis["direction"]));
    let angle = direction.dot(&truth.direction).abs().min(1.0).acos();
    let offset = truth.point - point;
    (angle, (offset - direction * offset.dot(&direction)).norm())
}

#[test]
fn the_axis_of_a_synthetic_flexion_trial_is_found_in_the_lab_frame() {
    let knee = synthetic_knee(&SyntheticKneeSettings::new(3, Condition::Noise)).unwrap();
    let folder = tempfile::tempdir().unwrap();
    let trial = folder.path().join("flexion.trc");
    std::fs::write(&trial, knee.trial.to_text()).unwrap();
    let femur = knee.femur_cluster.markers.join(",");
    let tibia = knee.tibia_cluster.markers.join(",");
    let epicondyles = format!("{},{}", knee.lateral_epicondyle, knee.medial_epicondyle);
    let truth = knee.true_axis_femur.in_lab(&knee.femur_poses[0]);
    for method in ["gal", "sara"] {
        let (code, stdout, stderr) = osim_tune(&["axis", s(&trial), "--femur", &femur, "--tibia", &tibia, "--method", method, "--epicondyles", &epicondyles, "--json"]);
        assert_eq!(code, 0, "{stderr}");
        let report: Value = serde_json::from_str(&stdout).unwrap();
        let (angle, distance) = errors(&truth, &report["axis"]);
        assert!(angle.to_degrees() < 1.5 && distance < 5e-3, "{method}: {:.2}°, {:.1} mm", angle.to_degrees(), distance * 1e3);
        assert!((vector(&report["axis"]["direction"]).norm() - 1.0).abs() < 1e-12);
        assert!(report["transepicondylar"]["frontal_angle_deg"].as_f64().unwrap().is_finite(), "{report}");
        assert!(report["rotation_range_deg"].as_f64().unwrap() > 70.0, "{report}");
    }
}

#[test]
fn too_little_rotation_is_refused_as_not_identifiable() {
    let mut settings = SyntheticKneeSettings::new(4, Condition::Noise);
    settings.flexion = (20f64.to_radians(), 30f64.to_radians());
    let knee = synthetic_knee(&settings).unwrap();
    let folder = tempfile::tempdir().unwrap();
    let trial = folder.path().join("small.trc");
    std::fs::write(&trial, knee.trial.to_text()).unwrap();
    let (code, _, stderr) = osim_tune(&["axis", s(&trial), "--femur", &knee.femur_cluster.markers.join(","), "--tibia", &knee.tibia_cluster.markers.join(",")]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("not identifiable"), "{stderr}");
}

/// The model's femur and tibia markers while `hinge` (a model whose knee_r turns about a known
/// axis) flexes the knee from 0 to −100°, everything else at its default.
fn hinge_trial(hinge: &OsimDocument) -> MarkerTable {
    let multibody = Multibody::new(&ModelSpec::read(hinge).unwrap()).unwrap();
    let knee = multibody.coordinate_index("knee_angle_r").unwrap();
    let markers: Vec<usize> = (0..multibody.markers.len())
        .filter(|&m| ["femur_r", "tibia_r"].contains(&multibody.bodies[multibody.markers[m].body].name.as_str()))
        .collect();
    let (mut kinematics, mut q) = (multibody.kinematics(), multibody.default_pose());
    let (mut times, mut positions) = (Vec::new(), Vec::new());
    for frame in 0..=100 {
        q[knee] = -(frame as f64).to_radians();
        multibody.realize(&q, &mut kinematics);
        times.push(frame as f64 / 100.0);
        positions.extend(markers.iter().map(|&m| Some(kinematics.marker_location(&multibody, m).into())));
    }
    let names = markers.iter().map(|&m| multibody.markers[m].name.clone()).collect();
    MarkerTable::new(TrcHeader::new(100.0, LengthUnit::Meters), names, times, positions).unwrap()
}

#[test]
fn a_hinge_axis_is_recovered_from_model_clusters_and_the_knee_is_swapped_onto_it() {
    let scaled = OsimDocument::read(Path::new(SCALED_MODEL)).unwrap();
    let known = JointAxis { point: Vector3::new(-0.003, -0.405, 0.004), direction: Vector3::new(-0.04, 0.06, 1.0).normalize() };
    let hinge = swap_knee(&scaled, "knee_r", &known, None).unwrap().document;
    let folder = tempfile::tempdir().unwrap();
    let trial = folder.path().join("hinge.trc");
    std::fs::write(&trial, hinge_trial(&hinge).to_text()).unwrap();
    let output = folder.path().join("out/swapped.osim");
    let arguments = ["axis", s(&trial), "--femur", "femur_r", "--tibia", "tibia_r", "--model", SCALED_MODEL, "--swap", "knee_r", "-o", s(&output), "--json"];
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(report["femur"]["segment"], "femur_r");
    let truth = Axis::new(known.point, known.direction).unwrap();
    let (angle, distance) = errors(&truth, &report["femur"]["axis"]);
    assert!(angle < 1e-6 && distance < 1e-6, "{angle} rad, {distance} m: {report}");
    assert!(report["swap"]["reference_pose_error"].as_f64().unwrap() < 1e-9, "{report}");
    assert_eq!(report["swap"]["paths"].as_array().unwrap().len(), 13, "{report}");
    let swapped = ModelSpec::read(&OsimDocument::read(&output).unwrap()).unwrap();
    assert_eq!(swapped.joints.iter().find(|j| j.name == "knee_r").unwrap().class, "PinJoint");
    let (code, _, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    let (code, _, stderr) = osim_tune(&["axis", s(&trial), "--femur", "femur_r", "--tibia", "tibia_r", "--model", SCALED_MODEL, "--swap", "knee_r", "-o", SCALED_MODEL]);
    assert_eq!(code, 2, "overwriting the model must be refused: {stderr}");
}
