//! `osim-tune ik MODEL TRIAL [--setup SETUP.xml] [--time START END] [--weights NAME=W,…] [--kalman HZ [--kalman-rates R.sto]] -o Q.mot [--errors ERR.sto] [--marker-locations L.sto]`

use std::path::{Path, PathBuf};

use crate::cli::{check_outputs, create_output_folders, Failure, Outcome};
use crate::io::atomic::write_atomically;
use crate::io::osim::OsimDocument;
use crate::io::table::{MarkerTable, StorageTable};
use crate::mechanics::Multibody;
use crate::model::ModelSpec;
use crate::setup::IkSetup;
use crate::solvers::{CoordinateValues, IkSettings, IkSolution, IkTasks, InverseKinematics, KalmanIkSettings, MarkerTask, MissingFrom, SmoothedKinematics};

/// Where the results go.
pub struct Outputs {
    pub motion: PathBuf,
    pub errors: Option<PathBuf>,
    /// The Kalman smoother's speeds and accelerations.
    pub kalman_rates: Option<PathBuf>,
    /// The tracked markers' locations in ground.
    pub marker_locations: Option<PathBuf>,
}

/// What the command line asks for besides the model, the trial and the outputs.
pub struct Request<'a> {
    pub setup: Option<&'a Path>,
    pub time: Option<[f64; 2]>,
    pub weights: &'a [String],
    /// Kalman smoothing at this cutoff (Hz) after the per-frame solve.
    pub kalman: Option<f64>,
}

pub fn run(model: &Path, trial_file: &Path, request: &Request, outputs: &Outputs) -> Result<Outcome, Failure> {
    let Request { setup, time, weights, kalman } = *request;
    if let Some(cutoff) = kalman.filter(|c| !(c.is_finite() && *c > 0.0)) {
        return Err(format!("--kalman {cutoff}: expected a cutoff frequency > 0 Hz").into());
    }
    if outputs.kalman_rates.is_some() && kalman.is_none() {
        return Err("--kalman-rates needs --kalman HZ (the rates are the smoother's)".into());
    }
    let inputs: Vec<&Path> = [model, trial_file].into_iter().chain(setup).collect();
    let inputs = inputs.as_slice();
    let named = [("-o", Some(outputs.motion.as_path())), ("--errors", outputs.errors.as_deref()), ("--kalman-rates", outputs.kalman_rates.as_deref()), ("--marker-locations", outputs.marker_locations.as_deref())];
    check_outputs(&named, inputs)?;
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let multibody = Multibody::new(&spec)?;
    let trial = crate::cli::read_marker_trial(trial_file)?;
    let (mut tasks, time) = match setup.map(IkSetup::read).transpose()? {
        Some(setup) => (IkTasks::from_task_set(&setup.tasks, &setup.file, CoordinateValues::read_setup_file(setup.coordinate_file.as_ref())?)?, time.or(Some([setup.time_range.start, setup.time_range.end]))),
        None => (every_marker(&multibody, &trial), time),
    };
    apply_weights(&mut tasks, &multibody, &trial, model, trial_file, weights)?;
    let ik = InverseKinematics::new(&multibody, &trial, trial_file, &tasks, IkSettings::default())?;
    let mut solution = ik.solve(time)?;
    let mut rates = None;
    if let Some(cutoff) = kalman {
        let smoothed = ik.smooth(&solution, &KalmanIkSettings::with_cutoff(cutoff))?;
        println!("Kalman-smoothed over {} frames (about {cutoff} Hz; the errors below are the smoothed poses')", smoothed.solution.frames.len());
        rates = Some(rates_table(&multibody, &smoothed)?);
        solution = smoothed.solution;
    }
    let motion = solution.motion_table(&multibody)?;
    let errors = solution.marker_errors_table()?;
    let locations = outputs.marker_locations.as_ref().map(|_| solution.marker_locations_table(&multibody)).transpose()?;
    create_output_folders(named.iter().filter_map(|(_, file)| *file))?;
    write_atomically(&outputs.motion, motion.to_text().as_bytes(), inputs)?;
    if let Some(file) = &outputs.errors {
        write_atomically(file, errors.to_text().as_bytes(), inputs)?;
    }
    if let (Some(file), Some(rates)) = (&outputs.kalman_rates, &rates) {
        write_atomically(file, rates.to_text().as_bytes(), inputs)?;
    }
    if let (Some(file), Some(locations)) = (&outputs.marker_locations, &locations) {
        write_atomically(file, locations.to_text().as_bytes(), inputs)?;
    }
    report(&ik, &solution, trial_file, outputs);
    Ok(if solution.unconverged().next().is_some() { Outcome::NotConverged } else { Outcome::Success })
}

/// The smoother's `<coordinate>_speed` and `<coordinate>_acceleration` per frame (rad/s, rad/s²
/// or m/s, m/s²).
fn rates_table(multibody: &Multibody, smoothed: &SmoothedKinematics) -> Result<StorageTable, Failure> {
    let mut labels = vec!["time".to_string()];
    for coordinate in &multibody.coordinates {
        labels.extend([format!("{}_speed", coordinate.name), format!("{}_acceleration", coordinate.name)]);
    }
    let mut values = Vec::with_capacity(smoothed.solution.frames.len() * labels.len());
    for ((frame, speeds), accelerations) in smoothed.solution.frames.iter().zip(&smoothed.speeds).zip(&smoothed.accelerations) {
        values.push(frame.time);
        values.extend(speeds.iter().zip(accelerations).flat_map(|(u, a)| [*u, *a]));
    }
    Ok(StorageTable::new("Kalman-smoothed speeds and accelerations", labels, values)?.with_in_degrees(false))
}

/// Every model marker the trial has, weight 1 (no setup given).
fn every_marker(multibody: &Multibody, trial: &MarkerTable) -> IkTasks {
    let markers = trial
        .marker_names()
        .iter()
        .filter(|name| multibody.markers.iter().any(|m| &m.name == *name))
        .map(|name| MarkerTask { name: name.clone(), weight: 1.0 })
        .collect();
    IkTasks { markers, coordinates: Vec::new(), coordinate_values: None }
}

/// The `NAME=W` weights applied to the marker tasks; a name that is not a marker of both the
/// model and the trial is an error.
fn apply_weights(tasks: &mut IkTasks, multibody: &Multibody, trial: &MarkerTable, model: &Path, trial_file: &Path, weights: &[String]) -> Result<(), Failure> {
    for assignment in weights {
        let (name, weight) = assignment.split_once('=').ok_or_else(|| format!("--weights {assignment:?}: expected NAME=WEIGHT, e.g. R.ASIS=10"))?;
        let (name, weight) = (name.trim(), weight.trim());
        let weight: f64 = weight.parse().ok().filter(|w: &f64| w.is_finite() && *w >= 0.0).ok_or_else(|| format!("--weights {name}={weight}: expected a number ≥ 0"))?;
        let in_model = multibody.markers.iter().any(|m| m.name == name);
        let in_trial = trial.marker_index(name).is_some();
        let missing = match (in_model, in_trial) {
            (true, true) => None,
            (false, true) => Some(format!("is not a marker of the model {}", model.display())),
            (true, false) => Some(format!("has no data in the trial {}", trial_file.display())),
            (false, false) => Some(format!("is neither a marker of the model {} nor in the trial {}", model.display(), trial_file.display())),
        };
        if let Some(problem) = missing {
            return Err(format!("--weights: marker {name:?} {problem}").into());
        }
        match tasks.markers.iter_mut().find(|t| t.name == name) {
            Some(task) => task.weight = weight,
            None => tasks.markers.push(MarkerTask { name: name.to_string(), weight }),
        }
    }
    Ok(())
}

fn report(ik: &InverseKinematics, solution: &IkSolution, trial_file: &Path, outputs: &Outputs) {
    let frames = &solution.frames;
    let (Some(first), Some(last)) = (frames.first(), frames.last()) else { return };
    println!(
        "{} frames of {} ({}–{} s), {} markers tracked → {}{}",
        frames.len(),
        trial_file.display(),
        first.time,
        last.time,
        solution.markers.len(),
        outputs.motion.display(),
        outputs.errors.as_ref().map_or(String::new(), |e| format!(", {}", e.display()))
    );
    let mean_rms = frames.iter().map(|f| f.errors.rms).sum::<f64>() / frames.len() as f64;
    let worst_rms = frames.iter().max_by(|a, b| a.errors.rms.total_cmp(&b.errors.rms)).unwrap_or(first);
    let worst = frames.iter().max_by(|a, b| a.errors.max.total_cmp(&b.errors.max)).unwrap_or(first);
    println!("marker RMS: mean {:.2} mm, max {:.2} mm (t = {} s)", 1e3 * mean_rms, 1e3 * worst_rms.errors.rms, worst_rms.time);
    println!("worst marker: {} {:.2} mm (t = {} s)", solution.worst_marker(worst).unwrap_or("-"), 1e3 * worst.errors.max, worst.time);
    let iterations: Vec<usize> = frames.iter().map(|f| f.iterations).collect();
    println!(
        "iterations per frame: mean {:.1}, max {}",
        iterations.iter().sum::<usize>() as f64 / frames.len() as f64,
        iterations.iter().max().copied().unwrap_or(0)
    );
    for ignored in ik.ignored_marker_tasks() {
        let place = match ignored.missing_from {
            MissingFrom::Model => "the model",
            MissingFrom::Trial => "the trial",
            MissingFrom::ModelAndTrial => "the model and the trial",
        };
        eprintln!("note: marker {} is not in {place}; not tracked", ignored.name);
    }
    if solution.markers.len() < 4 {
        eprintln!("warning: only {} markers tracked (OpenSim warns below 4)", solution.markers.len());
    }
    let with_gaps: Vec<&crate::solvers::IkFrame> = frames.iter().filter(|f| !f.missing_markers.is_empty()).collect();
    if !with_gaps.is_empty() {
        let mut names: Vec<&str> = with_gaps.iter().flat_map(|f| f.missing_markers.iter().map(|&i| solution.markers[i].as_str())).collect();
        names.sort_unstable();
        names.dedup();
        eprintln!("note: {} frames lack data of some markers, dropped in those frames: {}", with_gaps.len(), names.join(", "));
    }
    let unconverged: Vec<String> = solution.unconverged().map(|f| format!("{} s ({:?})", f.time, f.status)).collect();
    if !unconverged.is_empty() {
        eprintln!("warning: {} frames did not converge: {}", unconverged.len(), unconverged.join(", "));
    }
}
