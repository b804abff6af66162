//! `osim-tune run SETUP.xml`: OpenSim tool setups run as `opensim-cmd run-tool` runs them — the
//! files they name, outputs under OpenSim's names — checked against OpenSim 4.6's outputs, and
//! the setups it refuses.

mod common;

use std::path::{Path, PathBuf};

use common::{fixture, osim_tune};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::xml::Document;
use osim_tune::io::table::StorageTable;
use osim_tune::tuning::scale::read_marker_set;
use osim_tune::validation::{compare_scaled_models, row_errors, row_tolerance, ANALYZE_TOOL_CASES, ANALYZE_TOOL_INPUTS, SCALED_MODEL_TOLERANCE};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Copies `files` (relative to `fixtures/`) into `folder` under the names given.
fn copy_into(folder: &Path, files: &[(&str, &str)]) {
    for (from, to) in files {
        std::fs::copy(fixture(from), folder.join(to)).unwrap_or_else(|e| panic!("{from}: {e}"));
    }
}

/// Writes `file` in `folder` from the fixture `from` with `edits` (old → new text) applied.
fn edited_copy(folder: &Path, from: &str, file: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text = std::fs::read_to_string(fixture(from)).unwrap();
    for (old, new) in edits {
        assert!(text.contains(old), "{from}: no {old:?}");
        text = text.replace(old, new);
    }
    let path = folder.join(file);
    std::fs::write(&path, text).unwrap();
    path
}

/// The largest difference of `ours` from `opensim`'s row at the same time, over `columns`.
fn largest_difference(ours: &StorageTable, opensim: &StorageTable, columns: &[&str]) -> f64 {
    let mut largest = 0.0_f64;
    for (time, row) in ours.times().into_iter().zip(ours.rows()) {
        let k = opensim.times().iter().position(|t| (t - time).abs() < 1e-6).unwrap_or_else(|| panic!("OpenSim has no row at {time}"));
        for column in columns {
            let (i, j) = (ours.column_index(column).unwrap(), opensim.column_index(column).unwrap());
            largest = largest.max((row[i] - opensim.row(k).unwrap()[j]).abs());
        }
    }
    largest
}

/// OpenSim's subject01 example as a lab has it — the Scale setup and its files in one folder, the
/// generic model under the setup's name, the placed markers asked for as a MarkerSet file — then the IK and ID setups on the model scaling wrote:
/// every output lands under the name OpenSim gives it, the scaled-only model is OpenSim's, the
/// marker file holds the placed model's markers, the
/// IK errors file is `<name>_ik_marker_errors.sto` in the results directory, ID writes into its
/// results directory.
#[test]
fn the_subject01_setups_run_in_their_folder_as_opensim_names_the_outputs() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let scale_setup = edited_copy(dir, "subject01/subject01_Setup_Scale.xml", "subject01_Setup_Scale.xml", &[("<output_marker_file> Unassigned </output_marker_file>", "<output_marker_file> placed_markers.xml </output_marker_file>")]);
    copy_into(dir, &[
        ("subject01/gait2392_Scale_MarkerSet.xml", "gait2392_Scale_MarkerSet.xml"),
        ("subject01/subject01_static.trc", "subject01_static.trc"),
        ("../models/gait2392_millard2012muscle.osim", "gait2392_simbody.osim"),
        ("subject01/subject01_walk1.trc", "subject01_walk1.trc"),
        ("subject01/subject01_Setup_InverseDynamics.xml", "subject01_Setup_InverseDynamics.xml"),
        ("subject01/subject01_walk1_grf.xml", "subject01_walk1_grf.xml"),
        ("subject01/subject01_walk1_grf.mot", "subject01_walk1_grf.mot"),
    ]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&scale_setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.starts_with("osim-tune scale ") && stdout.contains("--scaled-only"), "{stdout}");
    let scaled = OsimDocument::read(&dir.join("subject01_scaledOnly.osim")).unwrap();
    let opensim = OsimDocument::read(&fixture("golden/scale/subject01_scaledOnly.osim")).unwrap();
    let differences = compare_scaled_models(&opensim, &scaled, SCALED_MODEL_TOLERANCE);
    assert!(differences.is_empty(), "{differences:#?}");
    assert_eq!(StorageTable::read(&dir.join("subject01_static_output.mot")).unwrap().n_rows(), 1);
    assert!(dir.join("subject01_scaleSet_applied.xml").is_file());
    let placed = OsimDocument::read(&dir.join("subject01_simbody.osim")).unwrap();
    let markers = read_marker_set(&dir.join("placed_markers.xml")).unwrap();
    // As many as OpenSim's placed model keeps (its golden has 39).
    let opensim_placed = OsimDocument::read(&fixture("golden/scale/subject01_simbody.osim")).unwrap();
    let opensim_markers = opensim_placed.xml.ids().filter(|&id| opensim_placed.xml.tag(id) == "Marker").count();
    assert_eq!(markers.len(), opensim_markers);
    for marker in &markers {
        let location = placed.xml.text(placed.resolve(&format!("/markerset/{}/location", marker.name)).unwrap()).unwrap();
        let location: Vec<f64> = location.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert_eq!(location, marker.location, "{}", marker.name);
    }

    let ik_setup = edited_copy(dir, "subject01/subject01_Setup_IK.xml", "subject01_Setup_IK.xml", &[("<time_range> 0.5 2.5</time_range>", "<time_range> 0.5 0.6</time_range>")]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&ik_setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.starts_with("osim-tune ik "), "{stdout}");
    assert_eq!(StorageTable::read(&dir.join("subject01_walk1_ik.mot")).unwrap().n_rows(), 7);
    assert_eq!(StorageTable::read(&dir.join("subject01_ik_marker_errors.sto")).unwrap().n_rows(), 7);

    let (code, _, stderr) = osim_tune(&["run", s(&dir.join("subject01_Setup_InverseDynamics.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    let forces = StorageTable::read(&dir.join("ResultsInverseDynamics/InverseDynamicsOutput.sto")).unwrap();
    assert!(forces.column_index("knee_angle_r_moment").is_some() && forces.n_rows() > 0);
}

/// An IK setup reporting errors and marker locations into a results directory, its trial named
/// with Windows separators, on OpenSim's scaled model (`oracle/gen_ik_marker_locations.py`: accuracy 1e-10): OpenSim 4.6's coordinates
/// to 1e-5 (° and m; 4.7e-7 found) and its `<name>_ik_model_marker_locations.sto` — the tracked
/// markers in its order — to 2e-8 m (printed to 1e-8).
#[test]
fn an_ik_setup_gives_opensims_coordinates_and_marker_locations() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/scale/subject01_simbody.osim", "subject01_simbody.osim"), ("subject01/subject01_walk1.trc", "subject01_walk1.trc")]);
    std::fs::create_dir(dir.join("data")).unwrap();
    std::fs::rename(dir.join("subject01_walk1.trc"), dir.join("data/subject01_walk1.trc")).unwrap();
    // Results in a subfolder; the trial named with Windows separators, as a setup from a Windows lab.
    let setup = edited_copy(dir, "golden/ik/marker_locations/setup_ik.xml", "setup_ik.xml", &[
        ("<results_directory>.</results_directory>", "<results_directory>results</results_directory>"),
        ("<marker_file>subject01_walk1.trc</marker_file>", "<marker_file>.\\data\\subject01_walk1.trc</marker_file>"),
    ]);
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    let ours = StorageTable::read(&dir.join("ik.mot")).unwrap();
    let opensim = StorageTable::read(&fixture("golden/ik/marker_locations/ik.mot")).unwrap();
    assert_eq!(ours.labels(), opensim.labels());
    assert!(largest_difference(&ours, &opensim, &column_names(&ours)) < 1e-5);
    let ours = StorageTable::read(&dir.join("results/subject01_ik_model_marker_locations.sto")).unwrap();
    let opensim = StorageTable::read(&fixture("golden/ik/marker_locations/subject01_ik_model_marker_locations.sto")).unwrap();
    assert_eq!((ours.labels(), ours.n_rows()), (opensim.labels(), 7));
    assert!(largest_difference(&ours, &opensim, &column_names(&ours)) < 2e-8);
    assert_eq!(StorageTable::read(&dir.join("results/subject01_ik_marker_errors.sto")).unwrap().n_rows(), 7);
}

/// Every column but time.
fn column_names(table: &StorageTable) -> Vec<&str> {
    table.labels()[1..].iter().map(String::as_str).collect()
}

/// An AnalyzeTool setup with a StaticOptimization and a JointReaction (OpenSim's arm26 runs,
/// `oracle/gen_static_optimization.py`): both run, each writing into the results directory under
/// OpenSim's names — `<tool>_<analysis>_…`, the analyses named `SO` and `reactions` here, as
/// OpenSim 4.6 names them (checked by hand) —, the controls also as a ControlSet; the reactions of
/// OpenSim's own forces are OpenSim's.
#[test]
fn an_analyze_setup_runs_static_optimization_then_joint_reaction() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[
        ("models/arm26.osim", "arm26.osim"),
        ("golden/static_optimization/arm26/arm26_motion.mot", "arm26_motion.mot"),
        ("golden/static_optimization/arm26/arm26_reserves.xml", "arm26_reserves.xml"),
        ("golden/static_optimization/arm26/arm26_StaticOptimization_force.sto", "opensim_forces.sto"),
    ]);
    let setup = dir.join("setup.xml");
    std::fs::write(&setup, ANALYZE_SETUP).unwrap();
    let (code, stdout, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    let commands: Vec<&str> = stdout.lines().filter(|l| l.starts_with("osim-tune ")).collect();
    assert_eq!(commands.len(), 2, "{stdout}");
    assert!(commands[0].starts_with("osim-tune so ") && commands[1].starts_with("osim-tune reaction "), "{stdout}");
    let activations = StorageTable::read(&dir.join("Results/arm26_SO_activation.sto")).unwrap();
    let opensim = StorageTable::read(&fixture("golden/static_optimization/arm26/arm26_StaticOptimization_activation.sto")).unwrap();
    assert_eq!((activations.labels(), activations.n_rows()), (opensim.labels(), opensim.n_rows()));
    // The controls as OpenSim's ControlSet: a ControlLinear per column, its nodes the rows
    // (OpenSim 4.6 reads it back to these values, checked by hand).
    let controls = Document::read(&dir.join("Results/arm26_SO_controls.xml")).unwrap();
    let linear: Vec<_> = controls.ids().filter(|&id| controls.tag(id) == "ControlLinear").collect();
    assert_eq!(linear.iter().map(|&id| controls.name(id).unwrap()).collect::<Vec<_>>(), activations.labels()[1..]);
    for (column, &control) in linear.iter().enumerate() {
        let nodes = controls.children(controls.child(control, "x_nodes").unwrap());
        let number = |node, tag| controls.text(controls.child(node, tag).unwrap()).unwrap().parse::<f64>().unwrap();
        let values: Vec<[f64; 2]> = nodes.iter().map(|&node| [number(node, "t"), number(node, "value")]).collect();
        let expected: Vec<[f64; 2]> = activations.rows().map(|row| [row[0], row[column + 1]]).collect();
        assert_eq!(values, expected);
    }
    let ours = StorageTable::read(&dir.join("Results/arm26_reactions_ReactionLoads.sto")).unwrap();
    let golden = StorageTable::read(&fixture("golden/joint_reaction/arm26/arm26_JointReactionParent_ReactionLoads.sto")).unwrap();
    assert_eq!(ours.labels(), golden.labels());
    let worst = ours.values().iter().zip(golden.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
    // An analysis without a name has an empty one in OpenSim's file names (checked by hand).
    std::fs::write(&setup, ANALYZE_SETUP.replace(r#"<StaticOptimization name="SO">"#, "<StaticOptimization>").replace("<results_directory>Results", "<results_directory>Unnamed")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(dir.join("Unnamed/arm26__activation.sto").is_file() && dir.join("Unnamed/arm26_reactions_ReactionLoads.sto").is_file());
}

/// arm26's AnalyzeTool, relative names as OpenSim's GUI writes them next to the files.
const ANALYZE_SETUP: &str = r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
    <AnalyzeTool name="arm26">
        <model_file>arm26.osim</model_file>
        <replace_force_set>false</replace_force_set>
        <force_set_files>arm26_reserves.xml</force_set_files>
        <results_directory>Results</results_directory>
        <initial_time>0.1</initial_time>
        <final_time>0.9</final_time>
        <AnalysisSet name="Analyses">
            <objects>
                <StaticOptimization name="SO"><on>true</on></StaticOptimization>
                <JointReaction name="reactions">
                    <on>true</on>
                    <forces_file>opensim_forces.sto</forces_file>
                    <joint_names> ALL</joint_names>
                    <apply_on_bodies> parent</apply_on_bodies>
                    <express_in_frame> child</express_in_frame>
                </JointReaction>
            </objects>
        </AnalysisSet>
        <coordinates_file>arm26_motion.mot</coordinates_file>
        <lowpass_cutoff_frequency_for_coordinates>-1</lowpass_cutoff_frequency_for_coordinates>
    </AnalyzeTool>
</OpenSimDocument>
"#;

/// The same setup reading a states file (OpenSim's forward simulation of arm26) instead of
/// coordinates: static optimisation and the joint reactions take its coordinates and speeds as
/// they are and spline the speeds for the accelerations, as OpenSim 4.6 does
/// (`oracle/gen_static_optimization.py` and `gen_joint_reaction.py`, case `arm26_states`):
/// OpenSim's controls meet our rows (its forces give the accelerations we track) and the reactions
/// of OpenSim's forces are OpenSim's.
#[test]
fn an_analyze_setup_reads_a_states_file_for_static_optimization_and_joint_reaction() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[
        ("models/arm26.osim", "arm26.osim"),
        ("golden/analyze_tool/states/arm26_states.sto", "arm26_states.sto"),
        ("golden/static_optimization/arm26/arm26_reserves.xml", "arm26_reserves.xml"),
        ("golden/static_optimization/arm26_states/arm26_states_StaticOptimization_force.sto", "opensim_forces.sto"),
        ("golden/static_optimization/arm26_states/arm26_states_StaticOptimization_activation.sto", "opensim_activation.sto"),
    ]);
    let setup = dir.join("setup.xml");
    let text = ANALYZE_SETUP.replace("<coordinates_file>arm26_motion.mot</coordinates_file>", "<states_file>arm26_states.sto</states_file>");
    std::fs::write(&setup, text.replace("<initial_time>0.1</initial_time>", "<initial_time>0.05</initial_time>").replace("<final_time>0.9</final_time>", "<final_time>0.25</final_time>")).unwrap();
    let (code, stdout, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let activations = StorageTable::read(&dir.join("Results/arm26_SO_activation.sto")).unwrap();
    let opensim = StorageTable::read(&dir.join("opensim_activation.sto")).unwrap();
    assert_eq!((activations.labels(), activations.n_rows()), (opensim.labels(), opensim.n_rows()));
    let (code, stdout, stderr) = osim_tune(&["so", s(&dir.join("arm26.osim")), s(&dir.join("arm26_states.sto")), "--states", "--actuators", s(&dir.join("arm26_reserves.xml")), "--time", "0.05", "0.25", "--compare", s(&dir.join("opensim_activation.sto")), "-o", s(&dir.join("flags"))]);
    assert_eq!(code, 0, "{stderr}");
    let miss: f64 = stdout.split("its controls miss our constraints by at most ").nth(1).and_then(|t| t.split_whitespace().next()).and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("{stdout}"));
    assert!(miss < 1e-9, "OpenSim's controls miss our rows by {miss:e}");
    let ours = StorageTable::read(&dir.join("Results/arm26_reactions_ReactionLoads.sto")).unwrap();
    let golden = StorageTable::read(&fixture("golden/joint_reaction/arm26_states/arm26_states_JointReactionParent_ReactionLoads.sto")).unwrap();
    assert_eq!((ours.labels(), ours.n_rows()), (golden.labels(), golden.n_rows()));
    let worst = ours.values().iter().zip(golden.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
}

/// AnalyzeTool setups (`oracle/gen_analyze_tool.py`): a MuscleAnalysis of every muscle and
/// coordinate with the coordinates filtered at 6 Hz, and of listed muscles (out of the model's
/// order, one unknown) and coordinates (one unknown) every second row; Kinematics and
/// BodyKinematics of every coordinate and body filtered at 6 Hz, and of listed ones (in radians,
/// velocities in the bodies' frames, the analyses named otherwise) every second row;
/// PointKinematics; MuscleAnalysis, ForceReporter, Actuation and StatesReporter with the muscles at
/// their default states and equilibrated, on gait2392 (Thelen, Millard) and Rajagopal2016; the
/// walk with its ground reactions and the residual and reserve actuators of a force set. We
/// write exactly OpenSim 4.6's files — the accelerations too, the model's forward dynamics at
/// those states —, with its rows, columns and values to 2e-8 (m, °, rad, N, W up to 1000;
/// relative beyond; accelerations relative to the row's largest; printed to 1e-8: `row_errors`)
/// — 5e-5 in the one row where OpenSim's assembler stops short of a clamped coordinate's bound
/// (`row_tolerance`).
#[test]
fn analyze_tool_setups_give_opensims_tables() {
    for case in ANALYZE_TOOL_CASES {
        let folder = tempfile::tempdir().unwrap();
        let dir = folder.path();
        let golden = format!("golden/analyze_tool/{case}");
        copy_into(dir, &[(&format!("{golden}/setup.xml"), "setup.xml"), ("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot")]);
        for (name, source) in ANALYZE_TOOL_INPUTS {
            std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), dir.join(name)).unwrap();
        }
        let (code, stdout, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
        assert_eq!(code, 0, "{case}: {stderr}");
        assert!(stdout.starts_with("osim-tune analyze "), "{stdout}");
        let opensim_files = std::fs::read_to_string(fixture(&format!("{golden}/files.txt"))).unwrap();
        let formed: Vec<&str> = opensim_files.lines().collect();
        let mut ours: Vec<String> = std::fs::read_dir(dir.join("Results")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        ours.sort();
        assert_eq!(ours, formed, "{case}");
        for entry in std::fs::read_dir(fixture(&golden)).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            if !name.ends_with(".sto") || ANALYZE_TOOL_INPUTS.iter().any(|(input, _)| *input == name) {
                continue;
            }
            let opensim = StorageTable::read(&fixture(&format!("{golden}/{name}"))).unwrap();
            let table = StorageTable::read(&dir.join("Results").join(&name)).unwrap();
            assert_eq!((table.labels(), table.n_rows(), table.in_degrees()), (opensim.labels(), opensim.n_rows(), opensim.in_degrees()), "{case}: {name}");
            for (theirs, ours) in opensim.rows().zip(table.rows()) {
                let worst = row_errors(&name, theirs, ours).into_iter().fold(0.0, f64::max);
                assert!(worst < row_tolerance(case, theirs[0]), "{case}: {name} at {} s: {worst}", theirs[0]);
            }
        }
        if case == "listed" {
            assert!(stderr.contains("no_such_muscle") && stderr.contains("no_such_coordinate"), "{stderr}");
        }
    }
}

/// `--dry-run` prints the command and writes nothing.
#[test]
fn a_dry_run_prints_the_command_only() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("subject01/subject01_Setup_InverseDynamics.xml", "setup.xml"), ("golden/scale/subject01_simbody.osim", "subject01_simbody.osim"), ("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot")]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&dir.join("setup.xml")), "--dry-run"]);
    assert_eq!(code, 0, "{stderr}");
    let expected = format!("osim-tune id {0}/subject01_simbody.osim {0}/subject01_walk1_ik.mot --setup {0}/setup.xml -o {0}/ResultsInverseDynamics/InverseDynamicsOutput.sto\n", dir.display());
    assert_eq!(stdout, expected);
    assert!(!dir.join("ResultsInverseDynamics").exists());
    // A ScaleTool whose MarkerPlacer is off writes the scaled model where its ModelScaler says,
    // and neither a scaled-only copy nor a static pose.
    copy_into(dir, &[("subject01/gait2392_Scale_MarkerSet.xml", "gait2392_Scale_MarkerSet.xml"), ("../models/gait2392_millard2012muscle.osim", "gait2392_simbody.osim")]);
    let unplaced = edited_copy(dir, "subject01/subject01_Setup_Scale.xml", "scale.xml", &[("<MarkerPlacer name=\"\">\n\t\t\t<!--Whether or not to use the marker placer during scale-->\n\t\t\t<apply> true </apply>", "<MarkerPlacer name=\"\">\n\t\t\t<apply> false </apply>")]);
    let (code, stdout, stderr) = osim_tune(&["run", s(&unplaced), "--dry-run"]);
    assert_eq!(code, 0, "{stderr}");
    let expected = format!("osim-tune scale {0}/gait2392_simbody.osim --setup {0}/scale.xml -o {0}/subject01_scaledOnly.osim --scale-set {0}/subject01_scaleSet_applied.xml\n", dir.display());
    assert_eq!(stdout, expected);
}

/// A tool osim-tune does not run, a missing input, an unset output and an analysis naming a
/// coordinate the model lacks are errors naming the setup and what is wrong (exit 2, nothing
/// written); `info` on a setup points to `run`.
#[test]
fn setups_it_cannot_run_are_refused_naming_what_is_wrong() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let moco = dir.join("moco.xml");
    std::fs::write(&moco, "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n<MocoStudy name=\"walk\"><model_file>m.osim</model_file></MocoStudy>\n</OpenSimDocument>\n").unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&moco)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("moco.xml:3: <MocoStudy> is not a tool osim-tune runs"), "{stderr}");

    let speeds = dir.join("speeds.xml");
    std::fs::write(&speeds, ANALYZE_SETUP.replace("<coordinates_file>", "<speeds_file>u.sto</speeds_file><coordinates_file>")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&speeds)]);
    assert!(code == 2 && stderr.contains("speeds.xml: speeds_file \"u.sto\" is not supported"), "{stderr}");

    let outputs = dir.join("outputs.xml");
    std::fs::write(&outputs, ANALYZE_SETUP.replace(r#"<StaticOptimization name="SO"><on>true</on></StaticOptimization>"#, r#"<OutputReporter name="outputs"><on>true</on></OutputReporter>"#).replace("<on>true</on>\n                    <forces_file>", "<on>false</on>\n                    <forces_file>")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&outputs)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("outputs.xml: the AnalysisSet has no analysis osim-tune runs that is on (MuscleAnalysis, Kinematics, BodyKinematics, PointKinematics, ForceReporter, Actuation, StatesReporter, ProbeReporter, InducedAccelerations, StaticOptimization, JointReaction; others on: OutputReporter)"), "{stderr}");

    let ik = edited_copy(dir, "subject01/subject01_Setup_IK.xml", "ik.xml", &[]);
    let (code, _, stderr) = osim_tune(&["info", s(&ik)]);
    assert!(code == 2 && stderr.contains("<InverseKinematicsTool> is a tool setup, not a model; `osim-tune run --dry-run"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["run", s(&ik)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("ik.xml: model_file \"subject01_simbody.osim\": no such file"), "{stderr}");

    let windows = edited_copy(dir, "subject01/subject01_Setup_IK.xml", "windows.xml", &[("<model_file>subject01_simbody.osim</model_file>", "<model_file>C:\\lab\\subject01_simbody.osim</model_file>")]);
    let (code, _, stderr) = osim_tune(&["run", s(&windows)]);
    assert!(code == 2 && stderr.contains("a Windows path: give it relative to the setup's folder"), "{stderr}");
    let forward = edited_copy(dir, "subject01/subject01_Setup_IK.xml", "forward.xml", &[("<model_file>subject01_simbody.osim</model_file>", "<model_file>D:/lab/subject01_simbody.osim</model_file>")]);
    let (code, _, stderr) = osim_tune(&["run", s(&forward)]);
    assert!(code == 2 && stderr.contains("a Windows path"), "{stderr}");

    copy_into(dir, &[("golden/scale/subject01_simbody.osim", "subject01_simbody.osim"), ("subject01/subject01_walk1.trc", "subject01_walk1.trc")]);
    let unnamed = edited_copy(dir, "subject01/subject01_Setup_IK.xml", "unnamed.xml", &[("<output_motion_file>subject01_walk1_ik.mot</output_motion_file>", "<output_motion_file>Unassigned</output_motion_file>")]);
    let (code, _, stderr) = osim_tune(&["run", s(&unnamed)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("unnamed.xml: output_motion_file is not set"), "{stderr}");
    let kinematics = dir.join("kinematics");
    std::fs::create_dir(&kinematics).unwrap();
    copy_into(&kinematics, &[("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot"), ("golden/scale/subject01_simbody.osim", "subject01_simbody.osim")]);
    let unknown = edited_copy(&kinematics, "golden/analyze_tool/kinematics_listed/setup.xml", "unknown.xml", &[("<coordinates> knee_angle_r pelvis_tx</coordinates>", "<coordinates> knee_angle_r no_such_coordinate</coordinates>")]);
    let (code, _, stderr) = osim_tune(&["run", s(&unknown)]);
    assert!(code == 2 && stderr.contains("unknown.xml: <Kinematics> names coordinate \"no_such_coordinate\", which the model does not have"), "{stderr}");
    assert!(!kinematics.join("Results").exists());
    let written: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).filter(|n| n.ends_with(".mot") || n.ends_with(".sto")).collect();
    assert!(written.is_empty(), "{written:?}");
}

/// What the muscles' states cannot give is named, not guessed: a controller osim-tune does not
/// apply (a ToyReflexController) could drive Rajagopal2016's CoordinateActuators, so ForceReporter
/// and Actuation are left out while the MuscleAnalysis and StatesReporter tables stay OpenSim's —
/// a PrescribedController in its place is applied (its actuator's force is its constant control
/// × optimal force 10 N·m); a muscle class without mechanics here (RigidTendonMuscle) leaves only
/// the path tables.
#[test]
fn tables_the_muscle_states_cannot_give_are_named() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot"), ("golden/scale_zoo/Rajagopal2016_scaled.osim", "Rajagopal2016_scaled.osim")]);
    let with_controller = |controller: &str, file: &str| {
        let controllers = format!("<ControllerSet name=\"Controllers\"><objects>{controller}</objects></ControllerSet>\n\t\t<coordinates_file>");
        edited_copy(dir, "golden/analyze_tool/rajagopal/setup.xml", file, &[("<coordinates_file>", controllers.as_str())])
    };
    let setup = with_controller("<ToyReflexController name=\"arms\" />", "setup.xml");
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("not written: ForceReporter's tables: controllers osim-tune does not apply (ToyReflexController arms"), "{stderr}");
    assert!(stderr.contains("not written: Actuation's tables: controllers osim-tune does not apply"), "{stderr}");
    assert!(stderr.contains("not written: Kinematics' accelerations (_dudt): controllers osim-tune does not apply"), "{stderr}");
    let written = |name: &str| dir.join("Results").join(name).exists();
    assert!(written("walk_StatesReporter_states.sto") && written("walk_MuscleAnalysis_TendonForce.sto"));
    assert!(!written("walk_ForceReporter_forces.sto") && !written("walk_Actuation_force.sto") && !written("walk_Kinematics_dudt.sto"));
    let prescribed = "<PrescribedController name=\"arms\"><actuator_list>shoulder_flex_r</actuator_list><FunctionSet name=\"ControlFunctions\"><objects><Constant><value>0.5</value></Constant></objects></FunctionSet></PrescribedController>";
    std::fs::remove_dir_all(dir.join("Results")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&with_controller(prescribed, "prescribed.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    let forces = StorageTable::read(&dir.join("Results/walk_ForceReporter_forces.sto")).unwrap();
    let shoulder = forces.column("shoulder_flex_r").unwrap();
    assert!(!shoulder.is_empty() && shoulder.iter().all(|&f| f == 5.0), "{shoulder:?}");
    assert!(forces.column("shoulder_flex_l").unwrap().iter().all(|&f| f == 0.0));

    // A muscle class without mechanics here (RigidTendonMuscle): its path tables only.
    let other = edited_copy(dir, "models/arm26.osim", "arm26_other.osim", &[("<Thelen2003Muscle name=\"BRA\">", "<RigidTendonMuscle name=\"BRA\">")]);
    let text = std::fs::read_to_string(other.as_path()).unwrap();
    let closing = text.rfind("</Thelen2003Muscle>").unwrap();
    std::fs::write(&other, format!("{}</RigidTendonMuscle>{}", &text[..closing], &text[closing + "</Thelen2003Muscle>".len()..])).unwrap();
    copy_into(dir, &[("golden/static_optimization/arm26/arm26_motion.mot", "arm26_motion.mot")]);
    let setup = edited_copy(dir, "golden/analyze_tool/degroote_rigid/setup.xml", "other.xml", &[("arm26_degroote_rigid.osim", "arm26_other.osim")]);
    std::fs::remove_dir_all(dir.join("Results")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("not written: the MuscleAnalysis' fiber, tendon, force, power and moment tables: muscle 'BRA' (RigidTendonMuscle) has no muscle mechanics here"), "{stderr}");
    assert!(stderr.contains("not written: StatesReporter's tables: muscle 'BRA'"), "{stderr}");
    assert!(written("walk_MuscleAnalysis_Length.sto") && !written("walk_MuscleAnalysis_FiberLength.sto") && !written("walk_StatesReporter_states.sto"));
}

/// A states file whose times do not increase is refused, naming the file and the row.
#[test]
fn a_states_file_is_checked_as_opensim_reads_it() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/analyze_tool/states/setup.xml", "setup.xml"), ("models/arm26.osim", "arm26.osim")]);
    let text = std::fs::read_to_string(fixture("golden/analyze_tool/states/arm26_states.sto")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header = lines.iter().position(|l| *l == "endheader").unwrap() + 2;
    let mut swapped = lines.clone();
    swapped.swap(header + 3, header + 4);
    std::fs::write(dir.join("arm26_states.sto"), swapped.join("\n")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert!(code == 2 && stderr.contains("arm26_states.sto: times must increase strictly, but row 4"), "{stderr}");
}

/// The induced accelerations add up: with the same contacts held, the dynamics is linear in
/// the forces, so `total` is the sum of every actuator's, gravity's and the speeds' (the Thelen
/// muscles' tendon forces do not change with the speeds); OpenSim's `PointConstraint` contacts
/// are noted as held at the setup's points.
#[test]
fn induced_accelerations_add_up_to_the_total() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/analyze_tool/induced_rolling/setup.xml", "setup.xml"), ("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot")]);
    for (name, source) in ANALYZE_TOOL_INPUTS {
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), dir.join(name)).unwrap();
    }
    let (code, _, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    for table in ["knee_angle_r", "pelvis_tx", "center_of_mass", "pelvis"] {
        let induced = StorageTable::read(&dir.join(format!("Results/walk_InducedAccelerations_{table}.sto"))).unwrap();
        let components = if table == "pelvis" { 6 } else if table == "center_of_mass" { 3 } else { 1 };
        for row in induced.rows() {
            let largest = row[1..].iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for k in 0..components {
                let sum: f64 = row[1 + components..].iter().skip(k).step_by(components).sum();
                assert!((sum - row[1 + k]).abs() < 1e-9 * largest, "{table} at {} s: total {} against the sum {sum}", row[0], row[1 + k]);
            }
        }
    }
    let setup = edited_copy(dir, "golden/analyze_tool/induced_potentials/setup.xml", "points.xml", &[]);
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("note: InducedAccelerations: PointConstraint left_foot holds calcn_l's point (0.0000, 0.0000, 0.0000) m at ground's point (0.0000, 0.0000, 0.0000) m, as OpenSim 4.6 holds it"), "{stderr}");
}

/// Contacts that cannot replace the external forces are refused naming the setup's line and
/// what is wrong, and nothing is written: fewer constraints than forces, a constraint on another
/// body than its force's, a WeldConstraint (OpenSim 4.6 fails on it there), a rolling surface
/// other than ground, a coordinate the model lacks.
#[test]
fn induced_accelerations_refuse_contacts_that_cannot_replace_the_forces() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/ik/subject01_walk1_ik.mot", "subject01_walk1_ik.mot")]);
    for (name, source) in ANALYZE_TOOL_INPUTS {
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join(source), dir.join(name)).unwrap();
    }
    let left = "\t\t\t\t\t\t\t<PointConstraint name=\"left_foot\">\n\t\t\t\t\t\t\t\t<isEnforced>false</isEnforced>\n\t\t\t\t\t\t\t\t<body_1>ground</body_1>\n\t\t\t\t\t\t\t\t<body_2>calcn_l</body_2>\n\t\t\t\t\t\t\t</PointConstraint>\n";
    let cases: [(&str, &str, &str, &str); 5] = [
        ("golden/analyze_tool/induced_potentials/setup.xml", left, "", "the ConstraintSet has 1 constraints for 2 external forces"),
        ("golden/analyze_tool/induced_potentials/setup.xml", "<body_2>calcn_l</body_2>", "<body_2>toes_l</body_2>", "left_foot holds toes_l, but the external force it replaces is applied to calcn_l"),
        ("golden/analyze_tool/induced_potentials/setup.xml", "<PointConstraint name=\"left_foot\">", "<WeldConstraint name=\"left_foot\">", "left_foot: a WeldConstraint cannot replace an external force here"),
        ("golden/analyze_tool/induced_rolling/setup.xml", "<rolling_body>calcn_l</rolling_body>\n\t\t\t\t\t\t\t\t<surface_body>ground</surface_body>", "<rolling_body>calcn_l</rolling_body>\n\t\t\t\t\t\t\t\t<surface_body>pelvis</surface_body>", "left_foot: the surface_body must be ground"),
        ("golden/analyze_tool/induced_rolling/setup.xml", "knee_angle_r ankle_angle_r", "knee_angle_r no_such_coordinate", "InducedAccelerations names coordinate \"no_such_coordinate\", which the model does not have"),
    ];
    for (k, (from, old, new, message)) in cases.into_iter().enumerate() {
        let setup = edited_copy(dir, from, &format!("bad{k}.xml"), &[(old, new)]);
        if new.starts_with("<WeldConstraint") {
            let text = std::fs::read_to_string(&setup).unwrap();
            let at = text.rfind("</PointConstraint>").unwrap();
            std::fs::write(&setup, format!("{}</WeldConstraint>{}", &text[..at], &text[at + "</PointConstraint>".len()..])).unwrap();
        }
        let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
        assert_eq!(code, 2, "{message}: {stderr}");
        assert!(stderr.contains(&format!("bad{k}.xml")) && stderr.contains(message), "{message}: {stderr}");
        assert!(!dir.join("Results").exists(), "{message}");
    }
}


/// A probe OpenSim disables (a muscle the model lacks) is noted and reports nothing; a probe the
/// AnalyzeTool cannot report (an `integrate` operation: it holds no probe states) leaves the
/// ProbeReporter's table out, named; the other analyses are written.
#[test]
fn probes_that_cannot_be_reported_are_named() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    copy_into(dir, &[("golden/analyze_tool/probes/setup.xml", "setup.xml"), ("golden/analyze_tool/states/arm26_states.sto", "arm26_states.sto")]);
    edited_copy(dir, "models/arm26_probes.osim", "arm26_probes.osim", &[("<Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameter name=\"TRIlat\">", "<Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameter name=\"no_such_muscle\">")]);
    let (code, _, stderr) = osim_tune(&["run", s(&dir.join("setup.xml"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("note: ProbeReporter: probe metabolics is disabled, as OpenSim disables it: the model has no muscle no_such_muscle"), "{stderr}");
    let probes = StorageTable::read(&dir.join("Results/walk_ProbeReporter_probes.sto")).unwrap();
    assert_eq!(probes.labels()[..3], ["time", "tuned_TOTAL", "bhargava_TOTAL"]);
    assert!(!probes.labels().iter().any(|l| l.starts_with("metabolics_")));
    edited_copy(dir, "models/arm26_probes.osim", "arm26_probes.osim", &[("<Umberger2010MuscleMetabolicsProbe name=\"tuned\">", "<Umberger2010MuscleMetabolicsProbe name=\"tuned\"><probe_operation>integrate</probe_operation>")]);
    let setup = edited_copy(dir, "golden/analyze_tool/probes/setup.xml", "kinematics.xml", &[("<ProbeReporter name=\"ProbeReporter\">", "<Kinematics name=\"Kinematics\"><on>true</on></Kinematics><ProbeReporter name=\"ProbeReporter\">")]);
    std::fs::remove_dir_all(dir.join("Results")).unwrap();
    let (code, _, stderr) = osim_tune(&["run", s(&setup)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("not written: ProbeReporter's tables: probe tuned's probe_operation \"integrate\""), "{stderr}");
    assert!(dir.join("Results/walk_Kinematics_q.sto").exists() && !dir.join("Results/walk_ProbeReporter_probes.sto").exists());
}
