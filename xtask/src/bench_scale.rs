//! `cargo xtask bench`, Scale step: OpenSim's subject01 setup on gait2392 (marker set, scale
//! factors, Model::scale, marker placement, the model serialised), beside OpenSim 4.6's
//! ScaleTool through Python (`oracle/bench_scale.py`, which also writes its output files).

use std::process::Command;
use std::time::Instant;

use osim_tune::io::osim::OsimDocument;
use osim_tune::setup::ScaleSetup;
use osim_tune::tuning::scale::run_scale_tool;

use crate::root;

const GENERIC: &str = "models/gait2392_millard2012muscle.osim";
const GOAL_SPEEDUP: f64 = 10.0;
const REPEATS: usize = 5;

pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    let setup = ScaleSetup::read(&root().join("fixtures/subject01/subject01_Setup_Scale.xml"))?;
    let mut samples = Vec::new();
    for _ in 0..REPEATS {
        let start = Instant::now();
        let generic = OsimDocument::read(&root().join(GENERIC))?;
        let outcome = run_scale_tool(&generic, &setup, &mut |_| {})?;
        std::hint::black_box(outcome.document.xml.serialize());
        samples.push(start.elapsed().as_secs_f64());
    }
    samples.sort_by(f64::total_cmp);
    let ours = samples[REPEATS / 2];
    println!("scale: subject01 Scale step (gait2392, 39 markers, measurements + placement)");
    println!("  osim-tune   {:>10.2} ms/run", ours * 1e3);
    match opensim_seconds() {
        Some(theirs) => {
            let speedup = theirs / ours;
            println!("  OpenSim 4.6 {:>10.2} ms/run (ScaleTool, Python bindings)", theirs * 1e3);
            println!("  speed-up    {speedup:>10.1}×  (goal ≥ {GOAL_SPEEDUP}×: {})", if speedup >= GOAL_SPEEDUP { "met" } else { "NOT met" });
        }
        None => println!("  OpenSim 4.6  skipped: `python3 oracle/bench_scale.py` failed (pip install opensim to compare)"),
    }
    Ok(())
}

fn opensim_seconds() -> Option<f64> {
    let script = root().join("oracle/bench_scale.py");
    let output = Command::new("python3")
        .arg(script)
        .arg(root().join(GENERIC))
        .arg(root().join("fixtures/subject01"))
        .arg(REPEATS.to_string())
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    String::from_utf8_lossy(&output.stdout).lines().find_map(|l| l.strip_prefix("seconds_per_run=")?.parse().ok())
}
