//! `cargo xtask validate`: one row per check — what, reference, worst error, tolerance, verdict.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{MarkerTable, StorageTable};
use osim_tune::model::ModelSpec;
use osim_tune::review::diff;

use crate::{files_with, geometry, ik, knee_swap, muscle, root, scale};

/// One line of the conformance table.
pub struct Row {
    pub what: String,
    pub reference: String,
    pub worst: f64,
    pub tolerance: f64,
    /// Where the worst case occurred, when that helps (empty otherwise).
    pub at: String,
}

pub fn run() -> ExitCode {
    let mut rows = Vec::new();
    let documents = [files_with(&root().join("models"), &["osim"]), files_with(&root().join("fixtures"), &["osim", "xml"])].concat();
    rows.push(document_round_trip(&documents));
    rows.push(single_edit_is_single_line(&documents));
    rows.push(respelled_documents_have_no_diff(&documents));
    rows.extend(coordinates_against_opensim());
    rows.extend(GOLDEN_MODELS.iter().flat_map(|(stem, file)| geometry::rows(stem, &root().join(file))));
    rows.extend(geometry::model_golden_rows());
    rows.extend(geometry::assembly_rows());
    rows.extend(geometry::analyze_tool_rows());
    rows.extend(muscle::MUSCLE_MODELS.iter().flat_map(|(stem, file)| muscle::rows(stem, &root().join(file))));
    rows.extend(muscle::thelen_velocity_rows());
    rows.extend(muscle::degroote_rows());
    rows.extend(ik::rows());
    rows.extend(crate::kalman_ik::rows());
    rows.extend(crate::dynamics::rows());
    rows.extend(crate::rra::rows());
    rows.extend(crate::cmc::rows());
    rows.extend(scale::rows());
    rows.extend(crate::knee_axis::rows());
    rows.extend(knee_swap::rows());
    rows.extend(crate::functional::rows());
    rows.extend(crate::functional_generated::rows());
    rows.push(storage_round_trip(&files_with(&root().join("fixtures"), &["sto", "mot"])));
    rows.push(marker_round_trip(&files_with(&root().join("fixtures"), &["trc"])));
    print_table(&rows)
}

fn print_table(rows: &[Row]) -> ExitCode {
    println!("{:<58} {:<40} {:>12} {:>10}  result", "check", "reference", "worst", "tolerance");
    let mut failures = 0;
    for row in rows {
        let pass = row.worst <= row.tolerance;
        failures += usize::from(!pass);
        println!("{:<58} {:<40} {:>12.3e} {:>10.1e}  {}", row.what, row.reference, row.worst, row.tolerance, if pass { "pass" } else { "FAIL" });
        if !row.at.is_empty() {
            println!("    worst at {}", row.at);
        }
    }
    println!("{} passed, {} failed", rows.len() - failures, failures);
    if failures == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}

fn read(path: &Path) -> Option<OsimDocument> {
    OsimDocument::read_object(path).map_err(|e| eprintln!("{e}")).ok()
}

/// Bytes that differ after read → write, summed over all documents (unreadable: counted as ∞).
fn document_round_trip(documents: &[PathBuf]) -> Row {
    let mut worst = 0.0f64;
    for path in documents {
        let original = std::fs::read(path).unwrap_or_default();
        let written = read(path).map(|d| d.xml.serialize());
        worst = worst.max(written.map_or(f64::INFINITY, |w| differing_bytes(&original, &w)));
    }
    Row { what: format!("round trip, byte-identical ({} documents)", documents.len()), reference: "the input file".into(), worst, tolerance: 0.0, at: String::new() }
}

fn differing_bytes(a: &[u8], b: &[u8]) -> f64 {
    (a.iter().zip(b).filter(|(x, y)| x != y).count() + a.len().abs_diff(b.len())) as f64
}

/// For each model, edit the first `optimal_fiber_length`; worst |changed lines − 1|.
fn single_edit_is_single_line(documents: &[PathBuf]) -> Row {
    let mut worst = 0.0f64;
    let models: Vec<_> = documents.iter().filter(|p| p.extension().is_some_and(|e| e == "osim")).collect();
    for path in &models {
        let Some(mut document) = read(path) else { worst = f64::INFINITY; continue };
        let Some(id) = document.xml.ids().find(|&id| document.xml.tag(id) == "optimal_fiber_length") else { continue };
        let property = document.path_of(id);
        let original = String::from_utf8_lossy(&document.xml.serialize()).into_owned();
        if document.set_property(&property, "0.123456").is_err() {
            worst = f64::INFINITY;
            continue;
        }
        let edited = String::from_utf8_lossy(&document.xml.serialize()).into_owned();
        let changed = original.lines().zip(edited.lines()).filter(|(a, b)| a != b).count();
        worst = worst.max((changed as f64 - 1.0).abs() + original.lines().count().abs_diff(edited.lines().count()) as f64);
    }
    Row { what: format!("set one property → one changed line ({} models)", models.len()), reference: "textual line diff".into(), worst, tolerance: 0.0, at: String::new() }
}

/// Every number re-spelled in scientific notation: the semantic diff must be empty.
fn respelled_documents_have_no_diff(documents: &[PathBuf]) -> Row {
    let mut worst = 0.0f64;
    for path in documents {
        let Some(original) = read(path) else { worst = f64::INFINITY; continue };
        let mut respelled = original.clone();
        let leaves: Vec<_> = respelled.xml.ids().filter(|&id| respelled.xml.children(id).is_empty()).collect();
        for id in leaves {
            let Some(value) = respelled.xml.text(id).map(|v| v.into_owned()) else { continue };
            let numbers: Option<Vec<f64>> = value.split_whitespace().map(|t| t.parse().ok()).collect();
            if let Some(numbers) = numbers.filter(|n| !n.is_empty()) {
                let spelled: Vec<String> = numbers.iter().map(|x| format!("{x:e}")).collect();
                let _ = respelled.xml.set_text(id, &format!(" {} ", spelled.join("  ")));
            }
        }
        worst = worst.max(diff(&original, &respelled, 0.0).differences.len() as f64);
    }
    Row { what: format!("diff ignores number spelling ({} documents)", documents.len()), reference: "0 differences".into(), worst, tolerance: 0.0, at: String::new() }
}

/// The models with OpenSim 4.6 geometry goldens: (golden folder name, model file).
const GOLDEN_MODELS: [(&str, &str); 8] = [
    ("gait2392_millard2012muscle", "models/gait2392_millard2012muscle.osim"),
    ("gait2354_simbody", "models/gait2354_simbody.osim"),
    ("subject01_simbody", "fixtures/subject01/OutputReference/subject01_simbody.osim"),
    ("leg6dof9musc", "fixtures/models/leg6dof9musc.osim"),
    ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
    ("arm26", "fixtures/models/arm26.osim"),
    ("joint_zoo", "fixtures/models/joint_zoo.osim"),
    ("wrap_zoo", "fixtures/models/wrap_zoo.osim"),
];

/// Coordinate ranges, defaults, motion types and flags against OpenSim 4.6's report.
fn coordinates_against_opensim() -> Vec<Row> {
    GOLDEN_MODELS.iter().map(|(stem, file)| coordinate_row(stem, file)).collect()
}

fn coordinate_row(stem: &str, file: &str) -> Row {
    let golden = std::fs::read_to_string(root().join(format!("fixtures/golden/geometry/{stem}/coordinates.csv"))).unwrap_or_default();
    let spec = read(&root().join(file)).and_then(|d| ModelSpec::read(&d).map_err(|e| eprintln!("{e}")).ok());
    let mut worst = if spec.is_none() || golden.is_empty() { f64::INFINITY } else { 0.0 };
    if let Some(spec) = spec {
        for row in golden.lines().skip(1).map(|l| l.split(',').collect::<Vec<_>>()) {
            let Some(c) = spec.coordinates().find(|c| c.name == row[0]) else { worst = f64::INFINITY; continue };
            let number = |i: usize| row[i].parse::<f64>().unwrap_or(f64::NAN);
            let motion = format!("{:?}", c.motion_type).to_lowercase();
            let flags_match = motion == row[2] && (c.locked, c.clamped) == (row[7] == "1", row[8] == "1");
            let error = [c.range[0] - number(4), c.range[1] - number(5), c.default_value - number(6)].iter().fold(0.0f64, |m, e| m.max(e.abs()));
            worst = worst.max(if flags_match { error } else { f64::INFINITY });
        }
    }
    Row { what: format!("coordinates, {stem}"), reference: "OpenSim 4.6 coordinates.csv".into(), worst, tolerance: 0.0, at: String::new() }
}

/// Largest |value − value after write → read| over all storage files (∞ on a parse failure).
fn storage_round_trip(files: &[PathBuf]) -> Row {
    let mut worst = 0.0f64;
    for path in files {
        let again = StorageTable::read(path).and_then(|t| StorageTable::parse(&t.to_text(), path).map(|u| (t, u)));
        worst = worst.max(match again {
            Ok((t, u)) if t.labels() == u.labels() => largest_difference(t.values(), u.values()),
            _ => f64::INFINITY,
        });
    }
    Row { what: format!("table round trip .sto/.mot ({} files)", files.len()), reference: "the input values".into(), worst, tolerance: 0.0, at: String::new() }
}

fn marker_round_trip(files: &[PathBuf]) -> Row {
    let mut worst = 0.0f64;
    for path in files {
        let again = MarkerTable::read(path).and_then(|t| MarkerTable::parse(&t.to_text(), path).map(|u| (t, u)));
        worst = worst.max(match again {
            Ok((t, u)) if t.marker_names() == u.marker_names() && t.positions().len() == u.positions().len() => {
                let flat = |m: &MarkerTable| m.positions().iter().flat_map(|p| p.unwrap_or([f64::NAN; 3])).collect::<Vec<_>>();
                largest_difference(&flat(&t), &flat(&u)).max(largest_difference(t.times(), u.times()))
            }
            _ => f64::INFINITY,
        });
    }
    Row { what: format!("table round trip .trc ({} files)", files.len()), reference: "the input values".into(), worst, tolerance: 0.0, at: String::new() }
}

/// max |a − b|, with NaN equal to NaN and NaN against a number infinite.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| {
        let d = if x.is_nan() && y.is_nan() { 0.0 } else if x.is_nan() || y.is_nan() { f64::INFINITY } else { (x - y).abs() };
        m.max(d)
    })
}
