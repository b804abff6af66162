//! `osim-tune analyze MODEL --motion COORDINATES --setup SETUP.xml -o DIR`: OpenSim's AnalyzeTool
//! running its `MuscleAnalysis`, `Kinematics`, `BodyKinematics`, `PointKinematics`,
//! `ForceReporter`, `Actuation`, `StatesReporter`, `ProbeReporter` and `InducedAccelerations` — the setup's time range, cutoff, muscle
//! equilibrium, and each analysis's step interval and lists — writing their tables under
//! OpenSim's names (`<name>_<analysis name>_Length.sto`, `…_q.sto`, `…_forces.sto`, …).

use std::path::{Path, PathBuf};

use super::analyze_inputs::{actuator_files, analyze_tool_analyses, check_analyses, controllers_of, external_loads_of, output_name};
use crate::analysis::{analyze_tool_tables, AnalyzeModel};
use crate::cli::{warn_about, write_files, Failure, Outcome};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::ModelSpec;
use crate::setup::AnalyzeSetup;

pub fn run(model: &Path, coordinates: &Path, setup_file: &Path, output: &Path) -> Result<Outcome, Failure> {
    let setup = AnalyzeSetup::read(setup_file)?;
    check_analyses(&setup, &analyze_tool_analyses(&setup))?;
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let mut read: Vec<PathBuf> = [model, coordinates, setup_file].map(Path::to_path_buf).to_vec();
    let (added, replace) = actuator_files(&[], Some(&setup), &mut read)?;
    let external = external_loads_of(None, Some(&setup), &geometry.multibody, &mut read)?;
    let name = output_name(None, Some(&setup), coordinates);
    let controls = controllers_of(&spec, &setup, &added, replace, &mut read)?;
    let analysed = AnalyzeModel { spec: &spec, geometry: &geometry, added: &added, replace, external: external.as_ref(), controls: &controls };
    let tables = analyze_tool_tables(&analysed, &StorageTable::read(coordinates)?, coordinates, &setup, &name)?;
    let files: Vec<(PathBuf, String)> = tables.files.iter().map(|(file, table)| (output.join(file), table.to_text())).collect();
    write_files(&files, &read)?;
    let (rows, first, last) = tables.rows;
    println!("AnalyzeTool: {rows} rows of {} ({first:.4}–{last:.4} s) → {} tables in {}", coordinates.display(), files.len(), output.display());
    let lists = [
        ("coordinates the file lacks, held as OpenSim's AnalyzeTool holds them (at 0; from a states file at their default values)", &tables.missing_coordinates),
        ("muscle_list names no muscle of the model (dropped, as OpenSim drops them)", &tables.unknown_muscles),
        ("moment_arm_coordinate_list names no coordinate of the model (dropped, as OpenSim drops them)", &tables.unknown_coordinates),
    ];
    for (what, names) in lists.into_iter().filter(|(_, names)| !names.is_empty()) {
        eprintln!("note: {what}: {}", names.join(", "));
    }
    for table in &tables.not_written {
        eprintln!("note: not written: {table}");
    }
    for note in &tables.notes {
        eprintln!("note: {note}");
    }
    warn_about(&tables.warnings);
    Ok(Outcome::Success)
}
