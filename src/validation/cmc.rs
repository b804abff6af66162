//! OpenSim 4.6's CMCTool on arm26 and subject01's walk (`fixtures/golden/cmc/<case>`,
//! `oracle/gen_cmc.py`) against ours, in two parts:
//! 1. what is deterministic before any optimisation — the muscles' states of the model's default
//!    state (equilibrated at the default pose) and after each 0.2 s settling, and the first
//!    window's force range (each generator's force at its lower and upper control, the muscles'
//!    states predicted over 0.03 s) — to the 6 digits OpenSim's verbose log prints (the walk's to
//!    what its integration allows, see [`cmc_tolerances`]); the first window's target: our forces
//!    are its optimum, so our performance may not exceed OpenSim's (IPOPT stops at its
//!    tolerance); and no task's position error may exceed the largest of OpenSim's by more than
//!    5 % (`POSITION_ERROR_MARGIN`);
//! 2. the tracked motion at the windows' ends, each quantity within a bound set by what the two
//!    implementations may differ by: OpenSim's root solve accepts a control within 2e-3 of the
//!    root (its abscissa tolerance, 4e-3), and the windows feed back through the muscles'
//!    activations, so the muscles' controls agree to that order — far less where, as in the fast
//!    case, a muscle's force barely depends on its control within a window and CMC's controls
//!    chatter —, the kinematics and the reserve actuators much better. Which way a root solve's
//!    last step goes turns on the forces' last digits, so the motion is chaotic at that level: a
//!    change of 1e-9 N in the optimiser's forces moves the arm26 coordinates by up to 1e-3 rad,
//!    and the bounds are set at two to three times what the runs show.

use std::path::Path;

use super::geometry::Worst;
use super::tool_case::{case_folder, file_differences};
use crate::analysis::{run_cmc, CmcOutputs};
use crate::io::table::StorageTable;
use crate::setup::CmcSetup;

/// The golden cases: arm26 at 0.40–0.65 s as opensim-core's arm26 CMC test runs it (filtered at
/// 6 Hz, fast target), the same with BRA and TRImed left out of CMC's control
/// (`actuators_to_exclude`), the same with BRA driven by a `PrescribedController` of the setup
/// that also adds to TRIlong's control, the same with opensim-core's EMG task (BIClong's
/// activation pulled towards `muscle_emg.sto`), and at 0.20–0.40 s unfiltered with the slow target;
/// subject01's walk at 0.80–0.86 s on the scaled gait2392 (92 muscles, ground reactions,
/// opensim-core's gait2354 CMC actuators, tasks and control constraints).
pub const CMC_CASES: [&str; 6] = ["fast", "slow", "exclude", "prescribed", "emg", "walk"];

/// The files `case`'s golden setup names, with where the repository keeps them.
pub fn cmc_inputs(case: &str) -> &'static [(&'static str, &'static str)] {
    const ARM26: [(&str, &str); 4] = [
        ("arm26.osim", "fixtures/models/arm26.osim"),
        ("arm26_InverseKinematics.mot", "fixtures/cmc/arm26_InverseKinematics.mot"),
        ("arm26_Reserve_Actuators.xml", "fixtures/cmc/arm26_Reserve_Actuators.xml"),
        ("arm26_ComputedMuscleControl_Tasks.xml", "fixtures/cmc/arm26_ComputedMuscleControl_Tasks.xml"),
    ];
    const ARM26_EMG: [(&str, &str); 6] = [
        ARM26[0],
        ARM26[1],
        ARM26[2],
        ("arm26_ComputedMuscleControl_Tasks_EMG.xml", "fixtures/cmc/arm26_ComputedMuscleControl_Tasks_EMG.xml"),
        ("muscle_emg.sto", "fixtures/cmc/muscle_emg.sto"),
        ARM26[3],
    ];
    const WALK: [(&str, &str); 7] = [
        ("subject01_simbody.osim", "fixtures/golden/scale/subject01_simbody.osim"),
        ("subject01_walk1_ik.mot", "fixtures/golden/ik/subject01_walk1_ik.mot"),
        ("subject01_walk1_grf.xml", "fixtures/subject01/subject01_walk1_grf.xml"),
        ("subject01_walk1_grf.mot", "fixtures/subject01/subject01_walk1_grf.mot"),
        ("gait2354_CMC_Actuators.xml", "fixtures/subject01/gait2354_CMC_Actuators.xml"),
        ("gait2354_CMC_Tasks.xml", "fixtures/subject01/gait2354_CMC_Tasks.xml"),
        ("gait2354_CMC_ControlConstraints.xml", "fixtures/subject01/gait2354_CMC_ControlConstraints.xml"),
    ];
    match case {
        "walk" => &WALK,
        "emg" => &ARM26_EMG,
        _ => &ARM26,
    }
}

/// How far our largest position error may exceed OpenSim's, relative.
pub const POSITION_ERROR_MARGIN: f64 = 0.05;

/// `case`'s bounds.
#[derive(Debug, Clone, Copy)]
pub struct CmcTolerances {
    /// The muscles' states of the default state and after each settling (activations; fiber
    /// lengths, m), absolute.
    pub initial_states: f64,
    /// The first window's force range (the forces at the controls' upper bounds, and at the lower
    /// bounds where `lower_forces`), relative to the force (at least 1 N).
    pub force_ranges: f64,
    pub lower_forces: bool,
    /// The tracked motion at the windows' ends, value by value.
    pub tracked: TrackedBounds,
}

/// Bounds on the tracked motion at the windows' ends.
#[derive(Debug, Clone, Copy)]
pub struct TrackedBounds {
    /// Coordinates (rad or m) and speeds (rad/s or m/s).
    pub coordinates: f64,
    pub speeds: f64,
    /// Muscles' controls and activations (excitation units), and fiber lengths (m).
    pub muscles: f64,
    pub fibers: f64,
    /// The residual and reserve actuators' controls.
    pub reserves: f64,
}

/// `case`'s bounds. arm26: the initial states to OpenSim's 6 printed digits, the first force
/// range to them and the predictor's accuracy (5e-6 per step, both integrators with their own
/// steps); the tracked motion as the module's documentation explains. The walk: Simbody's
/// accuracy is absolute on a fiber length under 1 m, so over the 0.4 s of settling the 92
/// muscles' fiber lengths may part by 1e-4 m, and the stiffest tendons (add_brev: a 2.2 cm tendon
/// on a 15 cm fiber) turn that into tens of newtons at low activation — the lower forces are not
/// compared, and the activations and fiber lengths then part further; the kinematics (whose toes
/// drift in both, stepped reserves being what CMC gives them) and the residual and reserve
/// controls follow closely.
pub fn cmc_tolerances(case: &str) -> CmcTolerances {
    match case {
        "fast" | "exclude" | "prescribed" | "emg" => CmcTolerances { initial_states: 2e-6, force_ranges: 3e-5, lower_forces: true, tracked: TrackedBounds { coordinates: 1e-3, speeds: 3e-2, muscles: 0.1, fibers: 2e-4, reserves: 1e-3 } },
        "slow" => CmcTolerances { initial_states: 2e-6, force_ranges: 3e-5, lower_forces: true, tracked: TrackedBounds { coordinates: 2e-3, speeds: 5e-2, muscles: 2e-2, fibers: 1e-4, reserves: 2e-4 } },
        _ => CmcTolerances { initial_states: 1e-4, force_ranges: 3e-5, lower_forces: false, tracked: TrackedBounds { coordinates: 3e-3, speeds: 0.2, muscles: 0.15, fibers: 2e-3, reserves: 5e-3 } },
    }
}

/// What a case's comparison found.
#[derive(Debug, Clone, Default)]
pub struct CmcComparison {
    /// The muscles' states of the default state and after each settling (absolute).
    pub initial_states: Worst,
    /// The first window's force range, relative to the force (at least 1 N).
    pub force_ranges: Worst,
    /// The first window's target value, ours and OpenSim's.
    pub performance: [f64; 2],
    /// The largest position error of any task at any window's start (rad or m), ours and
    /// OpenSim's.
    pub position_errors: [f64; 2],
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
    let ours: Vec<String> = outputs.files.iter().map(|(name, _)| name.clone()).collect();
    (comparison.missing_files, comparison.extra_files) = file_differences(&golden, &ours)?;
    compare_initial(&golden, &outputs, cmc_tolerances(case).lower_forces, &mut comparison)?;
    let largest = |table: &StorageTable| table.rows().flat_map(|row| row[1..].to_vec()).fold(0.0f64, |m, v| m.max(v.abs()));
    let (name, text) = outputs.files.iter().find(|(name, _)| name.ends_with("_pErr.sto")).ok_or("we wrote no _pErr.sto")?;
    let opensim = StorageTable::read(&golden.join(name)).map_err(|e| e.to_string())?;
    comparison.position_errors = [largest(&StorageTable::parse(text, Path::new(name)).map_err(|e| e.to_string())?), largest(&opensim)];
    let muscles: Vec<String> = outputs.files.iter().find(|(name, _)| name.ends_with("_states.sto")).map_or(String::new(), |(_, text)| text.lines().find(|l| l.starts_with("time")).unwrap_or_default().to_string()).split('\t').filter_map(|label| label.strip_prefix("/forceset/")?.strip_suffix("/activation")).map(String::from).collect();
    for suffix in ["_states.sto", "_controls.sto"] {
        let (name, text) = outputs.files.iter().find(|(name, _)| name.ends_with(suffix)).ok_or(format!("we wrote no {suffix}"))?;
        let opensim = StorageTable::read(&golden.join(name)).map_err(|e| e.to_string())?;
        let table = StorageTable::parse(text, Path::new(name)).map_err(|e| e.to_string())?;
        if opensim.labels() != table.labels() {
            return Err(format!("{name}: OpenSim's columns {:?}, ours {:?}", opensim.labels(), table.labels()));
        }
        compare_rows(name, &opensim, &table, &muscles, &mut comparison);
    }
    Ok((comparison, outputs))
}

/// Runs `case`'s setup (its inputs copied beside it into a temporary folder).
pub fn run_cmc_case(root: &Path, case: &str) -> Result<CmcOutputs, String> {
    let (_folder, setup_file) = case_folder(root, &root.join("fixtures/golden/cmc").join(case), cmc_inputs(case))?;
    let setup = CmcSetup::read(&setup_file).map_err(|e| e.to_string())?;
    let model = setup.tracking.tool.model_file.as_ref().ok_or("the golden setup names no model")?.resolved.clone();
    run_cmc(&model, &setup).map_err(|e| e.to_string())
}

/// The initial states and the first window's solve against `initial.json`.
fn compare_initial(golden: &Path, outputs: &CmcOutputs, lower_forces: bool, comparison: &mut CmcComparison) -> Result<(), String> {
    let text = std::fs::read_to_string(golden.join("initial.json")).map_err(|e| e.to_string())?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let numbers = |value: &serde_json::Value| -> Vec<f64> { value.as_array().map(|a| a.iter().filter_map(|v| v.as_f64()).collect()).unwrap_or_default() };
    let initial = outputs.initial.as_ref().ok_or("the case has muscles' states; we report no initial states")?;
    let compare = |worst: &mut Worst, label: &str, opensim: &[f64], ours: &[f64], relative: bool| {
        if opensim.len() != ours.len() {
            worst.update(f64::INFINITY, || format!("{label}: {} values, ours {}", opensim.len(), ours.len()));
        }
        for (k, (a, b)) in opensim.iter().zip(ours).enumerate() {
            worst.update((a - b).abs() / if relative { a.abs().max(1.0) } else { 1.0 }, || format!("{label} [{k}]"));
        }
    };
    // OpenSim's Z lists each muscle's activation and fiber length; ours all activations, then
    // all fiber lengths.
    let interleaved = |z: &[f64]| -> Vec<f64> {
        let n = z.len() / 2;
        (0..n).flat_map(|k| [z[k], z[n + k]]).collect()
    };
    let states = &mut comparison.initial_states;
    compare(states, "guess", &numbers(&json["z"]["guess"]), &interleaved(&initial.guess), false);
    compare(states, "settled #1", &numbers(&json["z"]["settled"][0]), &interleaved(&initial.settled[0]), false);
    compare(states, "settled #2", &numbers(&json["z"]["settled"][1]), &interleaved(&initial.settled[1]), false);
    let first = &json["first_window"][0];
    if lower_forces {
        compare(&mut comparison.force_ranges, "forces at the lower bounds", &numbers(&first["min_forces"]), &initial.first.force_range[0], true);
    }
    compare(&mut comparison.force_ranges, "forces at the upper bounds", &numbers(&first["max_forces"]), &initial.first.force_range[1], true);
    comparison.performance = [initial.first.performance, first["performance"].as_f64().ok_or("initial.json: no performance")?];
    Ok(())
}

/// Each of our rows against OpenSim's at the same time, by kind of column.
fn compare_rows(name: &str, opensim: &StorageTable, ours: &StorageTable, muscles: &[String], comparison: &mut CmcComparison) {
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
            } else if label.ends_with("/activation") || muscles.contains(label) {
                &mut comparison.muscles
            } else {
                &mut comparison.reserves
            };
            worst.update((row[j] - other[j]).abs(), || format!("{name} at {} s, {label}", row[0]));
        }
    }
    let first = ours.rows().next().map_or(0.0, |r| r[0]);
    let window = 0.01;
    let at_windows = theirs.iter().filter(|r| ((r[0] - first) / window - ((r[0] - first) / window).round()).abs() < 1e-6).count();
    comparison.missing_rows += at_windows.saturating_sub(matched);
}
