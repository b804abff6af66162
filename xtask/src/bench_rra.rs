//! `cargo xtask bench`, residual reduction: the RRATool goldens of `fixtures/golden/rra/` and a
//! whole second of the walk (0.5–1.5 s, the `walk` setup otherwise: 1000 CMC windows), each run
//! whole (inputs read, mass center adjusted, tracked, every file formed), beside OpenSim 4.6's
//! RRATool on the same setups (`oracle/bench_rra.py`).

use std::time::Instant;

use osim_tune::validation::{run_rra_case, RRA_CASES};

use crate::root;

/// The cases timed: each golden case over its own time range, and `second`.
const SECOND: (&str, &str, [f64; 2]) = ("second", "walk", [0.5, 1.5]);

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("residual reduction (RRATool): mass-center adjustment and CMC tracking, 1 ms windows");
    let theirs = crate::bench::opensim_case_seconds("oracle/bench_rra.py");
    let cases = RRA_CASES.iter().map(|&case| (case, case, None)).chain([(SECOND.0, SECOND.1, Some(SECOND.2))]);
    for (label, case, range) in cases {
        let start = Instant::now();
        let outputs = run_rra_case(&root(), case, range)?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {label:<17} osim-tune {ours:>8.3} s ({} windows)", outputs.windows);
        crate::bench::print_opensim_case(label, ours, &theirs);
    }
    Ok(())
}
