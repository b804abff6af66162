//! OpenSim 4.6's ForwardTool reproduced (`oracle/gen_forward_tool.py`): arm26 from its
//! equilibrated default state under time-varying excitations, from a states file's row with an
//! added CoordinateActuator under two controllers, and under the model's and the setup's
//! PrescribedControllers with a force on the hand; a top on a BallJoint and a brick on a
//! FreeJoint spinning under gravity; a scapula on a ScapulothoracicJoint and an arm on an
//! EllipsoidJoint falling; closed loops held by point, distance, point-on-line and weld
//! constraints; and `simulate` / `run` writing OpenSim's files.

mod common;

use common::{fixture, osim_tune};
use osim_tune::io::table::StorageTable;
use osim_tune::validation::{compare_forward_tool, FORWARD_TOOL_CASES};

#[test]
fn opensims_forward_simulations_are_reproduced() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for case in FORWARD_TOOL_CASES {
        let c = compare_forward_tool(root, case).unwrap();
        eprintln!("{case}: {c:?}");
        // Both integrators hold the setup's tolerance per state and step (OpenSim's
        // Runge–Kutta–Merson, our Dormand–Prince; 1e-9, 1e-12 for the whirling ellipsoid case);
        // over 0.2–0.5 s their global errors part the two by up to 3e-7 rad, 1.2e-5 rad/s, 3e-7 in
        // activation, 7e-8 m.
        assert!((c.start[0] - c.start[1]).abs() < 1e-15, "{case}: the initial time");
        assert!(c.value < 1e-6 && c.speed < 3e-5 && c.activation < 1e-6 && c.fiber_length < 2e-7, "{case}: {c:?}");
        assert!(c.control < 1e-12, "{case}: {c:?}");
    }
}

/// The `states` golden's setup, run by `run` in a folder as OpenSim's GUI leaves it, with a
/// Kinematics analysis added: OpenSim's three files under its names, the states starting at
/// OpenSim's initial state and the Kinematics `q` table equal to the states in degrees (the
/// analysis reads the simulated states).
#[test]
fn run_simulates_a_forward_setup_and_its_analyses_read_the_states() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let golden = fixture("golden/forward_tool/states");
    for file in ["arm26_controls.xml", "motor_controls.xml", "initial_states.sto", "elbow_actuator.xml"] {
        std::fs::copy(golden.join(file), dir.join(file)).unwrap();
    }
    std::fs::copy(fixture("models/arm26.osim"), dir.join("arm26.osim")).unwrap();
    let setup = std::fs::read_to_string(golden.join("setup.xml")).unwrap().replace(
        "<AnalysisSet name=\"Analyses\"><objects /></AnalysisSet>",
        "<AnalysisSet name=\"Analyses\"><objects><Kinematics name=\"Kinematics\"><on>true</on><step_interval>1</step_interval><in_degrees>true</in_degrees></Kinematics></objects></AnalysisSet>",
    ).replace("<results_directory>./</results_directory>", "<results_directory>out</results_directory>");
    std::fs::write(dir.join("setup.xml"), setup).unwrap();
    let (code, stdout, stderr) = osim_tune(&["run", dir.join("setup.xml").to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains(&format!("osim-tune simulate {0}/arm26.osim --setup {0}/setup.xml -o {0}/out", dir.display())), "{stdout}");
    let out = dir.join("out");
    let states = StorageTable::read(&out.join("arm26_states.sto")).unwrap();
    let opensim = StorageTable::read(&golden.join("arm26_states.sto")).unwrap();
    assert_eq!(states.labels(), opensim.labels());
    for (ours, theirs) in states.row(0).unwrap().iter().zip(opensim.row(0).unwrap()) {
        assert!((ours - theirs).abs() < 1e-12, "the initial state: {ours} against OpenSim's {theirs}");
    }
    let degrees = StorageTable::read(&out.join("arm26_states_degrees.mot")).unwrap();
    assert_eq!(degrees.in_degrees(), Some(true));
    let q = StorageTable::read(&out.join("arm26_Kinematics_q.sto")).unwrap();
    assert_eq!(q.n_rows(), states.n_rows());
    for (coordinate, label) in [("r_shoulder_elev", "/jointset/r_shoulder/r_shoulder_elev/value"), ("r_elbow_flex", "/jointset/r_elbow/r_elbow_flex/value")] {
        for (a, b) in q.column(coordinate).unwrap().iter().zip(degrees.column(label).unwrap()) {
            assert!((a - b).abs() < 1e-9, "{coordinate}: Kinematics {a}° against the states' {b}°");
        }
    }
    let controls = StorageTable::read(&out.join("arm26_controls.sto")).unwrap();
    assert_eq!(controls.labels().last().map(String::as_str), Some("elbow_motor"));
}

/// What `simulate` cannot do is refused, naming it (exit 2, nothing written): a controller class
/// it does not apply, a PrescribedController with a function too few, an empty time range.
#[test]
fn a_forward_setup_it_cannot_simulate_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let golden = fixture("golden/forward_tool/controls");
    std::fs::copy(golden.join("arm26_controls.xml"), dir.join("arm26_controls.xml")).unwrap();
    let text = std::fs::read_to_string(golden.join("setup.xml")).unwrap();
    let controller = "<ControlSetController name=\"c0\"><controls_file>arm26_controls.xml</controls_file></ControlSetController>";
    let model = fixture("models/arm26.osim");
    let refusals = [
        ("<ToyReflexController name=\"reflex\" />", ["ToyReflexController reflex", "does not apply"]),
        ("<PrescribedController name=\"p\"><actuator_list>TRIlong BRA</actuator_list><FunctionSet name=\"ControlFunctions\"><objects><Constant><value>0.1</value></Constant></objects></FunctionSet></PrescribedController>", ["PrescribedController p", "1 control functions for 2 actuators"]),
    ];
    for (replacement, expected) in refusals {
        std::fs::write(dir.join("setup.xml"), text.replace(controller, replacement)).unwrap();
        let (code, _, stderr) = osim_tune(&["simulate", model.to_str().unwrap(), "--setup", dir.join("setup.xml").to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
        assert_eq!(code, 2, "{stderr}");
        assert!(expected.iter().all(|e| stderr.contains(e)), "{stderr}");
        assert!(!dir.join("out").exists());
    }
    // An empty time range names the setup.
    std::fs::write(dir.join("setup.xml"), text.replace("<final_time>0.3</final_time>", "<final_time>0</final_time>")).unwrap();
    let (code, _, stderr) = osim_tune(&["simulate", model.to_str().unwrap(), "--setup", dir.join("setup.xml").to_str().unwrap(), "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("setup.xml") && stderr.contains("time range 0–0 s is empty"), "{stderr}");
    assert!(!dir.join("out").exists());
}

/// A forward simulation of closed loops stays on them: the `linked` golden's mechanisms (point,
/// distance, point-on-line and weld constraints) falling for 3 s at ForwardTool's default
/// tolerance 1e-5. Held only at the acceleration level, their poses drifted 6e-4 m off the
/// links by 3 s and their speeds 1e-2 m/s; projected back after each step that leaves them open
/// by more than the tolerance (as Simbody does), every recorded state keeps them within it.
#[test]
fn closed_loops_stay_closed_over_a_long_simulation() {
    use osim_tune::analysis::{initial_state, simulate_plant, ForwardModel, InitialSource};
    use osim_tune::setup::ForwardSetup;
    let mut setup = ForwardSetup::read(&fixture("golden/forward_tool/linked/setup.xml")).unwrap();
    setup.tool.final_time = 3.0;
    setup.integrator.error_tolerance = 1e-5;
    setup.integrator.maximum_steps = 100_000;
    let inputs = ForwardModel::read(&fixture("models/linked_mechanisms.osim"), &setup.tool).unwrap();
    let mut plant = inputs.plant().unwrap();
    let (start, initial) = initial_state(&plant, InitialSource::Defaults, 0.0, true).unwrap();
    plant.hold(&initial.q);
    let simulation = simulate_plant(&plant, &initial, [start, 3.0], &setup.integrator).unwrap();
    assert!(simulation.projections > 0, "the loops drift and are projected");
    let multibody = &inputs.geometry.multibody;
    let drift = simulation.states.iter().map(|s| multibody.link_drift(&s.q, &s.u)).fold((0.0f64, 0.0f64), |(p, r), (a, b)| (p.max(a), r.max(b)));
    assert!(drift.0 <= 1e-5 && drift.1 <= 1e-5, "drift {drift:?} (m, m/s) over {} states", simulation.states.len());
}
