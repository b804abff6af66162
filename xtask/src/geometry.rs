//! Geometry rows of the validation table: body poses, markers, path lengths and moment arms
//! against OpenSim 4.6, over the full golden sweep when `../shared/reference` (or
//! `$OSIM_TUNE_REFERENCE`) is present, else over the slice in `fixtures/golden/`; and the JSON
//! goldens of ellipsoid joints, station frames and a converted 3.x model.

use std::path::{Path, PathBuf};

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::MuscleGeometry;
use osim_tune::model::ModelSpec;
use osim_tune::validation::{case_tolerance, compare_assembly, compare_geometry, compare_model_golden, compare_analyze_tool_setup, Worst, ANALYZE_TOOL_CASES, OFF_BOUND_TOLERANCE};

use crate::root;
use crate::validate::Row;

/// The golden folder for `stem` and how to name it in the table.
fn golden_folder(stem: &str) -> (PathBuf, String) {
    let reference = std::env::var_os("OSIM_TUNE_REFERENCE").map(PathBuf::from).unwrap_or_else(|| root().join("../shared/reference"));
    let full = reference.join("geometry").join(stem);
    if full.join("poses.csv").exists() {
        (full, "OpenSim 4.6, all poses".into())
    } else {
        (root().join("fixtures/golden/geometry").join(stem), "OpenSim 4.6, fixture slice".into())
    }
}

pub fn rows(stem: &str, model: &Path) -> Vec<Row> {
    let (folder, reference) = golden_folder(stem);
    let failed = |what: &str, error: String| {
        eprintln!("{stem}: {error}");
        vec![Row { what: format!("{what}, {stem}"), reference: reference.clone(), worst: f64::INFINITY, tolerance: 0.0, at: String::new() }]
    };
    let spec = match OsimDocument::read(model).map_err(|e| e.to_string()).and_then(|d| ModelSpec::read(&d).map_err(|e| e.to_string())) {
        Ok(spec) => spec,
        Err(e) => return failed("model", e),
    };
    let geometry = match MuscleGeometry::new(&spec) {
        Ok(geometry) => geometry,
        Err(e) => return failed("mechanics", e.to_string()),
    };
    let comparison = match compare_geometry(&geometry, &folder) {
        Ok(comparison) => comparison,
        Err(e) => return failed("geometry", e.to_string()),
    };
    for mismatch in &comparison.span_mismatches {
        eprintln!("{stem}: {mismatch}");
    }
    let skipped = if comparison.skipped.is_empty() { String::new() } else { format!(", {} muscles wrapping over objects not computed skipped", comparison.skipped.len()) };
    // `of_muscles`: the row compares muscle values, so skipped muscles are mentioned.
    let row = |what: &str, worst: &Worst, tolerance: f64, of_muscles: bool| {
        (worst.count > 0).then(|| Row {
            what: format!("{what}, {stem} ({} values{})", worst.count, if of_muscles { skipped.as_str() } else { "" }),
            reference: reference.clone(),
            worst: worst.error,
            tolerance,
            at: worst.at.clone(),
        })
    };
    let mut rows: Vec<Row> = [
        row("body positions (m)", &comparison.body_positions, 1e-9, false),
        row("body rotations", &comparison.body_rotations, 1e-9, false),
        row("marker positions (m)", &comparison.markers, 1e-9, false),
        row("path lengths (m)", &comparison.lengths, 1e-9, true),
        row("moment arms (m)", &comparison.moment_arms, 1e-8, true),
    ]
    .into_iter()
    .flatten()
    .collect();
    rows.push(Row {
        what: format!("muscle × coordinate pairs spanned, {stem}"),
        reference: reference.clone(),
        worst: comparison.span_mismatches.len() as f64,
        tolerance: 0.0,
        at: comparison.span_mismatches.first().cloned().unwrap_or_default(),
    });
    rows
}

/// The default pose `initSystem` assembles: the linked mechanisms (constraints between bodies
/// broken by the default values; with their muscles' lengths and moment arms through the
/// constraints at four poses), leg6dof9musc (a coupler's dependent off its default) and
/// opensim-core's ThoracoscapularShoulderModel (moment arms through its PointConstraint).
pub fn assembly_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for (model, golden) in [("linked_mechanisms.osim", "constraint_assembly.json"), ("leg6dof9musc.osim", "constraint_assembly.json"), ("ThoracoscapularShoulderModel.osim", "shoulder_moment_arms.json")] {
        let reference = format!("OpenSim 4.6 initSystem, golden/{golden}");
        match compare_assembly(&root(), model, golden) {
            Ok(c) => {
                for (what, worst) in [("coordinates (rad or m)", &c.coordinates), ("markers (m)", &c.markers)] {
                    rows.push(Row { what: format!("{model} assembled default pose: {what}"), reference: reference.clone(), worst: worst.error, tolerance: 1e-9, at: worst.at.clone() });
                }
                for (what, worst, tolerance) in [("muscle lengths (m)", &c.lengths, 1e-12), ("moment arms through the constraints (m)", &c.moment_arms, 1e-9)] {
                    if worst.count > 0 {
                        let at = format!("{} ({} ill-defined not compared)", worst.at, c.ill_defined);
                        rows.push(Row { what: format!("{model}: {what}, {} values", worst.count), reference: reference.clone(), worst: worst.error, tolerance, at });
                    }
                }
            }
            Err(error) => rows.push(Row { what: format!("{model} assembled default pose"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error.to_string() }),
        }
    }
    rows
}

/// OpenSim 4.6's AnalyzeTool setups on subject01's walk (`golden/analyze_tool/`): the same files
/// (all but the accelerations), their values (absolute up to 1000, relative beyond).
pub fn analyze_tool_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for case in ANALYZE_TOOL_CASES {
        let reference = format!("OpenSim 4.6 AnalyzeTool, golden/analyze_tool/{case}");
        let what = format!("AnalyzeTool setup '{case}': every table formed");
        match compare_analyze_tool_setup(&root(), case) {
            Ok(c) if c.missing.is_empty() && c.extra.is_empty() => {
                rows.push(Row { what: format!("{what}, {} tables, {} values", c.tables, c.values.count), reference: reference.clone(), worst: c.values.error, tolerance: case_tolerance(case), at: c.values.at });
                if c.off_bound.count > 0 {
                    let what = format!("AnalyzeTool setup '{case}': {} values where OpenSim's assembly stops short of a clamped bound", c.off_bound.count);
                    rows.push(Row { what, reference, worst: c.off_bound.error, tolerance: OFF_BOUND_TOLERANCE, at: c.off_bound.at });
                }
            }
            Ok(c) => rows.push(Row { what, reference, worst: f64::INFINITY, tolerance: 0.0, at: format!("files OpenSim wrote and we did not: {:?}; ours it did not write: {:?}", c.missing, c.extra) }),
            Err(error) => rows.push(Row { what, reference, worst: f64::INFINITY, tolerance: 0.0, at: error }),
        }
    }
    rows
}

/// Models whose features OpenSim computes in its own way (`fixtures/golden/*.json`): joints that
/// glide on ellipsoids, station-defined frames, a 3.x model as OpenSim 4 converts it.
pub fn model_golden_rows() -> Vec<Row> {
    let cases = [
        ("ellipsoid joints", "models/ellipsoid_joints.osim", "golden/ellipsoid_joints.json"),
        ("station frames", "models/station_frames.osim", "golden/station_frames.json"),
        ("3.x conversion", "legacy/pendulum_leg_v30000_digits.osim", "golden/legacy_conversion.json"),
    ];
    let mut rows = Vec::new();
    for (label, model, golden) in cases {
        let reference = format!("OpenSim 4.6, {golden}");
        let comparison = match compare_model_golden(&root(), model, golden) {
            Ok(comparison) => comparison,
            Err(error) => {
                rows.push(Row { what: format!("{label}: model"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error.to_string() });
                continue;
            }
        };
        let quantities = [
            ("frames in their bodies", &comparison.frames, 1e-15),
            ("marker positions (m)", &comparison.markers, 1e-14),
            ("path lengths (m)", &comparison.lengths, 1e-14),
            ("moment arms (m)", &comparison.moment_arms, 1e-12),
            ("inverse dynamics (N·m)", &comparison.generalized_forces, 1e-11),
        ];
        for (what, worst, tolerance) in quantities.into_iter().filter(|(_, worst, _)| worst.count > 0) {
            rows.push(Row { what: format!("{label}: {what} ({} values)", worst.count), reference: reference.clone(), worst: worst.error, tolerance, at: worst.at.clone() });
        }
    }
    rows
}
