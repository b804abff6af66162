//! OpenSim's CMCTool (computed muscle control) on arm26 against OpenSim 4.6's
//! (`fixtures/golden/cmc`, `oracle/gen_cmc.py`), end to end through `osim-tune run`, and the
//! setups it refuses.

mod common;

use std::path::Path;

use common::{fixture, osim_tune};
use osim_tune::validation::{cmc_inputs, cmc_tolerances, compare_cmc_case, CMC_CASES, POSITION_ERROR_MARGIN};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Copies case `case`'s setup and every input into `folder`, the setup's text with `edits`.
fn case_folder(folder: &Path, case: &str, edits: &[(&str, &str)]) {
    for &(name, source) in cmc_inputs(case) {
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), folder.join(name)).unwrap();
    }
    let mut setup = std::fs::read_to_string(fixture(&format!("golden/cmc/{case}/setup.xml"))).unwrap();
    for (old, new) in edits {
        assert!(setup.contains(old), "no {old:?}");
        setup = setup.replace(old, new);
    }
    std::fs::write(folder.join("setup.xml"), setup).unwrap();
}

/// Every golden case: the muscles' default and settled states and the first window's force range
/// to OpenSim's printed digits (the walk's within its integration's reach), the first window's
/// target at least as well met as OpenSim's IPOPT meets it, the tasks tracked as closely as
/// OpenSim tracks them, and the tracked motion at every window's end within each case's stated
/// bounds (`cmc_tolerances`).
#[test]
fn cmc_agrees_with_opensim() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for case in CMC_CASES {
        let bounds = cmc_tolerances(case);
        let (c, outputs) = compare_cmc_case(root, case).unwrap();
        assert!(c.missing_files.is_empty() && c.extra_files.is_empty(), "{case}: {c:?}");
        assert!(c.initial_states.error < bounds.initial_states, "{case}: {:?}", c.initial_states);
        assert!(c.force_ranges.error < bounds.force_ranges, "{case}: {:?}", c.force_ranges);
        // Muscles and actuators: arm26's 6 and 2 reserves; gait2392's 92 and gait2354's 6 residuals
        // and 6 reserves.
        // (exclude: BRA and TRImed settle but are not CMC's to control; prescribed: BRA is not).
        let (muscles, generators) = match case { "walk" => (92, 104), "exclude" => (6, 6), "prescribed" => (6, 7), _ => (6, 8) };
        assert_eq!((c.initial_states.count, c.force_ranges.count), (3 * 2 * muscles, if bounds.lower_forces { 2 * generators } else { generators }), "{case}: values compared");
        let [ours, opensim] = c.performance;
        assert!(ours <= opensim * (1.0 + 1e-9) && ours >= 0.98 * opensim, "{case}: performance ours {ours}, OpenSim {opensim}");
        let [ours, opensim] = c.position_errors;
        assert!(ours <= opensim * (1.0 + POSITION_ERROR_MARGIN), "{case}: largest position error ours {ours}, OpenSim {opensim}");
        let tracked = bounds.tracked;
        assert!(c.coordinates.error < tracked.coordinates, "{case}: {:?}", c.coordinates);
        assert!(c.speeds.error < tracked.speeds, "{case}: {:?}", c.speeds);
        assert!(c.muscles.error < tracked.muscles, "{case}: {:?}", c.muscles);
        assert!(c.fibers.error < tracked.fibers, "{case}: {:?}", c.fibers);
        assert!(c.reserves.error < tracked.reserves, "{case}: {:?}", c.reserves);
        assert_eq!((c.missing_rows, c.extra_rows), (0, 0), "{case}: every window's end, and only those");
        assert_eq!(outputs.windows, match case { "fast" | "exclude" | "prescribed" | "emg" => 21, "slow" => 16, _ => 2 });
    }
}

/// `osim-tune run` writes CMC's files under OpenSim's names, tracking from 0.03 s after the
/// initial time as OpenSim does with muscles.
#[test]
fn run_writes_cmcs_files() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    case_folder(dir, "slow", &[]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.starts_with("osim-tune cmc ") && stdout.contains("tracked from 0.23"), "{stdout}");
    let mut written: Vec<String> = std::fs::read_dir(dir.join("Results")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    written.sort();
    let expected = std::fs::read_to_string(fixture("golden/cmc/slow/files.txt")).unwrap();
    assert_eq!(written, expected.lines().collect::<Vec<_>>());
    let controls = std::fs::read_to_string(dir.join("Results/arm26_CMC_slow_controls.xml")).unwrap();
    assert_eq!(controls.matches("<use_steps>true</use_steps>").count(), 6, "the six muscles' controls step, the reserves' ramp");
}

/// Actuators left out of CMC's control (`actuators_to_exclude`) keep the model's control, 0, in
/// the controls table and are not among CMC's own controls (the `ControlSet`), as OpenSim writes
/// them; a name no actuator has is reported and ignored.
#[test]
fn excluded_actuators_keep_the_models_zero_control() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    case_folder(dir, "exclude", &[]);
    let (code, _, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("no actuator is named \"r_elbow_flex\""), "{stderr}");
    let controls = osim_tune::io::table::StorageTable::read(&dir.join("Results/arm26_CMC_exclude_controls.sto")).unwrap();
    let opensim = osim_tune::io::table::StorageTable::read(&fixture("golden/cmc/exclude/arm26_CMC_exclude_controls.sto")).unwrap();
    assert_eq!(controls.labels(), opensim.labels());
    for muscle in ["BRA", "TRImed"] {
        assert!(controls.column(muscle).unwrap().iter().all(|&u| u == 0.0), "{muscle}");
    }
    assert!(controls.column("BIClong").unwrap().iter().any(|&u| u > 0.1), "the others are CMC's to set");
    let control_set = std::fs::read_to_string(dir.join("Results/arm26_CMC_exclude_controls.xml")).unwrap();
    let opensim_set = std::fs::read_to_string(fixture("golden/cmc/exclude/arm26_CMC_exclude_controls.xml")).unwrap();
    let names = |text: &str| text.match_indices("<ControlLinear name=\"").map(|(i, m)| text[i + m.len()..].split('"').next().unwrap().to_string()).collect::<Vec<_>>();
    assert_eq!(names(&control_set), names(&opensim_set));
    assert!(!control_set.contains("BRA.excitation") && !control_set.contains("TRImed.excitation"));
}

/// What CMC cannot run is refused with the setup named, and nothing is written.
#[test]
fn unusable_setups_are_refused() {
    let cases: [(&[(&str, &str)], &str); 6] = [
        (&[("<ControllerSet name=\"Controllers\">\n\t\t\t<objects />", "<ControllerSet name=\"Controllers\">\n\t\t\t<objects><ToyReflexController name=\"reflex\" /></objects>")], "controllers osim-tune does not apply"),
        (&[("<constraints_file />", "<constraints_file /><rra_controls_file>rra_controls.xml</rra_controls_file>")], "rra_controls_file"),
        (&[("<actuators_to_exclude />", "<actuators_to_exclude>TRIlong TRIlat TRImed BIClong BICshort BRA r_shoulder_elev_reserve r_elbow_flex_reserve</actuators_to_exclude>")], "leaves CMC no actuator"),
        (&[("<desired_points_file />", "<desired_points_file>points.sto</desired_points_file>")], "desired_points_file"),
        (&[("<task_set_file>arm26_ComputedMuscleControl_Tasks.xml</task_set_file>", "<task_set_file>none.xml</task_set_file>")], "task_set_file"),
        (&[("<cmc_time_window>0.01</cmc_time_window>", "<cmc_time_window>-0.01</cmc_time_window>")], "cmc_time_window"),
    ];
    for (edits, expected) in cases {
        let folder = tempfile::tempdir().unwrap();
        case_folder(folder.path(), "slow", edits);
        let (code, _, stderr) = osim_tune(&["run", s(&folder.path().join("setup.xml"))]);
        assert_eq!(code, 2, "{expected}: {stderr}");
        assert!(stderr.contains(expected), "{expected}: {stderr}");
        assert!(!folder.path().join("Results").exists(), "{expected}: nothing written");
    }
}


/// A `MuscleStateTrackingTask` needs its state in the model and its data in the task set's
/// `datafile`, in time order (OpenSim ignores a task without data and then fails on it): each gap is refused
/// naming the file and the task, and nothing is written.
#[test]
fn muscle_state_tasks_without_their_data_are_refused() {
    let (tasks, data) = ("arm26_ComputedMuscleControl_Tasks_EMG.xml", "muscle_emg.sto");
    let cases = [
        (tasks, "<datafile>muscle_emg.sto</datafile>", "", "tracks the task set's <datafile>, which is not given"),
        (tasks, "<datafile>muscle_emg.sto</datafile>", "<datafile>emg.sto</datafile>", "emg.sto"),
        (tasks, "\"BIClong.activation\"", "\"BICshort.activation\"", "no column \"BICshort.activation\""),
        (tasks, "\"BIClong.activation\"", "\"BIClong.excitation\"", "muscle BIClong has no state \"excitation\" (its states: activation, fiber_length)"),
        (tasks, "\"BIClong.activation\"", "\"biceps.activation\"", "the model has no muscle \"biceps\""),
        (data, "\n0.2\t", "\n0.05\t", "times must increase"),
    ];
    for (file, old, new, expected) in cases {
        let folder = tempfile::tempdir().unwrap();
        case_folder(folder.path(), "emg", &[]);
        let text = std::fs::read_to_string(folder.path().join(file)).unwrap();
        assert!(text.contains(old), "{old}");
        std::fs::write(folder.path().join(file), text.replace(old, new)).unwrap();
        let (code, _, stderr) = osim_tune(&["run", s(&folder.path().join("setup.xml"))]);
        assert_eq!(code, 2, "{expected}: {stderr}");
        assert!(stderr.contains(expected), "{expected}: {stderr}");
        assert!(!folder.path().join("Results").exists(), "{expected}: nothing written");
    }
}
