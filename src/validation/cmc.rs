//! OpenSim 4.6's CMCTool on arm26 (`fixtures/golden/cmc/<case>`, `oracle/gen_cmc.py`) against
//! ours, in two parts:
//! 1. what is deterministic before any optimisation — the muscles' states of the model's default
//!    state (equilibrated at the default pose) and after each 0.2 s settling, and the first window's force range (each generator's
//!    force at its lower and upper control, the muscles' states predicted over 0.03 s) — to the 6
//!    digits OpenSim's verbose log prints; the first window's target: our forces are its optimum,
//!    so our performance may not exceed OpenSim's (IPOPT stops at its tolerance);
//! 2. the tracked motion at the windows' ends, each quantity within a bound set by what the two
//!    implementations may differ by: OpenSim's root solve accepts a control within 2e-3 of the
//!    root (its abscissa tolerance, 4e-3), and the windows feed back through the muscles'
//!    activations, so the muscles' controls agree to that order — far less where, as in the fast
//!    case, a muscle's force barely depends on its control within a window and CMC's controls
//!    chatter —, the kinematics and the reserve actuators much better.

use std::path::Path;

use super::geometry::Worst;
use crate::analysis::{run_cmc, CmcOutputs};
use crate::io::table::StorageTable;
use crate::setup::CmcSetup;

/// The golden cases: 0.40–0.65 s as opensim-core's arm26 CMC test runs it (filtered at 6 Hz, fast
/// target), and 0.20–0.40 s unfiltered with the slow target.
pub const CMC_CASES: [&str; 2] = ["fast", "slow"];

/// The files the golden setups name, with where the repository keeps them.
pub const CMC_INPUTS: [(&str, &str); 4] = [
    ("arm26.osim", "fixtures/models/arm26.osim"),
    ("arm26_InverseKinematics.mot", "fixtures/cmc/arm26_InverseKinematics.mot"),
    ("arm26_Reserve_Actuators.xml", "fixtures/cmc/arm26_Reserve_Actuators.xml"),
    ("arm26_ComputedMuscleControl_Tasks.xml", "fixtures/cmc/arm26_ComputedMuscleControl_Tasks.xml"),
];

/// The bound on the initial states and the first force range, relative to the value (at least
/// 1): 6 printed digits, and the predictor's integration accuracy (5e-6 per step, both
/// integrators with their own steps over the 0.03 s window).
pub const CMC_INITIAL_TOLERANCE: f64 = 3e-5;

/// `case`'s bounds on the tracked motion at the windows' ends.
#[derive(Debug, Clone, Copy)]
pub struct CmcTolerances {
    /// Coordinates (rad) and speeds (rad/s).
    pub coordinates: f64,
    pub speeds: f64,
    /// Muscles' controls and activations (excitation units), and fiber lengths (m).
    pub muscles: f64,
    pub fibers: f64,
    /// The reserve actuators' controls.
    pub reserves: f64,
}

/// `case`'s bounds (see the module's documentation for why they are what they are).
pub fn cmc_tolerances(case: &str) -> CmcTolerances {
    if case == "fast" {
        CmcTolerances { coordinates: 1e-3, speeds: 3e-2, muscles: 0.1, fibers: 2e-4, reserves: 1e-3 }
    } else {
        CmcTolerances { coordinates: 5e-4, speeds: 2e-2, muscles: 1e-2, fibers: 1e-4, reserves: 2e-4 }
    }
}

/// What a case's comparison found.
#[derive(Debug, Clone, Default)]
pub struct CmcComparison {
    /// The muscles' states of the default state and after each settling, and the first window's
    /// force range, relative to the value (at least 1).
    pub initial: Worst,
    /// The first window's target value, ours and OpenSim's.
    pub performance: [f64; 2],
    /// The tracked states and controls at the windows' ends.
    pub coordinates: Worst,
    pub speeds: Worst,
    pub muscles: Worst,
    pub fibers: Worst,
    pub reserves: Worst,
    /// OpenSim's rows at the windows' ends that we lack, and rows we have that OpenSim lacks.
    pub missing_rows: usize,
    pub extra_rows: usize,
    /// Files OpenSim writes that we do not, and the other way round.
    pub missing_files: Vec<String>,
    pub extra_files: Vec<String>,
}

/// Runs `case`'s setup (its inputs copied beside it into a temporary folder) and compares.
pub fn compare_cmc_case(root: &Path, case: &str) -> Result<(CmcComparison, CmcOutputs), String> {
    let golden = root.join("fixtures/golden/cmc").join(case);
    let outputs = run_cmc_case(root, case)?;
    let mut comparison = CmcComparison::default();
    let written = std::fs::read_to_string(golden.join("files.txt")).map_err(|e| e.to_string())?;
    let ours: Vec<&str> = outputs.files.iter().map(|(name, _)| name.as_str()).collect();
    comparison.missing_files = written.lines().filter(|f| !ours.contains(f)).map(String::from).collect();
    comparison.extra_files = ours.iter().filter(|o| !written.lines().any(|f| f == **o)).map(|o| o.to_string()).collect();
    compare_initial(&golden, &outputs, &mut comparison)?;
    for suffix in ["_states.sto", "_controls.sto"] {
        let (name, text) = outputs.files.iter().find(|(name, _)| name.ends_with(suffix)).ok_or(format!("we wrote no {suffix}"))?;
        let opensim = StorageTable::read(&golden.join(name)).map_err(|e| e.to_string())?;
        let table = StorageTable::parse(text, Path::new(name)).map_err(|e| e.to_string())?;
        if opensim.labels() != table.labels() {
            return Err(format!("{name}: OpenSim's columns {:?}, ours {:?}", opensim.labels(), table.labels()));
        }
        compare_rows(name, &opensim, &table, &mut comparison);
    }
    Ok((comparison, outputs))
}

/// Runs `case`'s setup (its inputs copied beside it into a temporary folder).
pub fn run_cmc_case(root: &Path, case: &str) -> Result<CmcOutputs, String> {
    let folder = tempfile::tempdir().map_err(|e| e.to_string())?;
    for (name, source) in CMC_INPUTS {
        std::fs::copy(root.join(source), folder.path().join(name)).map_err(|e| format!("{source}: {e}"))?;
    }
    let setup_file = folder.path().join("setup.xml");
    std::fs::copy(root.join("fixtures/golden/cmc").join(case).join("setup.xml"), &setup_file).map_err(|e| e.to_string())?;
    let setup = CmcSetup::read(&setup_file).map_err(|e| e.to_string())?;
    let model = setup.tracking.tool.model_file.as_ref().ok_or("the golden setup names no model")?.resolved.clone();
    run_cmc(&model, &setup).map_err(|e| e.to_string())
}

/// The initial states and the first window's solve against `initial.json`.
fn compare_initial(golden: &Path, outputs: &CmcOutputs, comparison: &mut CmcComparison) -> Result<(), String> {
    let text = std::fs::read_to_string(golden.join("initial.json")).map_err(|e| e.to_string())?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let numbers = |value: &serde_json::Value| -> Vec<f64> { value.as_array().map(|a| a.iter().filter_map(|v| v.as_f64()).collect()).unwrap_or_default() };
    let initial = outputs.initial.as_ref().ok_or("the case has muscles' states; we report no initial states")?;
    let mut compare = |label: &str, opensim: &[f64], ours: &[f64]| {
        if opensim.len() != ours.len() {
            comparison.initial.update(f64::INFINITY, || format!("{label}: {} values, ours {}", opensim.len(), ours.len()));
        }
        for (k, (a, b)) in opensim.iter().zip(ours).enumerate() {
            comparison.initial.update((a - b).abs() / a.abs().max(1.0), || format!("{label} [{k}]"));
        }
    };
    // OpenSim's Z lists each muscle's activation and fiber length; ours all activations, then
    // all fiber lengths.
    let interleaved = |z: &[f64]| -> Vec<f64> {
        let n = z.len() / 2;
        (0..n).flat_map(|k| [z[k], z[n + k]]).collect()
    };
    compare("guess", &numbers(&json["z"]["guess"]), &interleaved(&initial.guess));
    compare("settled #1", &numbers(&json["z"]["settled"][0]), &interleaved(&initial.settled[0]));
    compare("settled #2", &numbers(&json["z"]["settled"][1]), &interleaved(&initial.settled[1]));
    let first = &json["first_window"][0];
    compare("min forces", &numbers(&first["min_forces"]), &initial.first.force_range[0]);
    compare("max forces", &numbers(&first["max_forces"]), &initial.first.force_range[1]);
    comparison.performance = [initial.first.performance, first["performance"].as_f64().ok_or("initial.json: no performance")?];
    Ok(())
}

/// Each of our rows against OpenSim's at the same time, by kind of column.
fn compare_rows(name: &str, opensim: &StorageTable, ours: &StorageTable, comparison: &mut CmcComparison) {
    let theirs: Vec<&[f64]> = opensim.rows().collect();
    let mut matched = 0;
    for row in ours.rows() {
        let Some(other) = theirs.iter().find(|r| (r[0] - row[0]).abs() < 1e-9) else {
            comparison.extra_rows += 1;
            continue;
        };
        matched += 1;
        for j in 1..row.len() {
            let label = &ours.labels()[j];
            let worst = if label.ends_with("/value") {
                &mut comparison.coordinates
            } else if label.ends_with("/speed") {
                &mut comparison.speeds
            } else if label.ends_with("/fiber_length") {
                &mut comparison.fibers
            } else if label.contains("reserve") {
                &mut comparison.reserves
            } else {
                &mut comparison.muscles
            };
            worst.update((row[j] - other[j]).abs(), || format!("{name} at {} s, {label}", row[0]));
        }
    }
    let first = ours.rows().next().map_or(0.0, |r| r[0]);
    let window = 0.01;
    let at_windows = theirs.iter().filter(|r| ((r[0] - first) / window - ((r[0] - first) / window).round()).abs() < 1e-6).count();
    comparison.missing_rows += at_windows.saturating_sub(matched);
}
