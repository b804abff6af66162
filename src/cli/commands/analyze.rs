//! `osim-tune analyze MODEL --motion MOTION -o DIR [--activation A | --activations FILE]`: each
//! row assembled as OpenSim's `AnalyzeTool` assembles it, then the muscle (and fiber) analyses.

use std::path::{Path, PathBuf};

use crate::analysis::{hill_muscles, Activations, FiberAnalysis, MuscleAnalysis};
use crate::cli::{Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::{Motion, MotionError, MuscleGeometry};
use crate::model::ModelSpec;
use crate::solvers::assemble;

/// Where fiber-equilibrium activations come from.
pub enum FiberInput {
    Uniform(f64),
    File(PathBuf),
}

pub fn run(
    model: &Path,
    motion: &Path,
    output: &Path,
    skip_unknown_columns: bool,
    fibers: Option<FiberInput>,
) -> Result<Outcome, Failure> {
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let motion_table = StorageTable::read(motion)?;
    let mut trajectory = Motion::from_table(
        &motion_table,
        motion,
        &geometry.multibody,
        skip_unknown_columns,
    )
    .map_err(|e| match e {
        MotionError::UnknownCoordinate { .. } => {
            format!("{e}; pass --skip-unknown-columns to skip such columns (marker or force data)")
                .into()
        }
        other => Failure::from(other),
    })?;
    trajectory.assemble_poses(|q| assemble(&geometry.multibody, q))?;
    let analysis = MuscleAnalysis::run(&geometry, &trajectory)?;
    let mut files = vec![
        ("Length.sto".to_string(), &analysis.lengths),
        (
            "MarkerLocations.sto".to_string(),
            &analysis.marker_locations,
        ),
    ];
    files.extend(
        analysis
            .moment_arms
            .iter()
            .map(|(coordinate, table)| (format!("MomentArm_{coordinate}.sto"), table)),
    );
    let mut inputs = vec![model.to_path_buf(), motion.to_path_buf()];
    let fiber_analysis = match fibers {
        Some(input) => Some(fiber_analysis(
            &spec,
            &geometry,
            &trajectory,
            input,
            &mut inputs,
        )?),
        None => None,
    };
    if let Some((fibers, _)) = &fiber_analysis {
        files.extend(
            fibers
                .tables
                .iter()
                .map(|t| (format!("{}.sto", t.name()), t)),
        );
        files.extend(
            fibers
                .moments
                .iter()
                .map(|(coordinate, table)| (format!("Moment_{coordinate}.sto"), table)),
        );
    }
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    for (name, _) in &files {
        ensure_not_an_input(&output.join(name), &inputs)?;
    }
    std::fs::create_dir_all(output)
        .map_err(|e| format!("{}: cannot create the output folder: {e}", output.display()))?;
    for (name, table) in &files {
        write_atomically(&output.join(name), table.to_text().as_bytes(), &inputs)?;
    }
    report(&trajectory, &analysis, motion, output, files.len());
    if let Some((fibers, skipped)) = &fiber_analysis {
        report_fibers(fibers, skipped);
    }
    Ok(Outcome::Success)
}

/// Static equilibrium of every supported muscle along the motion.
fn fiber_analysis(
    spec: &ModelSpec,
    geometry: &MuscleGeometry,
    motion: &Motion,
    input: FiberInput,
    inputs: &mut Vec<PathBuf>,
) -> Result<(FiberAnalysis, Vec<String>), Failure> {
    if let FiberInput::Uniform(a) = input {
        if !(0.0..=1.0).contains(&a) {
            return Err(format!("--activation {a}: expected a number in [0, 1]").into());
        }
    }
    // Muscle errors name the muscle and property; the model file completes the address.
    let in_model = |e: &dyn std::fmt::Display| format!("{}: {e}", spec.file.display());
    let (muscles, skipped) = hill_muscles(spec, geometry).map_err(|e| in_model(&e))?;
    let names: Vec<String> = muscles
        .iter()
        .map(|(p, _)| geometry.paths[*p].name.clone())
        .collect();
    let activations = match input {
        FiberInput::Uniform(a) => Activations::Uniform(a),
        FiberInput::File(file) => {
            let table = StorageTable::read(&file)?;
            inputs.push(file.clone());
            Activations::from_table(&table, &file, &names, "activation")?
        }
    };
    let fibers = FiberAnalysis::run(geometry, &muscles, motion, &activations).map_err(|e| in_model(&e))?;
    Ok((fibers, skipped))
}

fn report(
    motion: &Motion,
    analysis: &MuscleAnalysis,
    motion_file: &Path,
    output: &Path,
    files: usize,
) {
    println!(
        "{} rows of {} → {files} tables in {}",
        motion.len(),
        motion_file.display(),
        output.display()
    );
    if !motion.defaulted.is_empty() {
        eprintln!("note: coordinates not in the motion stay at their default (coupler dependents follow their coupler): {}", motion.defaulted.join(", "));
    }
    if !motion.ignored_columns.is_empty() {
        eprintln!(
            "note: skipped {} columns that are not coordinate values: {}",
            motion.ignored_columns.len(),
            abbreviated(&motion.ignored_columns)
        );
    }
    if !analysis.ignored_wraps.is_empty() {
        eprintln!("warning: wrap objects of classes OpenSim 4.6 does not have are not applied; lengths and moment arms of these muscles ignore their wrap objects:");
        for (muscle, wraps) in &analysis.ignored_wraps {
            eprintln!("  {muscle}: {}", wraps.join(", "));
        }
    }
}

fn report_fibers(fibers: &FiberAnalysis, skipped: &[String]) {
    if !skipped.is_empty() {
        eprintln!(
            "note: no fiber equilibrium for paths of other classes: {}",
            abbreviated(skipped)
        );
    }
    if !fibers.clamped.is_empty() {
        let clamped: Vec<String> = fibers
            .clamped
            .iter()
            .map(|(m, n)| format!("{m} ({n} rows)"))
            .collect();
        eprintln!(
            "note: fiber held at its minimum length, no fiber force (slack or overstretched path) in some rows: {}",
            abbreviated(&clamped)
        );
    }
}

/// The first few names, then how many more.
fn abbreviated(names: &[String]) -> String {
    let shown = names.iter().take(6).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 6 {
        format!("{shown}, … ({} more)", names.len() - 6)
    } else {
        shown
    }
}
