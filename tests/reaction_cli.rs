//! `osim-tune reaction`: OpenSim's JointReaction analysis from the command line, and its
//! refusals.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::io::table::StorageTable;

const MODEL: &str = "fixtures/models/arm26.osim";
const MOTION: &str = "fixtures/golden/static_optimization/arm26/arm26_motion.mot";
const RESERVES: &str = "fixtures/golden/static_optimization/arm26/arm26_reserves.xml";
const FORCES: &str = "fixtures/golden/static_optimization/arm26/arm26_StaticOptimization_force.sto";
const GOLDEN: &str = "fixtures/golden/joint_reaction/arm26/arm26_JointReactionParent_ReactionLoads.sto";

fn path(relative: &str) -> String {
    common::root().join(relative).display().to_string()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// An AnalyzeTool setup with a JointReaction as OpenSim writes one, its files absolute.
fn setup(folder: &Path, forces: &str) -> PathBuf {
    let text = format!(
        r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
    <AnalyzeTool name="arm26">
        <force_set_files> {reserves}</force_set_files>
        <replace_force_set>false</replace_force_set>
        <initial_time>0.1</initial_time>
        <final_time>0.9</final_time>
        <AnalysisSet name="Analyses">
            <objects>
                <JointReaction name="JointReaction">
                    <on>true</on>
                    <forces_file>{forces}</forces_file>
                    <joint_names> ALL</joint_names>
                    <apply_on_bodies> parent</apply_on_bodies>
                    <express_in_frame> child</express_in_frame>
                </JointReaction>
            </objects>
        </AnalysisSet>
        <coordinates_file>{motion}</coordinates_file>
        <lowpass_cutoff_frequency_for_coordinates>-1</lowpass_cutoff_frequency_for_coordinates>
    </AnalyzeTool>
</OpenSimDocument>
"#,
        reserves = path(RESERVES),
        motion = path(MOTION),
    );
    let file = folder.join("setup.xml");
    std::fs::write(&file, text).unwrap();
    file
}

/// From a setup alone: OpenSim's file name and labels, and its values (OpenSim 4.6's own
/// analysis of the same forces agrees to 6.6e-11 N, see tests/joint_reaction.rs).
#[test]
fn a_setup_reproduces_opensims_analysis() {
    let folder = tempfile::tempdir().unwrap();
    let setup = setup(folder.path(), &path(FORCES));
    let output = folder.path().join("out");
    let (code, stdout, stderr) = osim_tune(&["reaction", &path(MODEL), &path(MOTION), "--setup", s(&setup), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("3 joint loads at 81 frames"), "{stdout}");
    let ours = StorageTable::read(&output.join("arm26_JointReaction_ReactionLoads.sto")).unwrap();
    let golden = StorageTable::read(Path::new(&path(GOLDEN))).unwrap();
    assert_eq!(ours.labels(), golden.labels());
    let worst = ours.values().iter().zip(golden.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
}

/// The command line overrides the setup: the chosen joint, side and frame only.
#[test]
fn flags_choose_joints_sides_and_frames() {
    let folder = tempfile::tempdir().unwrap();
    let arguments = ["reaction", &path(MODEL), &path(MOTION), "--forces", &path(FORCES), "--actuators", &path(RESERVES), "--joints", "r_elbow", "--on", "child", "--in", "r_humerus", "--time", "0.2", "0.3", "--name", "elbow", "-o", s(folder.path())];
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    let table = StorageTable::read(&folder.path().join("elbow_JointReaction_ReactionLoads.sto")).unwrap();
    assert_eq!(table.labels()[1], "r_elbow_on_r_ulna_radius_hand_in_r_humerus_fx", "{stdout}");
    assert_eq!((table.n_columns(), table.n_rows()), (10, 11));
}

/// Each refusal names what is wrong and writes nothing.
#[test]
fn bad_requests_are_refused_naming_the_problem() {
    let folder = tempfile::tempdir().unwrap();
    let out = folder.path().join("out");
    let base = ["reaction", &path(MODEL), &path(MOTION)];
    let run = |extra: &[&str]| {
        let arguments: Vec<&str> = base.iter().copied().chain(extra.iter().copied()).chain(["-o", s(&out)]).collect();
        osim_tune(&arguments)
    };
    let with_reserves = |extra: &[&str]| -> Vec<String> { ["--forces", FORCES, "--actuators", RESERVES].iter().map(|p| if p.starts_with("--") { p.to_string() } else { path(p) }).chain(extra.iter().map(|e| e.to_string())).collect() };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec![], "no forces file"),
        (with_reserves(&["--joints", "knee"]), "joint \"knee\" does not exist in the model"),
        (with_reserves(&["--on", "both"]), "apply_on_bodies (--on) \"both\": expected child or parent"),
        (with_reserves(&["--in", "r_humerus,ground,child,parent"]), "express_in_frame (--in) has 4 entries; expected 1 or one per joint (3)"),
        (with_reserves(&["--time", "0", "0.05"]), "do not cover t = 0 s"),
        (with_reserves(&["--step-interval", "0"]), "--step-interval 0"),
    ];
    for (extra, expected) in cases {
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let (code, _, stderr) = run(&extra);
        assert_eq!(code, 2, "{extra:?}: {stderr}");
        assert!(stderr.contains(expected), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?} wrote output");
    }
}

/// A forces file without a column for one of the model's actuators is refused, naming it.
#[test]
fn a_missing_actuator_column_is_named() {
    let folder = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(path(FORCES)).unwrap().replace("\tBIClong\t", "\tBIClong_renamed\t");
    let forces = folder.path().join("forces.sto");
    std::fs::write(&forces, text).unwrap();
    let (code, _, stderr) = osim_tune(&["reaction", &path(MODEL), &path(MOTION), "--forces", s(&forces), "--actuators", &path(RESERVES), "-o", s(&folder.path().join("out"))]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("forces.sto: no column for the actuator(s) BIClong;"), "{stderr}");
}

/// A row whose forces file holds NaN (a frame static optimisation did not solve) gives NaN
/// loads there, with a warning; the other rows are computed.
#[test]
fn a_nan_force_row_is_reported() {
    let folder = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(path(FORCES)).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let row = lines.iter().position(|l| l.trim_start().starts_with("0.5")).unwrap();
    let mut fields: Vec<String> = lines[row].split('\t').map(str::to_string).collect();
    fields[1] = "NaN".into(); // TRIlong at t = 0.5 s
    lines[row] = fields.join("\t");
    let forces = folder.path().join("forces.sto");
    std::fs::write(&forces, lines.join("\n") + "\n").unwrap();
    let out = folder.path().join("out");
    let (code, _, stderr) = osim_tune(&["reaction", &path(MODEL), &path(MOTION), "--forces", s(&forces), "--actuators", &path(RESERVES), "--time", "0.45", "0.55", "--name", "arm", "-o", s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("warning: 1 rows (from t = 0.5 s) have a force that is not a number"), "{stderr}");
    let table = StorageTable::read(&out.join("arm_JointReaction_ReactionLoads.sto")).unwrap();
    for (k, time) in table.times().iter().enumerate() {
        let nan = table.row(k).unwrap()[1..].iter().any(|v| v.is_nan());
        assert_eq!(nan, (time - 0.5).abs() < 1e-9, "t = {time}");
    }
}

/// A model whose constraints osim-tune does not apply (here a RollingOnSurfaceConstraint) is
/// refused by the dynamics commands, naming the constraint; a disabled one is not in the way.
#[test]
fn unsupported_constraints_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let weld = |enforced: &str| {
        format!("<objects><RollingOnSurfaceConstraint name=\"hold\"><isEnforced>{enforced}</isEnforced><socket_rolling_body>/bodyset/r_humerus</socket_rolling_body><socket_surface_body>/ground</socket_surface_body></RollingOnSurfaceConstraint></objects>")
    };
    let original = std::fs::read_to_string(path(MODEL)).unwrap();
    for (enforced, expected_code) in [("true", 2), ("false", 0)] {
        let model = folder.path().join(format!("arm26_{enforced}.osim"));
        let set = "<ConstraintSet name=\"constraintset\">";
        let at = original.find(set).unwrap() + set.len();
        let edited = format!("{}{}", &original[..at], original[at..].replacen("<objects />", &weld(enforced), 1));
        std::fs::write(&model, edited).unwrap();
        let out = folder.path().join(format!("out_{enforced}"));
        let (code, _, stderr) = osim_tune(&["reaction", s(&model), &path(MOTION), "--forces", &path(FORCES), "--actuators", &path(RESERVES), "--time", "0.1", "0.9", "-o", s(&out)]);
        assert_eq!(code, expected_code, "{enforced}: {stderr}");
        if expected_code == 2 {
            assert!(stderr.contains("hold (RollingOnSurfaceConstraint)") && stderr.contains("only CoordinateCouplerConstraints"), "{stderr}");
            assert!(!out.exists());
        }
    }
}

/// Without --time or a setup, the analysis covers the forces file's times.
#[test]
fn the_forces_file_sets_the_default_time_range() {
    let folder = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = osim_tune(&["reaction", &path(MODEL), &path(MOTION), "--forces", &path(FORCES), "--actuators", &path(RESERVES), "--joints", "r_elbow", "-o", s(folder.path())]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("1 joint loads at 81 frames") && stdout.contains("(0.1000–0.9000 s)"), "{stdout}");
}

/// A `<ForceSet>` written as the root element (no `<OpenSimDocument>`, as OpenSim also reads)
/// adds the same actuators.
#[test]
fn a_bare_force_set_file_is_read() {
    let folder = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(path(RESERVES)).unwrap();
    let (start, end) = (text.find("<ForceSet").unwrap(), text.find("</ForceSet>").unwrap() + "</ForceSet>".len());
    let bare = folder.path().join("reserves.xml");
    std::fs::write(&bare, format!("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n{}\n", &text[start..end])).unwrap();
    let tables: Vec<StorageTable> = [path(RESERVES), bare.display().to_string()]
        .iter()
        .enumerate()
        .map(|(k, reserves)| {
            let out = folder.path().join(format!("out{k}"));
            let (code, _, stderr) = osim_tune(&["reaction", &path(MODEL), &path(MOTION), "--forces", &path(FORCES), "--actuators", reserves, "--name", "arm", "-o", s(&out)]);
            assert_eq!(code, 0, "{reserves}: {stderr}");
            StorageTable::read(&out.join("arm_JointReaction_ReactionLoads.sto")).unwrap()
        })
        .collect();
    assert_eq!(tables[0].values(), tables[1].values());
}

/// The chain the README gives for a forward simulation's joint loads: `forward` writes each
/// muscle's tendon force, `reaction --forces` takes them as its muscles' forces (arm26 has no
/// other actuator) over the simulation's times; with every force zero instead, the joints carry
/// other loads.
#[test]
fn forward_tendon_forces_drive_the_reaction() {
    let folder = tempfile::tempdir().unwrap();
    let case = common::root().join("fixtures/golden/forward/arm26");
    let (motion, excitations) = (case.join("motion.mot"), case.join("excitations.sto"));
    let simulation = folder.path().join("forward");
    let (code, _, stderr) = osim_tune(&["forward", &path(MODEL), s(&motion), "--excitations", s(&excitations), "--time", "0.2", "0.8", "--name", "arm", "-o", s(&simulation)]);
    assert_eq!(code, 0, "{stderr}");
    let tendon_forces = simulation.join("arm_tendon_force.sto");
    let reaction = |forces: &Path, out: &Path| {
        let (code, stdout, stderr) = osim_tune(&["reaction", &path(MODEL), s(&motion), "--forces", s(forces), "--name", "arm", "-o", s(out)]);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains("3 joint loads at 61 frames") && stdout.contains("(0.2000–0.8000 s)"), "{stdout}");
        StorageTable::read(&out.join("arm_JointReaction_ReactionLoads.sto")).unwrap()
    };
    let driven = reaction(&tendon_forces, &folder.path().join("driven"));
    assert!(driven.values().iter().all(|v| v.is_finite()));
    let table = StorageTable::read(&tendon_forces).unwrap();
    assert!(table.rows().all(|row| row[1..].iter().all(|f| *f > 0.0)), "every muscle pulls");
    let zeros = folder.path().join("zero_force.sto");
    let labels: Vec<String> = table.labels().to_vec();
    let values: Vec<f64> = table.rows().flat_map(|row| std::iter::once(row[0]).chain(row[1..].iter().map(|_| 0.0)).collect::<Vec<_>>()).collect();
    std::fs::write(&zeros, StorageTable::new("zero", labels, values).unwrap().to_text()).unwrap();
    let passive = reaction(&zeros, &folder.path().join("passive"));
    let largest = driven.values().iter().zip(passive.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(largest > 1.0, "the muscles' forces change the joint loads by {largest} N");
}
