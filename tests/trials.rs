//! `osim-tune trials`: isometric dynamometer contractions as functional-scaling trials. The
//! `planar` dynamometer golden (`oracle/gen_dynamometer.py`) is an isometric contraction —
//! knee at −1 rad, pad force 450 sin²(πt/2) N over 2 s — whose M3D OpenSim 4.6's inverse
//! dynamics gives; the trial row must hold its plateau's mean, the posture and the activations,
//! in the layout `scale` reads.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{DynamometryData, KneeMomentModel, TrialColumns, TrialOptions};
use serde_json::json;

fn golden(file: &str) -> PathBuf {
    common::fixture(&format!("golden/dynamometer/{file}"))
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A session folder with the planar contraction's files, `extra` files written into it, and
/// the session file of `contractions`.
fn session(folder: &Path, contractions: serde_json::Value) -> PathBuf {
    for file in ["coordinates.mot", "loadcell.xml", "loadcell.mot"] {
        std::fs::copy(golden(&format!("planar/{file}")), folder.join(file)).unwrap();
    }
    let subject = json!({ "estimated_muscles": ["vas_lat_r", "bifemlh_r"], "extension_agonists": ["vas_lat_r"], "flexion_agonists": ["bifemlh_r"], "agonist_activation": 0.8 });
    let file = folder.join("session.json");
    std::fs::write(&file, json!({ "subject": subject, "hip": "femur_rz", "contractions": contractions }).to_string()).unwrap();
    file
}

fn contraction(set: &str, direction: &str, load_cell: &str) -> serde_json::Value {
    json!({ "set": set, "direction": direction, "coordinates": "coordinates.mot", "load_cell": load_cell })
}

/// The plateau of OpenSim's M3D at 90 % of its peak, found here on its own: its frame times and
/// the mean M3D.
fn opensims_plateau() -> (Vec<f64>, f64) {
    let table = StorageTable::read(&golden("planar/inverse_dynamics.sto")).unwrap();
    let (times, moments) = (table.times(), table.column("knee_angle_r_moment").unwrap());
    let peak = (0..moments.len()).max_by(|&a, &b| moments[a].abs().total_cmp(&moments[b].abs())).unwrap();
    let held = |i: usize| moments[i].abs() >= 0.9 * moments[peak].abs();
    let (mut first, mut last) = (peak, peak);
    while first > 0 && held(first - 1) {
        first -= 1;
    }
    while last + 1 < moments.len() && held(last + 1) {
        last += 1;
    }
    (times[first..=last].to_vec(), moments[first..=last].iter().sum::<f64>() / (last - first + 1) as f64)
}

/// Each row holds the plateau's mean M3D (OpenSim's to 1e-9 N·m), the held posture and the
/// agonists' activations — the protocol's level, or an activation file's mean over the plateau
/// (a(t) = 0.5 + 0.1 t over a plateau symmetric about 1 s: 0.6) — and the folder reads as
/// functional-scaling trials.
#[test]
fn a_contraction_becomes_a_trial_row_at_its_plateau() {
    let folder = tempfile::tempdir().unwrap();
    let activations = folder.path().join("emg.sto");
    let rows: String = (0..=200).map(|i| format!("{}\t{}\n", i as f64 * 0.01, 0.5 + 0.1 * (i as f64 * 0.01))).collect();
    std::fs::write(&activations, format!("emg\nversion=1\nnRows=201\nnColumns=2\ninDegrees=no\nendheader\ntime\tbifemlh_r\n{rows}")).unwrap();
    let mut flexion = contraction("set5", "flexion", "loadcell.xml");
    flexion["activations"] = json!("emg.sto");
    let session = session(folder.path(), json!([contraction("set5", "extension", "loadcell.xml"), flexion]));
    let output = folder.path().join("trials");
    let (code, stdout, stderr) = osim_tune(&["trials", s(&common::fixture("models/dynamometer_planar.osim")), s(&session), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    let (times, mean) = opensims_plateau();
    assert!(stdout.contains(&format!("{:.3}–{:<8.3}", times[0], times[times.len() - 1])), "{stdout}");
    assert!((0.5 + 0.1 * times.iter().sum::<f64>() / times.len() as f64 - 0.6).abs() < 1e-12, "the plateau is symmetric about 1 s");
    let columns = TrialColumns { hip_flexion: "femur_rz".into(), ..TrialColumns::default() };
    let data = DynamometryData::read(&output, &TrialOptions { columns, ..TrialOptions::default() }).unwrap();
    assert_eq!(data.trials.len(), 2);
    for (trial, activation) in data.trials.iter().zip([0.8, 0.6]) {
        assert!((trial.moment - mean).abs() < 1e-9, "{} against OpenSim's {mean}", trial.moment);
        assert!((trial.knee_angle + 1.0).abs() < 1e-12 && (trial.ankle_angle - 0.1).abs() < 1e-12 && (trial.hip_flexion - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{trial:?}");
        assert!((trial.activations[0].1 - activation).abs() < 1e-12, "{trial:?}");
    }
}

/// Refusals name the contraction and the problem, exit 2 and write nothing: a crank that turns
/// (the `spatial` golden's isokinetic sweep), a set without one direction, contractions of one
/// direction pushing opposite ways, an activation outside (0, 1], an unknown direction, a set
/// name that is no file name.
#[test]
fn contractions_that_cannot_be_trials_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    for file in ["coordinates.mot", "loadcell.xml", "loadcell.mot"] {
        std::fs::copy(golden(&format!("spatial/{file}")), folder.path().join(format!("sweep_{file}"))).unwrap();
    }
    let text = std::fs::read_to_string(folder.path().join("sweep_loadcell.xml")).unwrap().replace("loadcell.mot", "sweep_loadcell.mot");
    std::fs::write(folder.path().join("sweep_loadcell.xml"), text).unwrap();
    let mut pulling = std::fs::read_to_string(golden("planar/loadcell.mot")).unwrap();
    let body = pulling.split_off(pulling.find("endheader").unwrap());
    let mut lines = body.lines();
    pulling.push_str(&format!("{}\n{}\n", lines.next().unwrap(), lines.next().unwrap()));
    for line in lines {
        let mut fields: Vec<String> = line.split('\t').map(String::from).collect();
        fields[1..7].iter_mut().for_each(|f| *f = (-f.parse::<f64>().unwrap()).to_string());
        pulling.push_str(&(fields.join("\t") + "\n"));
    }
    std::fs::write(folder.path().join("pull.mot"), pulling).unwrap();
    std::fs::write(folder.path().join("pull.xml"), std::fs::read_to_string(golden("planar/loadcell.xml")).unwrap().replace("loadcell.mot", "pull.mot")).unwrap();
    std::fs::write(folder.path().join("high.sto"), "a\nversion=1\nnRows=2\nnColumns=2\ninDegrees=no\nendheader\ntime\tvas_lat_r\n0\t1.2\n2\t1.2\n").unwrap();
    let mut high = contraction("set5", "extension", "loadcell.xml");
    high["activations"] = json!("high.sto");
    let mut sweep = contraction("set5", "flexion", "sweep_loadcell.xml");
    sweep["coordinates"] = json!("sweep_coordinates.mot");
    let output = folder.path().join("trials");
    let cases = [
        (json!([contraction("set5", "extension", "loadcell.xml"), sweep]), "dynamometer_planar", "contraction 2 (set5 flexion): the crank turned"),
        (json!([contraction("set5", "extension", "loadcell.xml")]), "dynamometer_planar", "set \"set5\" has no flexion contraction"),
        (json!([contraction("set5", "extension", "loadcell.xml"), contraction("set5", "extension", "pull.xml"), contraction("set5", "flexion", "loadcell.xml")]), "dynamometer_planar", "contraction 2 (extension) has M3D of the other sign"),
        (json!([high, contraction("set5", "flexion", "loadcell.xml")]), "dynamometer_planar", "vas_lat_r's mean activation over the plateau is 1.2"),
        (json!([contraction("set5", "sideways", "loadcell.xml")]), "dynamometer_planar", "direction \"sideways\""),
        (json!([contraction("../set5", "extension", "loadcell.xml")]), "dynamometer_planar", "set \"../set5\"; expected a name of letters"),
    ];
    for (contractions, model, expected) in cases {
        let session = session(folder.path(), contractions);
        let (code, _, stderr) = osim_tune(&["trials", s(&common::fixture(&format!("models/{model}.osim"))), s(&session), "-o", s(&output)]);
        assert_eq!(code, 2, "{expected}: {stderr}");
        assert!(stderr.contains(expected), "{expected}: {stderr}");
        assert!(!output.exists(), "{expected}");
    }
}

/// One table file: `name`, `columns` (time first) and `rows`, in degrees when `degrees`.
fn write_table(path: &Path, name: &str, columns: &[&str], rows: &[Vec<f64>], degrees: bool) {
    let body: String = rows.iter().map(|r| r.iter().map(f64::to_string).collect::<Vec<_>>().join("\t") + "\n").collect();
    let header = format!("{name}\nversion=1\nnRows={}\nnColumns={}\ninDegrees={}\nendheader\n{}\n", rows.len(), columns.len(), if degrees { "yes" } else { "no" }, columns.join("\t"));
    std::fs::write(path, header + &body).unwrap();
}

/// M3D at the first frame of `dynamometer` on `coordinates` with the load cell `xml`.
fn m3d(model: &Path, coordinates: &Path, xml: &Path, output: &Path) -> f64 {
    let (code, _, stderr) = osim_tune(&["dynamometer", s(model), s(coordinates), "--load-cell", s(xml), "-o", s(output)]);
    assert_eq!(code, 0, "{stderr}");
    StorageTable::read(output).unwrap().column("knee_angle_r_moment").unwrap()[0]
}

/// The thesis' chain from the dynamometer to the muscles (ch. 5 → ch. 6), end to end. For each
/// of train01's set5 trials (OpenSim-generated knee moments of the subject01 model with known
/// true L_opt and L_ts), a held contraction on the planar dynamometer set-up — its hip coordinate
/// renamed `hip_flexion_r`, posed at the trial's knee, hip and ankle angles — whose load cell
/// pushes with the force that makes M3D the trial's moment (M3D is affine in the load cell's
/// wrench: two `dynamometer` runs give the line). `trials` turns the ten contractions into a
/// trials folder and `scale` fits the subject01 model on it: every L_opt and L_ts within 10⁻⁴ of
/// the truth, as on train01's own files.
#[test]
fn contractions_scale_a_muscle_model_to_the_subjects_truth() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let planar = std::fs::read_to_string(common::fixture("models/dynamometer_planar.osim")).unwrap();
    let model = dir.join("dynamometer.osim");
    std::fs::write(&model, planar.replace("femur_rz", "hip_flexion_r")).unwrap();
    let train01 = common::fixture("dynamometry/train01");
    let mut subject: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(train01.join("subject.json")).unwrap()).unwrap();
    let object = subject.as_object_mut().unwrap();
    object.remove("trial_files");
    object.remove("trial_index");
    let coordinate_names = ["time", "femur_rx", "femur_ry", "hip_flexion_r", "femur_tx", "femur_ty", "femur_tz", "knee_angle_r", "ankle_angle_r", "crank_angle"];
    let load_cell_names = ["time", "loadcell_force_vx", "loadcell_force_vy", "loadcell_force_vz", "loadcell_torque_x", "loadcell_torque_y", "loadcell_torque_z"];
    // The planar golden's load cell at its peak (t = 1 s): the wrench the contractions scale.
    let golden_load_cell = StorageTable::read(&golden("planar/loadcell.mot")).unwrap();
    let peak: Vec<f64> = load_cell_names[1..].iter().map(|c| golden_load_cell.column(c).unwrap()[100]).collect();
    let load_cell = |file: &str, scale: f64| {
        let rows: Vec<Vec<f64>> = (0..=20).map(|i| std::iter::once(0.1 * i as f64).chain(peak.iter().map(|w| scale * w)).collect()).collect();
        write_table(&dir.join(format!("{file}.mot")), "loadcell", &load_cell_names, &rows, false);
        let xml = std::fs::read_to_string(golden("planar/loadcell.xml")).unwrap().replace("loadcell.mot", &format!("{file}.mot"));
        std::fs::write(dir.join(format!("{file}.xml")), xml).unwrap();
        dir.join(format!("{file}.xml"))
    };
    let mut contractions = Vec::new();
    let mut expected = Vec::new();
    for direction in ["extension", "flexion"] {
        let trials = StorageTable::read(&train01.join(format!("set5_{direction}.mot"))).unwrap();
        for row in 0..trials.times().len() {
            let value = |c: &str| trials.column(c).unwrap()[row];
            let (knee, hip, ankle, moment) = (value("knee_angle_r"), value("hip_flexion_r"), value("ankle_angle_r"), value("knee_moment"));
            let name = format!("{direction}{row}");
            let coordinates = dir.join(format!("{name}_ik.mot"));
            let posture = (0..=20).map(|i| vec![0.1 * i as f64, 0.0, 0.0, hip, 0.0, 0.5, 0.0, knee, ankle, knee]).collect::<Vec<_>>();
            write_table(&coordinates, "coordinates", &coordinate_names, &posture, true);
            let unloaded = m3d(&model, &coordinates, &load_cell(&format!("{name}_zero"), 0.0), &dir.join("m3d.sto"));
            let loaded = m3d(&model, &coordinates, &load_cell(&format!("{name}_peak"), 1.0), &dir.join("m3d.sto"));
            load_cell(&name, (moment - unloaded) / (loaded - unloaded));
            contractions.push(json!({ "set": "set5", "direction": direction, "coordinates": format!("{name}_ik.mot"), "load_cell": format!("{name}.xml") }));
            expected.push(moment);
        }
    }
    let session = dir.join("session.json");
    std::fs::write(&session, json!({ "subject": subject, "contractions": contractions }).to_string()).unwrap();
    let output = dir.join("trials");
    let (code, _, stderr) = osim_tune(&["trials", s(&model), s(&session), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    let written: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(output.join("subject.json")).unwrap()).unwrap();
    let keys = |v: &serde_json::Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&written), [keys(&subject), vec!["trial_files".to_string()]].concat(), "the subject's fields in the session's order");
    let data = DynamometryData::read(&output, &TrialOptions::default()).unwrap();
    for (trial, moment) in data.trials.iter().zip(&expected) {
        assert!((trial.moment - moment).abs() < 1e-6 * moment.abs().max(1.0), "{} against train01's {moment}", trial.moment);
    }
    let scaled = dir.join("scaled.osim");
    let (code, _, stderr) = osim_tune(&["scale", s(&common::fixture("golden/scale/subject01_simbody.osim")), s(&output), "-o", s(&scaled)]);
    assert_eq!(code, 0, "{stderr}");
    let spec = ModelSpec::read(&OsimDocument::read(&scaled).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    for (fitted, truth) in knee.nominal_parameters().iter().zip(common::true_parameters(&train01, knee.nominal_parameters())) {
        for (value, true_value) in [(fitted.optimal_fiber_length, truth.optimal_fiber_length), (fitted.tendon_slack_length, truth.tendon_slack_length)] {
            assert!((value / true_value - 1.0).abs() < 1e-4, "{}: {value} m against the truth {true_value} m", fitted.name);
        }
    }
}
