//! OpenSim 4's conversion of 2.x/3.x models (`model::upgrade`, `osim-tune convert`): the 4.x
//! document reads as the original does, and every value it writes is the one OpenSim 4.6 writes
//! when it converts the same model (`oracle/gen_upgrade.py`).

use std::path::{Path, PathBuf};

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::{upgrade, ModelSpec, UPGRADED_VERSION};
use osim_tune::review::flatten;
use osim_tune::validation::conversion_mismatches;
use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(name)
}

/// The model's spec without document positions (element ids differ between documents).
fn spec(document: &OsimDocument) -> Value {
    without_elements(serde_json::to_value(ModelSpec::read(document).unwrap()).unwrap())
}

fn without_elements(value: Value) -> Value {
    match value {
        Value::Object(map) => map.into_iter().filter(|(k, _)| k != "element").map(|(k, v)| (k, without_elements(v))).collect(),
        Value::Array(items) => items.into_iter().map(without_elements).collect(),
        other => other,
    }
}

/// The first part of two specs that differs, shown side by side.
fn assert_same_model(a: &Value, b: &Value, what: &str) {
    for part in ["bodies", "joints", "markers", "forces", "actuators", "constraints", "wrap_objects", "controllers", "probes", "gravity"] {
        if a[part] != b[part] {
            let (x, y) = (serde_json::to_string_pretty(&a[part]).unwrap(), serde_json::to_string_pretty(&b[part]).unwrap());
            let first = x.lines().zip(y.lines()).position(|(p, q)| p != q).unwrap_or(0);
            let around = |s: &str| s.lines().skip(first.saturating_sub(12)).take(20).collect::<Vec<_>>().join("\n");
            panic!("{what}: {part} differ:\n{}\n--- vs ---\n{}", around(&x), around(&y));
        }
    }
}

/// Every 2.x/3.x model among the fixtures reads the same after conversion: bodies, joints and
/// their frames and coordinates, markers, forces with their paths, constraints, wrap objects
/// (names without whitespace, as OpenSim 4 renames "Dynamic Mocap Model").
#[test]
fn legacy_models_read_the_same_after_conversion() {
    for path in [
        "legacy/pendulum_leg_v30000.osim",
        "legacy/pendulum_leg_v30000_digits.osim",
        "legacy/arm26_v20303.osim",
        "legacy/leg6dof9musc_v20303.osim",
        "ik_point_constraint/subject1_abdbonepin.osim",
        "ik_constraint_test/constraintTest_ikOnly.osim",
    ] {
        let document = OsimDocument::read(&fixture(path)).unwrap();
        let converted = upgrade(&document).unwrap();
        assert_eq!(converted.version.number, UPGRADED_VERSION);
        let (original, ours) = (ModelSpec::read(&document).unwrap(), ModelSpec::read(&converted).unwrap());
        assert_eq!(original.name.replace(' ', ""), ours.name, "{path}");
        assert_same_model(&spec(&document), &spec(&converted), path);
    }
}

/// Our conversion against OpenSim 4.6's of the same model: the same model, and every component
/// and value we write is one OpenSim writes (numbers equal as doubles — the values OpenSim
/// streams keep its six significant digits; socket paths in their absolute form).
#[test]
fn conversion_writes_what_opensim_writes() {
    for name in ["pendulum_leg_v30000_digits", "arm26_v20303", "leg6dof9musc_v20303"] {
        let original = OsimDocument::read(&fixture(&format!("legacy/{name}.osim"))).unwrap();
        let opensim = OsimDocument::read(&fixture(&format!("golden/upgrade/{name}.osim"))).unwrap();
        let ours = upgrade(&original).unwrap();
        assert_same_model(&spec(&opensim), &spec(&ours), name);
        let mismatches = conversion_mismatches(&opensim, &ours);
        assert!(mismatches.is_empty(), "{name}: {mismatches:#?}");
        let checked = flatten(&ours).entries.len();
        assert!(checked > 100, "{name}: {checked}");
        let mut altered = ours.clone().into_owned();
        altered.set_property("/bodyset/shank/mass", "3.75").or_else(|_| altered.set_property("/bodyset/r_humerus/mass", "1.9")).or_else(|_| altered.set_property("/bodyset/tibia_r/mass", "3.8")).unwrap();
        assert_eq!(conversion_mismatches(&opensim, &altered).len(), 1, "{name}: a changed mass is seen");
    }
}

/// A 4.x model is returned as it is.
#[test]
fn a_4x_model_is_not_converted() {
    let document = OsimDocument::read(&fixture("models/arm26.osim")).unwrap();
    assert_eq!(upgrade(&document).unwrap().xml.serialize(), document.xml.serialize());
}

/// A value the conversion computes with (a display geometry's transform, which no other part of
/// osim-tune reads) that is not what it must be names the file, line and component.
#[test]
fn a_bad_value_names_file_and_line() {
    let path = fixture("legacy/arm26_v20303.osim");
    let text = std::fs::read_to_string(&path).unwrap();
    let line = text.lines().position(|l| l.contains("<transform> -0 0 -0 0 0 0</transform>")).unwrap() + 1;
    let broken = text.replacen("<transform> -0 0 -0 0 0 0</transform>", "<transform> -0 0 -0 0 0</transform>", 1);
    let document = OsimDocument::parse(broken, &path).unwrap();
    let error = upgrade(&document).unwrap_err().to_string();
    assert!(error.contains(&format!("arm26_v20303.osim:{line}: DisplayGeometry: <transform> must be 6 numbers")), "{error}");
}
