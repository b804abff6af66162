//! Lossless reading and writing of OpenSim documents, component paths and the semantic diff.

mod common;

use osim_tune::io::osim::{Dialect, OsimDocument, PropertyKind};
use osim_tune::review::{diff, flatten, Change, FlatEntry};

#[test]
fn every_bundled_document_round_trips_byte_identically() {
    for path in common::opensim_documents() {
        let original = std::fs::read(&path).unwrap();
        let document = OsimDocument::read_object(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!document.xml.is_modified());
        assert!(document.xml.serialize() == original, "{} changed on round trip", path.display());
    }
}

#[test]
fn dialects_of_the_shipped_documents() {
    let setup = OsimDocument::read(&common::fixture("subject01/subject01_Setup_Scale.xml")).unwrap();
    assert_eq!((setup.version.number, setup.version.dialect, setup.object_class()), (20302, Dialect::V2, "ScaleTool"));
    let ik = OsimDocument::read(&common::fixture("subject01/subject01_Setup_IK.xml")).unwrap();
    assert_eq!(ik.version.dialect, Dialect::V3);
    let legacy = OsimDocument::read(&common::fixture("legacy/pendulum_leg_v30000.osim")).unwrap();
    assert_eq!(legacy.version.dialect, Dialect::V3);
}

#[test]
fn one_edit_changes_exactly_one_line() {
    let path = common::root().join("models/gait2392_millard2012muscle.osim");
    let original = std::fs::read_to_string(&path).unwrap();
    let mut document = OsimDocument::read(&path).unwrap();
    document.set_property("/forceset/vas_lat_r/tendon_slack_length", "0.17").unwrap();
    let edited = String::from_utf8(document.xml.serialize()).unwrap();
    let changed: Vec<(&str, &str)> = original.lines().zip(edited.lines()).filter(|(a, b)| a != b).collect();
    assert_eq!(original.lines().count(), edited.lines().count());
    assert_eq!(changed.len(), 1, "{changed:?}");
    assert_eq!(changed[0].1.trim(), "<tendon_slack_length>0.17</tendon_slack_length>");
}

#[test]
fn paths_address_components_like_opensim() {
    let document = OsimDocument::read(&common::root().join("models/gait2392_millard2012muscle.osim")).unwrap();
    let range = document.resolve("/jointset/knee_r/knee_angle_r/range").unwrap();
    assert_eq!(document.xml.text(range).unwrap(), "-2.0943950999999998 0.17453293");
    // The canonical path names the unnamed property that holds the coordinate.
    assert_eq!(document.path_of(range), "/jointset/knee_r/coordinates/knee_angle_r/range");
    let spline_x = document.resolve("/jointset/knee_r/translation1/function/x").unwrap();
    assert!(document.xml.text(spline_x).unwrap().trim().starts_with("-2.0944 -1.74533"));
    assert!(document.resolve("/forceset/no_such_muscle/optimal_fiber_length").is_err());
}

#[test]
fn every_flattened_path_resolves_back_to_its_element() {
    for name in ["models/gait2392_thelen2003muscle.osim", "fixtures/models/Rajagopal2016.osim", "fixtures/subject01/subject01_Setup_Scale.xml"] {
        let document = OsimDocument::read(&common::root().join(name)).unwrap();
        let mut checked = 0;
        for (path, entry) in flatten(&document).entries.iter().filter(|(p, _)| !p.contains('@')) {
            let id = document.resolve(path).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&document.path_of(id), path);
            if let FlatEntry::Property { value } = entry {
                assert_eq!(document.xml.text(id).unwrap(), value.as_str());
            }
            checked += 1;
        }
        assert!(checked > 100, "{name}: only {checked} paths");
    }
}

#[test]
fn set_refuses_values_of_another_kind_and_components() {
    let mut document = OsimDocument::read(&common::root().join("models/gait2354_simbody.osim")).unwrap();
    assert!(document.set_property("/forceset/vas_lat_r/optimal_fiber_length", "long").is_err());
    assert!(document.set_property("/jointset/knee_r/knee_angle_r/range", "0.1").is_err());
    assert!(document.set_property("/jointset/knee_r/knee_angle_r/clamped", "yes").is_err());
    assert!(document.set_property("/forceset/vas_lat_r", "1").is_err());
    assert!(!document.xml.is_modified());
}

#[test]
fn diff_reports_exactly_the_edits() {
    let path = common::root().join("models/gait2392_thelen2003muscle.osim");
    let original = OsimDocument::read(&path).unwrap();
    let mut edited = original.clone();
    let edits = [
        ("/forceset/vas_lat_r/tendon_slack_length", "0.17"),
        ("/forceset/rect_fem_r/optimal_fiber_length", "0.1"),
        ("/bodyset/femur_r/mass_center", "0 -0.18 0"),
        ("/jointset/knee_r/knee_angle_r/clamped", "true"),
    ];
    for (property, value) in edits {
        edited.set_property(property, value).unwrap();
    }
    let differences = diff(&original, &edited, 0.0);
    let paths: Vec<&str> = differences.differences.iter().map(|d| d.path.as_str()).collect();
    assert_eq!(
        paths,
        [
            "/bodyset/femur_r/mass_center",
            "/jointset/knee_r/coordinates/knee_angle_r/clamped",
            "/forceset/rect_fem_r/optimal_fiber_length",
            "/forceset/vas_lat_r/tendon_slack_length",
        ]
    );
    let Change::Changed { old, new, relative_change } = &differences.differences[3].change else { panic!() };
    let old_value: f64 = old.parse().unwrap();
    assert_eq!(new, "0.17");
    assert!((relative_change.unwrap() - (0.17 - old_value) / old_value).abs() < 1e-15);
}

#[test]
fn diff_ignores_number_spelling_whitespace_and_comments() {
    let path = common::root().join("models/gait2392_millard2012muscle.osim");
    let original = OsimDocument::read(&path).unwrap();
    let mut respelled_text = String::new();
    for line in String::from_utf8(original.xml.serialize()).unwrap().lines() {
        if line.trim_start().starts_with("<!--") {
            continue; // drop comment lines
        }
        respelled_text.push_str(line.trim_start());
        respelled_text.push_str("\r\n");
    }
    let mut respelled = OsimDocument::parse(respelled_text, &path).unwrap();
    let leaves: Vec<_> = respelled.xml.ids().filter(|&id| respelled.xml.children(id).is_empty()).collect();
    let mut respelled_count = 0;
    for id in leaves {
        let Some(value) = respelled.xml.text(id).map(|v| v.into_owned()) else { continue };
        if let PropertyKind::Numbers(_) = PropertyKind::of(&value) {
            let spelled: Vec<String> = value.split_whitespace().map(|t| format!("{:e}", t.parse::<f64>().unwrap())).collect();
            respelled.xml.set_text(id, &spelled.join("   ")).unwrap();
            respelled_count += 1;
        }
    }
    assert!(respelled_count > 1000);
    assert!(respelled.xml.serialize() != original.xml.serialize());
    let differences = diff(&original, &respelled, 0.0);
    assert!(differences.is_empty(), "{:?}", &differences.differences[..differences.differences.len().min(5)]);
}

#[test]
fn diff_reports_added_and_removed_components_once() {
    let a = OsimDocument::read(&common::fixture("models/leg6dof9musc.osim")).unwrap();
    let text = String::from_utf8(a.xml.serialize()).unwrap();
    let start = text.find("<Marker name=\"R.Heel\">").unwrap();
    let end = start + text[start..].find("</Marker>").unwrap() + "</Marker>".len();
    let without = format!("{}{}", &text[..start], &text[end..]);
    let b = OsimDocument::parse(without, a.xml.file()).unwrap();
    let removed = diff(&a, &b, 0.0);
    assert_eq!(removed.differences.len(), 1);
    assert_eq!(removed.differences[0].path, "/markerset/R.Heel");
    assert!(matches!(removed.differences[0].change, Change::Removed { .. }));
    let added = diff(&b, &a, 0.0);
    assert!(matches!(added.differences[..], [ref d] if matches!(d.change, Change::Added { .. })));
}

/// Bytes that are not UTF-8 — a Windows-1252 dash in a citation, as in OpenSim's own
/// `subject1_abdbonepin.osim`, and a Latin-1 `é` — do not stop a model OpenSim reads: it reads,
/// writes back byte-identical, and an edit changes only the edited value's bytes.
#[test]
fn stray_non_utf8_bytes_are_kept_byte_for_byte() {
    let original = std::fs::read(common::fixture("models/leg6dof9musc.osim")).unwrap();
    let at = |needle: &str| original.windows(needle.len()).position(|w| w == needle.as_bytes()).unwrap() + needle.len();
    let publications = at("<publications>");
    let mut bytes = original[..publications].to_vec();
    bytes.extend_from_slice(b"Ann Biomed Eng 33:829\x96840, Universit\xe9 ");
    bytes.extend_from_slice(&original[publications..]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("latin1.osim");
    std::fs::write(&file, &bytes).unwrap();
    let mut document = OsimDocument::read(&file).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(document.xml.serialize(), bytes);
    let text = document.xml.text(document.resolve("/publications").unwrap()).unwrap().into_owned();
    assert!(text.starts_with("Ann Biomed Eng 33:829?840, Universit? "), "{text}");
    osim_tune::model::ModelSpec::read(&document).unwrap();
    document.set_property("/forceset/bifemsh_r/tendon_slack_length", "0.2").unwrap();
    let find = |from: usize, needle: &[u8]| from + bytes[from..].windows(needle.len()).position(|w| w == needle).unwrap();
    let value = find(find(0, b"name=\"bifemsh_r\""), b"<tendon_slack_length>") + "<tendon_slack_length>".len();
    let value_end = find(value, b"<");
    let expected = [&bytes[..value], b"0.2", &bytes[value_end..]].concat();
    assert_eq!(document.xml.serialize(), expected);
}

/// A 4.0 model re-saved by OpenSim 4.6 (`oracle/gen_resaved_model.py`: arm26, whose muscles'
/// GeometryPaths OpenSim 4.5's conversion renames `path`) differs from its source only in the
/// version: each document is compared as OpenSim reads it for the other's version. An edit
/// inside a renamed path is then reported at the name OpenSim 4.6 gives it.
#[test]
fn a_model_resaved_by_a_newer_opensim_differs_only_in_its_version() {
    let source = OsimDocument::read(&common::fixture("models/arm26.osim")).unwrap();
    let resaved = OsimDocument::read(&common::fixture("golden/resaved/arm26_opensim46.osim")).unwrap();
    let differences = diff(&source, &resaved, 1e-12);
    assert_eq!((differences.version_change, differences.paths_renamed), (Some((40000, 40600)), 6));
    assert!(differences.differences.is_empty(), "{:#?}", differences.differences);
    let mut edited = resaved.clone();
    edited.set_property("/forceset/TRIlong/path/PathPointSet/TRIlong-P2/location", "-0.027 -0.114 -0.007").unwrap();
    let differences = diff(&source, &edited, 1e-12);
    let paths: Vec<&str> = differences.differences.iter().map(|d| d.path.as_str()).collect();
    assert_eq!(paths, ["/forceset/TRIlong/path/PathPointSet/TRIlong-P2/location"]);
}
