//! Hidden effects in OpenSim-generated data (issue 6 and the diagnosis mission, METHOD.md §8):
//! subjects hid01–30 (`oracle/gen_hidden_changes.py`) come from the scaled subject01 model with
//! one deficiency hidden — one knee muscle's L_ts by 2–6 % (hid01–06), L_opt by 5–15 % (07–08),
//! F_max by 10–25 % (09–10) or pennation angle α_opt by 3.4–8° (17–18), the recorded knee angle
//! off by 3–8° (11–12), one direction's or every trial's agonists activated at 80–95 % of the
//! recorded level (13–14, 21–22) or one agonist at 70–90 % (23–24), a group's L_ts by one factor
//! (15–16), the knee's axis moved by 3–8 mm (19–20), the measured moments offset by 2–6 N·m
//! (25–26), or the hip (27–28) or ankle (29–30) standing 3–8° off the recorded posture —
//! noise-free (hid01–02, 07, 09, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29) or with moment noise
//! σ = 5 (hid03–04, 08, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30) and 10 N·m (hid05–06). Only
//! the assertions read what was hidden (ground_truth.json). The candidate causes and their
//! verdict must name it wherever the data resolve it, recover its value, and never name
//! another cause.

mod common;

use common::{fixture, osim_tune};
use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{held_out_gain, Cause, CauseVerdict, DynamometryData, KneeMomentModel, SetSelection, SingleCause, TrialOptions, Verdict};
use osim_tune::validation::functional::{hidden_axis_offset, hidden_cause, hidden_value_error, single_cause_verdict};
use serde_json::Value;

/// The hidden cause of `subject` and its true value.
fn hidden(subject: &str) -> (Cause, f64) {
    hidden_cause(&truth(subject)).unwrap()
}

fn truth(subject: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture(&format!("dynamometry/hidden/{subject}/ground_truth.json"))).unwrap()).unwrap()
}

fn subject_data(subject: &str, sets: SetSelection) -> (ModelSpec, DynamometryData, KneeMomentModel) {
    let data = DynamometryData::read(&fixture(&format!("dynamometry/hidden/{subject}")), &TrialOptions { sets, ..TrialOptions::default() }).unwrap();
    let spec = ModelSpec::read(&OsimDocument::read(&fixture("golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    (spec, data, knee)
}

/// The ranking and its verdict at the subject file's σ (noise-free: exact), on `sets`.
fn verdict(subject: &str, sets: SetSelection) -> (Vec<SingleCause>, CauseVerdict) {
    let (spec, data, knee) = subject_data(subject, sets);
    let (causes, verdict) = single_cause_verdict(&spec, &knee, &data).unwrap();
    (causes, verdict.unwrap())
}

fn selections() -> [(&'static str, SetSelection); 2] {
    [("set5", SetSelection::Only(vec!["set5".into()])), ("all", SetSelection::All)]
}

#[test]
fn noise_free_subjects_name_the_hidden_cause_and_recover_it() {
    for subject in ["hid01", "hid02", "hid07", "hid09", "hid11", "hid13", "hid15", "hid17", "hid19", "hid21", "hid23", "hid25", "hid27", "hid29"] {
        let (cause, value) = hidden(subject);
        for (label, sets) in selections() {
            let (causes, verdict) = verdict(subject, sets);
            assert_eq!(verdict.verdict, Verdict::Named(cause.clone()), "{subject} {label}: {verdict:?}");
            // OpenSim's moments are printed to 10⁻⁶ N·m; the value is recovered to far better than 1 %
            // (an axis move to 10⁻⁴ mm).
            let error = causes[0].fitted / value - 1.0;
            assert!(error.abs() < 1e-4, "{subject} {label}: {} off by {:.4} %", cause.describe(), 100.0 * error);
            assert!(hidden_value_error(&causes[0], value, hidden_axis_offset(&truth(subject)), verdict.noise_sd) < 1e-4, "{subject} {label}: {:?}", causes[0]);
        }
    }
}

#[test]
fn noisy_subjects_are_named_where_the_effect_dwarfs_the_noise_and_never_wrongly() {
    for subject in ["hid03", "hid04", "hid05", "hid06", "hid08", "hid10", "hid12", "hid14", "hid16", "hid18", "hid20", "hid22", "hid24", "hid26", "hid28", "hid30"] {
        let (cause, value) = hidden(subject);
        for (label, sets) in selections() {
            let (causes, verdict) = verdict(subject, sets.clone());
            let context = format!("{subject} {label} (hidden {}): {verdict:?}", cause.describe());
            let named = match &verdict.verdict {
                Verdict::Named(named_cause) => {
                    assert_eq!(named_cause, &cause, "{context}");
                    assert!(hidden_value_error(&causes[0], value, hidden_axis_offset(&truth(subject)), verdict.noise_sd) <= 1.0, "{context}: fitted {:?} against {value}", causes[0]);
                    true
                }
                Verdict::MuscleNamed { muscle, parameters } => {
                    assert!(matches!(&cause, Cause::Muscle { muscle: m, parameter } if m == muscle && parameters.contains(parameter)), "{context}");
                    true
                }
                Verdict::Ambiguous { candidates } => {
                    assert!(candidates.contains(&cause), "{context}");
                    false
                }
                Verdict::NoEffect => false,
                Verdict::NotSingle => panic!("one deficiency hidden, yet no single cause accepted: {context}"),
            };
            // Power: on all 70 trials, where the unchanged model misses the measured moments by
            // more than 2.5 σ (RMS; a 2 ln K over it of n·(2.5² − 1) ≫ 10), the cause must be
            // named. set5's ten moments may not single it out: there one-parameter changes of
            // other muscles mimic hid20's axis offset (2.7 σ) as well as the truth does.
            if label == "set5" {
                continue;
            }
            let (_, data, knee) = subject_data(subject, sets);
            let sigma = data.noise_sd.unwrap();
            let moments = knee.moments(&knee.nominal_parameters()).unwrap();
            let squares: f64 = moments.iter().zip(data.measured_moments()).map(|(m, y)| (m - y).powi(2)).sum();
            let initial_rms = (squares / moments.len() as f64).sqrt();
            assert!(named || initial_rms < 2.5 * sigma, "{context}: initial RMS {initial_rms:.2} N·m at σ = {sigma}, not named");
        }
    }
}

#[test]
fn the_named_cause_predicts_trials_its_fit_did_not_see() {
    // Noise-free: each fold's fit recovers the hidden value, so the other fold is predicted
    // exactly — for a muscle parameter, an angle offset and an axis move (two variables) alike.
    for subject in ["hid01", "hid11", "hid19"] {
        let (cause, value) = hidden(subject);
        let (spec, data, knee) = subject_data(subject, SetSelection::Only(vec!["set5".into()]));
        let measured = data.measured_moments();
        let (causes, _) = single_cause_verdict(&spec, &knee, &data).unwrap();
        assert_eq!(causes[0].cause, cause);
        let gain = held_out_gain(&spec, &knee, &data, &knee.nominal_parameters(), &measured, &causes[0]).unwrap();
        assert!(gain.rms_before > 1.0 && gain.rms_after < 1e-4, "{subject}: {gain:?}");
        for fitted in &gain.fitted {
            assert!((fitted / value - 1.0).abs() < 1e-4, "{subject}: {gain:?}");
        }
    }
    // σ = 5 N·m, all 70 trials: the prediction error of unseen trials falls to the noise level.
    let (spec, data, knee) = subject_data("hid12", SetSelection::All);
    let measured = data.measured_moments();
    let (causes, _) = single_cause_verdict(&spec, &knee, &data).unwrap();
    let gain = held_out_gain(&spec, &knee, &data, &knee.nominal_parameters(), &measured, &causes[0]).unwrap();
    let sigma = data.noise_sd.unwrap();
    assert!(gain.rms_before > 1.5 * sigma && gain.rms_after < 1.2 * sigma, "{gain:?}");
}

#[test]
fn the_cause_model_changes_only_the_named_cause() {
    let dir = tempfile::tempdir().unwrap();
    let model = fixture("golden/scale/subject01_simbody.osim");
    let run = |subject: &str| {
        let (output, cause_model) = (dir.path().join(format!("{subject}.osim")), dir.path().join(format!("{subject}_cause.osim")));
        let folder = fixture(&format!("dynamometry/hidden/{subject}"));
        let arguments = ["scale", model.to_str().unwrap(), folder.to_str().unwrap(), "--sets", "set5", "-o", output.to_str().unwrap(), "--cause-model", cause_model.to_str().unwrap()];
        let (code, _, stderr) = osim_tune(&arguments);
        assert_eq!(code, 0, "{stderr}");
        (cause_model, stderr)
    };
    // hid15: the vasti's L_ts by one factor; the cause model differs from the input in exactly
    // those three values, each by the hidden factor.
    let (Cause::Group { muscles, .. }, factor) = hidden("hid15") else { panic!("hid15 hides a group change") };
    let (cause_model, _) = run("hid15");
    let (code, stdout, stderr) = osim_tune(&["diff", model.to_str().unwrap(), cause_model.to_str().unwrap(), "--json"]);
    assert_eq!(code, 1, "{stderr}");
    let differences: Value = serde_json::from_str(&stdout).unwrap();
    let differences = differences["differences"].as_array().unwrap();
    assert_eq!(differences.len(), 3, "{differences:?}");
    for difference in differences {
        let path = difference["path"].as_str().unwrap();
        assert!(muscles.iter().any(|m| path == format!("/forceset/{m}/tendon_slack_length")), "{path}");
        let (old, new) = (difference["old"].as_str().unwrap().parse::<f64>().unwrap(), difference["new"].as_str().unwrap().parse::<f64>().unwrap());
        assert!((new / old / factor - 1.0).abs() < 1e-6, "{difference}");
    }
    // The cause model and the model may not be one file.
    let (output, folder) = (dir.path().join("same.osim"), fixture("dynamometry/hidden/hid15"));
    let (code, _, stderr) = osim_tune(&["scale", model.to_str().unwrap(), folder.to_str().unwrap(), "-o", output.to_str().unwrap(), "--cause-model", output.to_str().unwrap()]);
    assert!(code == 2 && stderr.contains("--cause-model and -o name the same file") && !output.exists(), "{code} {stderr}");
    // hid19: the knee's axis moved; the cause model moves both offset frames of knee_r, and as
    // the initial model it reproduces the measured moments.
    let (cause_model, _) = run("hid19");
    let (code, stdout, stderr) = osim_tune(&["diff", model.to_str().unwrap(), cause_model.to_str().unwrap(), "--json"]);
    assert_eq!(code, 1, "{stderr}");
    let differences: Value = serde_json::from_str(&stdout).unwrap();
    let paths: Vec<&str> = differences["differences"].as_array().unwrap().iter().map(|d| d["path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["/jointset/knee_r/frames/femur_r_offset/translation", "/jointset/knee_r/frames/tibia_r_offset/translation"]);
    let spec = ModelSpec::read(&OsimDocument::read(&cause_model).unwrap()).unwrap();
    let (_, data, _) = subject_data("hid19", SetSelection::All);
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let moments = knee.moments(&knee.nominal_parameters()).unwrap();
    let largest = moments.iter().zip(data.measured_moments()).map(|(m, y)| (m - y).abs()).fold(0.0, f64::max);
    // The moments are printed to 10⁻⁶ N·m, the written offset to 17 digits.
    assert!(largest < 1e-4, "the cause model misses a measured moment by {largest} N·m");
    // hid11: an angle offset is in the trials; no cause model.
    let (cause_model, stderr) = run("hid11");
    assert!(!cause_model.exists() && stderr.contains("in the trials, not the model"), "{stderr}");
}
