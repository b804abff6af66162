//! `osim-tune id`: OpenSim's InverseDynamicsTool run from the command line, and its refusals.

mod common;

use std::path::Path;

use common::osim_tune;
use osim_tune::io::table::StorageTable;

const MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";
const IK: &str = "fixtures/golden/ik/subject01_walk1_ik.mot";
const SETUP: &str = "fixtures/subject01/subject01_Setup_InverseDynamics.xml";

fn path(relative: &str) -> String {
    common::root().join(relative).display().to_string()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The setup's time range, cutoff and external loads give OpenSim's table (8 printed decimals).
#[test]
fn the_setup_runs_opensims_inverse_dynamics() {
    let folder = tempfile::tempdir().unwrap();
    let output = folder.path().join("id.sto");
    let (code, stdout, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--setup", &path(SETUP), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("76 frames") && stdout.contains("low-pass 6 Hz"), "{stdout}");
    let ours = StorageTable::read(&output).unwrap();
    let golden = StorageTable::read(&common::fixture("golden/inverse_dynamics/subject01_walk1_InverseDynamics.sto")).unwrap();
    assert_eq!(ours.labels(), golden.labels());
    let worst = ours.values().iter().zip(golden.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst <= 6e-9, "{worst:e}");
}

/// The setup's `joints_to_report_body_forces` (ALL) gives OpenSim's body-forces table
/// (`oracle/gen_body_forces.py`): every joint's equivalent force and torque within OpenSim's 8
/// printed decimals (found 5.0e-9), OpenSim's choice between force and torque included.
#[test]
fn body_forces_at_joints_are_opensims() {
    let folder = tempfile::tempdir().unwrap();
    let setup = folder.path().join("setup.xml");
    let text = std::fs::read_to_string(path(SETUP)).unwrap().replace(
        "</InverseDynamicsTool>",
        "<joints_to_report_body_forces> ALL</joints_to_report_body_forces><output_body_forces_file>joints.sto</output_body_forces_file></InverseDynamicsTool>",
    );
    std::fs::write(&setup, text.replace("subject01_walk1_grf.xml", &path("fixtures/subject01/subject01_walk1_grf.xml"))).unwrap();
    let output = folder.path().join("out").join("id.sto");
    let (code, stdout, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--setup", s(&setup), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("body forces of 12 joint(s)"), "{stdout}");
    let ours = StorageTable::read(&folder.path().join("out").join("joints.sto")).unwrap();
    let golden = StorageTable::read(&common::fixture("golden/inverse_dynamics/subject01_walk1_body_forces.sto")).unwrap();
    assert_eq!(ours.labels(), golden.labels());
    assert_eq!(ours.n_rows(), golden.n_rows());
    let worst = ours.values().iter().zip(golden.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst <= 6e-9, "{worst:e}");
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--setup", s(&setup), "--body-force-joints", "knee_r,knee", "-o", s(&folder.path().join("again.sto"))]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--body-force-joints: joint \"knee\" does not exist in the model"), "{stderr}");
    assert!(!folder.path().join("again.sto").exists());
}

/// A setup that keeps the muscles in is refused (we apply gravity and external loads only).
#[test]
fn forces_left_in_the_model_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let setup = folder.path().join("setup.xml");
    let text = std::fs::read_to_string(path(SETUP)).unwrap().replace("<forces_to_exclude> muscles </forces_to_exclude>", "<forces_to_exclude> </forces_to_exclude>");
    std::fs::write(&setup, text).unwrap();
    let output = folder.path().join("id.sto");
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--setup", s(&setup), "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("forces_to_exclude leaves 92 force(s)") && stderr.contains("glut_med1_r (Millard2012EquilibriumMuscle)") && stderr.contains("and 87 more"), "{stderr}");
    assert!(!output.exists());
}

/// A load on a body the model lacks names the loads file, the line and the body.
#[test]
fn a_load_on_an_unknown_body_is_refused_with_its_line() {
    let folder = tempfile::tempdir().unwrap();
    let loads = folder.path().join("grf.xml");
    let text = std::fs::read_to_string(path("fixtures/subject01/subject01_walk1_grf.xml")).unwrap();
    let text = text.replace("<applied_to_body> calcn_l </applied_to_body>", "<applied_to_body> calcn_x </applied_to_body>");
    std::fs::write(&loads, text.replace("subject01_walk1_grf.mot", &path("fixtures/subject01/subject01_walk1_grf.mot"))).unwrap();
    let output = folder.path().join("id.sto");
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--external-loads", s(&loads), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("grf.xml:") && stderr.contains("ExternalForce_2") && stderr.contains("\"calcn_x\" is not a body"), "{stderr}");
    assert!(!output.exists());
}

/// An OpenSim 3.x loads file naming `external_loads_model_kinematics_file` is read as OpenSim 4
/// reads it: the option is ignored, with a warning, and the moments are those without it.
#[test]
fn a_model_kinematics_file_is_ignored_with_a_warning_as_opensim_4_does() {
    let folder = tempfile::tempdir().unwrap();
    let loads = folder.path().join("grf.xml");
    let text = std::fs::read_to_string(path("fixtures/subject01/subject01_walk1_grf.xml")).unwrap();
    let text = text.replace("subject01_walk1_grf.mot", &path("fixtures/subject01/subject01_walk1_grf.mot"));
    let text = text.replace("</ExternalLoads>", "<external_loads_model_kinematics_file> walk_ik.mot </external_loads_model_kinematics_file></ExternalLoads>");
    std::fs::write(&loads, text).unwrap();
    let (with, without) = (folder.path().join("with.sto"), folder.path().join("without.sto"));
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--external-loads", s(&loads), "-o", s(&with)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("grf.xml: external_loads_model_kinematics_file walk_ik.mot is ignored, as OpenSim 4 ignores it"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), &path(IK), "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"), "-o", s(&without)]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(std::fs::read_to_string(&with).unwrap(), std::fs::read_to_string(&without).unwrap());
}

#[test]
fn the_output_may_not_overwrite_an_input() {
    let folder = tempfile::tempdir().unwrap();
    let coordinates = folder.path().join("ik.mot");
    std::fs::copy(path(IK), &coordinates).unwrap();
    let before = std::fs::read(&coordinates).unwrap();
    let (code, _, stderr) = osim_tune(&["id", &path(MODEL), s(&coordinates), "-o", s(&coordinates)]);
    assert_eq!(code, 2, "{stderr}");
    assert_eq!(std::fs::read(&coordinates).unwrap(), before);
}

/// A 1 kg mass on a slider along ground's X (`sliding_mass.osim`) at x = A·sin(ωt), sampled
/// coarsely: with its exact speeds and accelerations given (`--rates`), the slider's force is
/// Newton's m·ẍ = −m·A·ω²·sin(ωt) to rounding — no spline error, no filter (the splines of the
/// same samples miss it by far more).
#[test]
fn given_rates_are_used_as_they_are() {
    let folder = tempfile::tempdir().unwrap();
    let (amplitude, omega) = (0.2, 2.0 * std::f64::consts::PI);
    let times: Vec<f64> = (0..=20).map(|i| i as f64 * 0.05).collect();
    let write = |name: &str, labels: &[&str], row: &dyn Fn(f64) -> Vec<f64>| {
        let values = times.iter().flat_map(|&t| std::iter::once(t).chain(row(t))).collect();
        let table = StorageTable::new(name, labels.iter().map(|l| l.to_string()).collect(), values).unwrap().with_in_degrees(false);
        let file = folder.path().join(format!("{name}.sto"));
        std::fs::write(&file, table.to_text()).unwrap();
        file
    };
    let coordinates = write("coordinates", &["time", "position"], &|t| vec![amplitude * (omega * t).sin()]);
    let rates = write("rates", &["time", "position_speed", "position_acceleration"], &|t| vec![amplitude * omega * (omega * t).cos(), -amplitude * omega * omega * (omega * t).sin()]);
    let model = path("fixtures/models/sliding_mass.osim");
    let run = |extra: &[&str], name: &str| {
        let output = folder.path().join(name);
        let mut arguments = vec!["id", &model, s(&coordinates), "-o", s(&output)];
        arguments.extend_from_slice(extra);
        let (code, stdout, stderr) = osim_tune(&arguments);
        assert_eq!(code, 0, "{stderr}");
        (stdout, StorageTable::read(&output).unwrap().column("position_force").unwrap())
    };
    let (stdout, given) = run(&["--rates", s(&rates)], "given.sto");
    assert!(stdout.contains("21 frames") && stdout.contains("not filtered, rates from"), "{stdout}");
    let newton = |t: f64| -amplitude * omega * omega * (omega * t).sin();
    let worst = times.iter().zip(&given).map(|(&t, f)| (f - newton(t)).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst:e}");
    let (_, splined) = run(&[], "splined.sto");
    let spline_error = times.iter().zip(&splined).map(|(&t, f)| (f - newton(t)).abs()).fold(0.0, f64::max);
    assert!(spline_error > 1e-3, "{spline_error:e}");
}

/// A rates file that does not match the coordinates is refused, naming what is wrong; --rates
/// and --lowpass exclude each other.
#[test]
fn mismatched_rates_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let output = folder.path().join("id.sto");
    let write = |name: &str, text: &str| {
        let file = folder.path().join(name);
        std::fs::write(&file, text).unwrap();
        file
    };
    let coordinates = write("q.sto", "q\nversion=1\nnRows=2\nnColumns=2\ninDegrees=no\nendheader\ntime\tposition\n0\t0\n0.1\t0.01\n");
    let short = write("short.sto", "r\nversion=1\nnRows=1\nnColumns=3\ninDegrees=no\nendheader\ntime\tposition_speed\tposition_acceleration\n0\t0\t0\n");
    let shifted = write("shifted.sto", "r\nversion=1\nnRows=2\nnColumns=3\ninDegrees=no\nendheader\ntime\tposition_speed\tposition_acceleration\n0\t0\t0\n0.2\t0\t0\n");
    let no_acceleration = write("partial.sto", "r\nversion=1\nnRows=2\nnColumns=2\ninDegrees=no\nendheader\ntime\tposition_speed\n0\t0\n0.1\t0\n");
    let model = path("fixtures/models/sliding_mass.osim");
    for (rates, expected) in [(&short, "has 1 rows; the coordinates"), (&shifted, "row 2 is at 0.2 s"), (&no_acceleration, "has no column \"position_acceleration\"")] {
        let (code, _, stderr) = osim_tune(&["id", &model, s(&coordinates), "--rates", s(rates), "-o", s(&output)]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(expected) && stderr.contains(s(rates)), "{stderr}");
        assert!(!output.exists());
    }
    let (code, _, stderr) = osim_tune(&["id", &model, s(&coordinates), "--rates", s(&short), "--lowpass", "6", "-o", s(&output)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}

/// A time range that holds no frame is refused, naming the file, the range and the frames'
/// span — from the splined coordinates and from given rates alike.
#[test]
fn a_time_range_without_frames_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let output = folder.path().join("id.sto");
    let coordinates = folder.path().join("q.sto");
    let rates = folder.path().join("rates.sto");
    let rows: String = (0..=10).map(|i| format!("{}\t{}\n", 0.1 * i as f64, 0.01 * i as f64)).collect();
    std::fs::write(&coordinates, format!("q\nversion=1\nnRows=11\nnColumns=2\ninDegrees=no\nendheader\ntime\tposition\n{rows}")).unwrap();
    let rows: String = (0..=10).map(|i| format!("{}\t0.1\t0\n", 0.1 * i as f64)).collect();
    std::fs::write(&rates, format!("r\nversion=1\nnRows=11\nnColumns=3\ninDegrees=no\nendheader\ntime\tposition_speed\tposition_acceleration\n{rows}")).unwrap();
    let model = path("fixtures/models/sliding_mass.osim");
    for extra in [vec![], vec!["--rates", s(&rates)]] {
        let mut arguments = vec!["id", &model, s(&coordinates), "--time", "5", "6", "-o", s(&output)];
        arguments.extend_from_slice(&extra);
        let (code, _, stderr) = osim_tune(&arguments);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(s(&coordinates)) && stderr.contains("no frame lies in the time range 5–6 s (the frames span 0–1 s)"), "{stderr}");
        assert!(!output.exists());
    }
}
