//! `osim-tune cmc MODEL --setup SETUP.xml -o DIR`: OpenSim's CMCTool (computed muscle control):
//! the muscles' excitations and the actuators' controls that track the desired kinematics,
//! writing what OpenSim writes.

use std::path::Path;

use super::analyze_inputs::{analyze_tool_analyses, check_analyses};
use crate::analysis::{run_cmc, CmcError};
use crate::cli::{warn_about, write_files, Failure, Outcome};
use crate::setup::CmcSetup;

pub fn run(model: &Path, setup_file: &Path, output: &Path) -> Result<Outcome, Failure> {
    let mut setup = CmcSetup::read(setup_file)?;
    let tool = &mut setup.tracking.tool;
    check_analyses(tool, &analyze_tool_analyses(tool))?;
    tool.results_directory.resolved = output.to_path_buf();
    let outputs = match run_cmc(model, &setup) {
        Ok(outputs) => outputs,
        Err(error @ CmcError::Tracking { .. }) => {
            eprintln!("error: CMC's tracking failed: {error}; no output written");
            return Ok(Outcome::NotConverged);
        }
        Err(error) => return Err(error.to_string().into()),
    };
    let files: Vec<(std::path::PathBuf, String)> = outputs.files.iter().map(|(name, text)| (output.join(name), text.clone())).collect();
    write_files(&files, &outputs.read)?;
    warn_about(&outputs.warnings);
    println!(
        "CMC over {}–{} s (tracked from {} s, after the muscles' initial states, to one window short of the end): {} windows → {} files in {}",
        outputs.range[0],
        outputs.range[1],
        outputs.start,
        outputs.windows,
        files.len(),
        output.display()
    );
    Ok(Outcome::Success)
}
