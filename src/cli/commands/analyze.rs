//! `osim-tune analyze MODEL --motion MOTION -o DIR`

use std::path::Path;

use crate::analysis::MuscleAnalysis;
use crate::cli::{Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::{Motion, MotionError, MuscleGeometry};
use crate::model::ModelSpec;

pub fn run(model: &Path, motion: &Path, output: &Path, skip_unknown_columns: bool) -> Result<Outcome, Failure> {
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let motion_table = StorageTable::read(motion)?;
    let trajectory = Motion::from_table(&motion_table, motion, &geometry.multibody, skip_unknown_columns).map_err(|e| match e {
        MotionError::UnknownCoordinate { .. } => format!("{e}; pass --skip-unknown-columns to skip such columns (marker or force data)").into(),
        other => Failure::from(other),
    })?;
    let analysis = MuscleAnalysis::run(&geometry, &trajectory)?;
    let mut files = vec![("Length.sto".to_string(), &analysis.lengths), ("MarkerLocations.sto".to_string(), &analysis.marker_locations)];
    files.extend(analysis.moment_arms.iter().map(|(coordinate, table)| (format!("MomentArm_{coordinate}.sto"), table)));
    let inputs = [model, motion];
    for (name, _) in &files {
        ensure_not_an_input(&output.join(name), &inputs)?;
    }
    std::fs::create_dir_all(output).map_err(|e| format!("{}: cannot create the output folder: {e}", output.display()))?;
    for (name, table) in &files {
        write_atomically(&output.join(name), table.to_text().as_bytes(), &inputs)?;
    }
    report(&trajectory, &analysis, motion, output, files.len());
    Ok(Outcome::Success)
}

fn report(motion: &Motion, analysis: &MuscleAnalysis, motion_file: &Path, output: &Path, files: usize) {
    println!("{} rows of {} → {files} tables in {}", motion.len(), motion_file.display(), output.display());
    if !motion.defaulted.is_empty() {
        eprintln!("note: coordinates not in the motion stay at their default (coupler dependents follow their coupler): {}", motion.defaulted.join(", "));
    }
    if !motion.ignored_columns.is_empty() {
        eprintln!("note: skipped {} columns that are not coordinate values: {}", motion.ignored_columns.len(), abbreviated(&motion.ignored_columns));
    }
    if !analysis.ignored_wraps.is_empty() {
        eprintln!("warning: wrapping is not applied yet; lengths and moment arms of these muscles ignore their wrap objects:");
        for (muscle, wraps) in &analysis.ignored_wraps {
            eprintln!("  {muscle}: {}", wraps.join(", "));
        }
    }
}

/// The first few names, then how many more.
fn abbreviated(names: &[String]) -> String {
    let shown = names.iter().take(6).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 6 { format!("{shown}, … ({} more)", names.len() - 6) } else { shown }
}
