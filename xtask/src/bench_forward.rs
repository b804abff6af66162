//! `cargo xtask bench`, forward simulation: each golden case of `fixtures/golden/forward/`
//! (arm26 with Thelen muscles and with compliant and rigid DeGroote ones, gait2392 with 92 Millard
//! muscles, Rajagopal2016 with 80) integrated at accuracy 1e-10 and read at its report times,
//! beside OpenSim 4.6 doing the same through its Python bindings (`oracle/bench_forward.py`; its
//! time includes the muscle moments it reports).

use std::time::Instant;

use osim_tune::validation::{compare_forward, FORWARD_CASES};

use crate::root;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("forward simulation: prescribed kinematics, muscles excited, accuracy 1e-10");
    let theirs = crate::bench::opensim_case_seconds("oracle/bench_forward.py");
    for case in &FORWARD_CASES {
        let start = Instant::now();
        let comparison = compare_forward(&root(), case, 1e-10, true)?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {:<17} osim-tune {ours:>8.3} s ({} steps)", case.case, comparison.steps);
        crate::bench::print_opensim_case(case.case, ours, &theirs);
    }
    Ok(())
}
