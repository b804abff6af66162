//! `osim-tune reaction MODEL COORDINATES [--forces F.sto] [--setup SETUP.xml] [--external-loads LOADS.xml] [--actuators F.xml,…] [--time START END] [--lowpass HZ] [--step-interval N] [--joints J,…] [--on child|parent,…] [--in FRAME,…] [--name NAME] -o DIR`

use std::path::{Path, PathBuf};

use super::analyze_inputs::{check_analyses, lowpass_cutoff, output_name, step_interval, time_range, AnalyzeInputs};
use crate::analysis::{joint_reactions, reaction_reports, ActuatorForces, JointReactionSettings, ReactionProblem};
use crate::cli::{create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::table::StorageTable;
use crate::setup::{AnalyzeSetup, JointReactionSetup};

/// What the command line asks for besides the model and the coordinates.
pub struct Request {
    pub forces: Option<PathBuf>,
    pub setup: Option<PathBuf>,
    pub external_loads: Option<PathBuf>,
    pub actuators: Vec<PathBuf>,
    pub time: Option<[f64; 2]>,
    pub lowpass: Option<f64>,
    pub step_interval: Option<usize>,
    /// The input is a states file (else a coordinates file, unless the setup names a states_file).
    pub states: bool,
    pub joints: Vec<String>,
    pub on: Vec<String>,
    pub frames: Vec<String>,
    pub name: Option<String>,
    pub output: PathBuf,
}

pub fn run(model: &Path, coordinates: &Path, request: &Request) -> Result<Outcome, Failure> {
    let setup = request.setup.as_deref().map(AnalyzeSetup::read).transpose()?;
    let analysis = setup.as_ref().map(check_setup).transpose()?;
    let mut read = AnalyzeInputs::read(model, coordinates, request.setup.as_deref(), setup.as_ref(), &request.actuators, request.external_loads.as_deref())?;
    let forces_file = forces_file(request, analysis.as_ref())?;
    read.files.push(forces_file.clone());
    let forces_table = StorageTable::read(&forces_file)?;
    let given = |cli: &[String], set: fn(&JointReactionSetup) -> &Vec<String>| if cli.is_empty() { analysis.as_ref().map(|a| set(a).clone()).unwrap_or_default() } else { cli.to_vec() };
    let (joints, on, frames) = (given(&request.joints, |a| &a.joint_names), given(&request.on, |a| &a.apply_on_bodies), given(&request.frames, |a| &a.express_in_frame));
    let where_given = request.setup.clone().unwrap_or_else(|| "the command line".into());
    let reports = reaction_reports(&read.spec, &read.geometry.multibody, &joints, &on, &frames, &where_given)?;
    let step_interval = step_interval(request.step_interval, analysis.as_ref().map(|a| a.step_interval))?;
    // Without --time or a setup, the rows the forces file covers.
    let force_times = forces_table.times();
    let given = time_range(request.time, request.lowpass, setup.as_ref())?;
    let range = match (force_times.first(), force_times.last()) {
        (Some(&first), Some(&last)) if request.time.is_none() && setup.is_none() => [first, last],
        _ => given,
    };
    let settings = JointReactionSettings {
        time_range: range,
        lowpass_cutoff: lowpass_cutoff(request.lowpass, setup.as_ref()),
        step_interval,
    };
    let name = output_name(request.name.as_deref(), setup.as_ref(), coordinates);
    let analysis_name = analysis.as_ref().map_or("JointReaction", |a| a.name.as_str());
    let output = request.output.join(format!("{name}_{analysis_name}_ReactionLoads.sto"));
    let input_paths = read.file_paths();
    ensure_not_an_input(&output, &input_paths)?;
    let problem = ReactionProblem { geometry: &read.geometry, generators: &read.generators, forces: ActuatorForces { table: &forces_table, file: &forces_file }, external: read.external.as_ref() };
    let table = StorageTable::read(coordinates)?;
    let result = joint_reactions(&problem, read.motion(&table, request.states, setup.as_ref()), coordinates, &reports, &settings)?;
    create_output_folders([output.as_path()])?;
    write_all_atomically(&[(&output, result.loads.to_text().as_bytes())], &input_paths)?;
    let times = result.loads.times();
    if let (Some(first), Some(last)) = (times.first(), times.last()) {
        println!("{} joint loads at {} frames of {} ({first:.4}–{last:.4} s) → {}", reports.len(), times.len(), coordinates.display(), output.display());
    }
    if !result.missing.is_empty() {
        println!("held at 0 (not in the coordinates, as OpenSim does): {}", result.missing.join(", "));
    }
    if !result.ignored_columns.is_empty() {
        println!("ignored (no coordinate of the model): {}", result.ignored_columns.join(", "));
    }
    if let Some(first) = result.rows_without_forces.first() {
        eprintln!("warning: {} rows (from t = {first} s) have a force that is not a number in {}; their loads are NaN", result.rows_without_forces.len(), forces_file.display());
    }
    if !result.unused_forces.is_empty() {
        println!("ignored in {} (no actuator of the model): {}", forces_file.display(), result.unused_forces.join(", "));
    }
    Ok(Outcome::Success)
}

/// `--forces`, else the setup's `forces_file`.
fn forces_file(request: &Request, analysis: Option<&JointReactionSetup>) -> Result<PathBuf, Failure> {
    request.forces.clone().or_else(|| analysis.and_then(|a| a.forces_file.as_ref()).map(|f| f.resolved.clone())).ok_or_else(|| {
        "no forces file: give --forces (e.g. static optimisation's _force.sto) or a setup whose JointReaction names forces_file; without one the forces are the model's at the muscles' states, which `osim-tune analyze --setup` (or `run`) computes".into()
    })
}

/// The setup's JointReaction, refusing what osim-tune does not do.
fn check_setup(setup: &AnalyzeSetup) -> Result<JointReactionSetup, Failure> {
    let analysis = setup.joint_reaction.clone().ok_or_else(|| format!("{}: the AnalysisSet has no JointReaction that is on", setup.file.display()))?;
    check_analyses(setup, &["JointReaction"])?;
    Ok(analysis)
}
