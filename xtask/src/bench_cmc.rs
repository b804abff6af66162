//! `cargo xtask bench`, computed muscle control: the CMCTool goldens of `fixtures/golden/cmc/`
//! (arm26, six muscles and two reserves, 0.01 s windows), each run whole (inputs read, initial
//! states, tracking, every file formed), beside OpenSim 4.6's CMCTool on the same setups
//! (`oracle/bench_cmc.py`).

use std::time::Instant;

use osim_tune::validation::{run_cmc_case, CMC_CASES};

use crate::root;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("computed muscle control (CMCTool): initial states and tracking, 10 ms windows");
    let theirs = crate::bench::opensim_case_seconds("oracle/bench_cmc.py");
    for case in CMC_CASES {
        let start = Instant::now();
        let outputs = run_cmc_case(&root(), case)?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {case:<17} osim-tune {ours:>8.3} s ({} windows)", outputs.windows);
        crate::bench::print_opensim_case(case, ours, &theirs);
    }
    Ok(())
}
