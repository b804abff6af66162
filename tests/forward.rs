//! Muscle-driven forward simulation along prescribed kinematics (`osim-tune forward`): against
//! OpenSim 4.6's integration of the same prescribed model (`fixtures/golden/forward/`), from
//! first principles (equilibrium is a fixed point; activation follows the closed form of the
//! first-order law), and from the command line with its refusals.

mod common;

use std::path::{Path, PathBuf};

use common::osim_tune;
use osim_tune::analysis::{driven_muscles, simulate, Activations, ForwardOutputs, ForwardSettings, InitialStates, PrescribedMotion};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::muscle::ActivationDynamics;
use osim_tune::mechanics::MuscleGeometry;
use osim_tune::model::ModelSpec;
use osim_tune::validation::{compare_forward, FORWARD_CASES};

const ARM26: &str = "fixtures/models/arm26.osim";

fn path(relative: &str) -> PathBuf {
    common::root().join(relative)
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The arm26 golden case's motion and excitations.
fn arm26_case() -> (PathBuf, PathBuf) {
    let case = path("fixtures/golden/forward/arm26");
    (case.join("motion.mot"), case.join("excitations.sto"))
}

/// OpenSim integrated at accuracy 1e-10; we integrate at 1e-12, so what is left is OpenSim's own
/// integration error (each case's bounds, `FORWARD_CASES`; found: activation 4.0e-9 / 3.6e-8 /
/// 3.5e-7, fiber length 3.0e-9 / 2.4e-9 / 1.4e-8 m for arm26 / gait2392 / Rajagopal2016), tendon
/// forces within 2.6e-6 / 1.1e-5 / 2.5e-6 of max(1 N, |F|) — rigid tendons included — and the
/// muscles' generalized forces within 8.4e-6 / 1.2e-6 / 1.0e-5 of max(1, |τ|). arm26 with
/// DeGroote muscles: fiber length 1.5e-12 m, tendon force 4.8e-9, activation 2.2e-10 — our own
/// integration error there, 8.1e-12 at accuracy 1e-14; with rigid tendons 7.2e-13 m, 8.1e-9 and
/// 1.1e-9 (OpenSim's own error).
#[test]
fn states_follow_opensims_integration() {
    for case in &FORWARD_CASES {
        let c = compare_forward(&common::root(), case, 1e-12, false).unwrap();
        let worst = [
            (&c.activation, case.activation_tolerance, "activation"),
            (&c.fiber_length, case.fiber_length_tolerance, "fiber length (m)"),
            (&c.tendon_force, 5e-5, "tendon force"),
            (&c.generalized_force, 5e-5, "generalized force"),
        ];
        for (w, bound, what) in worst {
            assert!(w.error <= bound && w.count > 0, "{}: {what} differs by {:e} at {} ({} compared)", case.case, w.error, w.at, w.count);
        }
    }
}

/// From our own start — OpenSim's `equilibrateMuscles` replicated: the static equilibrium for
/// Millard muscles, `initMuscleState`'s sharing of the path's speed for Thelen ones (arm26's
/// start agrees to 1e-16 m), the bisection for DeGroote's normalized tendon force — the
/// simulation follows OpenSim's within the same bounds as from OpenSim's own first states (found
/// 3.0e-9, 3.7e-9 and 1.2e-8 m in fiber length; DeGroote 4.0e-12 m).
#[test]
fn our_start_is_opensims() {
    for case in &FORWARD_CASES {
        let c = compare_forward(&common::root(), case, 1e-12, true).unwrap();
        assert!(c.fiber_length.error <= case.fiber_length_tolerance, "{}: fiber length differs by {:e} at {}", case.case, c.fiber_length.error, c.fiber_length.at);
        assert!(c.activation.error <= case.activation_tolerance && c.tendon_force.error <= 5e-5, "{}: {:e} {:e}", case.case, c.activation.error, c.tendon_force.error);
    }
}

/// A two-row table in `folder`: `labels` (after time) with `values` at t = 0 and t = 1.
fn constant_table(folder: &Path, name: &str, labels: &[&str], values: &[f64], in_degrees: bool) -> PathBuf {
    let header = format!("{name}\nversion=1\nnRows=7\nnColumns={}\ninDegrees={}\nendheader\ntime\t{}\n", labels.len() + 1, if in_degrees { "yes" } else { "no" }, labels.join("\t"));
    let row = |t: f64| format!("{t}\t{}\n", values.iter().map(f64::to_string).collect::<Vec<_>>().join("\t"));
    let file = folder.join(name);
    std::fs::write(&file, header + &(0..7).map(|k| row(k as f64 / 6.0)).collect::<String>()).unwrap();
    file
}

struct Arm {
    spec: ModelSpec,
    geometry: MuscleGeometry,
    names: Vec<String>,
}

fn arm() -> Arm {
    let spec = ModelSpec::read(&OsimDocument::read(&path(ARM26)).unwrap()).unwrap();
    let geometry = MuscleGeometry::new(&spec).unwrap();
    let names = spec.muscles().map(|m| m.name.clone()).collect();
    Arm { spec, geometry, names }
}

/// A still pose with constant excitations, started at a = u and static equilibrium, stays there:
/// the equilibrium solve and the fiber velocity agree on where the fiber is at rest.
#[test]
fn equilibrium_is_a_fixed_point() {
    let folder = tempfile::tempdir().unwrap();
    let arm = arm();
    let motion_file = constant_table(folder.path(), "still.mot", &["r_shoulder_elev", "r_elbow_flex"], &[20.0, 60.0], true);
    let u: Vec<f64> = (0..arm.names.len()).map(|k| 0.1 + 0.15 * k as f64).collect();
    let labels: Vec<&str> = arm.names.iter().map(String::as_str).collect();
    let excitation_file = constant_table(folder.path(), "u.sto", &labels, &u, false);
    let motion = PrescribedMotion::new(&arm.geometry.multibody, &StorageTable::read(&motion_file).unwrap(), &motion_file, None).unwrap();
    let excitations = Activations::from_table(&StorageTable::read(&excitation_file).unwrap(), &excitation_file, &arm.names, "excitation").unwrap();
    let muscles = driven_muscles(&arm.spec, &arm.geometry, &arm.names, false).unwrap();
    let settings = ForwardSettings { range: [0.0, 1.0], accuracy: 1e-10, initial: InitialStates::Equilibrium };
    let trajectory = simulate(&arm.geometry, &muscles, &motion, &excitations, &settings).unwrap();
    let (a0, l0) = trajectory.states(0.0);
    let (a1, l1) = trajectory.states(1.0);
    for k in 0..muscles.len() {
        assert!((a1[k] - a0[k]).abs() <= 1e-12 && (a0[k] - u[k]).abs() <= 1e-15, "{}: activation {} → {}", arm.names[k], a0[k], a1[k]);
        // The equilibrium leaves |F_m cos α − F_t| ≤ 1e-10 N, which the fiber velocity turns into a drift.
        assert!((l1[k] - l0[k]).abs() <= 1e-9, "{}: fiber length {} → {} m", arm.names[k], l0[k], l1[k]);
    }
}

/// Excitation 1 from a = 0.05: τ_a(0.5 + 1.5a) ȧ = 1 − a integrates to
/// t(a) = τ_a [2 ln((1 − a₀)/(1 − a)) − 1.5 (a − a₀)], which the simulated activation must meet.
#[test]
fn activation_follows_the_closed_form_of_the_first_order_law() {
    let folder = tempfile::tempdir().unwrap();
    let arm = arm();
    let motion_file = constant_table(folder.path(), "still.mot", &["r_shoulder_elev", "r_elbow_flex"], &[20.0, 60.0], true);
    let labels: Vec<&str> = arm.names.iter().map(String::as_str).collect();
    let excitation_file = constant_table(folder.path(), "u.sto", &labels, &vec![1.0; labels.len()], false);
    let motion = PrescribedMotion::new(&arm.geometry.multibody, &StorageTable::read(&motion_file).unwrap(), &motion_file, None).unwrap();
    let excitations = Activations::from_table(&StorageTable::read(&excitation_file).unwrap(), &excitation_file, &arm.names, "excitation").unwrap();
    let muscles = driven_muscles(&arm.spec, &arm.geometry, &arm.names, false).unwrap();
    let a0 = 0.05;
    let mut q = vec![0.0; arm.geometry.multibody.coordinates.len()];
    motion.pose(0.0, &mut q);
    let mut evaluation = osim_tune::mechanics::PathEvaluation::new(&arm.geometry, &muscles.iter().map(|m| m.path).collect::<Vec<_>>());
    evaluation.evaluate(&arm.geometry, &q);
    let initial = muscles.iter().enumerate().map(|(k, m)| [a0, m.muscle.equilibrium(a0, evaluation.length(k)).unwrap().fiber_length]).collect();
    let settings = ForwardSettings { range: [0.0, 0.2], accuracy: 1e-10, initial: InitialStates::Given(initial) };
    let trajectory = simulate(&arm.geometry, &muscles, &motion, &excitations, &settings).unwrap();
    let times: Vec<f64> = (0..=20).map(|k| k as f64 * 0.01).collect();
    let outputs = ForwardOutputs::new(&arm.geometry, &muscles, &motion, &trajectory, &times);
    for (k, muscle) in muscles.iter().enumerate() {
        let Some(ActivationDynamics::FirstOrder(dynamics)) = muscle.activation else { panic!("{}: Thelen muscles have first-order dynamics", muscle.name) };
        let tau = dynamics.activation_time_constant;
        for (row, &t) in times.iter().enumerate().skip(1) {
            let a = outputs.activations[row][k];
            let t_of_a = tau * (2.0 * ((1.0 - a0) / (1.0 - a)).ln() - 1.5 * (a - a0));
            // Near a = 1 the closed form amplifies an error δa by 2τ_a/(1 − a); stop there.
            if 1.0 - a > 1e-4 {
                assert!((t_of_a - t).abs() <= 1e-7, "{}: a({t}) = {a} is reached at {t_of_a} s", arm.names[k]);
            }
        }
    }
}

/// The command writes OpenSim's state names and the generalized forces of the muscles; compared
/// with its own generalized forces as if they were inverse dynamics, it finds no difference.
#[test]
fn the_command_writes_states_and_compares_with_inverse_dynamics() {
    let folder = tempfile::tempdir().unwrap();
    let (motion, excitations) = arm26_case();
    let out = folder.path().join("out");
    let (code, stdout, stderr) = osim_tune(&["forward", s(&path(ARM26)), s(&motion), "--excitations", s(&excitations), "--time", "0.2", "0.8", "--name", "arm", "-o", s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("6 muscles driven over 0.2000–0.8000 s"), "{stdout}");
    let states = StorageTable::read(&out.join("arm_states.sto")).unwrap();
    assert_eq!(states.n_rows(), 61);
    assert_eq!(&states.labels()[1..3], ["/forceset/TRIlong/activation", "/forceset/TRIlat/activation"]);
    assert!(states.labels().contains(&"/forceset/BRA/fiber_length".to_string()));
    let generalized = out.join("arm_muscle_generalized_forces.sto");
    assert_eq!(StorageTable::read(&generalized).unwrap().labels(), ["time", "r_shoulder_elev_moment", "r_elbow_flex_moment"]);
    assert!(out.join("arm_tendon_force.sto").exists());
    let again = folder.path().join("again");
    let (code, stdout, stderr) = osim_tune(&["forward", s(&path(ARM26)), s(&motion), "--excitations", s(&excitations), "--time", "0.2", "0.8", "--inverse-dynamics", s(&generalized), "--name", "arm", "-o", s(&again)]);
    assert_eq!(code, 0, "{stderr}");
    let line = stdout.lines().find(|l| l.starts_with("r_elbow_flex_moment")).unwrap_or_else(|| panic!("{stdout}"));
    let fields: Vec<f64> = line.split_whitespace().skip(1).map(|f| f.parse().unwrap()).collect();
    assert_eq!((fields[0], fields[2]), (0.0, 0.0), "{line}");
    assert!(fields[1] > 1.0, "{line}");
}

/// A DeGroote muscle's second state is OpenSim's `normalized_tendon_force`: its tendon force
/// over F_max.
#[test]
fn degroote_states_are_normalized_tendon_forces() {
    let folder = tempfile::tempdir().unwrap();
    let case = path("fixtures/golden/forward/arm26_degroote");
    let (motion, excitations) = (case.join("motion.mot"), case.join("excitations.sto"));
    let out = folder.path().join("out");
    let model = path("fixtures/models/arm26_degroote.osim");
    let (code, stdout, stderr) = osim_tune(&["forward", s(&model), s(&motion), "--excitations", s(&excitations), "--time", "0.2", "0.4", "--name", "arm", "-o", s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    let states = StorageTable::read(&out.join("arm_states.sto")).unwrap();
    let forces = StorageTable::read(&out.join("arm_tendon_force.sto")).unwrap();
    let normalized = states.column("/forceset/BRA/normalized_tendon_force").unwrap_or_else(|| panic!("{:?} {stdout}", states.labels()));
    let force = forces.column("BRA").unwrap();
    // BRA's F_max in arm26: 987.26 N.
    for (f, n) in force.iter().zip(&normalized) {
        assert!((f / 987.26 - n).abs() < 1e-12 && *n > 0.0, "{f} N against {n}");
    }
}

/// Bad input is refused (exit 2) with the file and what was expected, and nothing is written.
#[test]
fn bad_input_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let arm = arm();
    let (motion, excitations) = arm26_case();
    let labels: Vec<&str> = arm.names.iter().map(String::as_str).collect();
    let too_high = constant_table(folder.path(), "high.sto", &labels, &vec![1.5; labels.len()], false);
    let other = constant_table(folder.path(), "other.sto", &["soleus_r"], &[0.5], false);
    let out = folder.path().join("out");
    let model = path(ARM26);
    let run = |excitations: &Path, extra: &[&str]| {
        let mut arguments = vec!["forward", s(&model), s(&motion), "--excitations", s(excitations), "-o", s(&out)];
        arguments.extend_from_slice(extra);
        osim_tune(&arguments)
    };
    let (code, _, stderr) = run(&too_high, &[]);
    assert!(code == 2 && stderr.contains("high.sto") && stderr.contains("excitation of TRIlong is 1.5"), "{stderr}");
    let (code, _, stderr) = run(&other, &[]);
    assert!(code == 2 && stderr.contains("no muscle of") && stderr.contains("other.sto"), "{stderr}");
    let (code, _, stderr) = run(&excitations, &["--time", "0.5", "1.5"]);
    assert!(code == 2 && stderr.contains("not inside the motion"), "{stderr}");
    let (code, _, stderr) = run(&excitations, &["--accuracy", "0"]);
    assert!(code == 2 && stderr.contains("--accuracy 0"), "{stderr}");
    assert!(!out.exists());
}

/// With --activations the table is the activation: the states' activation columns are its
/// columns at every row it shares with the motion (no dynamics in between).
#[test]
fn activations_given_are_followed_exactly() {
    let folder = tempfile::tempdir().unwrap();
    let (motion, table) = arm26_case();
    let out = folder.path().join("out");
    let (code, _, stderr) = osim_tune(&["forward", s(&path(ARM26)), s(&motion), "--excitations", s(&table), "--activations", "--name", "arm", "-o", s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    let states = StorageTable::read(&out.join("arm_states.sto")).unwrap();
    let given = StorageTable::read(&table).unwrap();
    assert_eq!(states.n_rows(), given.n_rows());
    for muscle in &given.labels()[1..] {
        let ours = states.column(&format!("/forceset/{muscle}/activation")).unwrap();
        assert_eq!(ours, given.column(muscle).unwrap(), "{muscle}");
    }
}

/// A rigid tendon's force needs its path's speed, which over a BallJoint needs the angular
/// velocity the motion does not give: refused with the muscle named.
#[test]
fn a_rigid_tendon_across_a_ball_joint_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(path("fixtures/models/joint_zoo.osim")).unwrap();
    let start = text.find("<Thelen2003Muscle name=\"hip_knee\">").unwrap();
    let end = start + text[start..].find("</Thelen2003Muscle>").unwrap();
    let muscle = text[start..end].replacen("<Thelen2003Muscle name=\"hip_knee\">", "<Millard2012EquilibriumMuscle name=\"hip_knee\">\n<ignore_tendon_compliance>true</ignore_tendon_compliance>", 1);
    let model = folder.path().join("zoo.osim");
    std::fs::write(&model, format!("{}{muscle}</Millard2012EquilibriumMuscle>{}", &text[..start], &text[end + "</Thelen2003Muscle>".len()..])).unwrap();
    let motion = constant_table(folder.path(), "still.mot", &["hip_rx", "knee_flex"], &[10.0, 30.0], true);
    let excitations = constant_table(folder.path(), "u.sto", &["hip_knee"], &[0.3], false);
    let out = folder.path().join("out");
    let (code, _, stderr) = osim_tune(&["forward", s(&model), s(&motion), "--excitations", s(&excitations), "-o", s(&out)]);
    assert!(code == 2 && stderr.contains("muscle hip_knee") && stderr.contains("BallJoint"), "{stderr}");
    assert!(!out.exists());
}


