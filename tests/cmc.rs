//! OpenSim's CMCTool (computed muscle control) on arm26 against OpenSim 4.6's
//! (`fixtures/golden/cmc`, `oracle/gen_cmc.py`), end to end through `osim-tune run`, and the
//! setups it refuses.

mod common;

use std::path::Path;

use common::{fixture, osim_tune};
use osim_tune::validation::{cmc_tolerances, compare_cmc_case, CMC_CASES, CMC_INITIAL_TOLERANCE, CMC_INPUTS};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Copies case `case`'s setup and every input into `folder`, the setup's text with `edits`.
fn case_folder(folder: &Path, case: &str, edits: &[(&str, &str)]) {
    for (name, source) in CMC_INPUTS {
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), folder.join(name)).unwrap();
    }
    let mut setup = std::fs::read_to_string(fixture(&format!("golden/cmc/{case}/setup.xml"))).unwrap();
    for (old, new) in edits {
        assert!(setup.contains(old), "no {old:?}");
        setup = setup.replace(old, new);
    }
    std::fs::write(folder.join("setup.xml"), setup).unwrap();
}

/// Both golden cases: the muscles' settled initial states and the first window's force range to
/// OpenSim's printed digits, the first window's target at least as well met as OpenSim's IPOPT
/// meets it, and the tracked motion at every window's end within each case's stated bounds
/// (`cmc_tolerances`).
#[test]
fn cmc_agrees_with_opensim() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for case in CMC_CASES {
        let bounds = cmc_tolerances(case);
        let (comparison, outputs) = compare_cmc_case(root, case).unwrap();
        assert!(comparison.missing_files.is_empty() && comparison.extra_files.is_empty(), "{case}: {comparison:?}");
        assert!(comparison.initial.error < CMC_INITIAL_TOLERANCE, "{case}: {:?}", comparison.initial);
        assert_eq!(comparison.initial.count, 52, "{case}: initial values compared");
        let [ours, opensim] = comparison.performance;
        assert!(ours <= opensim * (1.0 + 1e-9) && ours >= 0.99 * opensim, "{case}: performance ours {ours}, OpenSim {opensim}");
        assert!(comparison.coordinates.error < bounds.coordinates, "{case}: {:?}", comparison.coordinates);
        assert!(comparison.speeds.error < bounds.speeds, "{case}: {:?}", comparison.speeds);
        assert!(comparison.muscles.error < bounds.muscles, "{case}: {:?}", comparison.muscles);
        assert!(comparison.fibers.error < bounds.fibers, "{case}: {:?}", comparison.fibers);
        assert!(comparison.reserves.error < bounds.reserves, "{case}: {:?}", comparison.reserves);
        assert_eq!((comparison.missing_rows, comparison.extra_rows), (0, 0), "{case}: every window's end, and only those");
        assert_eq!(outputs.windows, if case == "fast" { 21 } else { 16 });
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

/// What CMC cannot run is refused with the setup named, and nothing is written.
#[test]
fn unusable_setups_are_refused() {
    let cases: [(&[(&str, &str)], &str); 5] = [
        (&[("<constraints_file />", "<constraints_file /><rra_controls_file>rra_controls.xml</rra_controls_file>")], "rra_controls_file"),
        (&[("<use_verbose_printing>", "<actuators_to_exclude>BRA</actuators_to_exclude><use_verbose_printing>")], "actuators_to_exclude"),
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

