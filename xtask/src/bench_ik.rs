//! `cargo xtask bench`, inverse kinematics: subject01's walking trial (151 frames, the tasks,
//! weights and time range of OpenSim's `setup_ik_used.xml`) beside OpenSim 4.6's
//! `InverseKinematicsTool` through its Python bindings (`oracle/bench_ik.py`):
//! - whole run: read the model and the trial, solve every frame, build both output tables
//!   (OpenSim: `InverseKinematicsTool.run()`, which also writes them);
//! - per frame: the solver alone (OpenSim: `InverseKinematicsSolver.track`);
//! - [`kalman`], run last by `bench.rs`: Kalman smoothing of the solved frames (`ik --kalman 6`,
//!   no OpenSim counterpart): its run time on the trial and on the trial's frames ten times
//!   over (1510 frames), and the peak resident memory over the long run.

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::MarkerTable;
use osim_tune::mechanics::Multibody;
use osim_tune::model::ModelSpec;
use osim_tune::solvers::kalman_smoother::mean_interval;
use osim_tune::solvers::{IkFrame, IkSettings, IkSolution, InverseKinematics, KalmanIkSettings};
use osim_tune::validation::ik::{read_setup_tasks, IkCase};

use crate::bench::{median, median_seconds, print_peak_resident, reset_peak_resident};
use crate::root;

/// OpenSim must take at least this many times as long as osim-tune.
const GOAL_SPEEDUP: f64 = 10.0;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    let case = IkCase::subject01_walk1(&root());
    let (whole, per_frame, frames) = ours(&case)?;
    println!("inverse kinematics: subject01 walk1, {frames} frames, 31 markers + 4 coordinate tasks");
    let theirs = opensim(&case);
    print_row("whole run", whole, theirs.map(|t| t.0), "s");
    print_row("per frame", per_frame, theirs.map(|t| t.1), "µs");
    Ok(())
}

/// Times the Kalman smoother (6 Hz, two passes) on walk1's solved frames and on them repeated
/// ten times in a row, then prints the peak resident memory over the long run. Run last: the
/// allocator keeps what the long run freed, which would raise later peaks.
pub fn kalman() -> Result<(), Box<dyn std::error::Error>> {
    let case = &IkCase::subject01_walk1(&root());
    println!("Kalman-smoothed inverse kinematics (6 Hz, two passes): subject01 walk1");
    let (tasks, time_range) = read_setup_tasks(&case.setup)?;
    let spec = ModelSpec::read(&OsimDocument::read(&case.model)?)?;
    let multibody = Multibody::new(&spec)?;
    let trial = MarkerTable::read(&case.trial)?;
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default())?;
    let solution = ik.solve(time_range)?;
    let settings = KalmanIkSettings::with_cutoff(6.0);
    let seconds = median_seconds(5, || ik.smooth(&solution, &settings).map(|smoothed| drop(std::hint::black_box(smoothed))))?;
    println!("  {} frames: osim-tune {:>10.3} s", solution.frames.len(), seconds);
    let long = repeated(&solution, 10);
    let reset = reset_peak_resident();
    let start = Instant::now();
    std::hint::black_box(ik.smooth(&long, &settings)?);
    println!("  {} frames: osim-tune {:>10.3} s", long.frames.len(), start.elapsed().as_secs_f64());
    print_peak_resident(reset, "the long smoothing");
    Ok(())
}

/// `solution`'s frames `repeats` times in a row, each copy shifted by its frame count times the
/// mean frame interval (the same trial rows, so the smoother linearises the same markers).
fn repeated(solution: &IkSolution, repeats: usize) -> IkSolution {
    let frames = &solution.frames;
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    let period = mean_interval(&times) * frames.len() as f64;
    let copies = (0..repeats).flat_map(|r| frames.iter().map(move |f| IkFrame { time: f.time + r as f64 * period, ..f.clone() }));
    IkSolution { markers: solution.markers.clone(), coordinates: solution.coordinates.clone(), frames: copies.collect() }
}

fn print_row(what: &str, ours: f64, theirs: Option<f64>, unit: &str) {
    let scale = if unit == "s" { 1.0 } else { 1e6 };
    println!("  {what}: osim-tune {:>10.3} {unit}", ours * scale);
    match theirs {
        Some(theirs) => {
            let speedup = theirs / ours;
            println!("  {what}: OpenSim 4.6 {:>8.3} {unit} (Python bindings)", theirs * scale);
            println!("  {what}: speed-up {speedup:>9.1}×  (goal ≥ {GOAL_SPEEDUP}×: {})", if speedup >= GOAL_SPEEDUP { "met" } else { "NOT met" });
        }
        None => println!("  {what}: OpenSim 4.6 skipped: `python3 oracle/bench_ik.py` failed (pip install opensim to compare)"),
    }
}

/// Medians over repeated runs: (whole run s, solve s per frame, frames).
fn ours(case: &IkCase) -> Result<(f64, f64, usize), Box<dyn std::error::Error>> {
    let (tasks, time_range) = read_setup_tasks(&case.setup)?;
    let (mut whole, mut per_frame, mut frames) = (Vec::new(), Vec::new(), 0);
    for _ in 0..15 {
        let start = Instant::now();
        let spec = ModelSpec::read(&OsimDocument::read(&case.model)?)?;
        let multibody = Multibody::new(&spec)?;
        let trial = MarkerTable::read(&case.trial)?;
        let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default())?;
        let solve_start = Instant::now();
        let solution = ik.solve(time_range)?;
        let solve = solve_start.elapsed().as_secs_f64();
        let texts = (solution.motion_table(&multibody)?.to_text(), solution.marker_errors_table()?.to_text());
        whole.push(start.elapsed().as_secs_f64());
        std::hint::black_box(texts);
        frames = solution.frames.len();
        per_frame.push(solve / frames as f64);
    }
    Ok((median(whole), median(per_frame), frames))
}

/// (whole run s, solve s per frame) from `oracle/bench_ik.py`, if OpenSim can be imported.
fn opensim(case: &IkCase) -> Option<(f64, f64)> {
    let script = root().join("oracle/bench_ik.py");
    let arguments: [&Path; 4] = [&script, &case.setup, &case.model, &case.trial];
    let output = Command::new("python3").args(arguments.iter().map(|p| p.as_os_str())).output().ok()?;
    if !output.status.success() {
        return None;
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    let value = |key: &str| stdout.lines().find_map(|line| line.strip_prefix(key)).and_then(|v| v.trim().parse().ok());
    Some((value("seconds_tool=")?, value("seconds_per_frame=")?))
}
