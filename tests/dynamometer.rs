//! The extended dynamometer set-up (thesis ch. 5): M3D from the load cell against OpenSim 4.6's
//! inverse dynamics with the pad's load known (`oracle/gen_dynamometer.py`), Herzog's 2D
//! estimate where it is exact, the sensitivity of M3D to masses from statics, and the
//! command's output and refusals.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::analysis::{dynamometer_analysis, DynamometerModel, DynamometerSettings, ExternalLoads, Perturbations, SplinedMotion};
use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{BodyLoad, MotionState, Multibody};
use osim_tune::model::ModelSpec;
use osim_tune::io::table::StorageTable;
use osim_tune::validation::{dynamometer_golden_run, DYNAMOMETER_CASES};

fn model_file(case: &str) -> PathBuf {
    common::fixture(&format!("models/dynamometer_{case}.osim"))
}

fn golden(case: &str, file: &str) -> PathBuf {
    common::fixture(&format!("golden/dynamometer/{case}/{file}"))
}

fn largest(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |m, v| if v.is_nan() { f64::NAN } else { m.max(v.abs()) })
}

/// From the load cell alone: M3D is OpenSim's knee moment with the pad's load known, the pad's
/// load (F_tc and its moment about D) is the truth, and the pad's moment about the
/// dynamometer's axis less the crank's I_ZZ θ̈ is what a gravity-corrected dynamometer reads;
/// where Herzog's assumptions hold, M2D is the knee moment too. Bounds in `DYNAMOMETER_CASES`.
#[test]
fn the_load_cell_gives_opensims_knee_moment() {
    for case in &DYNAMOMETER_CASES {
        let c = case.compare(&common::root()).unwrap();
        for (what, worst) in [("M3D", &c.knee_moment), ("pad load", &c.pad_load), ("Mdyn", &c.dynamometer_moment)].into_iter().chain(c.herzog.as_ref().map(|w| ("M2D", w))) {
            assert!(worst.count > 0 && worst.error < case.tolerance, "{} {what}: {:e} at {}", case.case, worst.error, worst.at);
        }
        assert_eq!(c.herzog.is_some(), case.herzog_exact);
    }
    // The knee and the dynamometer turn the same way in the spatial case, so Mdyn keeps its sign.
    let (_, _, result) = dynamometer_golden_run(&common::root(), "spatial").unwrap();
    let reading = StorageTable::read(&golden("spatial", "loadcell.mot")).unwrap().column("dynamometer_moment").unwrap();
    assert!(largest(result.dynamometer.unwrap().iter().zip(&reading).map(|(m, r)| m - r)) < 1e-12);
}

/// Herzog's 2D estimate is exact when the knee's axis is the dynamometer's direction and lies
/// on the crank's line and the pad pushes perpendicular to the crank with no free moment
/// (the `planar` case: pad 0.30 m from the dynamometer's axis, knee 0.03 m beyond it): its
/// lever arms are d_d = 0.30 m and d_k = 0.33 m, and M2D agrees with M3D in the summary.
#[test]
fn herzog_is_exact_where_its_assumptions_hold() {
    let (_, _, result) = dynamometer_golden_run(&common::root(), "planar").unwrap();
    let herzog = result.herzog.as_ref().unwrap();
    for (estimate, frame) in herzog.iter().zip(&result.frames).filter(|(_, f)| f.pad_force.norm() > 1.0) {
        assert!((estimate.pad_distance - 0.30).abs() < 1e-9 && (estimate.knee_distance - 0.33).abs() < 1e-9, "{estimate:?}");
        assert!(frame.pad_force_angle() < 1e-9 && frame.axis_angle() < 1e-9);
        assert!((frame.axis_offset() - 0.03).abs() < 1e-12);
    }
    let summary = result.summary();
    assert_eq!(summary.perpendicular_share, 1.0);
    let m2d = summary.herzog.unwrap().positive.unwrap();
    assert!(m2d.mean.abs() < 1e-9 && m2d.largest < 1e-9);
    // Mdyn reads the pad's moment about the dynamometer's axis, which is 0.30/0.33 of the
    // pad's moment about the knee: too low, by the limb's weight and 1/11 of the pad's share.
    assert!(summary.dynamometer.unwrap().positive.unwrap().mean < 0.0);
}

/// In the static `planar` trial a body's extra mass Δm only adds its weight: below the knee,
/// at its mass center; on the crank, through the pad, also at the crank's mass center. So the
/// sensitivity to a mass is Δm |n·((c − r_knee) × g)|, the same in every frame.
#[test]
fn mass_sensitivity_is_the_weights_moment() {
    let (multibody, _, result) = dynamometer_golden_run(&common::root(), "planar").unwrap();
    let coordinates = golden("planar", "coordinates.mot");
    let motion = SplinedMotion::new(&multibody, &StorageTable::read(&coordinates).unwrap(), &coordinates, None).unwrap();
    let state = motion.state_at(&multibody, 0.5);
    let mut kinematics = multibody.kinematics();
    multibody.realize(&state.q, &mut kinematics);
    let knee = result.frames[0].knee_axis;
    for body in ["foot", "crank", "tibia"] {
        let b = multibody.body_index(body).unwrap();
        let center = kinematics.bodies[b].apply(&multibody.bodies[b].mass_center);
        let expected = Perturbations::THESIS.mass * knee.direction.dot(&(center - knee.point).cross(&multibody.gravity)).abs();
        let row = result.sensitivity.iter().find(|r| r.parameter == format!("{body} mass")).unwrap();
        assert!((row.max_change - expected).abs() < 1e-9 && (row.rms_change - expected).abs() < 1e-9, "{body}: {row:?} vs {expected}");
    }
    // The femur is above the knee: not perturbed.
    assert!(!result.sensitivity.iter().any(|r| r.parameter.starts_with("femur")));
}

/// On a knee whose translations follow splines of its angle (leg6dof9musc, its patella coupled)
/// with a crank added by OpenSim 4.6 (`oracle/gen_api_models.py`; the crank's coordinate
/// written with all its defaults, range ±10): M3D is the knee's generalized force by inverse
/// dynamics (Kane's sum) with the pad's load — the opposite of the crank's reaction — on the
/// shank. The reaction's projection and Kane's sum are different code; they agree to rounding.
#[test]
fn m3d_is_inverse_dynamics_with_the_pad_load_on_a_spline_knee() {
    let folder = tempfile::tempdir().unwrap();
    let spec = ModelSpec::read(&OsimDocument::read(&common::fixture("models/leg6dof9musc_crank.osim")).unwrap()).unwrap();
    let multibody = Multibody::new(&spec).unwrap();
    assert_eq!(multibody.coordinates[multibody.coordinate_index("crank_angle").unwrap()].range, [-10.0, 10.0]);
    let model = DynamometerModel::new(&multibody, "crank", "knee_angle_r").unwrap();
    let leg = StorageTable::read(&common::fixture("golden/static_optimization/leg6dof9musc/leg_motion.mot")).unwrap();
    let knee = leg.column_index("knee_angle_r").unwrap();
    let mut labels = leg.labels().to_vec();
    labels.push("crank_angle".into());
    let values: Vec<f64> = leg.rows().flat_map(|row| row.iter().copied().chain([row[knee] - 90.0 + 3.0 * (6.0 * row[0]).sin()]).collect::<Vec<_>>()).collect();
    let coordinates = folder.path().join("q.mot");
    std::fs::write(&coordinates, StorageTable::new("q", labels, values).unwrap().with_in_degrees(true).to_text()).unwrap();
    let mut cell = String::from("cell\nversion=1\nnRows=101\nnColumns=7\ninDegrees=no\nendheader\ntime\tlc_vx\tlc_vy\tlc_vz\tlc_tx\tlc_ty\tlc_tz\n");
    for t in leg.times() {
        cell += &format!("{t}\t{}\t{}\t{}\t{}\t{}\t{}\n", 100.0 * (3.0 * t).sin(), 400.0 + 100.0 * (2.0 * t).cos(), 20.0 * (5.0 * t).sin(), 2.0 * t.sin(), (3.0 * t).cos(), 3.0 * (2.0 * t).sin());
    }
    std::fs::write(folder.path().join("cell.mot"), cell).unwrap();
    let setup = folder.path().join("cell.xml");
    std::fs::write(&setup, r#"<?xml version="1.0" encoding="UTF-8" ?><OpenSimDocument Version="40000"><ExternalLoads name="cell"><objects><ExternalForce name="cell"><applied_to_body>crank</applied_to_body><force_expressed_in_body>crank</force_expressed_in_body><force_identifier>lc_v</force_identifier><torque_identifier>lc_t</torque_identifier></ExternalForce></objects><datafile>cell.mot</datafile></ExternalLoads></OpenSimDocument>"#).unwrap();
    let (loads, _) = ExternalLoads::read(&setup, &multibody).unwrap();
    let motion = SplinedMotion::new(&multibody, &StorageTable::read(&coordinates).unwrap(), &coordinates, None).unwrap();
    let settings = DynamometerSettings { time_range: [f64::NEG_INFINITY, f64::INFINITY], perturbations: Perturbations::THESIS };
    let result = dynamometer_analysis(&multibody, &model, &motion, &loads, None, &settings).unwrap();
    let (shank, knee) = (multibody.body_index("tibia_r").unwrap(), multibody.coordinate_index("knee_angle_r").unwrap());
    let mut kinematics = multibody.kinematics();
    for (&time, frame) in result.times.iter().zip(&result.frames) {
        let state = motion.state_at(&multibody, time);
        multibody.realize(&state.q, &mut kinematics);
        let mut applied = loads.at(time, &kinematics);
        applied.push(BodyLoad { body: shank, force: -frame.pad_force, point: frame.dynamometer_axis.point, torque: -frame.pad_moment });
        let forces = multibody.inverse_dynamics(&MotionState { q: &state.q, u: &state.u, udot: &state.udot }, &applied);
        assert!((forces[knee] - frame.knee_moment).abs() < 1e-9 * forces[knee].abs().max(1.0), "t = {time}: {} vs {}", frame.knee_moment, forces[knee]);
    }
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// From the command line: the per-frame table and the JSON summary, written beside each other.
#[test]
fn the_command_writes_the_table_and_the_summary() {
    let folder = tempfile::tempdir().unwrap();
    let (output, report) = (folder.path().join("knee.sto"), folder.path().join("summary.json"));
    let (model, coordinates, loads) = (model_file("spatial"), golden("spatial", "coordinates.mot"), golden("spatial", "loadcell.xml"));
    let arguments = ["dynamometer", s(&model), s(&coordinates), "--load-cell", s(&loads), "--dynamometer-moment", "dynamometer_moment", "--time", "0.2", "0.8", "--report", s(&report), "-o", s(&output)];
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("121 frames (0.2000–0.8000 s)") && stdout.contains("M2D (Herzog)") && stdout.contains("knee axis turned about tibia X"), "{stdout}");
    let table = StorageTable::read(&output).unwrap();
    assert_eq!(table.n_rows(), 121);
    for label in ["knee_angle_r_moment", "dynamometer_moment", "herzog_moment", "pad_force_x", "knee_torque_z", "pad_force_angle_deg", "knee_axis_offset"] {
        assert!(table.column_index(label).is_some(), "{label}");
    }
    let truth = StorageTable::read(&golden("spatial", "inverse_dynamics.sto")).unwrap();
    let (ours, theirs) = (table.column("knee_angle_r_moment").unwrap(), truth.column("knee_angle_r_moment").unwrap());
    assert!(largest(ours.iter().zip(&theirs[40..=160]).map(|(a, b)| a - b)) < 1e-9);
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(summary["frames"], 121);
    assert!(summary["dynamometer"]["positive"]["frames"] == 121 && summary["dynamometer"]["negative"].is_null());
    assert_eq!(summary["sensitivity"].as_array().unwrap().len(), 4 + 3 * 3);
}

/// Refusals name what is wrong, exit 2 and write nothing.
#[test]
fn bad_requests_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let output = folder.path().join("out.sto");
    let (model, coordinates, loads, pad) = (model_file("spatial"), golden("spatial", "coordinates.mot"), golden("spatial", "loadcell.xml"), golden("spatial", "pad.xml"));
    let run = |extra: &[&str], loads: &Path| {
        let mut arguments = vec!["dynamometer", s(&model), s(&coordinates), "--load-cell", s(loads), "-o", s(&output)];
        arguments.extend_from_slice(extra);
        osim_tune(&arguments)
    };
    for (extra, loads, expected) in [
        (vec!["--crank", "dynamometer"], &loads, "the crank \"dynamometer\" is not a body"),
        (vec!["--crank", "femur"], &loads, "must turn it about an axis fixed in ground"),
        (vec!["--knee", "knee_flexion"], &loads, "the knee coordinate \"knee_flexion\" is not a coordinate"),
        (vec!["--knee", "femur_tx"], &loads, "is not rotational"),
        (vec![], &pad, "no ExternalForce is applied to the crank"),
        (vec!["--dynamometer-moment", "dyn"], &loads, "has no column \"dyn\""),
        (vec!["--dynamometer-moment", "dynamometer_moment", "--dynamometer-sign", "-1"], &loads, "the other sign convention"),
        (vec!["--perturb-mass", "-0.1"], &loads, "--perturb-mass -0.1: expected a size ≥ 0"),
    ] {
        let (code, _, stderr) = run(&extra, loads);
        assert_eq!(code, 2, "{extra:?}: {stderr}");
        assert!(stderr.contains(expected), "{extra:?}: {stderr}");
        assert!(!output.exists());
    }
    // A load cell (the crank's origin) on the dynamometer's axis.
    let on_axis = folder.path().join("on_axis.osim");
    let text = std::fs::read_to_string(&model).unwrap().replace("<translation>-0.25 0 0</translation>", "<translation>0 0 0.1</translation>");
    std::fs::write(&on_axis, text).unwrap();
    let (code, _, stderr) = osim_tune(&["dynamometer", s(&on_axis), s(&coordinates), "--load-cell", s(&loads), "-o", s(&output)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("origin (the load cell) lies") && stderr.contains("off the axis") && !output.exists(), "{stderr}");
    // A motion without the crank's angle.
    let partial = folder.path().join("no_crank.mot");
    let text = std::fs::read_to_string(&coordinates).unwrap().replace("crank_angle", "dynamometer_angle");
    std::fs::write(&partial, text).unwrap();
    let (code, _, stderr) = osim_tune(&["dynamometer", s(&model), s(&partial), "--load-cell", s(&loads), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("has no column for crank_angle"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["dynamometer", s(&model), s(&coordinates), "--load-cell", s(&loads), "--report", s(&output), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--report and -o name the same file") && !output.exists(), "{stderr}");
    let (code, _, stderr) = osim_tune(&["dynamometer", s(&model), s(&coordinates), "--load-cell", s(&loads), "-o", s(&coordinates)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("input"), "{stderr}");
}
