//! Kinematics, markers, path lengths and moment arms against OpenSim 4.6 on a slice of its
//! goldens (`fixtures/golden/geometry/<model>/`: 15 random poses and the first, middle and last
//! angle of each knee sweep; the full sweep runs in `cargo xtask validate`).

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::MuscleGeometry;
use osim_tune::model::ModelSpec;
use osim_tune::validation::{compare_geometry, GeometryComparison};

fn compare(stem: &str, model: &str) -> GeometryComparison {
    let spec = ModelSpec::read(&OsimDocument::read(&common::root().join(model)).unwrap()).unwrap();
    let geometry = MuscleGeometry::new(&spec).unwrap_or_else(|e| panic!("{e}"));
    compare_geometry(&geometry, &common::fixture(&format!("golden/geometry/{stem}"))).unwrap()
}

/// Body positions, markers and lengths ≤ 1e-9 m, rotation entries ≤ 1e-9, moment arms ≤ 1e-8 m,
/// and the coordinates each muscle spans are the pairs OpenSim evaluated.
fn assert_agrees(stem: &str, c: &GeometryComparison) {
    for (what, worst, tolerance) in [
        ("body position", &c.body_positions, 1e-9),
        ("body rotation", &c.body_rotations, 1e-9),
        ("marker", &c.markers, 1e-9),
        ("length", &c.lengths, 1e-9),
        ("moment arm", &c.moment_arms, 1e-8),
    ] {
        assert!(worst.error <= tolerance, "{stem}: {what} off by {:e} at {}", worst.error, worst.at);
    }
    assert!(c.span_mismatches.is_empty(), "{stem}: {:?}", c.span_mismatches);
}

#[test]
fn gait2392_agrees_with_opensim() {
    let c = compare("gait2392_millard2012muscle", "models/gait2392_millard2012muscle.osim");
    assert_agrees("gait2392", &c);
    assert_eq!((c.body_positions.count, c.lengths.count), (21 * 12, 21 * 92));
    assert_eq!(c.moment_arms.count, 21 * 262);
}

#[test]
fn gait2354_agrees_with_opensim() {
    let c = compare("gait2354_simbody", "models/gait2354_simbody.osim");
    assert_agrees("gait2354", &c);
    assert_eq!(c.lengths.count, 21 * 54);
}

#[test]
fn scaled_subject01_agrees_with_opensim() {
    let c = compare("subject01_simbody", "fixtures/subject01/OutputReference/subject01_simbody.osim");
    assert_agrees("subject01", &c);
    assert_eq!(c.markers.count, 21 * 39);
}

/// leg6dof9musc and Rajagopal2016 couple the patella to the knee (moment arms follow the
/// couplers); Rajagopal2016 and arm26 wrap most muscles over cylinders, arm26's TRIlong and
/// BIClong also over ellipsoids.
#[test]
fn models_with_couplers_and_wrapping_agree() {
    for (stem, model) in [
        ("leg6dof9musc", "fixtures/models/leg6dof9musc.osim"),
        ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
        ("arm26", "fixtures/models/arm26.osim"),
    ] {
        let c = compare(stem, model);
        assert_agrees(stem, &c);
        assert!(c.body_positions.count > 0 && c.markers.count > 0, "{stem}");
    }
}

/// arm26's TRIlong wraps over the cylinder TRI, the ellipsoid TRIlonghh (quadrant +z) and the
/// cylinder TRIlongglen (OpenSim's passes over three wraps); BIClong over the ellipsoid
/// BIClonghh (quadrant −y, points 2–3). Both equal OpenSim: lengths ≤ 1.1e-15 m and moment arms
/// ≤ 2.7e-15 m on this slice (the ellipsoids wrap in 7 and 14 of its 21 poses); over all 174
/// golden poses (`cargo xtask validate`) 2.2e-15 m and 2.7e-15 m, the paths' iterations — the
/// fan of 298 closest points, the tangent points' Levenberg–Marquardt steps, the 1 mm polyline
/// over the surface — reproduced step by step.
#[test]
fn ellipsoid_wrapping_agrees_with_opensim() {
    let c = compare("arm26", "fixtures/models/arm26.osim");
    assert!(c.skipped.is_empty(), "{:?}", c.skipped);
    assert_agrees("arm26", &c);
    assert_eq!((c.lengths.count, c.moment_arms.count), (21 * 6, 21 * 9));
}

/// The wrap zoo (`oracle/gen_wrap_zoo.py`, all 55 poses): muscles over `WrapSphere`s — without
/// a quadrant (never a mandatory wrap: the segment changing the length least wraps), with the
/// quadrant −x (mandatory wraps, and flexor_close's far-side wraps, whose length OpenSim makes
/// negative: down to −0.154 m) — a cylinder and a sphere on one path, `WrapEllipsoid`s by the
/// hybrid, midpoint and axial methods with and without a quadrant, and `WrapTorus`es (OpenSim's
/// MINPACK iteration for the ring point, then a cylinder) with and without a quadrant: lengths
/// ≤ 1.8e-15 m and moment arms ≤ 6.2e-15 m.
#[test]
fn spheres_tori_and_every_ellipsoid_method_agree_with_opensim() {
    let c = compare("wrap_zoo", "fixtures/models/wrap_zoo.osim");
    assert!(c.skipped.is_empty(), "{:?}", c.skipped);
    assert_agrees("wrap_zoo", &c);
    assert_eq!((c.lengths.count, c.moment_arms.count), (55 * 13, 2200));
}

/// Every Rajagopal2016 muscle, 42 of them wrapping over `WrapCylinder`s (one or, for the
/// gastrocnemii, two), equals OpenSim. The gastrocnemii at full knee extension (knee_h00_k+000)
/// need OpenSim's stale ground locations of moved tangent points: without them their lengths
/// were 2.6 and 6.2 mm off.
#[test]
fn cylinder_wrapping_agrees_with_opensim() {
    let c = compare("Rajagopal2016", "fixtures/models/Rajagopal2016.osim");
    assert_agrees("Rajagopal2016", &c);
    assert!(c.skipped.is_empty(), "{:?}", c.skipped);
    assert_eq!((c.lengths.count, c.moment_arms.count), (21 * 80, 5334));
}

/// Ball, Free, Planar, Slider, Gimbal, Pin and an oblique CustomJoint with offset frames on both sides.
#[test]
fn every_joint_class_agrees_with_opensim() {
    let c = compare("joint_zoo", "fixtures/models/joint_zoo.osim");
    assert_agrees("joint_zoo", &c);
    assert!(c.moment_arms.count > 0 && c.markers.count > 0);
}

/// The error compiling the file at `relative` with the first occurrence of each `from`
/// replaced by its `to`.
fn compile_error(relative: &str, edits: &[(&str, &str)]) -> String {
    let path = common::root().join(relative);
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let document = OsimDocument::parse(text, &path).unwrap();
    let spec = ModelSpec::read(&document).unwrap_or_else(|e| panic!("{e}"));
    MuscleGeometry::new(&spec).err().map(|e| e.to_string()).unwrap_or_default()
}

#[test]
fn models_the_engine_cannot_compute_are_refused_naming_file_and_component() {
    let gait = "models/gait2354_simbody.osim";
    let message = compile_error(gait, &[("<axis>0 1 0</axis>", "<axis>0 0 2</axis>")]);
    assert!(message.contains("gait2354_simbody.osim") && message.contains("ground_pelvis") && message.contains("collinear"), "{message}");
    let message = compile_error(gait, &[("<CustomJoint name=\"ground_pelvis\">", "<ConstantCurvatureJoint name=\"ground_pelvis\">"), ("</CustomJoint>", "</ConstantCurvatureJoint>")]);
    assert!(message.contains("ground_pelvis") && message.contains("ConstantCurvatureJoint is not supported"), "{message}");
    let message = compile_error("fixtures/models/arm26.osim", &[("<method>hybrid</method>", "<method>spiral</method>")]);
    assert!(message.contains("arm26.osim") && message.contains("TRIlong") && message.contains("\"spiral\" is not one of OpenSim's"), "{message}");
    let legacy = "fixtures/legacy/pendulum_leg_v30000.osim";
    let message = compile_error(legacy, &[("<body>shank</body>", "<body>shin</body>")]);
    assert!(message.contains("pendulum_leg_v30000.osim") && message.contains("vasti") && message.contains("\"shin\" does not exist"), "{message}");
}
