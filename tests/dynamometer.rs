//! The extended dynamometer set-up (thesis ch. 5): M3D from the load cell against OpenSim 4.6's
//! inverse dynamics with the pad's load known (`oracle/gen_dynamometer.py`), Herzog's 2D
//! estimate where it is exact, the sensitivity of M3D to masses from statics, and the
//! command's output and refusals.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::analysis::{dynamometer_analysis, DynamometerModel, DynamometerResult, DynamometerSettings, ExternalLoads, MeasuredMoment, Perturbations, SplinedMotion};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::{Multibody, Vec3};
use osim_tune::model::ModelSpec;

fn model_file(case: &str) -> PathBuf {
    common::fixture(&format!("models/dynamometer_{case}.osim"))
}

fn golden(case: &str, file: &str) -> PathBuf {
    common::fixture(&format!("golden/dynamometer/{case}/{file}"))
}

/// The analysis of a golden case, with the dynamometer's moment.
fn analyse(case: &str) -> (Multibody, DynamometerModel, DynamometerResult) {
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&model_file(case)).unwrap()).unwrap()).unwrap();
    let model = DynamometerModel::new(&multibody, "crank", "knee_angle_r").unwrap();
    let (loads, data_file) = ExternalLoads::read(&golden(case, "loadcell.xml"), &multibody).unwrap();
    let measured = MeasuredMoment::new(&StorageTable::read(&data_file).unwrap(), &data_file, "dynamometer_moment", 1.0).unwrap();
    let coordinates = golden(case, "coordinates.mot");
    let motion = SplinedMotion::new(&multibody, &StorageTable::read(&coordinates).unwrap(), &coordinates, None).unwrap();
    let settings = DynamometerSettings { time_range: [f64::NEG_INFINITY, f64::INFINITY], lowpass_cutoff: None, perturbations: Perturbations::THESIS };
    let result = dynamometer_analysis(&multibody, &model, &motion, &loads, Some(&measured), &settings).unwrap();
    (multibody, model, result)
}

/// `pad_truth.csv`: per row F_tc (tibia on crank), its point p, its free torque T_tc (ground)
/// and the dynamometer's moment.
fn pad_truth(case: &str) -> Vec<[f64; 11]> {
    let text = std::fs::read_to_string(golden(case, "pad_truth.csv")).unwrap();
    text.lines().skip(1).map(|line| line.split(',').map(|v| v.parse().unwrap()).collect::<Vec<f64>>().try_into().unwrap()).collect()
}

fn largest(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |m, v| if v.is_nan() { f64::NAN } else { m.max(v.abs()) })
}

/// Misaligned axes (4° and 4–6 cm apart), a moving femur, an isokinetic sweep, a pad force
/// off the crank's normal with a free torque: from the load cell alone, M3D is OpenSim's knee
/// moment with the pad's load known (2.3e-13 N·m seen), and the pad's load is the truth.
/// Bound: 1e-9 N·m and N, the goldens' 17 digits of loads and coordinates and OpenSim's
/// splines reproduced.
#[test]
fn the_load_cell_gives_opensims_knee_moment() {
    let (_, _, result) = analyse("spatial");
    let id = StorageTable::read(&golden("spatial", "inverse_dynamics.sto")).unwrap();
    let truth = id.column("knee_angle_r_moment").unwrap();
    assert_eq!(result.frames.len(), truth.len());
    assert!(largest(result.frames.iter().zip(&truth).map(|(f, t)| f.knee_moment - t)) < 1e-9);
    let pads = pad_truth("spatial");
    for (frame, row) in result.frames.iter().zip(&pads) {
        let (force, point, torque) = (Vec3::new(row[1], row[2], row[3]), Vec3::new(row[4], row[5], row[6]), Vec3::new(row[7], row[8], row[9]));
        assert!((frame.pad_force - force).norm() < 1e-9, "{} vs {force}", frame.pad_force);
        let about_d = (point - frame.dynamometer_axis.point).cross(&force) + torque;
        assert!((frame.pad_moment - about_d).norm() < 1e-9);
        // What a gravity-corrected dynamometer reads: the pad's moment about its axis less the
        // crank's inertial moment (I_ZZ θ̈).
        assert!((frame.dynamometer_axis.direction.dot(&frame.pad_moment) - frame.crank_inertial_moment - row[10]).abs() < 1e-9);
    }
    // The knee and the dynamometer turn the same way here, so Mdyn keeps its sign.
    let mdyn = result.dynamometer.as_ref().unwrap();
    assert!(largest(mdyn.iter().zip(&pads).map(|(m, row)| m - row[10])) < 1e-12);
}

/// Herzog's 2D estimate is exact when the knee's axis is the dynamometer's direction and lies
/// on the crank's line and the pad pushes perpendicular to the crank with no free moment
/// (the `planar` case: pad 0.30 m from the dynamometer's axis, knee 0.03 m beyond it): M2D =
/// OpenSim's knee moment, d_d = 0.30 m, d_k = 0.33 m.
#[test]
fn herzog_is_exact_where_its_assumptions_hold() {
    let (_, _, result) = analyse("planar");
    let truth = StorageTable::read(&golden("planar", "inverse_dynamics.sto")).unwrap().column("knee_angle_r_moment").unwrap();
    let herzog = result.herzog.as_ref().unwrap();
    assert!(largest(herzog.iter().zip(&truth).map(|(h, t)| h.knee_moment - t)) < 1e-9);
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
    let (multibody, model, result) = analyse("planar");
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
    let _ = model;
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
    let (code, _, stderr) = osim_tune(&["dynamometer", s(&model), s(&coordinates), "--load-cell", s(&loads), "-o", s(&coordinates)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("input"), "{stderr}");
}
