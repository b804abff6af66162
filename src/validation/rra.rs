//! OpenSim 4.6's RRATool on subject01's walk (`fixtures/golden/rra/<case>`, `oracle/gen_rra.py`)
//! against ours: the mass-center adjustment (the adjusted body's mass center in the model OpenSim
//! wrote, its report's printed numbers), the controls' `ControlSet` (names, bounds, every node)
//! and every table OpenSim wrote, row by row at the times we record — the CMC windows' ends; OpenSim also records its integrator's internal steps when
//! it takes more than one per window, rows we do not have.

use std::path::Path;

use super::geometry::Worst;
use super::tool_case::{case_folder, file_differences};
use crate::analysis::{run_rra, RraOutputs};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::setup::{ControlSet, RraSetup};

/// The golden cases: the walk at 0.75–0.80 s as opensim-core's RRA example runs it (its control
/// constraints, integrator tolerance 1e-4), and 0.62–0.70 s filtered at 6 Hz with the mass center
/// adjusted over 0.5–1.5 s, the actuators' own bounds, tolerance 1e-5.
pub const RRA_CASES: [&str; 2] = ["walk", "filtered"];

/// The files the golden setups name, with where the repository keeps them.
pub const RRA_INPUTS: [(&str, &str); 7] = [
    ("subject01_simbody.osim", "fixtures/golden/scale/subject01_simbody.osim"),
    ("subject01_walk1_ik.mot", "fixtures/golden/ik/subject01_walk1_ik.mot"),
    ("subject01_walk1_grf.xml", "fixtures/subject01/subject01_walk1_grf.xml"),
    ("subject01_walk1_grf.mot", "fixtures/subject01/subject01_walk1_grf.mot"),
    ("gait2354_RRA_Actuators.xml", "fixtures/subject01/gait2354_RRA_Actuators.xml"),
    ("gait2354_RRA_Tasks.xml", "fixtures/subject01/gait2354_RRA_Tasks.xml"),
    ("gait2354_RRA_ControlConstraints.xml", "fixtures/subject01/gait2354_RRA_ControlConstraints.xml"),
];

/// The adjusted mass center's bound, m: the same closed-form move from the same averages of the
/// same inverse dynamics.
pub const RRA_MASS_CENTER_TOLERANCE: f64 = 1e-12;
/// The report's bound, relative: OpenSim prints 6 significant digits.
pub const RRA_REPORT_TOLERANCE: f64 = 1e-5;

/// `case`'s bounds on the tracked motion at the windows' ends: table values relative to their
/// row's largest, and position errors (rad or m). The tracking is the same algorithm with two
/// solver tolerances between us: OpenSim's optimizer (IPOPT, or its least squares when no bound
/// is active; ours is exact) and its integrator, which takes one Runge–Kutta–Merson step per
/// window at tolerance 1e-4 (`walk`) but adds steps of its own size control at 1e-5
/// (`filtered`, where we halve the window instead).
pub fn rra_tolerances(case: &str) -> (f64, f64) {
    if case == "walk" { (1e-6, 5e-8) } else { (1e-4, 5e-6) }
}

/// What a case's comparison found.
#[derive(Debug, Clone, Default)]
pub struct RraComparison {
    /// The adjusted body's mass center against the model OpenSim wrote, m.
    pub mass_center: f64,
    /// The report's numbers (mass-center move, masses, average residuals before, after and at
    /// the end), relative to their magnitude (at least 1): OpenSim prints 6 digits.
    pub report: Worst,
    /// Every table value but the position errors, relative to its row's largest magnitude.
    pub tables: Worst,
    /// The tasks' position errors (`_pErr.sto`), rad or m.
    pub position_errors: Worst,
    /// OpenSim's rows at the windows' ends that we lack, and rows we have that OpenSim lacks.
    pub missing_rows: usize,
    pub extra_rows: usize,
    /// Files OpenSim writes that we do not, and the other way round.
    pub missing_files: Vec<String>,
    pub extra_files: Vec<String>,
}

/// Runs `case`'s setup (its inputs copied beside it into a temporary folder) and compares.
pub fn compare_rra_case(root: &Path, case: &str) -> Result<(RraComparison, RraOutputs), String> {
    let golden = root.join("fixtures/golden/rra").join(case);
    let outputs = run_rra_case(root, case, None)?;
    let mut comparison = RraComparison::default();
    compare_files(&golden, &outputs, &mut comparison)?;
    compare_summary(&golden, &outputs, &mut comparison)?;
    Ok((comparison, outputs))
}

/// Runs `case`'s setup (its inputs copied beside it into a temporary folder), over `time_range`
/// (s) instead of the setup's when given.
pub fn run_rra_case(root: &Path, case: &str, time_range: Option<[f64; 2]>) -> Result<RraOutputs, String> {
    let (_folder, setup_file) = case_folder(root, &root.join("fixtures/golden/rra").join(case), &RRA_INPUTS)?;
    let mut setup = RraSetup::read(&setup_file).map_err(|e| e.to_string())?;
    if let Some([start, end]) = time_range {
        (setup.tracking.tool.initial_time, setup.tracking.tool.final_time) = (start, end);
    }
    let model = setup.tracking.tool.model_file.as_ref().ok_or("the golden setup names no model")?.resolved.clone();
    run_rra(&model, &setup).map_err(|e| e.to_string())
}

/// The files' names and every golden table's rows at the times both have.
fn compare_files(golden: &Path, outputs: &RraOutputs, comparison: &mut RraComparison) -> Result<(), String> {
    let mut ours: Vec<String> = outputs.files.iter().map(|(name, _)| name.clone()).collect();
    ours.extend(outputs.adjusted_model.iter().filter_map(|(path, _)| path.file_name()).map(|n| n.to_string_lossy().into_owned()));
    (comparison.missing_files, comparison.extra_files) = file_differences(golden, &ours)?;
    for (name, text) in outputs.files.iter().filter(|(name, _)| name.ends_with("_controls.xml")) {
        compare_control_sets(&golden.join(name), text, comparison)?;
    }
    for (name, text) in outputs.files.iter().filter(|(name, _)| name.ends_with(".sto")) {
        let opensim = StorageTable::read(&golden.join(name)).map_err(|e| e.to_string())?;
        let table = StorageTable::parse(text, Path::new(name)).map_err(|e| e.to_string())?;
        if opensim.labels() != table.labels() {
            return Err(format!("{name}: OpenSim's columns {:?}, ours {:?}", opensim.labels(), table.labels()));
        }
        compare_rows(name, &opensim, &table, comparison);
    }
    Ok(())
}

/// Our `ControlSet` document (`text`) against OpenSim's (`file`): the same controls, bounds and
/// node times (1e-12 s), each node's values among the tables' (relative to the node's largest).
fn compare_control_sets(file: &Path, text: &str, comparison: &mut RraComparison) -> Result<(), String> {
    let opensim = ControlSet::read(file).map_err(|e| e.to_string())?;
    let document = OsimDocument::parse(text.to_string(), Path::new("controls.xml")).map_err(|e| e.to_string())?;
    let ours = ControlSet::from_document(&document).map_err(|e| e.to_string())?;
    let names = |set: &ControlSet| set.controls.iter().map(|c| (c.name.clone(), c.bounds.default_min, c.bounds.default_max, c.nodes.len())).collect::<Vec<_>>();
    if names(&opensim) != names(&ours) {
        return Err(format!("{}: OpenSim's controls (name, bounds, nodes) {:?}, ours {:?}", file.display(), names(&opensim), names(&ours)));
    }
    for k in 0..opensim.controls.first().map_or(0, |c| c.nodes.len()) {
        let scale = opensim.controls.iter().fold(0.0f64, |m, c| m.max(c.nodes[k].1.abs())).max(f64::MIN_POSITIVE);
        for (theirs, mine) in opensim.controls.iter().zip(&ours.controls) {
            let ((t1, v1), (t2, v2)) = (theirs.nodes[k], mine.nodes[k]);
            let at = || format!("controls.xml node {k} of {}", mine.name);
            comparison.tables.update(if (t1 - t2).abs() > 1e-12 { f64::INFINITY } else { (v1 - v2).abs() / scale }, at);
        }
    }
    Ok(())
}

/// Each of our rows against OpenSim's at the same time.
fn compare_rows(name: &str, opensim: &StorageTable, ours: &StorageTable, comparison: &mut RraComparison) {
    let theirs: Vec<&[f64]> = opensim.rows().collect();
    let mut matched = 0;
    for row in ours.rows() {
        let Some(other) = theirs.iter().find(|r| (r[0] - row[0]).abs() < 1e-9) else {
            comparison.extra_rows += 1;
            continue;
        };
        matched += 1;
        let scale = other[1..].iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
        for j in 1..row.len() {
            let at = || format!("{name} at {} s, {}", row[0], ours.labels()[j]);
            if name.ends_with("_pErr.sto") {
                comparison.position_errors.update((row[j] - other[j]).abs(), at);
            } else {
                comparison.tables.update((row[j] - other[j]).abs() / scale, at);
            }
        }
    }
    let first = ours.rows().next().map_or(0.0, |r| r[0]);
    let at_windows = theirs.iter().filter(|r| ((r[0] - first) / 0.001 - ((r[0] - first) / 0.001).round()).abs() < 1e-6).count();
    comparison.missing_rows += at_windows.saturating_sub(matched);
}

/// The adjusted mass center and the report's numbers against `summary.json`.
fn compare_summary(golden: &Path, outputs: &RraOutputs, comparison: &mut RraComparison) -> Result<(), String> {
    let text = std::fs::read_to_string(golden.join("summary.json")).map_err(|e| e.to_string())?;
    let summary: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let adjusted = outputs.adjustment.as_ref().ok_or("the golden case adjusts a mass center; ours did not")?;
    let expected: Vec<f64> = summary["mass_center"].as_array().ok_or("summary.json: no mass_center")?.iter().filter_map(|v| v.as_f64()).collect();
    comparison.mass_center = expected.iter().zip(&adjusted.adjustment.mass_center[1]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let report: Vec<&str> = summary["report"].as_array().ok_or("summary.json: no report")?.iter().filter_map(|v| v.as_str()).collect();
    let a = &adjusted.adjustment;
    let mut printed: Vec<(String, f64)> = vec![("dx".into(), a.dx), ("dz".into(), a.dz), ("Total mass change".into(), a.total_mass_change)];
    printed.extend(a.masses.iter().map(|(body, _, new)| (format!("{body}: orig mass"), *new)));
    let lines = residual_lines(&report);
    for (k, residuals) in [adjusted.before, adjusted.after, outputs.final_residuals].iter().enumerate() {
        for (name, value) in crate::analysis::RESIDUALS.iter().zip(residuals) {
            let opensim = lines.get(k).and_then(|line| number_after(line, &format!("{name}="))).ok_or(format!("summary.json: no {name} in residual report {k}"))?;
            comparison.report.update((opensim - value).abs() / value.abs().max(1.0), || format!("residuals {k} {name}"));
        }
    }
    for (label, value) in printed {
        let line = report.iter().find(|l| l.contains(&label)).ok_or(format!("summary.json: no {label}"))?;
        let key = if label.ends_with("orig mass") { "new mass = ".to_string() } else if label == "Total mass change" { "Total mass change: ".into() } else { format!("{label} =") };
        let opensim = number_after(line, &key).ok_or(format!("summary.json: {line}: no number after {key}"))?;
        comparison.report.update((opensim - value).abs() / value.abs().max(1.0), || label.clone());
    }
    Ok(())
}

/// The report's residual lines, force then moment line joined: before, after, final.
fn residual_lines(report: &[&str]) -> Vec<String> {
    let lines: Vec<&&str> = report.iter().filter(|l| l.contains("FX=") || l.contains("MX=")).collect();
    lines.chunks(2).map(|pair| pair.iter().map(|l| l.to_string()).collect::<Vec<_>>().join(" ")).collect()
}

/// The number that follows `key` in `line`.
fn number_after(line: &str, key: &str) -> Option<f64> {
    let rest = &line[line.find(key)? + key.len()..];
    let end = rest.find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c))).unwrap_or(rest.len());
    rest[..end].parse().ok()
}
