//! `cargo xtask bench`, single thread, each beside OpenSim 4.6 doing the same work through its
//! Python bindings when `python3 -c "import opensim"` works:
//! - geometry: lengths and moment arms of all gait2392 muscles about every coordinate each
//!   spans, per pose (`oracle/bench_geometry.py`);
//! - equilibrium: path lengths and the static equilibrium of all 92 gait2392 Millard muscles at
//!   activation 0.5, per pose (`oracle/bench_equilibrium.py`, `equilibrateMuscles`).

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::HillMuscle;
use osim_tune::mechanics::{MuscleGeometry, PathEvaluation, PathScratch};
use osim_tune::model::ModelSpec;
use osim_tune::validation::GoldenPoses;

use crate::root;

const MODEL: &str = "models/gait2392_millard2012muscle.osim";
const GOLDEN: &str = "fixtures/golden/geometry/gait2392_millard2012muscle";
/// OpenSim per pose must take at least this many times as long as osim-tune.
const GOAL_SPEEDUP: f64 = 20.0;

pub fn run() -> ExitCode {
    let geometry = seconds_per_pose().map(|(ours, pairs)| {
        println!("geometry: gait2392, 92 muscles, {pairs} muscle × coordinate pairs per pose");
        compare(ours, opensim_seconds_per_pose("oracle/bench_geometry.py", true));
    });
    let equilibrium = equilibrium_seconds_per_pose().map(|ours| {
        println!("equilibrium: gait2392 Millard, 92 muscles at activation 0.5 per pose (path lengths included)");
        compare(ours, opensim_seconds_per_pose("oracle/bench_equilibrium.py", false));
    });
    let ik = crate::bench_ik::run();
    let scale = crate::bench_scale::run();
    let functional = crate::bench_functional::run();
    let forward = crate::bench_forward::run();
    let reaction = crate::bench_reaction::run();
    let analyze = crate::bench_analyze::run();
    let rra = crate::bench_rra::run();
    let cmc = crate::bench_cmc::run();
    let kalman = crate::bench_ik::kalman();
    match geometry.and(equilibrium).and(ik).and(scale).and(functional).and(forward).and(reaction).and(analyze).and(rra).and(cmc).and(kalman) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// (case, seconds) from an oracle script printing `<case>_seconds=<s>` per line; empty when it
/// cannot run (no `import opensim`).
pub(crate) fn opensim_case_seconds(script: &str) -> Vec<(String, f64)> {
    let Ok(output) = std::process::Command::new("python3").arg(crate::root().join(script)).output() else { return Vec::new() };
    if !output.status.success() {
        return Vec::new();
    }
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_once("_seconds=").and_then(|(case, s)| Some((case.to_string(), s.trim().parse().ok()?))))
        .collect()
}

/// The end of a case's line: OpenSim's time for it and the speed-up, or why it is missing.
pub(crate) fn print_opensim_case(case: &str, ours: f64, theirs: &[(String, f64)]) {
    match theirs.iter().find(|(name, _)| name == case) {
        Some((_, seconds)) => println!("   OpenSim 4.6 {seconds:>8.3} s   speed-up {:>6.1}×", seconds / ours),
        None => println!("   OpenSim 4.6 skipped (`python3 -c \"import opensim\"` failed)"),
    }
}

fn compare(ours: f64, theirs: Option<f64>) {
    println!("  osim-tune   {:>10.2} µs/pose", ours * 1e6);
    match theirs {
        Some(theirs) => {
            let speedup = theirs / ours;
            println!("  OpenSim 4.6 {:>10.2} µs/pose (Python bindings)", theirs * 1e6);
            println!("  speed-up    {speedup:>10.1}×  (goal ≥ {GOAL_SPEEDUP}×: {})", if speedup >= GOAL_SPEEDUP { "met" } else { "NOT met" });
        }
        None => println!("  OpenSim 4.6  skipped: `python3 -c \"import opensim\"` failed (pip install opensim to compare)"),
    }
}

/// Median over repeated sweeps: path lengths (no moment arms: `equilibrateMuscles` realizes
/// velocities, not moment arms), then every muscle's static equilibrium.
fn equilibrium_seconds_per_pose() -> Result<f64, Box<dyn std::error::Error>> {
    let spec = ModelSpec::read(&OsimDocument::read(&root().join(MODEL))?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let muscles = spec.forces.iter().filter(|f| f.muscle.is_some()).map(HillMuscle::from_force).collect::<Result<Vec<_>, _>>()?;
    let poses = GoldenPoses::read(&root().join(GOLDEN).join("poses.csv"), &geometry.multibody)?;
    let qs: Vec<&Vec<f64>> = poses.ids.iter().map(|id| &poses.values[id]).collect();
    let mut kinematics = geometry.multibody.kinematics();
    let mut scratch = PathScratch::default();
    let mut samples = Vec::new();
    let mut checksum = 0.0;
    for _ in 0..30 {
        let start = Instant::now();
        for q in &qs {
            geometry.multibody.realize(q, &mut kinematics);
            for (path, muscle) in geometry.paths.iter().zip(&muscles) {
                checksum += muscle.equilibrium(0.5, path.length(&kinematics, q, &mut scratch))?.tendon_force;
            }
        }
        samples.push(start.elapsed().as_secs_f64() / qs.len() as f64);
    }
    std::hint::black_box(checksum);
    samples.sort_by(f64::total_cmp);
    Ok(samples[samples.len() / 2])
}

/// Median over repeated sweeps of the golden poses.
fn seconds_per_pose() -> Result<(f64, usize), Box<dyn std::error::Error>> {
    let spec = ModelSpec::read(&OsimDocument::read(&root().join(MODEL))?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let poses = GoldenPoses::read(&root().join(GOLDEN).join("poses.csv"), &geometry.multibody)?;
    let qs: Vec<&Vec<f64>> = poses.ids.iter().map(|id| &poses.values[id]).collect();
    let muscles: Vec<usize> = (0..geometry.paths.len()).collect();
    let pairs = geometry.paths.iter().map(|p| p.spanned.len()).sum();
    let mut evaluation = PathEvaluation::new(&geometry, &muscles);
    let mut samples = Vec::new();
    let mut checksum = 0.0;
    for _ in 0..30 {
        let start = Instant::now();
        for _ in 0..20 {
            for q in &qs {
                evaluation.evaluate(&geometry, q);
                checksum += evaluation.length(0) + evaluation.moment_arms(0)[0];
            }
        }
        samples.push(start.elapsed().as_secs_f64() / (20 * qs.len()) as f64);
    }
    std::hint::black_box(checksum);
    samples.sort_by(f64::total_cmp);
    Ok((samples[samples.len() / 2], pairs))
}

/// Runs an oracle timing script on the bench model and poses (and, with `pairs`, the
/// muscle × coordinate pairs).
fn opensim_seconds_per_pose(script: &str, pairs: bool) -> Option<f64> {
    let folder = root().join(GOLDEN);
    let (script, model, poses, pairs_file) = (root().join(script), root().join(MODEL), folder.join("poses.csv"), folder.join("muscle_coordinates.csv"));
    let mut arguments: Vec<&Path> = vec![&script, &model, &poses];
    if pairs {
        arguments.push(&pairs_file);
    }
    let output = Command::new("python3").args(arguments.iter().map(|p| p.as_os_str())).output().ok()?;
    if !output.status.success() {
        return None;
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    stdout.lines().find_map(|line| line.strip_prefix("seconds_per_pose=")).and_then(|v| v.trim().parse().ok())
}

/// The median of `samples`.
pub fn median(mut samples: Vec<f64>) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// The median wall time (s) of `repeats` runs of `run`, or its first error.
pub fn median_seconds<E>(repeats: usize, mut run: impl FnMut() -> Result<(), E>) -> Result<f64, E> {
    let mut seconds = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let start = std::time::Instant::now();
        run()?;
        seconds.push(start.elapsed().as_secs_f64());
    }
    Ok(median(seconds))
}

/// Prints VmHWM: over `what` when the mark was `reset` before it, else the process's.
pub fn print_peak_resident(reset: bool, what: &str) {
    let over = if reset { what } else { "the process (the mark could not be reset)" };
    match peak_resident_kib() {
        Some(kib) => println!("  peak resident memory over {over}: {:.1} MiB", kib as f64 / 1024.0),
        None => println!("  peak resident memory: /proc/self/status not readable"),
    }
}

/// Resets VmHWM to the current resident set (Linux ≥ 4.0: `5` to /proc/self/clear_refs);
/// whether it could.
pub fn reset_peak_resident() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// VmHWM from /proc/self/status, KiB.
fn peak_resident_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|l| l.strip_prefix("VmHWM:")?.trim().strip_suffix("kB")?.trim().parse().ok())
}
