//! `osim-tune emg`: predicted activations against EMG by cross-correlation, checked from first
//! principles — an affine image of the prediction correlates perfectly at lag 0, a delayed copy
//! at its delay, an inverted one at −1 — and its refusals.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A storage table `name` in `folder` with `labels` and one row per time of `times`.
fn table(folder: &Path, name: &str, labels: &[&str], times: &[f64], value: impl Fn(usize, f64) -> f64) -> PathBuf {
    let mut text = format!("{name}\nversion=1\nnRows={}\nnColumns={}\ninDegrees=no\nendheader\ntime\t{}\n", times.len(), labels.len() + 1, labels.join("\t"));
    for &t in times {
        let row: Vec<String> = (0..labels.len()).map(|k| format!("{:.17e}", value(k, t))).collect();
        text += &format!("{t:.17e}\t{}\n", row.join("\t"));
    }
    let file = folder.join(name);
    std::fs::write(&file, text).unwrap();
    file
}

fn prediction(k: usize, t: f64) -> f64 {
    0.5 + 0.3 * (2.0 * std::f64::consts::PI * (2.0 + k as f64) * t).sin()
}

/// (muscle, r(0), best r, lag) rows of the printed table.
fn rows(stdout: &str) -> Vec<(String, f64, f64, f64)> {
    stdout
        .lines()
        .skip(2)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f[0].to_string(), f[2].parse().unwrap(), f[3].parse().unwrap(), f[4].parse().unwrap())
        })
        .collect()
}

#[test]
fn affine_delayed_and_inverted_copies_are_recognised() {
    let folder = tempfile::tempdir().unwrap();
    let times: Vec<f64> = (0..=100).map(|k| k as f64 / 100.0).collect();
    let predicted = table(folder.path(), "predicted.sto", &["affine", "delayed", "inverted"], &times, prediction);
    let fine: Vec<f64> = (-200..=1200).map(|k| k as f64 / 1000.0).collect();
    let emg = table(folder.path(), "emg.sto", &["affine", "delayed", "inverted"], &fine, |k, t| match k {
        0 => 2.0 * prediction(0, t) + 0.1,
        1 => prediction(1, t - 0.05),
        _ => 1.0 - prediction(2, t),
    });
    let (code, stdout, stderr) = osim_tune(&["emg", s(&predicted), s(&emg)]);
    assert_eq!(code, 0, "{stderr}");
    let rows = rows(&stdout);
    assert_eq!(rows.len(), 3, "{stdout}");
    assert_eq!((rows[0].1, rows[0].2, rows[0].3), (1.0, 1.0, 0.0), "{stdout}");
    // Delayed by 0.05 s: perfect at lag +0.05 (the prediction pairs with later EMG), and at lag
    // 0 the correlation of a 3 Hz sine with itself 0.15 periods later, cos(0.3π) = 0.588, up to
    // the unequal number of periods in the window.
    assert!(rows[1].2 >= 0.9995 && (rows[1].3 - 0.05).abs() < 1e-9, "{stdout}");
    assert!((rows[1].1 - (0.3 * std::f64::consts::PI).cos()).abs() < 0.02, "{stdout}");
    assert_eq!(rows[2].1, -1.0, "{stdout}");
}

#[test]
fn forward_state_names_pairs_and_json() {
    let folder = tempfile::tempdir().unwrap();
    let times: Vec<f64> = (0..=50).map(|k| k as f64 / 50.0).collect();
    let predicted = table(folder.path(), "states.sto", &["/forceset/BIClong/activation", "/forceset/BIClong/fiber_length"], &times, prediction);
    let emg = table(folder.path(), "emg.sto", &["biceps"], &times, |_, t| prediction(0, t));
    let (code, stdout, stderr) = osim_tune(&["emg", s(&predicted), s(&emg), "--pair", "BIClong=biceps", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json[0]["muscle"], "BIClong");
    assert_eq!(json[0]["at_zero_lag"], 1.0);
    assert_eq!(json[0]["rows"], 51);
}

#[test]
fn bad_input_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let times: Vec<f64> = (0..=10).map(|k| k as f64 / 10.0).collect();
    let predicted = table(folder.path(), "predicted.sto", &["soleus_r"], &times, prediction);
    let emg = table(folder.path(), "emg.sto", &["SOL", "GM"], &times, prediction);
    let (code, _, stderr) = osim_tune(&["emg", s(&predicted), s(&emg)]);
    assert!(code == 2 && stderr.contains("share no muscle name") && stderr.contains("--pair"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["emg", s(&predicted), s(&emg), "--pair", "soleus_r=SOLEUS"]);
    assert!(code == 2 && stderr.contains("emg.sto: no column named \"SOLEUS\" (it has SOL, GM)"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["emg", s(&predicted), s(&emg), "--pair", "soleus_r"]);
    assert!(code == 2 && stderr.contains("expected MUSCLE=CHANNEL"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["emg", s(&predicted), s(&emg), "--pair", "soleus_r=SOL", "--max-lag", "-1"]);
    assert!(code == 2 && stderr.contains("max lag -1"), "{stderr}");
}
