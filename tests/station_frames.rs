//! `StationDefinedFrame`s (OpenSim 4.5) against OpenSim 4.6 (`fixtures/golden/station_frames.json`,
//! `oracle/gen_station_frames.py`): each frame's transform in its body, and a joint, markers and
//! a path point on such frames (one behind an offset frame) at three poses.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::validation::compare_model_golden;

#[test]
fn station_defined_frames_are_placed_as_opensim_places_them() {
    let c = compare_model_golden(&common::root(), "models/station_frames.osim", "golden/station_frames.json").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((c.frames.count, c.markers.count, c.lengths.count), (2 * 12, 3 * 3 * 3, 3));
    assert!(c.frames.error < 1e-15 && c.markers.error < 1e-15 && c.lengths.error < 1e-15, "{c:?}");
    // OpenSim's PinJoint constructor put an offset frame of its own on knee_frame.
    let document = OsimDocument::read(&common::fixture("models/station_frames.osim")).unwrap();
    let knee = ModelSpec::read(&document).unwrap().joints.into_iter().find(|j| j.name == "knee").unwrap();
    assert_eq!((knee.parent.name.as_str(), knee.parent.body.as_str(), knee.parent.offsets.len()), ("knee_frame_offset", "thigh", 2));
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
