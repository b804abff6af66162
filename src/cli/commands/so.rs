//! `osim-tune so MODEL COORDINATES [--setup SETUP.xml] [--external-loads LOADS.xml] [--actuators F.xml,…] [--time START END] [--lowpass HZ] [--step-interval N] [--activation-exponent P] [--compare ACT.sto] [--pia sum-of-squares|min-max] [--time-constant-scale F] [--name NAME] -o DIR`

use std::path::{Path, PathBuf};

use super::analyze_inputs::{check_analyses, lowpass_cutoff, output_name, step_interval, time_range, AnalyzeInputs};
use crate::analysis::{
    physiological_inverse, static_optimization, Contraction, MAX_LINEARISATIONS, Criterion, ExternalLoads, Generator, MotionInput, PhysiologicalInverseSettings, ReferenceControls, StaticOptimizationError, StaticOptimizationResult,
    StaticOptimizationSettings,
};
use crate::cli::{create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::control_set_document;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::tuning::functional::root_mean_square;
use crate::setup::{AnalyzeSetup, StaticOptimizationSetup};

/// Link accelerations (m/s² or rad/s²) above which the tracked motion is said to break the links:
/// OpenSim's StaticOptimization warns above 1e-6 of its constraints.
const LINK_ACCELERATION_NOTE: f64 = 1e-6;

/// What the command line asks for besides the model and the coordinates.
pub struct Request {
    pub setup: Option<PathBuf>,
    pub external_loads: Option<PathBuf>,
    pub actuators: Vec<PathBuf>,
    pub time: Option<[f64; 2]>,
    pub lowpass: Option<f64>,
    pub step_interval: Option<usize>,
    /// The input is a states file (else a coordinates file, unless the setup names a states_file).
    pub states: bool,
    pub activation_exponent: Option<f64>,
    pub compare: Option<PathBuf>,
    /// The physiological inverse approach by this criterion instead of static optimisation.
    pub pia: Option<Criterion>,
    pub time_constant_scale: f64,
    /// With `pia`: the Hill model's equilibrium forces with compliant tendons.
    pub compliant_tendons: bool,
    /// With `pia`: the weight of skeleton dynamics as a penalty, per N²·m² or N².
    pub moment_weight: Option<f64>,
    pub name: Option<String>,
    pub output: PathBuf,
}

pub fn run(model: &Path, coordinates: &Path, request: &Request) -> Result<Outcome, Failure> {
    let setup = request.setup.as_deref().map(AnalyzeSetup::read).transpose()?;
    let analysis = setup.as_ref().map(check_setup).transpose()?;
    let read = AnalyzeInputs::read(model, coordinates, request.setup.as_deref(), setup.as_ref(), &request.actuators, request.external_loads.as_deref())?;
    let settings = settings(request, setup.as_ref(), analysis.as_ref())?;
    let name = output_name(request.name.as_deref(), setup.as_ref(), coordinates);
    let table = StorageTable::read(coordinates)?;
    let motion = read.motion(&table, request.states, setup.as_ref());
    let problem = Problem { geometry: &read.geometry, generators: &read.generators, motion, coordinates, loads: read.external.as_ref(), inputs: &read.files };
    match request.pia {
        Some(criterion) => {
            let contraction = if request.compliant_tendons { Contraction::CompliantTendon { max_linearisations: MAX_LINEARISATIONS } } else { Contraction::RigidTendon };
            let settings = PhysiologicalInverseSettings { frames: settings, criterion, time_constant_scale: request.time_constant_scale, contraction, moment_weight: request.moment_weight };
            physiological(&problem, request, &format!("{name}_PhysiologicalInverse"), settings)
        }
        None if request.compliant_tendons || request.moment_weight.is_some() => Err("--compliant-tendons and --moment-weight apply to the physiological inverse approach; give --pia".into()),
        None => {
            // OpenSim names the files after the tool and the analysis: `<name>_<analysis>_activation.sto`.
            let prefix = format!("{name}_{}", analysis.as_ref().map_or("StaticOptimization", |a| a.name.as_str()));
            static_optimisation(&problem, request, &prefix, &settings)
        }
    }
}

/// What both methods solve on.
struct Problem<'a> {
    geometry: &'a MuscleGeometry,
    generators: &'a [Generator],
    motion: MotionInput<'a>,
    coordinates: &'a Path,
    loads: Option<&'a ExternalLoads>,
    inputs: &'a [PathBuf],
}

fn static_optimisation(problem: &Problem, request: &Request, prefix: &str, settings: &StaticOptimizationSettings) -> Result<Outcome, Failure> {
    let outputs = [output_file(&request.output, prefix, "activation"), output_file(&request.output, prefix, "force"), request.output.join(format!("{prefix}_controls.xml"))];
    let input_paths: Vec<&Path> = problem.inputs.iter().map(PathBuf::as_path).chain(request.compare.as_deref()).collect();
    for output in &outputs {
        ensure_not_an_input(output, &input_paths)?;
    }
    let compared = request.compare.as_deref().map(StorageTable::read).transpose()?;
    let reference = compared.as_ref().zip(request.compare.as_deref()).map(|(table, file)| ReferenceControls { table, file });
    let result = static_optimization(problem.geometry, problem.generators, problem.motion, problem.coordinates, problem.loads, settings, reference)?;
    create_output_folders(outputs.iter().map(PathBuf::as_path))?;
    let texts = [result.activations.to_text(), result.forces.to_text(), control_set_document(&result.activations)];
    let files: Vec<(&Path, &[u8])> = outputs.iter().zip(&texts).map(|(file, text)| (file.as_path(), text.as_bytes())).collect();
    write_all_atomically(&files, &input_paths)?;
    report(&result, problem.coordinates, &outputs, request.compare.as_deref());
    print_model_check(problem.generators, &result.activations, &result.forces);
    Ok(if result.failures.is_empty() { Outcome::Success } else { Outcome::NotConverged })
}

fn physiological(problem: &Problem, request: &Request, prefix: &str, settings: PhysiologicalInverseSettings) -> Result<Outcome, Failure> {
    if request.compare.is_some() {
        return Err("--compare judges static optimisation; it does not apply with --pia".into());
    }
    if !(settings.time_constant_scale > 0.0 && settings.time_constant_scale.is_finite()) {
        return Err(format!("--time-constant-scale {}: expected a number > 0", settings.time_constant_scale).into());
    }
    if let Some(weight) = settings.moment_weight.filter(|w| !(*w > 0.0 && w.is_finite())) {
        return Err(format!("--moment-weight {weight}: expected a number > 0").into());
    }
    let kinds = ["activation", "force", "excitation", "deviation"];
    let outputs: Vec<PathBuf> = kinds.iter().map(|kind| output_file(&request.output, prefix, kind)).chain([request.output.join(format!("{prefix}_controls.xml"))]).collect();
    let input_paths: Vec<&Path> = problem.inputs.iter().map(PathBuf::as_path).collect();
    for output in &outputs {
        ensure_not_an_input(output, &input_paths)?;
    }
    let result = match physiological_inverse(problem.geometry, problem.generators, problem.motion, problem.coordinates, problem.loads, &settings) {
        Ok(result) => result,
        Err(error @ StaticOptimizationError::NoSolution { .. }) => {
            eprintln!("error: {error}; no output written");
            if settings.moment_weight.is_none() {
                eprintln!("hint: --moment-weight W meets inverse dynamics as a penalty instead, and its _deviation.sto shows where the muscles fall short");
            }
            return Ok(Outcome::NotConverged);
        }
        Err(error) => return Err(error.into()),
    };
    create_output_folders(outputs.iter().map(PathBuf::as_path))?;
    let mut texts = [&result.activations, &result.forces, &result.excitations, &result.deviations].map(StorageTable::to_text).to_vec();
    texts.push(control_set_document(&result.excitations));
    let files: Vec<(&Path, &[u8])> = outputs.iter().map(PathBuf::as_path).zip(texts.iter().map(String::as_bytes)).collect();
    write_all_atomically(&files, &input_paths)?;
    let times = result.activations.times();
    if let (Some(first), Some(last)) = (times.first(), times.last()) {
        println!("{} frames of {} ({first:.4}–{last:.4} s), {:?} → {}", times.len(), problem.coordinates.display(), settings.criterion, request.output.display());
    }
    println!("largest activation {:.4}, Σa² over the motion {:.4}, largest |generalized force − inverse dynamics| {:.2e}", result.max_activation, result.sum_of_squares, result.max_violation);
    if let Some(weight) = settings.moment_weight {
        print_deviations(weight, &result.deviations);
    }
    if settings.contraction != Contraction::RigidTendon {
        println!("compliant tendons: the linearised Hill model settled after {} re-solves", result.iterations);
    }
    print_model_check(problem.generators, &result.activations, &result.forces);
    Ok(Outcome::Success)
}

/// The RMS over the motion of each coordinate's generalized force − inverse dynamics the penalty
/// of weight `weight` left, where above 10⁻³ N·m or N.
fn print_deviations(weight: f64, deviations: &StorageTable) {
    println!("skeleton dynamics as a penalty (W = {weight}): RMS generalized force − inverse dynamics per coordinate, where above 10⁻³");
    for (j, label) in deviations.labels().iter().enumerate().skip(1) {
        let rms = root_mean_square(deviations.rows().map(|row| row[j]));
        if rms > 1e-3 {
            println!("  {label:<28} {rms:>10.4}");
        }
    }
}

/// Activation at or above which a muscle counts as at its limit.
const SATURATED: f64 = 0.99;

/// What the solution says of the model: the muscles at their limit (activation ≥
/// [`SATURATED`]) in how many frames, and each actuator's RMS and peak force — the reserves and
/// residuals an OpenSim user keeps small against the joint moments.
fn print_model_check(generators: &[Generator], activations: &StorageTable, forces: &StorageTable) {
    let frames = activations.n_rows();
    let column = |table: &StorageTable, name: &str| -> Vec<f64> {
        let Some(j) = table.column_index(name) else { return Vec::new() };
        table.rows().map(|row| row[j]).filter(|v| v.is_finite()).collect()
    };
    let saturated: Vec<String> = generators
        .iter()
        .filter(|g| g.time_constants().is_some())
        .filter_map(|g| {
            let count = column(activations, &g.name).iter().filter(|&&a| a >= SATURATED).count();
            (count > 0).then(|| format!("{} ({count})", g.name))
        })
        .collect();
    match saturated.is_empty() {
        true => println!("no muscle reaches activation {SATURATED}"),
        false => println!("muscles at activation ≥ {SATURATED} (frames of {frames}): {}", saturated.join(", ")),
    }
    let actuators: Vec<&Generator> = generators.iter().filter(|g| g.time_constants().is_none()).collect();
    if !actuators.is_empty() {
        println!("actuators: RMS and peak |force| (N·m or N)");
        for actuator in actuators {
            let force = column(forces, &actuator.name);
            let rms = root_mean_square(force.iter().copied());
            println!("  {:<28} {rms:>10.3} {:>10.3}", actuator.name, force.iter().fold(0.0, |m: f64, f| m.max(f.abs())));
        }
    }
}

/// `<DIR>/<name>_<method>_<kind>.sto` (OpenSim's names for static optimisation).
fn output_file(directory: &Path, prefix: &str, kind: &str) -> PathBuf {
    directory.join(format!("{prefix}_{kind}.sto"))
}

/// The setup's StaticOptimization, refusing what osim-tune does not do.
fn check_setup(setup: &AnalyzeSetup) -> Result<StaticOptimizationSetup, Failure> {
    let file = setup.file.display();
    let analysis = setup.static_optimization.clone().ok_or_else(|| format!("{file}: the AnalysisSet has no StaticOptimization that is on"))?;
    check_analyses(setup, &["StaticOptimization"])?;
    // OpenSim 4.6's AnalyzeTool ends in a segmentation fault with it (tried on leg6dof9musc), so
    // there is no behaviour of OpenSim's to follow.
    if !analysis.use_model_force_set {
        return Err(format!("{file}: use_model_force_set false (an actuator per coordinate) is not supported (OpenSim 4.6 itself crashes on it)").into());
    }
    Ok(analysis)
}

/// The command line's values, else the setup's, else all rows, unfiltered, every row.
fn settings(request: &Request, setup: Option<&AnalyzeSetup>, analysis: Option<&StaticOptimizationSetup>) -> Result<StaticOptimizationSettings, Failure> {
    let time_range = time_range(request.time, request.lowpass, setup)?;
    let step_interval = step_interval(request.step_interval, analysis.map(|a| a.step_interval))?;
    let lowpass_cutoff = lowpass_cutoff(request.lowpass, setup);
    let use_muscle_physiology = analysis.is_none_or(|a| a.use_muscle_physiology);
    let activation_exponent = request.activation_exponent.or(analysis.map(|a| a.activation_exponent)).unwrap_or(2.0);
    if !(activation_exponent > 1.0 && activation_exponent.is_finite()) {
        return Err(format!("activation exponent {activation_exponent}: expected a number > 1").into());
    }
    Ok(StaticOptimizationSettings { time_range, lowpass_cutoff, step_interval, use_muscle_physiology, activation_exponent })
}

fn report(result: &StaticOptimizationResult, coordinates: &Path, outputs: &[PathBuf; 3], compare: Option<&Path>) {
    let times = result.activations.times();
    let (Some(first), Some(last)) = (times.first(), times.last()) else { return };
    println!("{} frames of {} ({first:.4}–{last:.4} s) → {}, {}, {}", times.len(), coordinates.display(), outputs[0].display(), outputs[1].display(), outputs[2].display());
    println!("largest |generalized force − inverse dynamics|: {:.2e}", result.max_violation);
    if result.link_acceleration_error > LINK_ACCELERATION_NOTE {
        eprintln!(
            "note: the tracked accelerations break the links between bodies by up to {:.2e} m/s² or rad/s²; the controls give the nearest accelerations that keep them (OpenSim's StaticOptimization cannot meet its constraints there)",
            result.link_acceleration_error
        );
    }
    if !result.missing.is_empty() {
        println!("held at 0 (not in the coordinates, as OpenSim does): {}", result.missing.join(", "));
    }
    if let Some(file) = compare {
        let frames = &result.reference;
        let violation = frames.iter().map(|f| f.violation).fold(0.0, f64::max);
        let bounds = frames.iter().map(|f| f.bound_violation).fold(0.0, f64::max);
        let gap = frames.iter().map(|f| f.objective / f.our_objective - 1.0).fold(f64::NEG_INFINITY, f64::max);
        println!(
            "{}: {} frames compared; its controls miss our constraints by at most {violation:.2e} and our bounds by {bounds:.2e}; its Σ|a|ᵖ is at most {:.3} % above ours",
            file.display(),
            frames.len(),
            100.0 * gap
        );
    }
    for failure in &result.failures {
        eprintln!("t = {} s: no solution ({}); its controls are written as NaN", failure.time, failure.status);
    }
}
