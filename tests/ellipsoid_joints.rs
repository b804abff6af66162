//! Joints that glide on an ellipsoid — `ScapulothoracicJoint` and `EllipsoidJoint` — against
//! OpenSim 4.6 (`fixtures/golden/ellipsoid_joints.json`, `oracle/gen_ellipsoid_joints.py`):
//! markers, a muscle's length and moment arms, and inverse dynamics at four poses.

mod common;

use osim_tune::validation::compare_model_golden;

#[test]
fn ellipsoid_joints_compute_as_opensim() {
    let c = compare_model_golden(&common::root(), "models/ellipsoid_joints.osim", "golden/ellipsoid_joints.json").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((c.markers.count, c.lengths.count, c.moment_arms.count, c.generalized_forces.count), (4 * 2 * 3, 4, 4 * 7, 4 * 7));
    assert!(c.markers.error < 1e-14 && c.lengths.error < 1e-14, "{c:?}");
    assert!(c.moment_arms.error < 1e-12 && c.generalized_forces.error < 1e-11, "{c:?}");
}
