//! `cargo xtask bench`, the AnalyzeTool: each golden setup of `fixtures/golden/analyze_tool/`
//! (MuscleAnalysis, kinematics, reporters, joint reactions; default, equilibrated and
//! states-file muscle states) beside OpenSim 4.6's AnalyzeTool running it
//! (`oracle/bench_analyze_tool.py`). Our time includes reading the model and the files and the
//! comparison with OpenSim's tables; OpenSim's is its `AnalyzeTool.run` alone.

use std::time::Instant;

use osim_tune::validation::{compare_analyze_tool_setup, ANALYZE_TOOL_CASES};

use crate::root;

/// Times both sides and prints a block like the other benchmarks.
pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    println!("AnalyzeTool: every golden setup, its tables compared with OpenSim's");
    let theirs = crate::bench::opensim_case_seconds("oracle/bench_analyze_tool.py");
    for case in ANALYZE_TOOL_CASES {
        let start = Instant::now();
        compare_analyze_tool_setup(&root(), case)?;
        let ours = start.elapsed().as_secs_f64();
        print!("  {case:<21} osim-tune {ours:>8.3} s");
        crate::bench::print_opensim_case(case, ours, &theirs);
    }
    Ok(())
}
