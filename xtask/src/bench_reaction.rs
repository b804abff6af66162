//! `cargo xtask bench`, joint reactions: each golden case of `fixtures/golden/joint_reaction/`
//! (two analyses, every joint on child and on parent, driven by a static-optimisation forces
//! file) beside OpenSim 4.6's AnalyzeTool running the same two JointReaction analyses
//! (`oracle/bench_joint_reaction.py`). Our time includes reading the model and the files and the
//! comparison with OpenSim's tables; OpenSim's is its `AnalyzeTool.run` alone.

use std::time::Instant;

use osim_tune::validation::JOINT_REACTION_CASES;

use crate::root;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("joint reactions: every joint on child and parent, forces from static optimisation");
    let theirs = crate::bench::opensim_case_seconds("oracle/bench_joint_reaction.py");
    for case in &JOINT_REACTION_CASES {
        let start = Instant::now();
        case.compare(&root())?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {:<17} osim-tune {ours:>8.3} s", case.case);
        crate::bench::print_opensim_case(case.case, ours, &theirs);
    }
    Ok(())
}
