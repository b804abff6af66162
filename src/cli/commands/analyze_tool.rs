//! `osim-tune analyze MODEL --motion COORDINATES --setup SETUP.xml -o DIR`: OpenSim's AnalyzeTool
//! running its `MuscleAnalysis` — the setup's time range, cutoff, step interval, muscle and
//! coordinate lists — writing the path-geometry tables under OpenSim's names
//! (`<name>_MuscleAnalysis_Length.sto`, `…_MomentArm_<coordinate>.sto`).

use std::path::{Path, PathBuf};

use super::analyze_inputs::{lowpass_cutoff, output_name};
use crate::analysis::{analyze_tool_motion, MuscleAnalysis};
use crate::cli::{create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::ModelSpec;
use crate::setup::AnalyzeSetup;

pub fn run(model: &Path, coordinates: &Path, setup_file: &Path, output: &Path) -> Result<Outcome, Failure> {
    let setup = AnalyzeSetup::read(setup_file)?;
    let file = setup_file.display();
    let analysis = setup.muscle_analysis.clone().ok_or_else(|| format!("{file}: the AnalysisSet has no MuscleAnalysis that is on"))?;
    if let Some(states) = &setup.states_or_speeds_file {
        return Err(format!("{file}: states_file/speeds_file {} is not supported; give coordinates_file (COORDINATES)", states.written).into());
    }
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let table = StorageTable::read(coordinates)?;
    let range = [setup.initial_time, setup.final_time];
    let motion = analyze_tool_motion(&geometry.multibody, &table, coordinates, lowpass_cutoff(None, Some(&setup)), range, analysis.step_interval)?;
    let selected = MuscleAnalysis::run(&geometry, &motion)?.setup_tables(&geometry.multibody, &analysis)?;
    let name = output_name(None, Some(&setup), coordinates);
    let files: Vec<(PathBuf, String)> = selected.tables.iter().map(|t| (output.join(format!("{name}_{}_{}.sto", analysis.name, t.name())), t.to_text())).collect();
    let inputs = [model, coordinates, setup_file];
    for (path, _) in &files {
        ensure_not_an_input(path, &inputs)?;
    }
    create_output_folders(files.iter().map(|(path, _)| path.as_path()))?;
    let contents: Vec<(&Path, &[u8])> = files.iter().map(|(path, text)| (path.as_path(), text.as_bytes())).collect();
    write_all_atomically(&contents, &inputs)?;
    let (first, last) = (motion.times[0], motion.times[motion.len() - 1]);
    println!("MuscleAnalysis: {} rows of {} ({first:.4}–{last:.4} s) → {} tables in {}", motion.len(), coordinates.display(), files.len(), output.display());
    let notes = [
        ("muscle_list names no muscle of the model (dropped, as OpenSim drops them)", &selected.unknown_muscles),
        ("moment_arm_coordinate_list names no coordinate of the model (dropped, as OpenSim drops them)", &selected.unknown_coordinates),
        ("coordinates the file lacks, held at 0 as OpenSim's AnalyzeTool holds them", &motion.defaulted),
    ];
    for (what, names) in notes.into_iter().filter(|(_, names)| !names.is_empty()) {
        eprintln!("note: {what}: {}", names.join(", "));
    }
    eprintln!("note: the fiber, tendon, force and power tables need the muscles' states and are not written (`analyze --activation A` solves static equilibria)");
    Ok(Outcome::Success)
}
