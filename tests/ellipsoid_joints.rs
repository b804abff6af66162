//! Joints that glide on an ellipsoid — `ScapulothoracicJoint` and `EllipsoidJoint` — against
//! OpenSim 4.6 (`fixtures/golden/ellipsoid_joints.json`, `oracle/gen_ellipsoid_joints.py`):
//! markers, a muscle's length and moment arms, and inverse dynamics at four poses.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{MotionState, MuscleGeometry, PathEvaluation};
use osim_tune::model::ModelSpec;
use serde_json::Value;

fn numbers(value: &Value) -> Vec<f64> {
    value.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect()
}

#[test]
fn ellipsoid_joints_compute_as_opensim() {
    let document = OsimDocument::read(&common::fixture("models/ellipsoid_joints.osim")).unwrap();
    let spec = ModelSpec::read(&document).unwrap();
    let geometry = MuscleGeometry::new(&spec).unwrap_or_else(|e| panic!("{e}"));
    let multibody = &geometry.multibody;
    let golden: Value = serde_json::from_str(&std::fs::read_to_string(common::fixture("golden/ellipsoid_joints.json")).unwrap()).unwrap();
    let names: Vec<&str> = multibody.coordinates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, golden["coordinates"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect::<Vec<_>>());
    let mut evaluation = PathEvaluation::loading(&geometry, &[0]);
    for pose in golden["poses"].as_array().unwrap() {
        let (q, u, udot) = (numbers(&pose["q"]), numbers(&pose["u"]), numbers(&pose["udot"]));
        evaluation.evaluate(&geometry, &q);
        for (m, marker) in multibody.markers.iter().enumerate() {
            let ours = evaluation.kinematics().marker_location(multibody, m);
            for (axis, expected) in numbers(&pose["markers_in_ground"][&marker.name]).into_iter().enumerate() {
                assert!((ours[axis] - expected).abs() < 1e-14, "{q:?}: {} {ours:?}", marker.name);
            }
        }
        assert!((evaluation.length(0) - pose["length"].as_f64().unwrap()).abs() < 1e-14, "{q:?}: length {}", evaluation.length(0));
        let mut arms = vec![0.0; names.len()];
        for (&c, &arm) in evaluation.coordinates(&geometry, 0).iter().zip(evaluation.moment_arms(0)) {
            arms[c] = arm;
        }
        for (c, name) in names.iter().enumerate() {
            let expected = pose["moment_arms"][name].as_f64().unwrap();
            assert!((arms[c] - expected).abs() < 1e-12, "{q:?}: moment arm about {name}: {} vs {expected}", arms[c]);
        }
        let forces = multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]);
        for ((ours, expected), name) in forces.iter().zip(numbers(&pose["generalized_forces"])).zip(&names) {
            assert!((ours - expected).abs() < 1e-11, "{q:?}: {name}: {ours} vs {expected}");
        }
    }
}
