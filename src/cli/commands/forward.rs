//! `osim-tune forward MODEL COORDINATES --excitations U.sto [--activations] [--inverse-dynamics ID.sto] [--time START END] [--lowpass HZ] [--accuracy TOL] [--name NAME] -o DIR`

use std::path::{Path, PathBuf};

use crate::analysis::{
    compare_with_inverse_dynamics, driven_muscles, inverse_dynamics_times, simulate, Activations, CoordinateComparison, ForwardError, ForwardOutputs, ForwardSettings, InitialStates,
    PrescribedMotion,
};
use crate::cli::{check_time_and_cutoff, create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::ModelSpec;

/// What the command line asks for besides the model and the coordinates.
pub struct Request {
    pub excitations: PathBuf,
    /// The table holds activations: no activation dynamics.
    pub activations: bool,
    pub inverse_dynamics: Option<PathBuf>,
    pub time: Option<[f64; 2]>,
    pub lowpass: Option<f64>,
    pub accuracy: f64,
    pub name: Option<String>,
    pub output: PathBuf,
}

pub fn run(model: &Path, coordinates: &Path, request: &Request) -> Result<Outcome, Failure> {
    check_time_and_cutoff(request.time, request.lowpass)?;
    if !(request.accuracy > 0.0 && request.accuracy < 1.0) {
        return Err(format!("--accuracy {}: expected a tolerance in (0, 1)", request.accuracy).into());
    }
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let name = request.name.clone().unwrap_or_else(|| coordinates.file_stem().map_or_else(|| "forward".into(), |s| s.to_string_lossy().into_owned()));
    let outputs = ["states", "tendon_force", "muscle_generalized_forces"].map(|kind| request.output.join(format!("{name}_{kind}.sto")));
    let inputs: Vec<&Path> = [model, coordinates, &request.excitations].into_iter().chain(request.inverse_dynamics.as_deref()).collect();
    for output in &outputs {
        ensure_not_an_input(output, &inputs)?;
    }
    let motion = PrescribedMotion::new(&geometry.multibody, &StorageTable::read(coordinates)?, coordinates, request.lowpass)?;
    let excitation_table = StorageTable::read(&request.excitations)?;
    let driven_names: Vec<String> = spec.muscles().filter(|m| m.applies_force && excitation_table.column_index(&m.name).is_some()).map(|m| m.name.clone()).collect();
    if driven_names.is_empty() {
        return Err(ForwardError::NoDrivenMuscle { model: model.into(), excitations: request.excitations.clone() }.into());
    }
    let muscles = driven_muscles(&spec, &geometry, &driven_names, request.activations)?;
    let excitations = Activations::from_table(&excitation_table, &request.excitations, &driven_names, if request.activations { "activation" } else { "excitation" })?;
    let range = simulated_range(request, &motion, &excitation_table)?;
    let settings = ForwardSettings { range, accuracy: request.accuracy, initial: InitialStates::Equilibrium };
    let trajectory = match simulate(&geometry, &muscles, &motion, &excitations, &settings) {
        Ok(trajectory) => trajectory,
        Err(error @ (ForwardError::MuscleState { .. } | ForwardError::Integration { .. })) => {
            eprintln!("error: the forward simulation failed: {error}; no output written");
            return Ok(Outcome::NotConverged);
        }
        Err(error) => return Err(error.into()),
    };
    let report_times: Vec<f64> = motion.times.iter().copied().filter(|t| (range[0]..=range[1]).contains(t)).collect();
    let results = ForwardOutputs::new(&geometry, &muscles, &motion, &trajectory, &report_times);
    let comparison = match &request.inverse_dynamics {
        Some(file) => {
            let table = StorageTable::read(file)?;
            let at_rows = ForwardOutputs::new(&geometry, &muscles, &motion, &trajectory, &inverse_dynamics_times(&table, range));
            Some(compare_with_inverse_dynamics(&at_rows, &table, file)?)
        }
        None => None,
    };
    let texts = [results.states_table(&name)?, results.tendon_force_table(&name)?, results.generalized_force_table(&name)?].map(|t| t.to_text());
    create_output_folders(outputs.iter().map(PathBuf::as_path))?;
    let files: Vec<(&Path, &[u8])> = outputs.iter().map(PathBuf::as_path).zip(texts.iter().map(String::as_bytes)).collect();
    write_all_atomically(&files, &inputs)?;
    println!(
        "{} muscles driven over {:.4}–{:.4} s ({} steps, {} rejected, {} evaluations; accuracy {:e}) → {}",
        muscles.len(),
        range[0],
        range[1],
        trajectory.accepted_steps,
        trajectory.rejected_steps,
        trajectory.evaluations,
        request.accuracy,
        request.output.display()
    );
    if !motion.defaulted.is_empty() {
        println!("not in the coordinates, held at their default value (or following their coupler): {}", motion.defaulted.join(", "));
    }
    if !motion.ignored_columns.is_empty() {
        println!("columns that are no coordinate, ignored: {}", motion.ignored_columns.join(", "));
    }
    let undriven = spec.muscles().filter(|m| m.applies_force && !driven_names.contains(&m.name)).count();
    if undriven > 0 {
        println!("{undriven} muscles of the model have no excitation column and produce no force");
    }
    if let (Some(comparison), Some(file)) = (comparison, &request.inverse_dynamics) {
        print_comparison(&comparison, file);
    }
    Ok(Outcome::Success)
}

/// `--time`, else the motion's range; it must lie inside the motion and the excitations.
fn simulated_range(request: &Request, motion: &PrescribedMotion, excitations: &StorageTable) -> Result<[f64; 2], ForwardError> {
    let whole = motion.range();
    let range = request.time.unwrap_or(whole);
    if range[0] < whole[0] || range[1] > whole[1] || range[0] >= range[1] {
        return Err(ForwardError::TimeRange { asked: range, motion: whole });
    }
    let times = excitations.times();
    let covered = [times.first().copied().unwrap_or(f64::NAN), times.last().copied().unwrap_or(f64::NAN)];
    if !(covered[0] <= range[0] && covered[1] >= range[1]) {
        return Err(ForwardError::ExcitationsTooShort { file: request.excitations.clone(), covered, simulated: range });
    }
    Ok(range)
}

fn print_comparison(comparison: &[CoordinateComparison], file: &Path) {
    println!("muscles' generalized forces against {}:", file.display());
    println!("{:<28} {:>12} {:>12} {:>12} {:>9}", "coordinate", "RMS diff", "RMS ID", "max diff", "at (s)");
    for c in comparison {
        println!("{:<28} {:>12.3} {:>12.3} {:>12.3} {:>9.4}", c.label, c.rms_difference, c.rms_inverse_dynamics, c.max_difference, c.time_of_max);
    }
}
