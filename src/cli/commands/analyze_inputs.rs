//! What the AnalyzeTool commands (`so`, `reaction`) read besides the model and the coordinates:
//! the added actuators, the external loads and the output name, from the command line or else
//! from the AnalyzeTool setup.

use std::path::{Path, PathBuf};

use crate::analysis::ExternalLoads;
use crate::cli::{read_external_loads, Failure};
use crate::mechanics::Multibody;
use crate::model::{read_force_set, ActuatorSpec};
use crate::setup::{read_document, AnalyzeSetup};

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
pub fn external_loads(file: Option<&Path>, setup: Option<&AnalyzeSetup>, multibody: &Multibody, inputs: &mut Vec<PathBuf>) -> Result<Option<ExternalLoads>, Failure> {
    let file = file.map(Path::to_path_buf).or_else(|| setup.and_then(|s| s.external_loads_file.as_ref()).map(|p| p.resolved.clone()));
    file.map(|file| read_external_loads(&file, multibody, inputs)).transpose()
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

/// The `--lowpass` cutoff, else the setup's when it filters (≥ 0), else none.
pub fn lowpass_cutoff(lowpass: Option<f64>, setup: Option<&AnalyzeSetup>) -> Option<f64> {
    lowpass.or(setup.map(|s| s.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0))
}
