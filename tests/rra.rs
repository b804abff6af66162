//! OpenSim's RRATool (residual reduction): its mass-center adjustment and CMC tracking against
//! OpenSim 4.6's (`fixtures/golden/rra`, `oracle/gen_rra.py`), end to end through `osim-tune run`,
//! and the setups it refuses.

mod common;

use std::path::Path;

use common::{fixture, osim_tune};
use osim_tune::validation::{compare_rra_case, rra_tolerances, RRA_CASES, RRA_INPUTS, RRA_MASS_CENTER_TOLERANCE, RRA_REPORT_TOLERANCE};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Copies case `case`'s setup and every input into `folder`, the setup's text with `edits`.
fn case_folder(folder: &Path, case: &str, edits: &[(&str, &str)]) {
    for (name, source) in RRA_INPUTS {
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), folder.join(name)).unwrap();
    }
    let mut setup = std::fs::read_to_string(fixture(&format!("golden/rra/{case}/setup.xml"))).unwrap();
    for (old, new) in edits {
        assert!(setup.contains(old), "no {old:?}");
        setup = setup.replace(old, new);
    }
    std::fs::write(folder.join("setup.xml"), setup).unwrap();
}

/// Both golden cases: the adjusted mass center, the report's numbers, and the tracked motion at
/// every window's end — position errors, states, controls, Kinematics and Actuation tables —
/// each within its stated bound (`rra_tolerances`).
#[test]
fn rra_agrees_with_opensim() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for case in RRA_CASES {
        let (table_tolerance, error_tolerance) = rra_tolerances(case);
        let (comparison, outputs) = compare_rra_case(root, case).unwrap();
        assert!(comparison.missing_files.is_empty() && comparison.extra_files.is_empty(), "{case}: {comparison:?}");
        assert!(comparison.mass_center < RRA_MASS_CENTER_TOLERANCE, "{case}: {}", comparison.mass_center);
        assert!(comparison.report.error < RRA_REPORT_TOLERANCE, "{case}: {:?}", comparison.report);
        assert!(comparison.tables.error < table_tolerance, "{case}: {:?}", comparison.tables);
        assert!(comparison.position_errors.error < error_tolerance, "{case}: {:?}", comparison.position_errors);
        assert_eq!((comparison.missing_rows, comparison.extra_rows), (0, 0), "{case}: every window's end, and only those");
        assert!(comparison.tables.count > 10_000, "{case}: {} values compared", comparison.tables.count);
        assert_eq!(outputs.windows, if case == "walk" { 49 } else { 79 });
    }
}

/// `osim-tune run` writes RRA's files under OpenSim's names, reports the adjustment, and the
/// adjusted model differs from the model it read in the adjusted body's mass center only.
#[test]
fn run_writes_rras_files_and_the_adjusted_model() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    case_folder(dir, "walk", &[]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.starts_with("osim-tune rra ") && stdout.contains("Mass-center adjustment of torso") && stdout.contains("Recommended mass adjustments"), "{stdout}");
    let mut written: Vec<String> = std::fs::read_dir(dir.join("Results")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    written.sort();
    let expected = std::fs::read_to_string(fixture("golden/rra/walk/files.txt")).unwrap();
    assert_eq!(written, expected.lines().collect::<Vec<_>>());
    let original = std::fs::read_to_string(dir.join("subject01_simbody.osim")).unwrap();
    let adjusted = std::fs::read_to_string(dir.join("Results/subject01_walk1_RRA_walk_adjusted.osim")).unwrap();
    let changed: Vec<(&str, &str)> = original.lines().zip(adjusted.lines()).filter(|(a, b)| a != b).collect();
    assert_eq!(original.lines().count(), adjusted.lines().count());
    assert_eq!(changed.len(), 1, "{changed:?}");
    assert!(changed[0].1.trim().starts_with("<mass_center>"), "{changed:?}");
    let residuals = std::fs::read_to_string(dir.join("Results/subject01_walk1_RRA_walk_avgResiduals.txt")).unwrap();
    assert!(residuals.starts_with("Average Residuals:\n\nFX average = "), "{residuals}");
}

/// What RRA cannot run is refused with the setup named, and nothing is written.
#[test]
fn unusable_setups_are_refused() {
    let cases: [(&[(&str, &str)], &str); 5] = [
        (&[("<desired_points_file />", "<desired_points_file>points.sto</desired_points_file>")], "desired_points_file"),
        (&[("<replace_force_set>true</replace_force_set>", "<replace_force_set>false</replace_force_set>")], "ideal actuators only"),
        (&[("<task_set_file>gait2354_RRA_Tasks.xml</task_set_file>", "<task_set_file>none.xml</task_set_file>")], "task_set_file"),
        (&[("<adjusted_com_body>torso</adjusted_com_body>", "<adjusted_com_body>head</adjusted_com_body>")], "head"),
        (&[("<adjusted_com_body>torso</adjusted_com_body>", "<adjusted_com_body></adjusted_com_body>")], "adjusted_com_body"),
    ];
    for (edits, expected) in cases {
        let folder = tempfile::tempdir().unwrap();
        case_folder(folder.path(), "walk", edits);
        let (code, _, stderr) = osim_tune(&["run", s(&folder.path().join("setup.xml"))]);
        assert_eq!(code, 2, "{expected}: {stderr}");
        assert!(stderr.contains(expected), "{expected}: {stderr}");
        assert!(!folder.path().join("Results").exists(), "{expected}: nothing written");
    }
}

/// A task on a coordinate the model lacks is named with its file.
#[test]
fn a_task_on_an_unknown_coordinate_is_named() {
    let stderr = refused_with_tasks_edited("<coordinate> pelvis_tz </coordinate>", "<coordinate> pelvis_tw </coordinate>");
    assert!(stderr.contains("gait2354_RRA_Tasks.xml") && stderr.contains("pelvis_tw"), "{stderr}");
}

/// The walk case with its first `old` of the task file replaced by `new`: RRA exits 2 and
/// writes nothing; its error output.
fn refused_with_tasks_edited(old: &str, new: &str) -> String {
    let folder = tempfile::tempdir().unwrap();
    case_folder(folder.path(), "walk", &[]);
    let tasks = folder.path().join("gait2354_RRA_Tasks.xml");
    let text = std::fs::read_to_string(&tasks).unwrap();
    assert!(text.contains(old), "{old}");
    std::fs::write(&tasks, text.replacen(old, new, 1)).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&folder.path().join("setup.xml"))]);
    assert_eq!(code, 2, "{stderr}");
    assert!(!folder.path().join("Results").exists(), "nothing written");
    stderr
}

/// A muscle state tracking task has no muscle to act on in RRA: refused, naming the task.
#[test]
fn a_muscle_state_task_is_refused() {
    let stderr = refused_with_tasks_edited("<objects>", "<objects><MuscleStateTrackingTask name=\"soleus_r.activation\" />");
    assert!(stderr.contains("gait2354_RRA_Tasks.xml") && stderr.contains("soleus_r.activation") && stderr.contains("RRA drives no muscles"), "{stderr}");
}
