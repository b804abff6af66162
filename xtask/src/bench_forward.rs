//! `cargo xtask bench`, forward simulation: each golden case of `fixtures/golden/forward/`
//! (arm26 with Thelen and with DeGroote muscles, gait2392 with 92 Millard muscles, Rajagopal2016
//! with 80) integrated at accuracy
//! 1e-10 and read at its report times, beside OpenSim 4.6 doing the same through its Python
//! bindings (`oracle/bench_forward.py`; its time includes the muscle moments it reports).

use std::process::Command;
use std::time::Instant;

use osim_tune::validation::{compare_forward, FORWARD_CASES};

use crate::root;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("forward simulation: prescribed kinematics, muscles excited, accuracy 1e-10");
    let theirs = opensim();
    for case in &FORWARD_CASES {
        let start = Instant::now();
        let comparison = compare_forward(&root(), case, 1e-10, true)?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {:<17} osim-tune {ours:>8.3} s ({} steps)", case.case, comparison.steps);
        match theirs.iter().find(|(name, _)| name == case.case) {
            Some((_, seconds)) => println!("   OpenSim 4.6 {seconds:>8.3} s   speed-up {:>6.1}×", seconds / ours),
            None => println!("   OpenSim 4.6 skipped (`python3 -c \"import opensim\"` failed)"),
        }
    }
    Ok(())
}

/// (case, seconds) from `oracle/bench_forward.py`; empty when it cannot run.
fn opensim() -> Vec<(String, f64)> {
    let Ok(output) = Command::new("python3").arg(root().join("oracle/bench_forward.py")).output() else { return Vec::new() };
    if !output.status.success() {
        return Vec::new();
    }
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_once("_seconds=").and_then(|(case, s)| Some((case.to_string(), s.trim().parse().ok()?))))
        .collect()
}
