//! `osim-tune so`: OpenSim's static optimisation from the command line, and its refusals.

mod common;

use std::path::Path;

use common::osim_tune;
use osim_tune::io::table::StorageTable;

const MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";
const IK: &str = "fixtures/golden/ik/subject01_walk1_ik.mot";
const ACTIVATIONS: &str = "fixtures/golden/static_optimization/subject01_walk1_StaticOptimization_activation.sto";

fn path(relative: &str) -> String {
    common::root().join(relative).display().to_string()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// subject01's setup, its file names made absolute, the residuals and loads of the golden run.
fn setup(folder: &Path, step_interval: &str, exponent: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(path("fixtures/subject01/setup_static_optimization.xml")).unwrap();
    let text = text
        .replace("gait2392_SO_weak_Residual_Actuators.xml", &path("fixtures/subject01/gait2392_SO_Residual_Actuators.xml"))
        .replace("foot_floor_loads.xml", &path("fixtures/subject01/subject01_walk1_grf.xml"))
        .replace("<step_interval> 10 </step_interval>", &format!("<step_interval> {step_interval} </step_interval>"))
        .replace("<activation_exponent>       2.00000000 </activation_exponent>", &format!("<activation_exponent> {exponent} </activation_exponent>"));
    let text = regex_free_replace(&text, "lowpass_cutoff_frequency_for_coordinates", "6");
    let file = folder.join("setup.xml");
    std::fs::write(&file, text).unwrap();
    file
}

/// Replaces the text of the element `tag` by `value`.
fn regex_free_replace(text: &str, tag: &str, value: &str) -> String {
    let (open, close) = (format!("<{tag}>"), format!("</{tag}>"));
    let start = text.find(&open).unwrap() + open.len();
    let end = text[start..].find(&close).unwrap() + start;
    format!("{}{value}{}", &text[..start], &text[end..])
}

/// Flags alone: OpenSim's file names, its columns, and OpenSim's controls judged on our problem.
#[test]
fn the_walk_is_solved_and_opensims_controls_are_judged() {
    let folder = tempfile::tempdir().unwrap();
    let arguments = [
        "so", &path(MODEL), &path(IK),
        "--actuators", &path("fixtures/subject01/gait2392_SO_Residual_Actuators.xml"),
        "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"),
        "--time", "0.5", "2", "--lowpass", "6", "--compare", &path(ACTIVATIONS), "--name", "walk", "-o", s(folder.path()),
    ];
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("95 frames") && stdout.contains("19 frames compared"), "{stdout}");
    let activations = StorageTable::read(&folder.path().join("walk_StaticOptimization_activation.sto")).unwrap();
    assert_eq!(activations.labels(), StorageTable::read(Path::new(&path(ACTIVATIONS))).unwrap().labels());
    // The model check: each residual actuator's peak |force| as the force file has it, and the
    // muscles at their limit with their frame counts.
    let forces = StorageTable::read(&folder.path().join("walk_StaticOptimization_force.sto")).unwrap();
    for actuator in ["FX", "FY", "FZ", "MX", "MY", "MZ"] {
        let j = forces.column_index(actuator).unwrap();
        let peak = forces.rows().map(|row| row[j].abs()).fold(0.0, f64::max);
        let line = stdout.lines().find(|l| l.split_whitespace().next() == Some(actuator)).unwrap_or_else(|| panic!("no line for {actuator}: {stdout}"));
        let printed: f64 = line.split_whitespace().nth(2).unwrap().parse().unwrap();
        assert!((printed - peak).abs() <= 5e-4, "{actuator}: printed {printed}, file {peak}");
    }
    let j = activations.column_index("med_gas_r").unwrap();
    let saturated = activations.rows().filter(|row| row[j] >= 0.99).count();
    assert!(saturated > 0 && stdout.contains(&format!("med_gas_r ({saturated})")), "{saturated}: {stdout}");
}

/// The setup's step interval solves the first and last rows and every 10th between them.
#[test]
fn the_setup_runs_with_its_step_interval() {
    let folder = tempfile::tempdir().unwrap();
    let setup = setup(folder.path(), "10", "2.00000000");
    let output = folder.path().join("out");
    let (code, stdout, stderr) = osim_tune(&["so", &path(MODEL), &path(IK), "--setup", s(&setup), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    let times = StorageTable::read(&output.join("subject01_StaticOptimization_activation.sto")).unwrap().times();
    let every = StorageTable::read(Path::new(&path(ACTIVATIONS))).unwrap().times();
    assert_eq!(times[0], every[0], "{stdout}");
    assert!((times[times.len() - 1] - 1.998).abs() < 1e-9, "OpenSim's last row is 1.998 s: {stdout}");
    let steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(steps[1..steps.len() - 1].iter().all(|d| (d - 0.16).abs() < 1e-9), "{steps:?}");
}

/// The objective Σ|a|ᵖ needs p > 1 (the setup's value is checked when it is read).
#[test]
fn an_activation_exponent_of_one_or_less_and_use_model_force_set_false_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let setup = setup(folder.path(), "1", "0.5");
    let output = folder.path().join("out");
    let (code, _, stderr) = osim_tune(&["so", &path(MODEL), &path(IK), "--setup", s(&setup), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("activation_exponent") && stderr.contains("a number ≥ 1"), "{stderr}");
    let (code, _, stderr) = osim_tune(&["so", &path(MODEL), &path(IK), "--activation-exponent", "1", "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("activation exponent 1: expected a number > 1"), "{stderr}");
    // use_model_force_set false: OpenSim 4.6 crashes on it, so it is refused, saying why.
    let text = std::fs::read_to_string(&setup).unwrap().replace("<activation_exponent> 0.5 </activation_exponent>", "<activation_exponent> 2 </activation_exponent>");
    std::fs::write(&setup, text.replace("<use_model_force_set> true </use_model_force_set>", "<use_model_force_set> false </use_model_force_set>")).unwrap();
    let (code, _, stderr) = osim_tune(&["so", &path(MODEL), &path(IK), "--setup", s(&setup), "-o", s(&output)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("use_model_force_set false") && stderr.contains("OpenSim 4.6 itself crashes on it"), "{stderr}");
    assert!(!output.exists());
}

/// --pia: the physiological inverse approach writes activations, forces and excitations (also as a
/// ControlSet), and its
/// min–max criterion's largest activation is no larger than the sum-of-squares one's.
#[test]
fn the_physiological_inverse_approach_runs_from_the_command_line() {
    let folder = tempfile::tempdir().unwrap();
    let largest = |criterion: &str| {
        let output = folder.path().join(criterion);
        let arguments = [
            "so", &path(MODEL), &path(IK),
            "--actuators", &path("fixtures/subject01/gait2392_SO_Residual_Actuators.xml"),
            "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"),
            "--time", "0.5", "2", "--lowpass", "6", "--pia", criterion, "--name", "walk", "-o", s(&output),
        ];
        let (code, stdout, stderr) = osim_tune(&arguments);
        assert_eq!(code, 0, "{stderr}");
        for kind in ["activation", "force", "excitation", "deviation"] {
            assert!(output.join(format!("walk_PhysiologicalInverse_{kind}.sto")).exists(), "{kind}");
        }
        let excitations = StorageTable::read(&output.join("walk_PhysiologicalInverse_excitation.sto")).unwrap();
        // The excitations also as OpenSim's ControlSet (a ForwardTool's controls), a control per column.
        let controls = std::fs::read_to_string(output.join("walk_PhysiologicalInverse_controls.xml")).unwrap();
        assert_eq!(controls.matches("<ControlLinear name=").count(), excitations.n_columns() - 1);
        assert_eq!(controls.matches("<ControlLinearNode>").count(), (excitations.n_columns() - 1) * excitations.n_rows());
        assert!(excitations.rows().all(|r| r[1..].iter().all(|u| (0.0..=1.0).contains(u))));
        assert!(stdout.contains("95 frames"), "{stdout}");
        let activations = StorageTable::read(&output.join("walk_PhysiologicalInverse_activation.sto")).unwrap();
        let muscles: Vec<usize> = (1..activations.n_columns()).filter(|&j| excitations.column_index(&activations.labels()[j]).is_some()).collect();
        activations.rows().flat_map(|r| muscles.iter().map(move |&j| r[j])).fold(0.0, f64::max)
    };
    assert!(largest("min-max") <= largest("sum-of-squares") + 1e-6);
    let (code, _, stderr) = osim_tune(&["so", &path(MODEL), &path(IK), "--pia", "min-max", "--compare", &path(ACTIVATIONS), "-o", s(folder.path())]);
    assert_eq!(code, 2);
    assert!(stderr.contains("does not apply with --pia"), "{stderr}");
}

/// arm26 (six Thelen muscles over wrap objects), the smooth motion of its OpenSim static
/// optimisation golden, and its reserve actuators.
fn arm26() -> (String, String, String) {
    let golden = "fixtures/golden/static_optimization/arm26";
    (path("fixtures/models/arm26.osim"), path(&format!("{golden}/arm26_motion.mot")), path(&format!("{golden}/arm26_reserves.xml")))
}

/// --pia --compliant-tendons on arm26 (Thelen muscles over wrap objects, unfiltered): the
/// written forces are each muscle's tendon force in static equilibrium at its written
/// activation — as `analyze --activations` solves them row by row — and they meet inverse
/// dynamics. The flag needs --pia.
#[test]
fn compliant_tendons_pull_with_their_equilibrium_forces() {
    let folder = tempfile::tempdir().unwrap();
    let (model, motion, reserves) = arm26();
    let output = folder.path().join("pia");
    let (code, stdout, stderr) = osim_tune(&["so", &model, &motion, "--actuators", &reserves, "--pia", "sum-of-squares", "--compliant-tendons", "--name", "arm", "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("settled after"), "{stdout}");
    let violation: f64 = stdout.split("inverse dynamics| ").nth(1).and_then(|t| t.split_whitespace().next()).unwrap().parse().unwrap();
    assert!(violation <= 1e-6, "{stdout}");
    let activations = output.join("arm_PhysiologicalInverse_activation.sto");
    let analysis = folder.path().join("analysis");
    let (code, _, stderr) = osim_tune(&["analyze", &model, "--motion", &motion, "--activations", s(&activations), "-o", s(&analysis)]);
    assert_eq!(code, 0, "{stderr}");
    let (ours, equilibria) = (StorageTable::read(&output.join("arm_PhysiologicalInverse_force.sto")).unwrap(), StorageTable::read(&analysis.join("TendonForce.sto")).unwrap());
    assert_eq!(ours.times(), equilibria.times());
    for (j, muscle) in equilibria.labels().iter().enumerate().skip(1) {
        let k = ours.column_index(muscle).unwrap();
        for (row, expected) in ours.rows().zip(equilibria.rows()) {
            assert!((row[k] - expected[j]).abs() <= 1e-9 * expected[j].abs().max(1.0), "{muscle} at {} s: {} N, equilibrium {} N", row[0], row[k], expected[j]);
        }
    }
    let (code, _, stderr) = osim_tune(&["so", &model, &motion, "--compliant-tendons", "-o", s(&folder.path().join("so"))]);
    assert_eq!(code, 2);
    assert!(stderr.contains("give --pia"), "{stderr}");
}

/// arm26 with DeGroote–Fregly muscles by min–max: the weak tie-break lets one activation swing
/// between two values from one linearisation to the next (undamped: 0.78 ↔ 0.81 for 25 re-solves,
/// never settling); the proximal damping settles it, meeting inverse dynamics.
#[test]
fn a_swinging_compliant_min_max_is_damped_until_it_settles() {
    let folder = tempfile::tempdir().unwrap();
    let (_, motion, reserves) = arm26();
    let model = path("fixtures/models/arm26_degroote.osim");
    let (code, stdout, stderr) = osim_tune(&["so", &model, &motion, "--actuators", &reserves, "--pia", "min-max", "--compliant-tendons", "-o", s(folder.path())]);
    assert_eq!(code, 0, "{stderr}");
    let violation: f64 = stdout.split("inverse dynamics| ").nth(1).and_then(|t| t.split_whitespace().next()).unwrap().parse().unwrap();
    assert!(stdout.contains("settled after") && violation <= 1e-6, "{stdout}");
}

/// The Thelen-muscle walk (0.6–0.9 s): with rigid tendons and force–velocity the muscles meet
/// inverse dynamics; in static equilibrium beside compliant tendons (no fiber velocity) they
/// cannot — exit 1, nothing written, and the hint to the penalty form — which then shows the
/// left knee falling short.
#[test]
fn compliant_tendons_too_weak_for_the_motion_exit_1_and_the_penalty_shows_where() {
    let folder = tempfile::tempdir().unwrap();
    let model = path("fixtures/subject01/OutputReference/subject01_simbody.osim");
    let output = folder.path().join("pia");
    let common = [
        "so", &model, &path(IK),
        "--actuators", &path("fixtures/subject01/gait2392_SO_Residual_Actuators.xml"),
        "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"),
        "--time", "0.6", "0.9", "--lowpass", "6", "--pia", "sum-of-squares", "--name", "walk", "-o", s(&output),
    ];
    let (code, _, stderr) = osim_tune(&common);
    assert_eq!(code, 0, "rigid tendons: {stderr}");
    std::fs::remove_dir_all(&output).unwrap();
    let (code, _, stderr) = osim_tune(&[&common[..], &["--compliant-tendons"]].concat());
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("no solution") && stderr.contains("hint: --moment-weight"), "{stderr}");
    assert!(!output.exists());
    let (code, _, stderr) = osim_tune(&[&common[..], &["--compliant-tendons", "--moment-weight", "1"]].concat());
    assert_eq!(code, 0, "{stderr}");
    let deviations = StorageTable::read(&output.join("walk_PhysiologicalInverse_deviation.sto")).unwrap();
    let j = deviations.column_index("knee_angle_l_moment").unwrap();
    let largest = deviations.rows().map(|row| row[j].abs()).fold(0.0, f64::max);
    assert!(largest > 5.0, "the left knee falls short by {largest} N·m at most");
}

/// --moment-weight W: skeleton dynamics as a penalty, min Σa² + W Σ d² with d = generalized force
/// − inverse dynamics. arm26's reserves are unbounded coordinate actuators of optimal force 1, so
/// at the optimum each one's control is a = −W·d on its coordinate (the gradient 2a + 2W·d = 0),
/// with rigid tendons and, at the settled linearisation, with compliant ones. The deviations are
/// written per coordinate.
#[test]
fn a_moment_weight_trades_deviations_against_controls() {
    let folder = tempfile::tempdir().unwrap();
    let (model, motion, reserves) = arm26();
    let weight = 0.5;
    for (label, compliant, tolerance) in [("rigid", None, 1e-6), ("compliant", Some("--compliant-tendons"), 1e-5)] {
        let output = folder.path().join(label);
        let mut arguments = vec!["so", &model, &motion, "--actuators", &reserves, "--pia", "sum-of-squares", "--moment-weight", "0.5", "--name", "arm", "-o", s(&output)];
        arguments.extend(compliant);
        let (code, stdout, stderr) = osim_tune(&arguments);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains("as a penalty (W = 0.5)"), "{stdout}");
        let activations = StorageTable::read(&output.join("arm_PhysiologicalInverse_activation.sto")).unwrap();
        let deviations = StorageTable::read(&output.join("arm_PhysiologicalInverse_deviation.sto")).unwrap();
        let mut largest = 0.0f64;
        for coordinate in ["r_shoulder_elev", "r_elbow_flex"] {
            let (a, d) = (activations.column_index(&format!("reserve_{coordinate}")).unwrap(), deviations.column_index(&format!("{coordinate}_moment")).unwrap());
            for (control, deviation) in activations.rows().zip(deviations.rows()) {
                assert!((control[a] + weight * deviation[d]).abs() <= tolerance * control[a].abs().max(1.0), "{label} {coordinate} at {} s: control {}, deviation {}", control[0], control[a], deviation[d]);
                largest = largest.max(deviation[d].abs());
            }
        }
        assert!(largest > 0.1, "{label}: the penalty should leave deviations ({largest} N·m at most)");
    }
    let (code, _, stderr) = osim_tune(&["so", &model, &motion, "--pia", "min-max", "--moment-weight", "0", "-o", s(&folder.path().join("zero"))]);
    assert_eq!(code, 2);
    assert!(stderr.contains("--moment-weight 0: expected a number > 0"), "{stderr}");
}

/// Without residual actuators nothing can hold the pelvis against the ground reactions: the
/// physiological inverse problem has no solution, which exits 1 and writes nothing — unless
/// skeleton dynamics is a penalty.
#[test]
fn an_unsolvable_physiological_inverse_problem_exits_1_and_writes_nothing() {
    let folder = tempfile::tempdir().unwrap();
    let output = folder.path().join("out");
    let arguments = ["so", &path(MODEL), &path(IK), "--external-loads", &path("fixtures/subject01/subject01_walk1_grf.xml"), "--time", "0.5", "0.7", "--pia", "sum-of-squares", "-o", s(&output)];
    let (code, _, stderr) = osim_tune(&arguments);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("physiological inverse problem has no solution") && stderr.contains("hint: --moment-weight"), "{stderr}");
    assert!(!output.exists());
    // As a penalty, skeleton dynamics is met where the muscles can meet it (the coordinates
    // filtered as OpenSim's setups do): the pelvis rows keep what no muscle can hold.
    let (code, _, stderr) = osim_tune(&[&arguments[..], &["--lowpass", "6", "--moment-weight", "1"]].concat());
    assert_eq!(code, 0, "{stderr}");
    let deviations = StorageTable::read(&output.join("subject01_walk1_ik_PhysiologicalInverse_deviation.sto")).unwrap();
    let largest = |pelvis: bool| {
        let columns: Vec<usize> = (1..deviations.n_columns()).filter(|&j| deviations.labels()[j].starts_with("pelvis") == pelvis).collect();
        deviations.rows().flat_map(|row| columns.iter().map(move |&j| row[j].abs())).fold(0.0, f64::max)
    };
    assert!(largest(true) > 10.0 && largest(false) < 1.0, "pelvis {} N or N·m, joints {} N·m", largest(true), largest(false));
}

/// A closed loop (the parallelogram golden's ConstantDistanceConstraint): static optimisation
/// runs, its forces meeting OpenSim's rows (tests/static_optimization.rs); so does the
/// physiological inverse approach, whose sum of squares over the frames separates into static
/// optimisation's per frame while activation dynamics does not bind (the activations change by
/// at most 0.02 per 10 ms frame here, far within what τ_a = 10 ms and τ_d = 40 ms allow), so it
/// gives static optimisation's activations, to the solvers' tolerance, with the loop's force
/// taking up the rest: its deviations per coordinate are 0.
#[test]
fn a_closed_loop_is_solved_by_both_optimisations() {
    let folder = tempfile::tempdir().unwrap();
    let [model, motion, reserves] = parallelogram(["parallelogram.osim", "parallelogram_motion.mot", "parallelogram_reserves.xml"]);
    let [compare] = parallelogram(["parallelogram_StaticOptimization_activation.sto"]);
    let so = folder.path().join("so");
    let (code, stdout, stderr) = osim_tune(&["so", &model, &motion, "--actuators", &reserves, "--time", "0.1", "0.9", "--compare", &compare, "--name", "loop", "-o", s(&so)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("81 frames"), "{stdout}");
    assert!(!stderr.contains("break the links"), "the golden motion keeps its loop closed: {stderr}");
    let pia = folder.path().join("pia");
    let (code, stdout, stderr) = osim_tune(&["so", &model, &motion, "--actuators", &reserves, "--time", "0.1", "0.9", "--pia", "sum-of-squares", "--name", "loop", "-o", s(&pia)]);
    assert_eq!(code, 0, "{stderr}");
    let read = |folder: &Path, analysis: &str| StorageTable::read(&folder.join(format!("loop_{analysis}_activation.sto"))).unwrap();
    let (ours, physiological) = (read(&so, "StaticOptimization"), read(&pia, "PhysiologicalInverse"));
    assert_eq!(ours.n_rows(), physiological.n_rows());
    let largest = ours.rows().zip(physiological.rows()).flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()).collect::<Vec<_>>()).fold(0.0, f64::max);
    assert!(largest < 1e-6, "the two optimisations part by {largest:e}: {stdout}");
    let deviation: f64 = stdout.split("largest |generalized force − inverse dynamics| ").nth(1).and_then(|t| t.split_whitespace().next()).and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("{stdout}"));
    assert!(deviation < 1e-6, "{stdout}");
}

/// Rows off the loop are assembled first, as OpenSim's AnalyzeTool assembles them: the
/// parallelogram's crank moved +0.5° and its rocker −0.5° off the golden motion assemble back onto
/// it (the nearest closed pose, both coordinates weighted alike), and their speeds and
/// accelerations are the golden's, so static optimisation and the joint reactions (OpenSim's SO
/// forces) give the golden motion's results to the assembly's accuracy. Without the assembly the
/// poses would be 0.5° off.
#[test]
fn poses_off_a_loop_are_assembled_onto_it() {
    let folder = tempfile::tempdir().unwrap();
    let [model, motion, reserves] = parallelogram(["parallelogram.osim", "parallelogram_motion.mot", "parallelogram_reserves.xml"]);
    let [forces] = parallelogram(["parallelogram_StaticOptimization_force.sto"]);
    let off_motion = moved_motion(&motion, folder.path(), |_| 0.5);
    let run = |command: &str, motion: &str, name: &str| {
        let out = folder.path().join(name);
        let extra: &[&str] = if command == "so" { &[] } else { &["--forces", &forces] };
        let arguments = [&[command, &model, motion, "--actuators", &reserves, "--time", "0.1", "0.9", "--name", name, "-o", s(&out)], extra].concat();
        let (code, _, stderr) = osim_tune(&arguments);
        assert_eq!(code, 0, "{stderr}");
        let table = if command == "so" { "StaticOptimization_activation" } else { "JointReaction_ReactionLoads" };
        StorageTable::read(&out.join(format!("{name}_{table}.sto"))).unwrap()
    };
    for command in ["so", "reaction"] {
        let (on, off) = (run(command, &motion, &format!("{command}_on")), run(command, s(&off_motion), &format!("{command}_off")));
        assert_eq!(on.n_rows(), 81);
        let largest = on.rows().zip(off.rows()).flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()).collect::<Vec<_>>()).fold(0.0, f64::max);
        // The assembly stops at steps of 1e-10 rad, its least-squares goal converging to ~1e-8
        // rad here: found 2e-9 in the controls, 1.6e-6 N in loads up to 60 N.
        let bound = if command == "so" { 1e-7 } else { 1e-5 };
        assert!(largest < bound, "{command}: off-loop poses give results {largest:e} away");
    }
}

/// The parallelogram's golden motion with the crank moved by +`offset(t)` degrees and the rocker
/// by −`offset(t)`, written into `folder`.
fn moved_motion(motion: &str, folder: &Path, offset: impl Fn(f64) -> f64) -> std::path::PathBuf {
    let text = std::fs::read_to_string(motion).unwrap();
    let (header, body) = text.split_at(text.find("time\t").unwrap());
    let mut lines = body.lines();
    let mut moved = format!("{header}{}\n", lines.next().unwrap());
    for line in lines {
        let v: Vec<f64> = line.split('\t').map(|x| x.parse().unwrap()).collect();
        moved.push_str(&format!("{}\t{}\t{}\n", v[0], v[1] + offset(v[0]), v[2] - offset(v[0])));
    }
    let file = folder.join("moved.mot");
    std::fs::write(&file, moved).unwrap();
    file
}

/// A motion whose accelerations break its loop (crank and rocker moved apart by ±2° sin 2πt:
/// each pose assembles onto the loop, the splined accelerations do not keep it) is solved — the
/// controls give the nearest accelerations that keep the loop — with a note saying how far the
/// tracked ones break it: the distance's acceleration L sinθ (θ̈₁ − θ̈₃) + …, with θ̈₁ − θ̈₃ up to
/// 4°·(2π)² ≈ 2.8 rad/s² and L sinθ up to 0.33 m, and the speeds' part (found 1.02 m/s²).
#[test]
fn accelerations_breaking_a_loop_are_noted() {
    let folder = tempfile::tempdir().unwrap();
    let [model, motion, reserves] = parallelogram(["parallelogram.osim", "parallelogram_motion.mot", "parallelogram_reserves.xml"]);
    let moved = moved_motion(&motion, folder.path(), |t| 2.0 * (2.0 * std::f64::consts::PI * t).sin());
    let (code, _, stderr) = osim_tune(&["so", &model, s(&moved), "--actuators", &reserves, "--time", "0.1", "0.9", "-o", s(&folder.path().join("out"))]);
    assert_eq!(code, 0, "{stderr}");
    let note = stderr.split("break the links between bodies by up to ").nth(1).unwrap_or_else(|| panic!("no note: {stderr}"));
    let error: f64 = note.split_whitespace().next().unwrap().parse().unwrap();
    assert!(error > 0.5 && error < 1.5, "{error} m/s²");
}

/// The parallelogram golden's `files` (fixtures/golden/static_optimization/parallelogram/).
fn parallelogram<const N: usize>(files: [&str; N]) -> [String; N] {
    files.map(|file| path(&format!("fixtures/golden/static_optimization/parallelogram/{file}")))
}
