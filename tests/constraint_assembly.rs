//! Constraints between bodies as OpenSim 4.6 holds them (`oracle/gen_constraint_assembly.py`):
//! the default pose `initSystem` assembles, and inverse kinematics with every link class.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::{tied_coordinates, Multibody};
use osim_tune::model::ModelSpec;
use osim_tune::solvers::assemble;
use osim_tune::validation::compare_assembly;
use osim_tune::validation::ik::{compare_ik, IkCase, IkFrames};

/// The largest coordinate (rad or m) and marker (m) differences of our assembled default pose
/// from OpenSim's.
fn assembled_differences(model: &str) -> (f64, f64) {
    let comparison = compare_assembly(&common::root(), model, "constraint_assembly.json").unwrap_or_else(|e| panic!("{e}"));
    assert!(comparison.markers.count > 0);
    (comparison.coordinates.error, comparison.markers.error)
}

/// Five mechanisms whose default values break their constraints (a point loop, a constant
/// distance, a point on a line with a coordinate free to satisfy it, a weld, a coupler driven
/// through the weld): assembly moves them as OpenSim's does, to OpenSim's assembly accuracy
/// (1e-12 in the model; the nearest-pose problem is well conditioned here).
#[test]
fn the_default_pose_of_linked_mechanisms_is_assembled_as_opensim_assembles_it() {
    let (coordinates, markers) = assembled_differences("linked_mechanisms.osim");
    assert!(coordinates < 1e-9 && markers < 1e-9, "{coordinates:e} rad or m, {markers:e} m");
}

/// A model whose only constraint is a coupler: the dependent follows its independent
/// coordinate (2e-8 rad from its own default value); OpenSim's assembler, at its default
/// accuracy 1e-9, leaves the others within 5e-10 of their defaults.
#[test]
fn a_coupled_default_pose_follows_the_coupler() {
    let (coordinates, markers) = assembled_differences("leg6dof9musc.osim");
    assert!(coordinates < 1e-9 && markers < 1e-9, "{coordinates:e} rad or m, {markers:e} m");
    let path = common::fixture("models/leg6dof9musc.osim");
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap();
    let defaults: Vec<f64> = multibody.coordinates.iter().map(|c| c.default_value).collect();
    assert_eq!(multibody.default_pose(), assemble(&multibody, &defaults).unwrap());
}

/// Inverse kinematics holds every link class exactly and matches OpenSim over the trial.
#[test]
fn inverse_kinematics_holds_every_link_class_as_opensim() {
    let comparison = compare_ik(&IkCase::linked_mechanisms(&common::root()), IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 20);
    assert!(comparison.passes(), "{comparison:?}");
}

/// A link whose error moves only at second order: a reed on a pin whose tip must be 1.5 m from
/// a ground point 1 m from the pin — its farthest reach, so the tip must point straight away
/// (angle −π/2) and the distance's slope vanishes there. Holding it needs multipliers far
/// beyond the augmented Lagrangian's first weight (OpenSim's PushUpToesOnGround test models
/// have such links); assembly still closes it, at the angle first principles give.
/// A reed on a pin about z at the origin, its tip 0.5 m down, held `distance` m from the ground
/// point `point` (a `ConstantDistanceConstraint`), its angle's default `angle`.
fn reed(point: [f64; 3], distance: f64, angle: f64) -> Multibody {
    let text = format!(
        r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000"><Model name="reed"><Ground name="ground"/>
<BodySet name="bodyset"><objects><Body name="reed"><mass>1</mass><mass_center>0 0 0</mass_center><inertia>0.1 0.1 0.1 0 0 0</inertia></Body></objects></BodySet>
<JointSet name="jointset"><objects><PinJoint name="pin"><socket_parent_frame>/ground</socket_parent_frame><socket_child_frame>/bodyset/reed</socket_child_frame>
<coordinates><Coordinate name="angle"><default_value>{angle}</default_value></Coordinate></coordinates></PinJoint></objects></JointSet>
<ConstraintSet name="constraintset"><objects><ConstantDistanceConstraint name="taut"><socket_body_1>/ground</socket_body_1><socket_body_2>/bodyset/reed</socket_body_2>
<location_body_1>{} {} {}</location_body_1><location_body_2>0 -0.5 0</location_body_2><constant_distance>{distance}</constant_distance></ConstantDistanceConstraint></objects></ConstraintSet>
</Model></OpenSimDocument>"#,
        point[0], point[1], point[2]
    );
    Multibody::new(&ModelSpec::read(&OsimDocument::parse(text, std::path::Path::new("reed.osim")).unwrap()).unwrap()).unwrap()
}

/// The distance of the reed's link at pose `q` (m).
fn reed_distance(multibody: &Multibody, q: &[f64]) -> f64 {
    let mut kinematics = multibody.kinematics();
    multibody.realize(q, &mut kinematics);
    let [ground, tip] = &multibody.links[0].ends;
    (kinematics.bodies[tip.body].apply(&tip.location) - kinematics.bodies[ground.body].apply(&ground.location)).norm()
}

/// A link whose error moves only at second order: the reed's tip must be 1.5 m from a ground
/// point 1 m from the pin — its farthest reach, so the tip must point straight away (angle
/// −π/2) and the distance's slope vanishes there. Holding it needs multipliers far beyond the
/// augmented Lagrangian's first weight (OpenSim's PushUpToesOnGround test models have such
/// links); assembly still closes it, at the angle first principles give.
#[test]
fn a_link_that_moves_only_at_second_order_is_closed() {
    let multibody = reed([1.0, 0.0, 0.0], 1.5, 0.3);
    let q = assemble(&multibody, &[0.3]).unwrap();
    assert!((reed_distance(&multibody, &q) - 1.5).abs() <= 1e-10, "{q:?}");
    assert!((q[0] + std::f64::consts::FRAC_PI_2).abs() < 1e-4, "{q:?}");
}

/// A distance link whose points coincide at the start (its slope undefined there) still
/// assembles: the tip starts on the ground point and must end 0.3 m from it, the nearest such
/// angle being 2·asin(0.3) either way.
#[test]
fn a_distance_link_starting_at_zero_length_is_closed() {
    let multibody = reed([0.0, -0.5, 0.0], 0.3, 0.0);
    let q = assemble(&multibody, &[0.0]).unwrap();
    assert!((reed_distance(&multibody, &q) - 0.3).abs() <= 1e-10, "{q:?}");
    assert!((q[0].abs() - 2.0 * 0.3_f64.asin()).abs() < 1e-8, "{q:?}");
}

/// Moment arms through the constraints, as OpenSim's `MomentArmSolver` computes them (the
/// coordinate's speed lit, the others projected onto the velocity constraints), for muscles
/// across every link class and the coupler, at the assembled default pose and three trial
/// poses, to 1e-9 m (7e-13 found); about coordinates the constraints (nearly) fix — the welded
/// cap's y rotation and z translation, whose lit speeds project to 1e-16 and 1e-4 — OpenSim's
/// values are round-off over round-off (NaN for the first) and are not compared.
#[test]
fn moment_arms_through_links_are_opensims() {
    let comparison = compare_assembly(&common::root(), "linked_mechanisms.osim", "constraint_assembly.json").unwrap_or_else(|e| panic!("{e}"));
    assert!(comparison.lengths.count == 20 && comparison.lengths.error < 1e-12, "{:?}", comparison.lengths);
    assert!(comparison.moment_arms.error < 1e-9, "{:?}", comparison.moment_arms);
    assert!(comparison.moment_arms.count > 4 * 5 * 15, "{comparison:?}");
}

/// A published model with a PointConstraint: opensim-core's ThoracoscapularShoulderModel (Seth
/// et al. 2019; the acromioclavicular joint closed by `AC`, 33 muscles). Along couplers only,
/// the scapula muscles' moment arms were off by up to 0.31 m (LatissimusDorsi_I about
/// scapula_winging); through the constraint they are OpenSim's to round-off, at the assembled
/// default pose and two assembled poses away from it.
#[test]
fn a_published_shoulder_models_moment_arms_are_opensims() {
    let comparison = compare_assembly(&common::root(), "ThoracoscapularShoulderModel.osim", "shoulder_moment_arms.json").unwrap_or_else(|e| panic!("{e}"));
    assert!(comparison.coordinates.error < 1e-9 && comparison.markers.error < 1e-9, "{comparison:?}");
    assert!(comparison.lengths.count == 3 * 33 && comparison.lengths.error < 1e-12, "{:?}", comparison.lengths);
    assert!(comparison.moment_arms.count > 3 * 33 * 15 && comparison.moment_arms.error < 1e-9, "{:?}", comparison.moment_arms);
}

/// `analyze` assembles every row as OpenSim's AnalyzeTool does: along OpenSim's IK solution
/// with elbow_flexion moved 3°, which opens the point loop, the muscle lengths are
/// AnalyzeTool's (printed to 8 decimals; unassembled, the loop muscle would be 1 mm off).
#[test]
fn analyze_assembles_each_row_as_opensims_analyze_tool() {
    let golden = common::fixture("golden/analyze_linked");
    let out = tempfile::tempdir().unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_osim-tune"))
        .args(["analyze", common::fixture("models/linked_mechanisms.osim").to_str().unwrap(), "--motion"])
        .arg(golden.join("perturbed.mot"))
        .arg("-o")
        .arg(out.path())
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let ours = StorageTable::read(&out.path().join("Length.sto")).unwrap();
    let opensim = StorageTable::read(&golden.join("Length.sto")).unwrap();
    assert_eq!(ours.n_rows(), opensim.n_rows());
    let mut worst = 0.0_f64;
    for label in opensim.labels().iter().skip(1) {
        for (a, b) in ours.column(label).unwrap().iter().zip(opensim.column(label).unwrap()) {
            worst = worst.max((a - b).abs());
        }
    }
    assert!(worst < 6e-9, "{worst:e} m");
}

/// The coordinates a path's moment arms are taken about grow through the links to every
/// coordinate a chain of constraints ties to them, whatever repeats the start holds (a path's
/// conditional points repeat their coordinate): three pendulums, the first tied to the second,
/// the second to the third; from the first (twice), all three.
#[test]
fn links_tie_coordinates_together_whatever_the_start_repeats() {
    let pendulum = |k: usize| {
        format!(
            "<PinJoint name=\"pin{k}\"><socket_parent_frame>ground_offset{k}</socket_parent_frame><socket_child_frame>/bodyset/b{k}</socket_child_frame>\
             <coordinates><Coordinate name=\"q{k}\"/></coordinates><frames><PhysicalOffsetFrame name=\"ground_offset{k}\"><socket_parent>/ground</socket_parent>\
             <translation>{k} 0 0</translation><orientation>0 0 0</orientation></PhysicalOffsetFrame></frames></PinJoint>"
        )
    };
    let body = |k: usize| format!("<Body name=\"b{k}\"><mass>1</mass><mass_center>0 0 0</mass_center><inertia>0.1 0.1 0.1 0 0 0</inertia></Body>");
    let tie = |a: usize, b: usize| {
        format!("<PointConstraint name=\"tie{a}{b}\"><socket_body_1>/bodyset/b{a}</socket_body_1><socket_body_2>/bodyset/b{b}</socket_body_2><location_body_1>0.5 -1 0</location_body_1><location_body_2>-0.5 -1 0</location_body_2></PointConstraint>")
    };
    let text = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" ?><OpenSimDocument Version=\"40000\"><Model name=\"chain\"><Ground name=\"ground\"/>\
         <BodySet name=\"bodyset\"><objects>{}</objects></BodySet><JointSet name=\"jointset\"><objects>{}</objects></JointSet>\
         <ConstraintSet name=\"constraintset\"><objects>{}{}</objects></ConstraintSet></Model></OpenSimDocument>",
        (1..=3).map(body).collect::<String>(),
        (1..=3).map(pendulum).collect::<String>(),
        tie(1, 2),
        tie(2, 3)
    );
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::parse(text, std::path::Path::new("chain.osim")).unwrap()).unwrap()).unwrap();
    for start in [vec![0], vec![0, 0], vec![2, 2, 2]] {
        assert_eq!(tied_coordinates(&multibody, &start), vec![0, 1, 2], "{start:?}");
    }
}
