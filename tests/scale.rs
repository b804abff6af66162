//! Linear scaling against OpenSim 4.6's ScaleTool on the subject01 example
//! (fixtures/golden/scale, from ../shared/reference/pipelines/gait2392_subject01), and by
//! manual factors on five other example models (fixtures/golden/scale_zoo, `oracle/gen_scale_zoo.py`).

mod common;

use common::fixture;
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{MarkerTable, StorageTable};
use osim_tune::mechanics::Multibody;
use osim_tune::model::ModelSpec;
use osim_tune::review::Tolerance;
use osim_tune::setup::ScaleSetup;
use osim_tune::solvers::{CoordinateValues, IkSettings, IkTasks, InverseKinematics};
use osim_tune::validation::{compare_scaled_models, marker_objective, SCALED_MODEL_TOLERANCE};
use osim_tune::tuning::scale::{averaged_frame, move_markers_to_pose, read_marker_set, run_scale_tool, scale_model, update_marker_set, ScaleOutcome, ScaleSet};

/// OpenSim's per-body factors, full precision (`scale_factors.csv`).
fn opensim_scale_set() -> ScaleSet {
    let text = std::fs::read_to_string(fixture("golden/scale/scale_factors.csv")).unwrap();
    let mut set = ScaleSet::unit(std::iter::empty());
    for line in text.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let factors = [1, 2, 3].map(|k| fields[k].parse::<f64>().unwrap());
        set.bodies.push(osim_tune::tuning::scale::BodyScaleFactors { body: fields[0].into(), factors });
    }
    set
}

#[test]
fn scaling_by_opensims_factors_gives_opensims_scaled_model() {
    let generic = OsimDocument::read(&fixture("../models/gait2392_millard2012muscle.osim")).unwrap();
    let markers = read_marker_set(&fixture("subject01/gait2392_Scale_MarkerSet.xml")).unwrap();
    let with_markers = update_marker_set(&generic, &markers).unwrap();
    let scaled = scale_model(&with_markers, &opensim_scale_set(), true, Some(72.6)).unwrap();
    let golden = OsimDocument::read(&fixture("golden/scale/subject01_scaledOnly.osim")).unwrap();
    let differences = compare_scaled_models(&golden, &scaled.document, SCALED_MODEL_TOLERANCE);
    for d in differences.iter().take(60) {
        println!("{} {:?}", d.path, d.change);
    }
    assert!(differences.is_empty(), "{} differences", differences.len());
}

#[test]
fn the_comparison_sees_an_unscaled_model_and_a_single_changed_value() {
    let generic = OsimDocument::read(&fixture("../models/gait2392_millard2012muscle.osim")).unwrap();
    let markers = read_marker_set(&fixture("subject01/gait2392_Scale_MarkerSet.xml")).unwrap();
    let with_markers = update_marker_set(&generic, &markers).unwrap();
    let golden = OsimDocument::read(&fixture("golden/scale/subject01_scaledOnly.osim")).unwrap();
    let unscaled = compare_scaled_models(&golden, &with_markers, SCALED_MODEL_TOLERANCE);
    assert!(unscaled.len() > 500, "{} differences", unscaled.len());
    let mut scaled = scale_model(&with_markers, &opensim_scale_set(), true, Some(72.6)).unwrap().document;
    scaled.set_property("/forceset/vas_int_r/tendon_slack_length", "0.1412").unwrap();
    let differences = compare_scaled_models(&golden, &scaled, SCALED_MODEL_TOLERANCE);
    assert_eq!(differences.iter().map(|d| d.path.as_str()).collect::<Vec<_>>(), ["/forceset/vas_int_r/tendon_slack_length"]);
}

/// The setup `setup` run on the model `model` (both under `fixtures/`).
fn scale_by(setup: &str, model: &str) -> (ScaleSetup, ScaleOutcome) {
    let setup = ScaleSetup::read(&fixture(setup)).unwrap();
    let generic = OsimDocument::read(&fixture(model)).unwrap();
    let outcome = run_scale_tool(&generic, &setup, &mut |_| {}).unwrap();
    (setup, outcome)
}

/// The subject01 setup as OpenSim 4.6 printed it, run on the generic model from `models/`.
fn run_subject01() -> (ScaleSetup, ScaleOutcome) {
    scale_by("subject01/subject01_Setup_Scale.xml", "../models/gait2392_millard2012muscle.osim")
}

/// `outcome`'s scaled model against OpenSim's at `golden` (under `fixtures/golden`): equal in
/// every property.
fn assert_scaled_model_is_opensims(outcome: &ScaleOutcome, golden: &str) {
    let opensim = OsimDocument::read(&fixture(&format!("golden/{golden}"))).unwrap();
    let differences = compare_scaled_models(&opensim, &outcome.scaled.as_ref().unwrap().document, SCALED_MODEL_TOLERANCE);
    assert!(differences.is_empty(), "{golden}: {differences:#?}");
}

#[test]
fn subject01_scale_factors_equal_opensims() {
    let (_, outcome) = run_subject01();
    let golden = opensim_scale_set();
    for body in &golden.bodies {
        let ours = outcome.scale_set.factors(&body.body).unwrap();
        for (a, b) in ours.iter().zip(body.factors) {
            assert!((a - b).abs() <= 1e-9 * b, "{}: {a} vs OpenSim {b}", body.body);
        }
    }
    assert_eq!(outcome.unknown_bodies, ["patella_r", "patella_l"]);
}

/// leg6dof9musc (mass distribution preserved), joint_zoo (masses scaled with the volumes,
/// Ball/Free/Planar/Slider/Gimbal/Pin and oblique CustomJoints on offset frames),
/// Rajagopal2016 (42 muscles wrapping over `WrapCylinder`s, whose L_opt and L_ts follow their
/// wrapped path lengths, and the cylinders themselves scaled), arm26 (TRIlong and BIClong also
/// over `WrapEllipsoid`s, scaled along their own axes) and the wrap zoo (spheres, ellipsoids by
/// every method, tori; wrap objects written without their default rotation and translation)
/// the ellipsoid joints (a `ScapulothoracicJoint`'s radii and winging origin, an
/// `EllipsoidJoint`'s radii) and the station frames (`StationDefinedFrame`s' stations), each body scaled by its own anisotropic manual factors: every property as OpenSim 4.6 wrote
/// it.
#[test]
fn other_models_scaled_by_manual_factors_equal_opensims() {
    for model in ["leg6dof9musc", "joint_zoo", "Rajagopal2016", "arm26", "wrap_zoo", "ellipsoid_joints", "station_frames"] {
        let (_, outcome) = scale_by(&format!("golden/scale_zoo/{model}_setup.xml"), &format!("models/{model}.osim"));
        assert_scaled_model_is_opensims(&outcome, &format!("scale_zoo/{model}_scaled.osim"));
    }
}

/// 2.x/3.x documents — arm26 and leg6dof9musc as OpenSim 2 wrote them (wrap objects, display
/// geometry, moving and conditional path points, a coupler), the abdbonepin shoulder model as
/// OpenSim 3 did (a point constraint) — converted to OpenSim 4's format as OpenSim 4.6's ScaleTool
/// loads them, then scaled by manual factors: every property as OpenSim 4.6 wrote it.
#[test]
fn legacy_models_are_converted_and_scaled_as_opensim() {
    for (model, path) in [("arm26_v20303", "legacy/arm26_v20303.osim"), ("leg6dof9musc_v20303", "legacy/leg6dof9musc_v20303.osim"), ("abdbonepin_v30000", "ik_point_constraint/subject1_abdbonepin.osim")] {
        let (_, outcome) = scale_by(&format!("golden/scale_zoo/{model}_setup.xml"), path);
        assert_scaled_model_is_opensims(&outcome, &format!("scale_zoo/{model}_scaled.osim"));
    }
}

/// A muscle wrapping over an object of a class OpenSim 4.6 no longer has (arm26 with its
/// ellipsoid TRIlonghh made a 3.x `WrapCylinderObst`), whose wrapping osim-tune does not
/// compute: the scaling is refused, naming the muscle and its objects, since its L_opt and L_ts
/// would not follow a path length.
#[test]
fn scaling_a_model_with_unknown_wrapping_is_refused() {
    let setup = ScaleSetup::read(&fixture("golden/scale_zoo/joint_zoo_setup.xml")).unwrap();
    let path = fixture("models/arm26.osim");
    let text = std::fs::read_to_string(&path).unwrap();
    let obstacle = text.replacen("<WrapEllipsoid name=\"TRIlonghh\">", "<WrapCylinderObst name=\"TRIlonghh\">", 1).replacen("</WrapEllipsoid>", "</WrapCylinderObst>", 1);
    let arm = OsimDocument::parse(obstacle, &path).unwrap();
    let error = run_scale_tool(&arm, &setup, &mut |_| {}).unwrap_err().to_string();
    assert!(error.contains("arm26.osim") && error.contains("TRIlong: its path wraps over TRI, TRIlonghh, TRIlongglen, among which one of a class OpenSim 4.6 does not have"), "{error}");
}

/// OpenSim's static pose (`file` in `fixtures/golden`, printed to 8 decimals, rad and m), in the
/// CoordinateSet order of `multibody`.
fn opensim_static_pose(multibody: &Multibody, file: &str) -> Vec<f64> {
    let table = StorageTable::read(&fixture(&format!("golden/{file}"))).unwrap();
    let value = |name: &str| {
        let label = table.labels().iter().find(|l| l.ends_with(&format!("/{name}/value"))).unwrap().clone();
        table.column(&label).unwrap()[0]
    };
    multibody.coordinates.iter().map(|c| value(&c.name)).collect()
}

#[test]
fn subject01_scale_step_gives_opensims_scaled_model() {
    let (_, outcome) = run_subject01();
    assert_scaled_model_is_opensims(&outcome, "scale/subject01_scaledOnly.osim");
}

/// OpenSim's MarkerPlacer solves the static pose with the assembler's default accuracy, so its
/// pose is not the minimum of its own objective; ours must be at least as good. Markers moved
/// at OpenSim's pose (`pose_file`) must land where OpenSim put them (`placed_file`), to the 1e-8
/// print precision of that pose (bound 1e-7 m). Returns how many markers were moved.
fn assert_placement_is_opensims_at_a_better_pose(outcome: &ScaleOutcome, setup: &ScaleSetup, pose_file: &str, placed_file: &str) -> usize {
    let scaled = &outcome.scaled.as_ref().unwrap().document;
    let multibody = Multibody::new(&ModelSpec::read(scaled).unwrap()).unwrap();
    let placement = outcome.placement.as_ref().unwrap();
    let opensim_pose = opensim_static_pose(&multibody, pose_file);
    let placer = setup.marker_placer.as_ref().unwrap();
    let trial = MarkerTable::read(&placer.marker_file.as_ref().unwrap().resolved).unwrap();
    let static_pose = averaged_frame(&trial.in_meters(), placer.time_range).unwrap();
    let objective = |q: &[f64]| marker_objective(&multibody, &placer.ik_tasks, &static_pose, q).unwrap();
    let (ours, opensim) = (objective(&placement.frame.q), objective(&opensim_pose));
    assert!(ours <= opensim, "static objective {ours} worse than OpenSim's {opensim}");
    assert!(placement.deleted.is_empty() && placement.without_data.is_empty());

    let at_opensim_pose = move_markers_to_pose(scaled, &static_pose, &opensim_pose).unwrap();
    let golden = OsimDocument::read(&fixture(&format!("golden/{placed_file}"))).unwrap();
    let differences = compare_scaled_models(&golden, &at_opensim_pose.document, Tolerance { relative: 0.0, absolute: 1e-7 });
    assert!(differences.is_empty(), "{differences:#?}");
    placement.moved.len()
}

#[test]
fn subject01_marker_placement_is_opensims_at_a_better_static_pose() {
    let (setup, outcome) = run_subject01();
    let moved = assert_placement_is_opensims_at_a_better_pose(&outcome, &setup, "scale/subject01_static_output.mot", "scale/subject01_simbody.osim");
    assert_eq!(moved, 39);
}

/// Measurements on a model whose default values break its constraints
/// (`oracle/gen_constraint_assembly.py`): OpenSim measures the model's marker pairs at its
/// default state, which `initSystem` assembles — across a point-constrained elbow, a
/// constant-distance rod and a weld — and so do we: every property as OpenSim wrote it.
#[test]
fn a_model_with_constraints_is_measured_at_its_assembled_default_pose() {
    let (_, outcome) = scale_by("golden/scale_linked/setup.xml", "models/linked_mechanisms.osim");
    assert_scaled_model_is_opensims(&outcome, "scale_linked/scaled.osim");
}

/// leg6dof9musc and a synthetic static trial (`oracle/gen_scale_measured.py`: the model scaled
/// anisotropically, 1.5 mm marker noise): five measurements of within- and across-body marker
/// pairs (one on two axes only), the patella and toes scaled with their neighbours, then marker
/// placement with one task weighted 10 and one not applied. The scaled model is OpenSim's in
/// every property; the placement as for subject01.
#[test]
fn leg6dof9musc_scaled_by_measurements_and_placed_as_opensim() {
    let (setup, outcome) = scale_by("golden/scale_measured/setup.xml", "models/leg6dof9musc.osim");
    assert_scaled_model_is_opensims(&outcome, "scale_measured/scaledOnly.osim");
    let moved = assert_placement_is_opensims_at_a_better_pose(&outcome, &setup, "scale_measured/static_pose.mot", "scale_measured/placed.osim");
    assert_eq!(moved, 12);
}

/// A `from_file` coordinate task in marker placement (`oracle/gen_scale_measured.py`:
/// knee_angle_r pulled, weight 5, toward `coordinates.mot`, which changes over time, over a
/// time range starting at 0.05 s): the coordinate file's spline is evaluated at the range's
/// start, as OpenSim's state time. OpenSim's static pose is not converged (its knee 0.26° off
/// ours): ours is the better minimum of the objective with the coordinate task, and the
/// markers placed at OpenSim's pose are OpenSim's placed model.
#[test]
fn a_from_file_task_in_marker_placement_follows_the_coordinate_file_as_opensim() {
    let (setup, outcome) = scale_by("golden/scale_measured/setup_from_file.xml", "models/leg6dof9musc.osim");
    let (_, plain) = scale_by("golden/scale_measured/setup.xml", "models/leg6dof9musc.osim");
    let scaled = &outcome.scaled.as_ref().unwrap().document;
    let multibody = Multibody::new(&ModelSpec::read(scaled).unwrap()).unwrap();
    let opensim_pose = opensim_static_pose(&multibody, "scale_measured/static_pose_from_file.mot");
    let placement = outcome.placement.as_ref().unwrap();
    assert_eq!(placement.frame.time, 0.05);
    let placer = setup.marker_placer.as_ref().unwrap();
    let trial_file = &placer.marker_file.as_ref().unwrap().resolved;
    let static_pose = averaged_frame(&MarkerTable::read(trial_file).unwrap().in_meters(), placer.time_range).unwrap();
    let values = CoordinateValues::read_setup_file(placer.coordinate_file.as_ref()).unwrap();
    let tasks = IkTasks::from_task_set(&placer.ik_tasks, &setup.file, values).unwrap();
    let ik = InverseKinematics::new(&multibody, &static_pose, trial_file, &tasks, IkSettings::default()).unwrap();
    let mut workspace = ik.workspace();
    let (ours, opensim) = (ik.objective(0, &placement.frame.q, &mut workspace).unwrap(), ik.objective(0, &opensim_pose, &mut workspace).unwrap());
    assert!(ours <= opensim, "objective {ours} worse than OpenSim's {opensim}");
    let worst = placement.frame.q.iter().zip(&opensim_pose).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 0.01, "static pose {worst} rad or m from OpenSim's (its convergence: 4.5e-3)");
    let knee = multibody.coordinate_index("knee_angle_r").unwrap();
    let target = (-40.0_f64 + 150.0 * 0.05).to_radians();
    let (pulled, free) = (placement.frame.q[knee], plain.placement.as_ref().unwrap().frame.q[knee]);
    assert!((pulled - target).abs() + 0.1 < (free - target).abs(), "the task pulls the knee toward −32.5° at 0.05 s: {pulled} vs {free}");
    let at_opensim_pose = move_markers_to_pose(scaled, &static_pose, &opensim_pose).unwrap();
    let golden = OsimDocument::read(&fixture("golden/scale_measured/placed_from_file.osim")).unwrap();
    let differences = compare_scaled_models(&golden, &at_opensim_pose.document, Tolerance { relative: 0.0, absolute: 1e-7 });
    assert!(differences.is_empty(), "{differences:#?}");
}

/// A 3.x marker-set file names bodies by `<body>`: a marker on `ground` is on `/ground` (as
/// OpenSim's conversion makes it), the others on `/bodyset/<body>`.
#[test]
fn a_3x_marker_set_puts_ground_markers_on_ground() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("markers.xml");
    let text = "<OpenSimDocument Version=\"30000\"><MarkerSet><objects>\
        <Marker name=\"LAB\"><body>ground</body><location>0 0 0</location></Marker>\
        <Marker name=\"KNEE\"><body>femur_r</body><location>0 -0.4 0.05</location><fixed>true</fixed></Marker>\
        </objects></MarkerSet></OpenSimDocument>";
    std::fs::write(&path, text).unwrap();
    let markers = read_marker_set(&path).unwrap();
    assert_eq!(markers.iter().map(|m| m.parent_frame.as_str()).collect::<Vec<_>>(), ["/ground", "/bodyset/femur_r"]);
    assert!(markers[1].fixed);
}
