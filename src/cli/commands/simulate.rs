//! `osim-tune simulate MODEL --setup SETUP.xml -o DIR`: OpenSim's ForwardTool — the model's
//! forward dynamics integrated from its initial state under the setup's controllers — writing
//! `<name>_states.sto`, `<name>_states_degrees.mot` and `<name>_controls.sto`, and the tables of
//! the AnalysisSet's analyses formed from the simulated states.

use std::path::Path;

use super::analyze_inputs::{analyze_tool_analyses, check_analyses};
use crate::analysis::{analyze_tool_tables, controls_table, initial_state, simulate_plant, states_table, ForwardModel, InitialSource, SimulationError};
use crate::cli::{warn_about, write_files, Failure, Outcome};
use crate::setup::{ForwardSetup, SetupPath};

pub fn run(model: &Path, setup_file: &Path, output: &Path) -> Result<Outcome, Failure> {
    let setup = ForwardSetup::read(setup_file)?;
    let tool = &setup.tool;
    check_analyses(tool, &analyze_tool_analyses(tool))?;
    let inputs = ForwardModel::read(model, tool)?;
    warn_about(inputs.external.as_ref().map_or(&[][..], |loads| &loads.warnings));
    let mut read = inputs.read.clone();
    read.push(setup_file.to_path_buf());
    let in_setup = |error: SimulationError| -> Failure { format!("{}: {error}", setup_file.display()).into() };
    let mut plant = inputs.plant().map_err(in_setup)?;
    let source = match &inputs.states {
        Some((table, file)) => InitialSource::File { table, file },
        None => InitialSource::Defaults,
    };
    let (start, initial) = initial_state(&plant, source, tool.initial_time, tool.solve_for_equilibrium_for_auxiliary_states).map_err(in_setup)?;
    if start != tool.initial_time {
        println!("the initial time is {start} s, the states file's row at or before {} s (OpenSim does not interpolate initial states)", tool.initial_time);
    }
    plant.hold(&initial.q);
    let simulation = match simulate_plant(&plant, &initial, [start, tool.final_time], &setup.integrator) {
        Ok(simulation) => simulation,
        Err(error @ SimulationError::Integration { .. }) => {
            eprintln!("error: the forward simulation failed: {error}; no output written");
            return Ok(Outcome::NotConverged);
        }
        Err(error) => return Err(in_setup(error)),
    };
    let name = &tool.name;
    let states = states_table(&plant, &simulation, false)?;
    let mut files = vec![
        (output.join(format!("{name}_states.sto")), states.to_text()),
        (output.join(format!("{name}_states_degrees.mot")), states_table(&plant, &simulation, true)?.to_text()),
        (output.join(format!("{name}_controls.sto")), controls_table(&plant, &simulation)?.to_text()),
    ];
    if tool.has_analyze_tables() {
        let states_file = output.join(format!("{name}_states.sto"));
        let mut analyses = tool.clone();
        analyses.states_file = Some(SetupPath { written: states_file.display().to_string(), resolved: states_file.clone() });
        analyses.initial_time = start;
        let tables = analyze_tool_tables(&inputs.analysed(), &states, &states_file, &analyses, name)?;
        files.extend(tables.files.iter().map(|(file, table)| (output.join(file), table.to_text())));
        warn_about(&tables.warnings);
        for note in &tables.notes {
            eprintln!("note: {note}");
        }
    }
    write_files(&files, &read)?;
    println!(
        "ForwardTool: {start}–{} s in {} steps ({} rejected, {} evaluations, {} projections onto the links) → {} files in {}",
        tool.final_time,
        simulation.accepted_steps,
        simulation.rejected_steps,
        simulation.evaluations,
        simulation.projections,
        files.len(),
        output.display()
    );
    Ok(Outcome::Success)
}
