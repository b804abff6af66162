//! `StationDefinedFrame`s (OpenSim 4.5) against OpenSim 4.6 (`fixtures/golden/station_frames.json`,
//! `oracle/gen_station_frames.py`): each frame's transform in its body, and a joint, markers and
//! a path point on such frames (one behind an offset frame) at three poses.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{body_fixed_xyz, MuscleGeometry, PathEvaluation};
use osim_tune::model::ModelSpec;
use serde_json::Value;

fn numbers(value: &Value) -> Vec<f64> {
    value.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect()
}

#[test]
fn station_defined_frames_are_placed_as_opensim_places_them() {
    let document = OsimDocument::read(&common::fixture("models/station_frames.osim")).unwrap();
    let spec = ModelSpec::read(&document).unwrap_or_else(|e| panic!("{e}"));
    let golden: Value = serde_json::from_str(&std::fs::read_to_string(common::fixture("golden/station_frames.json")).unwrap()).unwrap();
    let knee = spec.joints.iter().find(|j| j.name == "knee").unwrap();
    // OpenSim's PinJoint constructor put an offset frame of its own on knee_frame.
    assert_eq!((knee.parent.name.as_str(), knee.parent.body.as_str(), knee.parent.offsets.len()), ("knee_frame_offset", "thigh", 2));
    let frame = &golden["frames_in_body"]["knee_frame"];
    let rotation = body_fixed_xyz(knee.parent.offsets[0].orientation);
    for (i, row) in frame["rotation"].as_array().unwrap().iter().enumerate() {
        for (j, expected) in numbers(row).into_iter().enumerate() {
            assert!((rotation[(i, j)] - expected).abs() < 1e-15, "knee_frame R[{i}][{j}] = {}", rotation[(i, j)]);
        }
    }
    for (ours, expected) in knee.parent.offsets[0].translation.iter().zip(numbers(&frame["origin"])) {
        assert!((ours - expected).abs() < 1e-16);
    }
    let geometry = MuscleGeometry::new(&spec).unwrap();
    let multibody = &geometry.multibody;
    let mut evaluation = PathEvaluation::new(&geometry, &[0]);
    for pose in golden["poses"].as_array().unwrap() {
        let q = numbers(&pose["q"]);
        evaluation.evaluate(&geometry, &q);
        for (m, marker) in multibody.markers.iter().enumerate() {
            let ours = evaluation.kinematics().marker_location(multibody, m);
            for (axis, expected) in numbers(&pose["markers_in_ground"][&marker.name]).into_iter().enumerate() {
                assert!((ours[axis] - expected).abs() < 1e-15, "{q:?}: {} {ours:?}", marker.name);
            }
        }
        assert!((evaluation.length(0) - pose["length"].as_f64().unwrap()).abs() < 1e-15, "{q:?}: {}", evaluation.length(0));
    }
}

/// Stations on two bodies cannot define a frame (OpenSim asserts the same): the error names the
/// frame, the socket and the bodies.
#[test]
fn stations_on_different_bodies_are_refused() {
    let path = common::fixture("models/station_frames.osim");
    let text = std::fs::read_to_string(&path).unwrap();
    let moved = text.replacen("<socket_point_c>/medial_condyle</socket_point_c>", "<socket_point_c>/medial_malleolus</socket_point_c>", 1);
    assert_ne!(moved, text);
    let document = OsimDocument::parse(moved, &path).unwrap();
    let message = ModelSpec::read(&document).unwrap_err().to_string();
    assert!(message.contains("knee_frame") && message.contains("socket_point_c") && message.contains("shank") && message.contains("thigh"), "{message}");
}
