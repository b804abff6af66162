//! What the AnalyzeTool commands (`so`, `reaction`) read besides the coordinates: the model with
//! its muscles and actuators and the added ones, the external loads, the output name, time range,
//! cutoff and step interval — from the command line, or else from the AnalyzeTool setup.

use std::path::{Path, PathBuf};

use crate::analysis::{generators, muscle_state_names, Controllers, ExternalLoads, Generator, MotionInput};
use crate::io::table::StorageTable;
use crate::cli::{read_external_loads, Failure};
use crate::io::osim::OsimDocument;
use crate::mechanics::{MuscleGeometry, Multibody};
use crate::model::{read_force_set, ActuatorSpec, ModelSpec};
use crate::setup::{read_document, AnalyzeSetup};

/// What an AnalyzeTool command works on besides the coordinates.
pub struct AnalyzeInputs {
    pub spec: ModelSpec,
    pub geometry: MuscleGeometry,
    /// The model's muscles and actuators, then the added ones (or only those, with the setup's
    /// `replace_force_set`).
    pub generators: Vec<Generator>,
    pub external: Option<ExternalLoads>,
    /// Each muscle's name and second state's name, as a states file names them.
    pub muscle_states: Vec<(String, &'static str)>,
    /// Every file read (model, coordinates, setup, actuators, loads and their data), which no
    /// output may overwrite.
    pub files: Vec<PathBuf>,
}

impl AnalyzeInputs {
    /// Reads `model` and the actuators and external loads the flags (`actuators`,
    /// `external_loads`) or else the setup (read from `setup_file`) name.
    pub fn read(model: &Path, coordinates: &Path, setup_file: Option<&Path>, setup: Option<&AnalyzeSetup>, actuators: &[PathBuf], external_loads: Option<&Path>) -> Result<AnalyzeInputs, Failure> {
        let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
        let geometry = MuscleGeometry::new(&spec)?;
        let mut files: Vec<PathBuf> = [model, coordinates].into_iter().chain(setup_file).map(Path::to_path_buf).collect();
        let (added, replace) = actuator_files(actuators, setup, &mut files)?;
        let generators = generators(&spec, &geometry, &added, replace)?;
        let external = external_loads_of(external_loads, setup, &geometry.multibody, &mut files)?;
        let muscle_states = muscle_state_names(&spec);
        Ok(AnalyzeInputs { spec, geometry, generators, external, muscle_states, files })
    }

    /// `table` (the input file's) as a states file when `states` (the `--states` flag) or the
    /// setup names a states_file, else as coordinates.
    pub fn motion<'a>(&'a self, table: &'a StorageTable, states: bool, setup: Option<&AnalyzeSetup>) -> MotionInput<'a> {
        if states || setup.is_some_and(|s| s.states_file.is_some()) {
            MotionInput::States { table, muscles: &self.muscle_states }
        } else {
            MotionInput::Coordinates(table)
        }
    }

    /// [`AnalyzeInputs::files`] as paths.
    pub fn file_paths(&self) -> Vec<&Path> {
        self.files.iter().map(PathBuf::as_path).collect()
    }
}

/// The actuators of the `--actuators` files, else of the setup's `force_set_files` (a `<ForceSet>`
/// inside `<OpenSimDocument>` or as the root, as OpenSim reads both), and whether they replace
/// the model's forces (the setup's `replace_force_set`; never for `--actuators`). Each file read
/// joins `inputs`.
pub fn actuator_files(actuators: &[PathBuf], setup: Option<&AnalyzeSetup>, inputs: &mut Vec<PathBuf>) -> Result<(Vec<ActuatorSpec>, bool), Failure> {
    let (files, replace): (Vec<PathBuf>, bool) = match setup {
        Some(setup) if actuators.is_empty() => (setup.force_set_files.iter().map(|f| f.resolved.clone()).collect(), setup.replace_force_set && !setup.force_set_files.is_empty()),
        _ => (actuators.to_vec(), false),
    };
    let mut specs = Vec::new();
    for file in files {
        specs.extend(read_force_set(&read_document(&file)?)?);
        inputs.push(file);
    }
    Ok((specs, replace))
}

/// The `--external-loads` file, else the setup's, read on `multibody`; its files join `inputs`.
pub fn external_loads_of(file: Option<&Path>, setup: Option<&AnalyzeSetup>, multibody: &Multibody, inputs: &mut Vec<PathBuf>) -> Result<Option<ExternalLoads>, Failure> {
    let file = file.map(Path::to_path_buf).or_else(|| setup.and_then(|s| s.external_loads_file.as_ref()).map(|p| p.resolved.clone()));
    file.map(|file| read_external_loads(&file, multibody, inputs)).transpose()
}

/// The controllers of the model `spec` and of `setup` over the model's actuators and those
/// `added` (the model's replaced when `replace`); their files join `inputs`.
pub fn controllers_of(spec: &ModelSpec, setup: &AnalyzeSetup, added: &[ActuatorSpec], replace: bool, inputs: &mut Vec<PathBuf>) -> Result<Controllers, Failure> {
    let controllers = Controllers::of_model(spec, &setup.controllers, added, replace)?;
    inputs.extend(controllers.files.iter().cloned());
    Ok(controllers)
}

/// The `--name`, else the setup's name, else the coordinates file's stem.
pub fn output_name(name: Option<&str>, setup: Option<&AnalyzeSetup>, coordinates: &Path) -> String {
    name.map(str::to_string)
        .or_else(|| setup.map(|s| s.name.clone()).filter(|n| !n.is_empty()))
        .unwrap_or_else(|| coordinates.file_stem().map_or_else(|| "analysis".into(), |s| s.to_string_lossy().into_owned()))
}

/// The `--time` range, else the setup's, else every row; checks `--lowpass` too.
pub fn time_range(time: Option<[f64; 2]>, lowpass: Option<f64>, setup: Option<&AnalyzeSetup>) -> Result<[f64; 2], Failure> {
    crate::cli::check_time_and_cutoff(time, lowpass)?;
    Ok(time.or(setup.map(|s| [s.initial_time, s.final_time])).unwrap_or([f64::NEG_INFINITY, f64::INFINITY]))
}

/// The `--step-interval`, else the analysis's, else 1; 0 is refused.
pub fn step_interval(flag: Option<usize>, analysis: Option<usize>) -> Result<usize, Failure> {
    if flag == Some(0) {
        return Err("--step-interval 0: expected a whole number ≥ 1".into());
    }
    Ok(flag.or(analysis).unwrap_or(1))
}

/// The `--lowpass` cutoff, else the setup's when it filters (≥ 0), else none.
pub fn lowpass_cutoff(lowpass: Option<f64>, setup: Option<&AnalyzeSetup>) -> Option<f64> {
    lowpass.or(setup.map(|s| s.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0))
}

/// The analyses of `setup` that `analyze --setup` (and `simulate`, on its states) runs.
pub fn analyze_tool_analyses(setup: &AnalyzeSetup) -> Vec<&'static str> {
    let mut runs = vec!["MuscleAnalysis", "Kinematics", "BodyKinematics", "PointKinematics", "ForceReporter", "Actuation", "StatesReporter", "ProbeReporter", "InducedAccelerations"];
    if setup.joint_reaction_from_states() {
        runs.push("JointReaction");
    }
    runs
}

/// Refuses a setup whose speeds come from a speeds file, and prints the setup's analyses other
/// than `runs` (the classes the calling command runs) as not run.
pub fn check_analyses(setup: &AnalyzeSetup, runs: &[&str]) -> Result<(), Failure> {
    if let Some(speeds) = &setup.speeds_file {
        return Err(format!("{}: speeds_file {} is not supported; the speeds are the coordinates' spline derivatives", setup.file.display(), speeds.written).into());
    }
    let commands = [
        ("MuscleAnalysis", setup.muscle_analysis.is_some(), "analyze --setup"),
        ("Kinematics", setup.kinematics.is_some(), "analyze --setup"),
        ("BodyKinematics", setup.body_kinematics.is_some(), "analyze --setup"),
        ("PointKinematics", !setup.point_kinematics.is_empty(), "analyze --setup"),
        ("ForceReporter", setup.force_reporter.is_some(), "analyze --setup"),
        ("Actuation", setup.actuation.is_some(), "analyze --setup"),
        ("StatesReporter", setup.states_reporter.is_some(), "analyze --setup"),
        ("ProbeReporter", setup.probe_reporter.is_some(), "analyze --setup"),
        ("InducedAccelerations", setup.induced_accelerations.is_some(), "analyze --setup"),
        ("StaticOptimization", setup.static_optimization.is_some(), "so"),
        ("JointReaction", setup.joint_reaction.is_some() && !setup.joint_reaction_from_states(), "reaction"),
        ("JointReaction", setup.joint_reaction_from_states(), "analyze --setup"),
    ];
    let mut others = setup.other_analyses.clone();
    others.extend(commands.iter().filter(|(class, on, _)| *on && !runs.contains(class)).map(|(class, _, command)| format!("{class} (run by osim-tune {command})")));
    if !others.is_empty() {
        println!("not run (only {} here): {}", runs.join(", "), others.join(", "));
    }
    Ok(())
}
