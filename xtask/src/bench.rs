//! `cargo xtask bench`: lengths and moment arms of all gait2392 muscles about every coordinate
//! each spans, per pose, single thread; beside OpenSim 4.6 doing the same work through its
//! Python bindings (`oracle/bench_geometry.py`) when `python3 -c "import opensim"` works.

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{MuscleGeometry, PathEvaluation};
use osim_tune::model::ModelSpec;
use osim_tune::validation::GoldenPoses;

use crate::root;

const MODEL: &str = "models/gait2392_millard2012muscle.osim";
const GOLDEN: &str = "fixtures/golden/geometry/gait2392_millard2012muscle";
/// OpenSim per pose must take at least this many times as long as osim-tune.
const GOAL_SPEEDUP: f64 = 20.0;

pub fn run() -> ExitCode {
    match seconds_per_pose() {
        Ok((ours, pairs)) => {
            println!("gait2392, 92 muscles, {pairs} muscle × coordinate pairs per pose");
            println!("osim-tune   {:>10.2} µs/pose", ours * 1e6);
            match opensim_seconds_per_pose() {
                Some(theirs) => {
                    let speedup = theirs / ours;
                    println!("OpenSim 4.6 {:>10.2} µs/pose (Python bindings)", theirs * 1e6);
                    println!("speed-up    {speedup:>10.1}×  (goal ≥ {GOAL_SPEEDUP}×: {})", if speedup >= GOAL_SPEEDUP { "met" } else { "NOT met" });
                }
                None => println!("OpenSim 4.6  skipped: `python3 -c \"import opensim\"` failed (pip install opensim to compare)"),
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
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

fn opensim_seconds_per_pose() -> Option<f64> {
    let folder = root().join(GOLDEN);
    let script = root().join("oracle/bench_geometry.py");
    let arguments = [script.as_path(), &root().join(MODEL), &folder.join("poses.csv"), &folder.join("muscle_coordinates.csv")];
    let output = Command::new("python3").args(arguments.iter().map(|p: &&Path| p.as_os_str())).output().ok()?;
    if !output.status.success() {
        return None;
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    stdout.lines().find_map(|line| line.strip_prefix("seconds_per_pose=")).and_then(|v| v.trim().parse().ok())
}
