//! OpenSim 4.6's ForwardTool goldens (`fixtures/golden/forward_tool/<case>/`,
//! `oracle/gen_forward_tool.py`): the setup run as `simulate` runs it, our states read from the
//! integrator's dense output at the times OpenSim recorded, compared state by state; the
//! controls compared at the same times.

use std::path::Path;

use crate::analysis::{initial_state, simulate_plant, state_labels, state_values, ForwardModel, InitialSource};
use crate::io::table::StorageTable;
use crate::setup::ForwardSetup;

/// The ForwardTool golden cases.
pub const FORWARD_TOOL_CASES: [&str; 6] = ["controls", "states", "prescribed", "ball_free", "ellipsoid", "linked"];

/// The ForwardTool goldens `cargo xtask validate` adds (slow for the tests: the
/// thoracoscapular shoulder, 33 wrapping muscles, ~15 s).
pub const FORWARD_TOOL_VALIDATE_CASES: [&str; 1] = ["shoulder"];

/// How far our simulation is from OpenSim's.
#[derive(Debug, Clone, Default)]
pub struct ForwardToolComparison {
    /// Rows compared and the largest |ours − OpenSim's| over them: coordinate values (rad or
    /// m), speeds (rad/s or m/s), muscle activations, fiber lengths (m); and controls.
    pub rows: usize,
    pub value: f64,
    pub speed: f64,
    pub activation: f64,
    pub fiber_length: f64,
    pub control: f64,
    /// Our initial time against OpenSim's (s).
    pub start: [f64; 2],
    /// The setup's integrator error tolerance, which both simulations held.
    pub tolerance: f64,
}

/// Runs golden `case` under `root` and compares it with OpenSim's files.
pub fn compare_forward_tool(root: &Path, case: &str) -> Result<ForwardToolComparison, String> {
    let golden = root.join("fixtures/golden/forward_tool").join(case);
    let text = |e: &dyn std::fmt::Display| e.to_string();
    let setup = ForwardSetup::read(&golden.join("setup.xml")).map_err(|e| text(&e))?;
    let tool = &setup.tool;
    // The model beside the setup, else the repository's copy (the goldens share arm26).
    let model = tool.model_file.as_ref().map(|m| m.resolved.clone()).filter(|m| m.exists());
    let model = model.unwrap_or_else(|| root.join("fixtures/models").join(tool.model_file.as_ref().map_or("", |m| &m.written)));
    let inputs = ForwardModel::read(&model, tool)?;
    let mut plant = inputs.plant().map_err(|e| text(&e))?;
    let source = inputs.states.as_ref().map_or(InitialSource::Defaults, |(table, file)| InitialSource::File { table, file });
    let (start, initial) = initial_state(&plant, source, tool.initial_time, tool.solve_for_equilibrium_for_auxiliary_states).map_err(|e| text(&e))?;
    plant.hold(&initial.q);
    let simulation = simulate_plant(&plant, &initial, [start, tool.final_time], &setup.integrator).map_err(|e| text(&e))?;
    let opensim = StorageTable::read(&golden.join(format!("{}_states.sto", tool.name))).map_err(|e| text(&e))?;
    let labels = state_labels(&plant);
    if opensim.labels() != labels.as_slice() {
        return Err(format!("{case}: OpenSim's state labels {:?}, ours {labels:?}", opensim.labels()));
    }
    let mut comparison = ForwardToolComparison { rows: opensim.n_rows(), start: [start, opensim.times()[0]], tolerance: setup.integrator.error_tolerance, ..ForwardToolComparison::default() };
    for row in opensim.rows() {
        let ours = state_values(&plant, &simulation.at(&plant, row[0]));
        for ((label, theirs), ours) in labels[1..].iter().zip(&row[1..]).zip(ours) {
            let worst = match label.rsplit('/').next() {
                Some("value") => &mut comparison.value,
                Some("speed") => &mut comparison.speed,
                Some("activation") => &mut comparison.activation,
                _ => &mut comparison.fiber_length,
            };
            *worst = worst.max((ours - theirs).abs());
        }
    }
    let controls_table = StorageTable::read(&golden.join(format!("{}_controls.sto", tool.name))).map_err(|e| text(&e))?;
    for row in controls_table.rows() {
        for (label, theirs) in controls_table.labels()[1..].iter().zip(&row[1..]) {
            comparison.control = comparison.control.max((plant.control(label, row[0]) - theirs).abs());
        }
    }
    Ok(comparison)
}
