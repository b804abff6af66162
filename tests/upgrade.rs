//! OpenSim 4's conversion of 2.x/3.x models: the converted 4.x document reads as the original.

use std::path::Path;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::{upgrade, ModelSpec};

fn converted(path: &str) -> (ModelSpec, ModelSpec) {
    let document = OsimDocument::read(Path::new(path)).unwrap();
    let original = ModelSpec::read(&document).unwrap();
    let upgraded = upgrade(&document).unwrap();
    std::fs::write(format!("/tmp/up/{}", Path::new(path).file_name().unwrap().to_string_lossy()), upgraded.xml.serialize()).unwrap();
    (original, ModelSpec::read(&upgraded).unwrap())
}

#[test]
fn legacy_models_read_the_same_after_conversion() {
    for path in ["fixtures/legacy/pendulum_leg_v30000.osim", "fixtures/ik_point_constraint/subject1_abdbonepin.osim", "fixtures/ik_constraint_test/constraintTest_ikOnly.osim"] {
        let (original, upgraded) = converted(path);
        // OpenSim 4 takes whitespace out of names ("Dynamic Mocap Model").
        assert_eq!(original.name.replace(' ', ""), upgraded.name, "{path}");
        let (a, b) = (without_elements(serde_json::to_value(&original).unwrap()), without_elements(serde_json::to_value(&upgraded).unwrap()));
        for part in ["bodies", "joints", "markers", "forces", "actuators", "constraints", "wrap_objects", "controllers", "probes", "gravity"] {
            if a[part] != b[part] {
                let (x, y) = (serde_json::to_string_pretty(&a[part]).unwrap(), serde_json::to_string_pretty(&b[part]).unwrap());
                let first = x.lines().zip(y.lines()).position(|(p, q)| p != q).unwrap_or(0);
                panic!("{path}: {part} differ at line {first}:\n{}\n---\n{}", x.lines().skip(first.saturating_sub(20)).take(30).collect::<Vec<_>>().join("\n"), y.lines().skip(first.saturating_sub(20)).take(30).collect::<Vec<_>>().join("\n"));
            }
        }
    }
}

/// The value without document positions (`element` ids differ between the two documents).
fn without_elements(value: serde_json::Value) -> serde_json::Value {
    match value {
        serde_json::Value::Object(map) => map.into_iter().filter(|(k, _)| k != "element").map(|(k, v)| (k, without_elements(v))).collect(),
        serde_json::Value::Array(items) => items.into_iter().map(without_elements).collect(),
        other => other,
    }
}
