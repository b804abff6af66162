//! Inverse dynamics against OpenSim 4.6's `InverseDynamicsSolver` at 8 random states per model
//! (`fixtures/golden/inverse_dynamics/`): CustomJoints with spline-driven translations
//! (gait2392, Rajagopal2016 with its patellae coupled, leg6dof9musc), arm26 and the joint zoo's
//! Ball, Free, Gimbal, Planar, Slider, Pin and oblique custom joints; first principles for
//! applied loads; and OpenSim's InverseDynamicsTool on subject01's walk.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::{BodyLoad, MotionState, Multibody, Vec3};
use osim_tune::model::ModelSpec;
use osim_tune::validation::{compare_inverse_dynamics, Subject01Walk};

fn multibody(model: &str) -> Multibody {
    let spec = ModelSpec::read(&OsimDocument::read(&common::root().join(model)).unwrap()).unwrap();
    Multibody::new(&spec).unwrap()
}

/// Generalized forces within 1e-12 of OpenSim's, relative to max(1, |τ|) (rounding; the forces
/// reach some hundreds of N·m; found: ≤ 1.3e-14).
#[test]
fn generalized_forces_agree_with_opensim() {
    for (stem, model) in [
        ("gait2392_millard2012muscle", "models/gait2392_millard2012muscle.osim"),
        ("arm26", "fixtures/models/arm26.osim"),
        ("leg6dof9musc", "fixtures/models/leg6dof9musc.osim"),
        ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
        ("joint_zoo", "fixtures/models/joint_zoo.osim"),
    ] {
        let worst = compare_inverse_dynamics(&multibody(model), &common::fixture(&format!("golden/inverse_dynamics/{stem}.csv"))).unwrap();
        assert!(worst.error <= 1e-12, "{stem}: off by {:e} at {}", worst.error, worst.at);
        assert_eq!(worst.count % 8, 0);
    }
}

/// A force F at a point p of a body, at rest, must be balanced by τ = −Jₚᵀ F: its power per
/// unit speed along each coordinate's motion of p (central differences of p(q)).
#[test]
fn an_applied_force_is_balanced_by_its_virtual_work() {
    let model = multibody("models/gait2392_millard2012muscle.osim");
    let n = model.coordinates.len();
    let q: Vec<f64> = model.coordinates.iter().map(|c| 0.3 * c.range[0] + 0.5 * c.range[1]).collect();
    let zero = vec![0.0; n];
    let state = MotionState { q: &q, u: &zero, udot: &zero };
    let body = model.body_index("tibia_r").unwrap();
    let local = Vec3::new(0.02, -0.3, 0.01);
    let at = |q: &[f64]| {
        let mut kinematics = model.kinematics();
        model.realize(q, &mut kinematics);
        kinematics.bodies[body].apply(&local)
    };
    let load = BodyLoad { body, force: Vec3::new(30.0, 700.0, -20.0), point: at(&q), torque: Vec3::new(1.0, -2.0, 3.0) };
    let loaded = model.inverse_dynamics(&state, &[load]);
    let unloaded = model.inverse_dynamics(&state, &[]);
    let h = 1e-6;
    for c in 0..n {
        let (mut plus, mut minus) = (q.clone(), q.clone());
        plus[c] += h;
        minus[c] -= h;
        let velocity = (at(&plus) - at(&minus)) / (2.0 * h);
        let mut kinematics = model.kinematics();
        model.realize(&q, &mut kinematics);
        let turning = if model.is_moved_by(body, model.coordinate_joint(c)) { kinematics.axes[c].angular } else { Vec3::zeros() };
        let expected = -(load.force.dot(&velocity) + load.torque.dot(&turning));
        assert!((loaded[c] - unloaded[c] - expected).abs() < 1e-6, "{}: {} vs {expected}", model.coordinates[c].name, loaded[c] - unloaded[c]);
    }
}

/// OpenSim 4.6's InverseDynamicsTool on subject01's walk (the pipeline golden: subject01's
/// setup, IK from 0 s, GRF on both feet, 6 Hz low-pass): the same 76 frames (0.398 + k·0.016 s,
/// OpenSim's padded and resampled grid) and every generalized force within 6e-9 — OpenSim prints
/// 8 decimals, so rounding alone is up to 5e-9.
#[test]
fn the_tool_reproduces_opensims_walking_inverse_dynamics() {
    let walk = Subject01Walk::load(&common::root()).unwrap();
    let golden = StorageTable::read(&common::fixture("golden/inverse_dynamics/subject01_walk1_InverseDynamics.sto")).unwrap();
    let worst = walk.inverse_dynamics(&golden, false).unwrap();
    assert_eq!(worst.count, 76 * 24);
    assert!(worst.error <= 6e-9, "{:e} at {}", worst.error, worst.at);
}
