//! `osim-tune trials`: isometric dynamometer contractions as functional-scaling trials. The
//! `planar` dynamometer golden (`oracle/gen_dynamometer.py`) is an isometric contraction —
//! knee at −1 rad, pad force 450 sin²(πt/2) N over 2 s — whose M3D OpenSim 4.6's inverse
//! dynamics gives; the trial row must hold its plateau's mean, the posture and the activations,
//! in the layout `scale` reads.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::io::table::StorageTable;
use osim_tune::tuning::functional::{DynamometryData, TrialColumns, TrialOptions};
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
