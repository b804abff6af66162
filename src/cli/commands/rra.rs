//! `osim-tune rra MODEL --setup SETUP.xml -o DIR`: OpenSim's RRATool (residual reduction): the
//! mass-center adjustment from the average residuals, then CMC tracking of the desired kinematics
//! with the setup's actuators, writing what OpenSim writes.

use std::path::Path;

use super::analyze_inputs::{analyze_tool_analyses, check_analyses};
use crate::analysis::{run_rra, Adjusted, CmcError, ResidualReductionError, Residuals, RESIDUALS};
use crate::cli::{warn_about, write_files, Failure, Outcome};
use crate::io::osim::format_numbers;
use crate::setup::RraSetup;

pub fn run(model: &Path, setup_file: &Path, output: &Path) -> Result<Outcome, Failure> {
    let mut setup = RraSetup::read(setup_file)?;
    check_analyses(&setup.tracking.tool, &analyze_tool_analyses(&setup.tracking.tool))?;
    setup.tracking.tool.results_directory.resolved = output.to_path_buf();
    let outputs = match run_rra(model, &setup) {
        Ok(outputs) => outputs,
        Err(error @ ResidualReductionError::Cmc(CmcError::Tracking { .. })) => {
            eprintln!("error: RRA's tracking failed: {error}; no output written");
            return Ok(Outcome::NotConverged);
        }
        Err(error) => return Err(error.into()),
    };
    let mut files: Vec<(std::path::PathBuf, String)> = outputs.files.iter().map(|(name, text)| (output.join(name), text.clone())).collect();
    files.extend(outputs.adjusted_model.clone());
    write_files(&files, &outputs.read)?;
    warn_about(&outputs.warnings);
    if let Some(adjusted) = &outputs.adjustment {
        print!("{}", report(adjusted));
    }
    println!("Final average residuals (after the kinematics adjustment): {}", residuals_line(&outputs.final_residuals));
    println!("RRA over {}–{} s (tracked to one window short of the end, as CMC): {} windows → {} files in {}", outputs.range[0], outputs.range[1], outputs.windows, files.len(), output.display());
    Ok(Outcome::Success)
}

/// OpenSim's summary of the mass adjustments and the average residuals before and after.
fn report(adjusted: &Adjusted) -> String {
    let a = &adjusted.adjustment;
    let mut text = format!("Mass-center adjustment of {}: dx = {}, dz = {} m; new mass center {} m\n", a.body, a.dx, a.dz, format_numbers(&a.mass_center[1]));
    text.push_str(&format!("Recommended mass adjustments: total mass change {} kg\n", a.total_mass_change));
    for (body, mass, new) in &a.masses {
        text.push_str(&format!("  {body}: mass {mass} kg → {new} kg\n"));
    }
    text.push_str(&format!("Average residuals before adjusting {}'s mass center: {}\n", a.body, residuals_line(&adjusted.before)));
    text.push_str(&format!("Average residuals after adjusting {}'s mass center: {}\n", a.body, residuals_line(&adjusted.after)));
    text
}

/// `FX=… FY=… FZ=… MX=… MY=… MZ=…`.
fn residuals_line(residuals: &Residuals) -> String {
    RESIDUALS.iter().zip(residuals).map(|(name, value)| format!("{name}={value}")).collect::<Vec<_>>().join(" ")
}

