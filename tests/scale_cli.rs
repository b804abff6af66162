//! `osim-tune scale` end to end: the OpenSim setup, a trials folder, and refused input.

mod common;

use std::path::{Path, PathBuf};

use common::{fixture, osim_tune};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::validation::{compare_scaled_models, SCALED_MODEL_TOLERANCE};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn generic() -> PathBuf {
    fixture("../models/gait2392_millard2012muscle.osim")
}

/// A copy of fixtures/subject01 in a temporary folder, with `edit` applied to the setup text.
fn subject01_copy(edit: impl Fn(String) -> String) -> tempfile::TempDir {
    let folder = tempfile::tempdir().unwrap();
    for file in ["subject01_Setup_Scale.xml", "gait2392_Scale_MarkerSet.xml", "subject01_static.trc", "subject.json"] {
        std::fs::copy(fixture(&format!("subject01/{file}")), folder.path().join(file)).unwrap();
    }
    let setup = folder.path().join("subject01_Setup_Scale.xml");
    std::fs::write(&setup, edit(std::fs::read_to_string(&setup).unwrap())).unwrap();
    folder
}

#[test]
fn scale_with_the_opensim_setup_writes_the_scaled_model_and_its_side_files() {
    let out = tempfile::tempdir().unwrap();
    let (model, scaled_only, scale_set, pose) = ["s.osim", "only.osim", "set.xml", "new/folder/pose.mot"].map(|f| out.path().join(f)).into();
    let (setup, generic) = (fixture("subject01/subject01_Setup_Scale.xml"), generic());
    let arguments = ["scale", s(&generic), "--setup", s(&setup), "-o", s(&model), "--scaled-only", s(&scaled_only), "--scale-set", s(&scale_set), "--static-pose", s(&pose)];
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("measurement thigh") && stdout.contains("markers moved: 39"), "{stdout}");
    assert!(stdout.contains("\"patella_r\" is named in the setup but not in the model"), "{stdout}");
    let golden = OsimDocument::read(&fixture("golden/scale/subject01_scaledOnly.osim")).unwrap();
    assert!(compare_scaled_models(&golden, &OsimDocument::read(&scaled_only).unwrap(), SCALED_MODEL_TOLERANCE).is_empty());
    let set = OsimDocument::read(&scale_set).unwrap();
    assert_eq!(set.object_class(), "ScaleSet");
    assert!(String::from_utf8(set.xml.serialize()).unwrap().contains("<scales> 1.14724 1.14724 1.14724</scales>"));
    let pose = StorageTable::read(&pose).unwrap();
    assert_eq!((pose.n_rows(), pose.in_degrees()), (1, Some(true)));
    assert!(pose.column("knee_angle_r").is_some());
    let placed = OsimDocument::read(&model).unwrap();
    assert_ne!(placed.xml.serialize(), OsimDocument::read(&scaled_only).unwrap().xml.serialize());
}

#[test]
fn scale_of_a_trials_folder_uses_the_subject_file_and_the_built_in_measurements() {
    let out = tempfile::tempdir().unwrap();
    let model = out.path().join("s.osim");
    let (code, stdout, stderr) = osim_tune(&["scale", s(&generic()), s(&fixture("subject01")), "--linear", "-o", s(&model), "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // Measured factors of OpenSim's subject01 run (scale_factors.csv); femur and tibia take the
    // thigh and shank measurements here because the built-in setup has no manual factors.
    assert!((summary["scale_factors"]["pelvis"][0].as_f64().unwrap() - 1.0245770378331935).abs() < 1e-12);
    assert!((summary["scale_factors"]["talus_r"][1].as_f64().unwrap() - 1.1139780740531091).abs() < 1e-12);
    assert!((summary["scale_factors"]["tibia_r"][2].as_f64().unwrap() - 1.1139780740531091).abs() < 1e-12);
    let thigh = summary["measurements"].as_array().unwrap().iter().find(|m| m["name"] == "thigh").unwrap()["factor"].as_f64().unwrap();
    assert_eq!(summary["scale_factors"]["femur_l"][0].as_f64().unwrap(), thigh);
    assert!(OsimDocument::read(&model).is_ok());
}

/// Runs `scale` on a copy of subject01 whose setup is edited by `edit`; it must fail with exit 2,
/// mention every string of `expected` and write nothing.
fn assert_scale_fails(edit: impl Fn(String) -> String, expected: &[&str]) {
    let folder = subject01_copy(edit);
    let model = folder.path().join("out.osim");
    let setup = folder.path().join("subject01_Setup_Scale.xml");
    let (code, _, stderr) = osim_tune(&["scale", s(&generic()), "--setup", s(&setup), "-o", s(&model)]);
    assert_eq!(code, 2, "{stderr}");
    for text in expected {
        assert!(stderr.contains(text), "{text:?} not in {stderr}");
    }
    assert!(!model.exists());
}

#[test]
fn bad_scale_input_is_named_and_writes_nothing() {
    assert_scale_fails(|t| t.replacen("V.Sacral Top.Head", "V.Sacral Top.Hat", 1), &["measurement \"torso\"", "Top.Hat", "subject01_static.trc"]);
    assert_scale_fails(|t| t.replace("<mass>      72.60000000 </mass>", "<mass> 0 </mass>"), &["subject <mass>", "subject01_Setup_Scale.xml"]);
    assert_scale_fails(|t| t.replace("1.14724000       1.14724000       1.14724000", "5 5 5"), &["scale factor of manual scale of femur_r", "5"]);
    assert_scale_fails(|t| t.replacen("<time_range>       1.00000000       2.00000000 </time_range>", "<time_range> 10 11 </time_range>", 1), &["outside the trial"]);
    assert_scale_fails(|t| t.replace("gait2392_Scale_MarkerSet.xml", "missing.xml"), &["missing.xml"]);
}

#[test]
fn scale_refuses_to_overwrite_an_input_and_needs_a_source() {
    let setup = fixture("subject01/subject01_Setup_Scale.xml");
    let (code, _, stderr) = osim_tune(&["scale", s(&generic()), "--setup", s(&setup), "-o", s(&fixture("subject01/subject01_static.trc"))]);
    assert_eq!(code, 2);
    assert!(stderr.contains("input"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["scale", s(&generic()), "-o", "/tmp/never.osim"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--setup"), "{stderr}");
}
