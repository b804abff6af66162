//! `osim-tune analyze` end to end against OpenSim 4.6 (`fixtures/golden/analysis/`, made by
//! `oracle/gen_muscle_analysis.py`: the subject01 IK motion read as an OpenSim Storage,
//! converted to radians by OpenSim, every 20th row), and its bad-input errors.

mod common;

use std::path::Path;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::{MuscleGeometry, PathEvaluation};
use osim_tune::model::ModelSpec;
use osim_tune::validation::GoldenTable;

const MODEL: &str = "fixtures/subject01/OutputReference/subject01_simbody.osim";
const MOTION: &str = "fixtures/subject01/OutputReference/subject01_walk1_ik.mot";

fn path(relative: &str) -> String {
    common::root().join(relative).to_string_lossy().into_owned()
}

/// Largest |ours − OpenSim| over the golden's rows (matched by time) and columns.
fn worst_difference(ours: &StorageTable, golden: &GoldenTable) -> f64 {
    let mut worst = 0.0f64;
    for (r, row) in golden.rows.iter().enumerate() {
        let time: f64 = row[0].parse().unwrap();
        let ours_row = ours.rows().find(|values| values[0] == time).unwrap_or_else(|| panic!("no row at t = {time}"));
        for (c, label) in golden.header.iter().enumerate().skip(1) {
            let column = ours.column_index(label).unwrap_or_else(|| panic!("no column {label}"));
            worst = worst.max((ours_row[column] - golden.number(r, c).unwrap()).abs());
        }
    }
    assert!(golden.rows.len() >= 10);
    worst
}

#[test]
fn analyze_reproduces_opensim_along_the_walking_motion() {
    let out = tempfile::tempdir().unwrap();
    let (code, _, stderr) = common::osim_tune(&["analyze", &path(MODEL), "--motion", &path(MOTION), "-o", &out.path().to_string_lossy(), "--skip-unknown-columns"]);
    assert_eq!(code, 0, "{stderr}");
    let golden = |name: &str| GoldenTable::read(&common::fixture(&format!("golden/analysis/subject01_walk1/{name}.csv"))).unwrap();
    let ours = |name: &str| StorageTable::read(&out.path().join(name)).unwrap();
    assert!(worst_difference(&ours("Length.sto"), &golden("lengths")) <= 1e-9);
    assert!(worst_difference(&ours("MarkerLocations.sto"), &golden("markers")) <= 1e-9);
    for coordinate in ["hip_flexion_r", "knee_angle_r", "ankle_angle_r", "lumbar_extension"] {
        let error = worst_difference(&ours(&format!("MomentArm_{coordinate}.sto")), &golden(&format!("moment_arms_{coordinate}")));
        assert!(error <= 1e-8, "{coordinate}: {error:e}");
    }
    // One table per spanned coordinate: 2 × (hip 3, knee, ankle, subtalar, mtp) + lumbar 3; no
    // muscle crosses the pelvis' free joint.
    let moment_arm_tables = std::fs::read_dir(out.path()).unwrap().filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("MomentArm_")).count();
    assert_eq!(moment_arm_tables, 17);
}

#[test]
fn a_column_that_is_no_coordinate_is_an_error_naming_file_and_column() {
    let out = tempfile::tempdir().unwrap();
    let (code, _, stderr) = common::osim_tune(&["analyze", &path(MODEL), "--motion", &path(MOTION), "-o", &out.path().to_string_lossy()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("subject01_walk1_ik.mot") && stderr.contains("\"R.ASIS_tx\"") && stderr.contains("--skip-unknown-columns"), "{stderr}");
    assert_eq!(std::fs::read_dir(out.path()).unwrap().count(), 0, "nothing is written on error");
}

#[test]
fn missing_coordinates_take_their_default_and_radians_are_read_as_such() {
    let out = tempfile::tempdir().unwrap();
    let motion = out.path().join("knee.sto");
    let table = StorageTable::new("knee", vec!["time".into(), "knee_angle_r".into()], vec![0.0, -1.0, 1.0, 0.0]).unwrap().with_in_degrees(false);
    std::fs::write(&motion, table.to_text()).unwrap();
    let (code, _, stderr) = common::osim_tune(&["analyze", &path(MODEL), "--motion", &motion.to_string_lossy(), "-o", &out.path().join("r").to_string_lossy()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("stay at their default"), "{stderr}");
    let knee = StorageTable::read(&out.path().join("r/MomentArm_knee_angle_r.sto")).unwrap();
    let lengths = StorageTable::read(&out.path().join("r/Length.sto")).unwrap();
    let vastus = lengths.column_index("vas_int_r").unwrap();
    // Flexing the knee (negative angle in gait2392) lengthens the vastus, an extensor: its
    // moment arm −∂L/∂q is positive.
    assert!(lengths.value(0, vastus).unwrap() > lengths.value(1, vastus).unwrap());
    assert!(knee.value(0, vastus).unwrap() > 0.0);
    // The column was read as −1 rad (not −1°) and every other coordinate took its default.
    let spec = ModelSpec::read(&OsimDocument::read(&common::root().join(MODEL)).unwrap()).unwrap();
    let geometry = MuscleGeometry::new(&spec).unwrap();
    let mut q = geometry.multibody.default_pose();
    q[geometry.multibody.coordinate_index("knee_angle_r").unwrap()] = -1.0;
    let m = geometry.path_index("vas_int_r").unwrap();
    let mut evaluation = PathEvaluation::new(&geometry, &[m]);
    evaluation.evaluate(&geometry, &q);
    assert_eq!(lengths.value(0, vastus).unwrap(), evaluation.length(0));
}

/// OpenSim's `Storage` takes a version-less header's "Angles are in degrees." as the unit
/// (opensim-core's runningModel CMC kinematics say so in a `.sto`): the walk's IK motion renamed
/// `.sto` with that sentence gives OpenSim's lengths; the sentence after a `version` line is
/// only a comment, and the angles are read as radians.
#[test]
fn a_simm_headers_angle_sentence_declares_degrees() {
    let out = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(path(MOTION)).unwrap();
    let golden = GoldenTable::read(&common::fixture("golden/analysis/subject01_walk1/lengths.csv")).unwrap();
    let lengths = |header_line: &str, name: &str| {
        let motion = out.path().join(format!("{name}.sto"));
        std::fs::write(&motion, text.replacen("# SIMM Motion File Header:", header_line, 1)).unwrap();
        let results = out.path().join(name);
        let (code, _, stderr) = common::osim_tune(&["analyze", &path(MODEL), "--motion", &motion.to_string_lossy(), "-o", &results.to_string_lossy(), "--skip-unknown-columns"]);
        assert_eq!(code, 0, "{stderr}");
        worst_difference(&StorageTable::read(&results.join("Length.sto")).unwrap(), &golden)
    };
    assert!(lengths("# SIMM Motion File Header:\nAngles are in degrees.", "degrees") <= 1e-9);
    assert!(lengths("version=1\nAngles are in degrees.", "radians") > 1e-2);
}

#[test]
fn analyze_never_writes_over_its_inputs() {
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("Length.sto");
    std::fs::copy(common::root().join(MODEL), &model).unwrap();
    let before = std::fs::read(&model).unwrap();
    let (code, _, stderr) = common::osim_tune(&["analyze", &model.to_string_lossy(), "--motion", &path(MOTION), "-o", &out.path().to_string_lossy(), "--skip-unknown-columns"]);
    assert_eq!(code, 2, "{stderr}");
    assert_eq!(std::fs::read(&model).unwrap(), before);
    assert!(Path::new(&model).exists());
}

/// Writes the knee-sweep poses of the gait2392 geometry golden as a motion (radians), one row
/// per pose, time = row index; returns the pose ids in row order.
fn sweep_motion(file: &Path) -> Vec<String> {
    let poses = GoldenTable::read(&common::fixture("golden/geometry/gait2392_millard2012muscle/poses.csv")).unwrap();
    let rows: Vec<usize> = (0..poses.rows.len()).filter(|&r| poses.rows[r][0].starts_with("knee_")).collect();
    let mut labels = vec!["time".to_string()];
    labels.extend(poses.header[1..].iter().cloned());
    let mut values = Vec::new();
    for (t, &r) in rows.iter().enumerate() {
        values.push(t as f64);
        values.extend((1..poses.header.len()).map(|c| poses.number(r, c).unwrap()));
    }
    let table = StorageTable::new("sweep", labels, values).unwrap().with_in_degrees(false);
    std::fs::write(file, table.to_text()).unwrap();
    rows.iter().map(|&r| poses.rows[r][0].clone()).collect()
}

/// `--activation 0.5` along knee sweeps gives OpenSim's equilibrium fiber lengths and tendon
/// forces (`fixtures/golden/muscle/`, OpenSim 4.6 `equilibrateMuscles`). Bound: our static
/// balance is exact, OpenSim stops at 1e-8 F_max, so fiber lengths agree to 1e-7 m and forces
/// to 2e-5 N in these rows (the largest such imbalance in them is 1.2e-5 N).
#[test]
fn activation_adds_the_fiber_tables_of_opensims_equilibrium() {
    let out = tempfile::tempdir().unwrap();
    let motion = out.path().join("sweep.mot");
    let ids = sweep_motion(&motion);
    let model = path("models/gait2392_millard2012muscle.osim");
    let dir = out.path().join("out");
    let (code, _, stderr) = common::osim_tune(&["analyze", &model, "--motion", &motion.to_string_lossy(), "-o", &dir.to_string_lossy(), "--activation", "0.5"]);
    assert_eq!(code, 0, "{stderr}");
    let golden = GoldenTable::read(&common::fixture("golden/muscle/gait2392_millard2012muscle/equilibrium.csv")).unwrap();
    let (fiber, tendon) = (StorageTable::read(&dir.join("FiberLength.sto")).unwrap(), StorageTable::read(&dir.join("TendonForce.sto")).unwrap());
    let mut compared = 0;
    for (r, row) in golden.rows.iter().enumerate().filter(|(_, row)| row[2] == "0.5") {
        let Some(t) = ids.iter().position(|id| *id == row[0]) else { continue };
        let column = fiber.column_index(&row[1]).unwrap();
        let fiber_error = (fiber.value(t, column).unwrap() - golden.number(r, golden.column("fiber_length").unwrap()).unwrap()).abs();
        let force_error = (tendon.value(t, column).unwrap() - golden.number(r, golden.column("tendon_force").unwrap()).unwrap()).abs();
        assert!(fiber_error <= 1e-7 && force_error <= 2e-5, "{} {}: {fiber_error:e} m, {force_error:e} N", row[0], row[1]);
        compared += 1;
    }
    assert_eq!(compared, 6 * 13);
    let moments = StorageTable::read(&dir.join("Moment_knee_angle_r.sto")).unwrap();
    let total = moments.column_index("total").unwrap();
    for t in 0..ids.len() {
        let row = moments.row(t).unwrap();
        let sum: f64 = row[1..total].iter().sum();
        assert!((row[total] - sum).abs() <= 1e-9 * sum.abs().max(1.0));
    }
}

#[test]
fn bad_activations_are_errors_and_write_nothing() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().join("out");
    let run = |extra: &[&str]| {
        let (model, motion, dir) = (path("models/gait2392_millard2012muscle.osim"), path(MOTION), dir.to_string_lossy().into_owned());
        let mut args = vec!["analyze", &model, "--motion", &motion, "--skip-unknown-columns", "-o", &dir];
        args.extend_from_slice(extra);
        common::osim_tune(&args)
    };
    let (code, _, stderr) = run(&["--activation", "1.5"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--activation 1.5") && stderr.contains("[0, 1]"), "{stderr}");
    // The IK motion itself has no muscle columns: every muscle is missing.
    let (code, _, stderr) = run(&["--activations", &path(MOTION)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("subject01_walk1_ik.mot") && stderr.contains("no activation column for muscles glut_med1_r"), "{stderr}");
    assert!(!dir.exists(), "nothing may be written on error");
}

/// A rigid tendon may have `tendon_slack_length` 0 (OpenSim's ThoracoscapularShoulderModel has
/// such muscles): the fiber then spans the whole path, fiber length × cos(pennation) = path
/// length, with a finite force. A compliant tendon's L_ts 0 is refused, naming the property.
#[test]
fn a_rigid_tendon_may_have_no_slack_length() {
    let out = tempfile::tempdir().unwrap();
    let motion = out.path().join("default.mot");
    std::fs::write(&motion, StorageTable::new("default", vec!["time".into()], vec![0.0, 1.0]).unwrap().to_text()).unwrap();
    let edited = |muscle: &str| {
        let model = out.path().join(format!("{muscle}.osim"));
        let assignment = format!("/forceset/{muscle}/tendon_slack_length=0");
        let (code, _, stderr) = common::osim_tune(&["set", &path("fixtures/models/Rajagopal2016.osim"), "-o", &model.to_string_lossy(), &assignment]);
        assert_eq!(code, 0, "{stderr}");
        model.to_string_lossy().into_owned()
    };
    let dir = out.path().join("rigid");
    let (code, _, stderr) = common::osim_tune(&["analyze", &edited("addbrev_r"), "--motion", &motion.to_string_lossy(), "--activation", "0.5", "-o", &dir.to_string_lossy()]);
    assert_eq!(code, 0, "{stderr}");
    let value = |table: &str| {
        let table = StorageTable::read(&dir.join(table)).unwrap();
        table.value(0, table.column_index("addbrev_r").unwrap()).unwrap()
    };
    let (path_length, fiber, pennation) = (value("Length.sto"), value("FiberLength.sto"), value("PennationAngle.sto"));
    assert!((fiber * pennation.cos() - path_length).abs() < 1e-15, "{fiber} m × cos {pennation} vs {path_length} m");
    assert_eq!(value("TendonLength.sto"), 0.0);
    assert!(value("TendonForce.sto").is_finite() && value("TendonForce.sto") > 0.0);
    let (code, _, stderr) = common::osim_tune(&["analyze", &edited("bflh_r"), "--motion", &motion.to_string_lossy(), "-o", &out.path().join("compliant").to_string_lossy()]);
    assert_eq!(code, 2);
    assert!(stderr.contains("bflh_r") && stderr.contains("tendon_slack_length") && stderr.contains("compliant tendon"), "{stderr}");
}
