//! Inverse kinematics: against OpenSim 4.6's InverseKinematicsTool on subject01's walking trial,
//! and from first principles on synthetic trials (markers placed by our own kinematics at a
//! known pose must give that pose back; bounds, locks, couplers, missing markers).

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{LengthUnit, MarkerTable, StorageTable, TrcHeader};
use osim_tune::mechanics::Multibody;
use osim_tune::model::{FrameChain, MarkerSpec, ModelSpec};
use osim_tune::solvers::{
    ConstraintWeight, CoordinateTarget, CoordinateTask, IkError, IkSettings, IkTasks, InverseKinematics, KalmanIkSettings, LeastSquaresStatus, MarkerTask, MissingFrom,
};
use osim_tune::validation::ik::{compare_ik, read_setup_tasks, IkCase, IkFrames, RMS_SLACK_METERS};

// ---------------------------------------------------------------- against OpenSim 4.6

#[test]
fn subject01_walk1_matches_opensim_over_the_whole_trial() {
    let comparison = compare_ik(&IkCase::subject01_walk1(&common::root()), IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 151);
    assert_eq!(comparison.unconverged, 0);
    for coordinate in &comparison.coordinates {
        assert!(coordinate.worst <= coordinate.tolerance, "{coordinate:?}");
    }
    // Ours is the better minimum of the same objective in every frame…
    assert!(comparison.objective_excess < 0.0, "{comparison:?}");
    // …and the unweighted marker RMS stays within the stated slack of OpenSim's.
    assert!(comparison.rms_excess <= RMS_SLACK_METERS, "{comparison:?}");
    // subtalar angles balance weight-1000 coordinate tasks against the markers: they agree to
    // 1e-6° only if the marker goal is divided by the total marker weight, as Simbody does.
    for name in ["subtalar_angle_r", "subtalar_angle_l", "mtp_angle_r", "mtp_angle_l"] {
        let difference = comparison.coordinates.iter().find(|c| c.name == name).unwrap();
        assert!(difference.worst < 1e-6, "{difference:?}");
    }
    assert!(comparison.passes());
}

/// Against OpenSim run to convergence (accuracy 1e-10) the 0.05° / 0.1 mm hold.
#[test]
fn subject01_walk1_matches_converged_opensim_within_five_hundredths_of_a_degree() {
    let comparison = compare_ik(&IkCase::subject01_walk1_converged(&common::root()), IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 151);
    assert!(comparison.passes(), "{comparison:?}");
    let worst = comparison.worst_coordinate().unwrap();
    assert!(worst.worst < 0.05, "{worst:?}");
}

/// A model with a `PointConstraint` (and a `ScapulothoracicJoint`): the constraint is held and
/// the solution is OpenSim's to 1e-4°, no worse in any frame's objective.
#[test]
fn a_point_constraint_is_held_as_opensim_holds_it() {
    let comparison = compare_ik(&IkCase::shoulder_point_constraint(&common::root()), IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 101);
    assert!(comparison.passes(), "{comparison:?}");
}

/// With a finite constraint weight the point link is a goal, not held: it opens (by more than
/// the exact solve's 1e-10 m) and the markers fit better; Kalman smoothing holds it exactly.
#[test]
fn a_point_constraint_is_a_goal_under_a_finite_weight_and_held_by_the_smoother() {
    let case = IkCase::shoulder_point_constraint(&common::root());
    let (multibody, trial) = load(&case.model, &case.trial);
    let (tasks, _) = read_setup_tasks(&case.setup).unwrap();
    let gap = |weight: ConstraintWeight| {
        let settings = IkSettings { constraint_weight: weight, ..IkSettings::default() };
        let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, settings).unwrap();
        let frame = ik.solve(Some([0.5, 0.5])).unwrap().frames.remove(0);
        let mut kinematics = multibody.kinematics();
        multibody.realize(&frame.q, &mut kinematics);
        let [a, b] = &multibody.links[0].ends;
        ((kinematics.bodies[a.body].apply(&a.location) - kinematics.bodies[b.body].apply(&b.location)).norm(), frame.errors.rms)
    };
    let (exact_gap, exact_rms) = gap(ConstraintWeight::Infinite);
    let (soft_gap, soft_rms) = gap(ConstraintWeight::Finite(1.0));
    assert!(exact_gap <= 1e-10 && soft_gap > 1e-6 && soft_rms < exact_rms, "{exact_gap:e} {soft_gap:e} {exact_rms} {soft_rms}");
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap();
    let smoothed = ik.smooth(&ik.solve(Some([0.0, 0.1])).unwrap(), &KalmanIkSettings::with_cutoff(6.0)).unwrap();
    for (frame, u) in smoothed.solution.frames.iter().zip(&smoothed.speeds) {
        let (position, rate) = multibody.link_drift(&frame.q, u);
        assert!(position <= 1e-10 && rate <= 1e-9, "t = {}: the AC joint open by {position:e} m, {rate:e} m/s", frame.time);
    }
}

/// A constraint inverse kinematics does not hold (here the same link as a
/// `RollingOnSurfaceConstraint`) is refused, named, rather than ignored.
#[test]
fn a_constraint_ik_does_not_hold_is_refused() {
    let case = IkCase::shoulder_point_constraint(&common::root());
    let text = std::fs::read(&case.model).unwrap();
    let text = String::from_utf8_lossy(&text).replace("PointConstraint", "RollingOnSurfaceConstraint");
    let spec = ModelSpec::read(&OsimDocument::parse(text, &case.model).unwrap()).unwrap();
    let multibody = Multibody::new(&spec).unwrap();
    let trial = MarkerTable::read(&case.trial).unwrap();
    let (tasks, _) = read_setup_tasks(&case.setup).unwrap();
    let error = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap_err();
    assert!(error.to_string().contains("AC (RollingOnSurfaceConstraint)") && error.to_string().contains("isEnforced"), "{error}");
}

/// `from_file` coordinate tasks follow the setup's `coordinate_file` through OpenSim's quintic
/// splines: OpenSim's solution to its convergence, the pulled coordinates moved off the
/// markers-only pose by degrees.
#[test]
fn coordinate_tasks_from_a_file_match_opensim() {
    let case = IkCase::subject01_coordinate_file(&common::root());
    let comparison = compare_ik(&case, IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 25);
    assert!(comparison.passes(), "{comparison:?}");
    let pulled = StorageTable::read(&case.motion).unwrap();
    let free = StorageTable::read(&IkCase::subject01_walk1_converged(&common::root()).motion).unwrap();
    let at = |table: &StorageTable, time: f64| table.times().iter().position(|t| (t - time).abs() < 1e-6).unwrap();
    let knee = |table: &StorageTable, time: f64| table.column("knee_angle_r").unwrap()[at(table, time)];
    assert!((knee(&pulled, 0.8) - knee(&free, 0.8)).abs() > 1.0, "the knee task pulls by degrees");
}

#[test]
fn single_frames_started_from_opensims_previous_frame_match_too() {
    let comparison = compare_ik(&IkCase::subject01_walk1(&common::root()), IkFrames::EveryNth(5)).unwrap();
    assert_eq!(comparison.frames, 31);
    assert!(comparison.passes(), "{comparison:?}");
}

#[test]
fn the_motion_table_has_opensims_layout() {
    let case = IkCase::subject01_walk1(&common::root());
    let (multibody, trial) = load(&case.model, &case.trial);
    let (tasks, range) = read_setup_tasks(&case.setup).unwrap();
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap();
    let solution = ik.solve(range).unwrap();
    let ours = solution.motion_table(&multibody).unwrap();
    let golden = StorageTable::read(&case.motion).unwrap();
    assert_eq!(ours.name(), golden.name());
    assert_eq!(ours.in_degrees(), Some(true));
    assert_eq!(ours.labels(), golden.labels());
    assert_eq!(ours.comments(), golden.comments());
    assert_eq!(ours.times(), golden.times());
    let header = |text: &str| text.lines().take_while(|l| *l != "endheader").map(String::from).collect::<Vec<_>>();
    assert_eq!(header(&ours.to_text()), header(&std::fs::read_to_string(&case.motion).unwrap()));
    let errors = solution.marker_errors_table().unwrap();
    let golden_errors = StorageTable::read(&case.errors).unwrap();
    assert_eq!((errors.name(), errors.labels(), errors.in_degrees()), (golden_errors.name(), golden_errors.labels(), golden_errors.in_degrees()));
    // OpenSim's order of markers in use is the trial's column order.
    assert_eq!(solution.markers.first().map(String::as_str), Some("R.ASIS"));
    assert_eq!(solution.markers.len(), 31);
}

// ---------------------------------------------------------------- first principles

/// A model with `per_body` markers added on every body (a non-coplanar set), so every
/// coordinate is observable.
fn with_markers(file: &str, per_body: usize) -> ModelSpec {
    let mut spec = ModelSpec::read(&OsimDocument::read(&common::fixture(file)).unwrap()).unwrap();
    let offsets = [[0.05, 0.01, 0.0], [0.0, 0.06, 0.02], [0.01, 0.0, 0.07], [0.04, 0.04, 0.04]];
    for body in spec.bodies.clone() {
        for (k, location) in offsets.iter().take(per_body).enumerate() {
            let frame = FrameChain { name: body.name.clone(), body: body.name.clone(), offsets: Vec::new() };
            spec.markers.push(MarkerSpec { name: format!("{}_m{k}", body.name), frame, location: *location, fixed: false });
        }
    }
    spec
}

fn set_coordinate(spec: &mut ModelSpec, name: &str, edit: impl FnOnce(&mut osim_tune::model::CoordinateSpec)) {
    let coordinate = spec.joints.iter_mut().flat_map(|j| j.coordinates.iter_mut()).find(|c| c.name == name).unwrap();
    edit(coordinate);
}

/// Every model marker, frame by frame, where our kinematics puts it at `poses` (m).
fn synthetic_trial(multibody: &Multibody, poses: &[Vec<f64>]) -> MarkerTable {
    let mut kinematics = multibody.kinematics();
    let mut positions = Vec::new();
    for q in poses {
        multibody.realize(q, &mut kinematics);
        for m in 0..multibody.markers.len() {
            let p = kinematics.marker_location(multibody, m);
            positions.push(Some([p.x, p.y, p.z]));
        }
    }
    let names = multibody.markers.iter().map(|m| m.name.clone()).collect();
    let times = (0..poses.len()).map(|f| f as f64 / 100.0).collect();
    MarkerTable::new(TrcHeader::new(100.0, LengthUnit::Meters), names, times, positions).unwrap()
}

/// `exact` with Gaussian noise of `sd` (m) on every coordinate of every marker (seeded).
fn with_noise(exact: &MarkerTable, sd: f64, seed: u64) -> MarkerTable {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let (noise, mut rng) = (Normal::new(0.0, sd).unwrap(), rand::rngs::StdRng::seed_from_u64(seed));
    let positions = (0..exact.n_frames()).flat_map(|f| (0..exact.marker_names().len()).map(move |m| (f, m))).map(|(f, m)| exact.position(f, m).map(|p| p.map(|v| v + noise.sample(&mut rng)))).collect();
    MarkerTable::new(exact.header().clone(), exact.marker_names().to_vec(), exact.times().to_vec(), positions).unwrap()
}

/// The default pose moved by a few tenths of a radian (or centimetres) per coordinate.
fn shifted_pose(multibody: &Multibody, amount: f64) -> Vec<f64> {
    multibody
        .coordinates
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let step = if c.unit == osim_tune::model::CoordinateUnit::Meter { 0.1 * amount } else { amount };
            c.default_value + step * (1.3 * k as f64 + 0.7).sin()
        })
        .collect()
}

fn load(model: &std::path::Path, trial: &std::path::Path) -> (Multibody, MarkerTable) {
    let spec = ModelSpec::read(&OsimDocument::read(model).unwrap()).unwrap();
    (Multibody::new(&spec).unwrap(), MarkerTable::read(trial).unwrap())
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn a_pose_of_every_joint_type_is_recovered_exactly() {
    // Free, Ball, Gimbal, Custom, Pin, Planar and Slider joints; Ball and Free rotations are
    // Euler angles in the assembler, while their speeds are angular velocities.
    let multibody = Multibody::new(&with_markers("models/joint_zoo.osim", 3)).unwrap();
    let target = shifted_pose(&multibody, 0.3);
    let trial = synthetic_trial(&multibody, std::slice::from_ref(&target));
    let ik = InverseKinematics::new(&multibody, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let solution = ik.solve(None).unwrap();
    let frame = &solution.frames[0];
    assert_eq!(frame.status, LeastSquaresStatus::Converged);
    assert!(max_difference(&frame.q, &target) < 1e-9, "{:?} vs {target:?}", frame.q);
    assert!(frame.errors.max < 1e-10 && frame.errors.rms < 1e-10);
}

#[test]
fn a_walking_pose_of_the_scaled_gait_model_is_recovered_from_the_default_pose() {
    let case = IkCase::subject01_walk1(&common::root());
    let (multibody, _) = load(&case.model, &case.trial);
    let golden = osim_tune::mechanics::Motion::from_table(&StorageTable::read(&case.motion).unwrap(), &case.motion, &multibody, false).unwrap();
    let targets = vec![golden.pose(40).to_vec(), golden.pose(41).to_vec()];
    let trial = synthetic_trial(&multibody, &targets);
    let ik = InverseKinematics::new(&multibody, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let solution = ik.solve(None).unwrap();
    for (frame, target) in solution.frames.iter().zip(&targets) {
        assert_eq!(frame.status, LeastSquaresStatus::Converged);
        // mtp angles move no marker: they stay where they start (0, as the golden).
        assert!(max_difference(&frame.q, target) < 1e-9, "frame {}", frame.frame);
    }
}

#[test]
fn a_clamped_coordinate_stops_exactly_at_its_bound() {
    let mut spec = with_markers("models/joint_zoo.osim", 3);
    let multibody = Multibody::new(&spec).unwrap();
    let knee = multibody.coordinate_index("knee_flex").unwrap();
    let mut target = shifted_pose(&multibody, 0.3);
    target[knee] = 0.4;
    let trial = synthetic_trial(&multibody, &[target]);
    set_coordinate(&mut spec, "knee_flex", |c| {
        c.clamped = true;
        c.range = [-0.5, 0.1];
    });
    let clamped = Multibody::new(&spec).unwrap();
    let ik = InverseKinematics::new(&clamped, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let bounded = ik.solve(None).unwrap().frames.remove(0);
    assert_eq!(bounded.status, LeastSquaresStatus::Converged);
    assert_eq!(bounded.q[knee], 0.1);
    // At an active bound the optimum is the optimum with the coordinate locked there.
    set_coordinate(&mut spec, "knee_flex", |c| {
        c.clamped = false;
        c.locked = true;
        c.default_value = 0.1;
    });
    let locked = Multibody::new(&spec).unwrap();
    let ik = InverseKinematics::new(&locked, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let reference = ik.solve(None).unwrap().frames.remove(0);
    assert!(max_difference(&bounded.q, &reference.q) < 1e-9);
    assert!((bounded.objective - reference.objective).abs() <= 1e-12 * reference.objective);
}

#[test]
fn an_unclamped_coordinate_ignores_its_range() {
    let mut spec = with_markers("models/joint_zoo.osim", 3);
    let multibody = Multibody::new(&spec).unwrap();
    let knee = multibody.coordinate_index("knee_flex").unwrap();
    let mut target = shifted_pose(&multibody, 0.3);
    target[knee] = 0.4;
    let trial = synthetic_trial(&multibody, std::slice::from_ref(&target));
    set_coordinate(&mut spec, "knee_flex", |c| c.range = [-0.5, 0.1]);
    let ranged = Multibody::new(&spec).unwrap();
    let ik = InverseKinematics::new(&ranged, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let frame = ik.solve(None).unwrap().frames.remove(0);
    assert!((frame.q[knee] - 0.4).abs() < 1e-9);
}

#[test]
fn a_locked_coordinate_keeps_its_default_value() {
    let mut spec = with_markers("models/joint_zoo.osim", 3);
    set_coordinate(&mut spec, "hip_ry", |c| {
        c.locked = true;
        c.default_value = -0.05;
    });
    let multibody = Multibody::new(&spec).unwrap();
    let hip = multibody.coordinate_index("hip_ry").unwrap();
    let target = shifted_pose(&multibody, 0.3);
    assert!((target[hip] + 0.05).abs() > 0.1);
    let trial = synthetic_trial(&multibody, &[target.clone(), target]);
    // A coordinate task on a locked coordinate is dropped (OpenSim locks the q instead).
    let tasks = IkTasks { markers: Vec::new(), coordinates: vec![CoordinateTask { name: "hip_ry".into(), weight: 5.0, target: CoordinateTarget::Value(0.3) }], coordinate_values: None };
    let ik = InverseKinematics::new(&multibody, &trial, "synthetic.trc".as_ref(), &tasks, IkSettings::default()).unwrap();
    assert_eq!(ik.locked_coordinate_tasks(), ["hip_ry"]);
    let mut start = multibody.default_pose();
    start[hip] = 1.0;
    let mut workspace = ik.workspace();
    let frame = ik.solve_frame(1, &mut start, &mut workspace).unwrap();
    assert_eq!(frame.q[hip], -0.05);
    for frame in ik.solve(None).unwrap().frames {
        assert_eq!(frame.q[hip], -0.05);
        assert_eq!(frame.status, LeastSquaresStatus::Converged);
    }
}

#[test]
fn markers_missing_in_a_frame_are_dropped_for_that_frame() {
    let multibody = Multibody::new(&with_markers("models/joint_zoo.osim", 3)).unwrap();
    let target = shifted_pose(&multibody, 0.2);
    let full = synthetic_trial(&multibody, &[target.clone(), target.clone(), target.clone()]);
    let n = full.n_markers();
    let mut positions = full.positions().to_vec();
    positions[n] = None; // frame 1: first marker missing
    positions[n + 4] = Some([f64::NAN, 0.0, 0.0]); // and a NaN one
    for p in &mut positions[2 * n..] {
        *p = None; // frame 2: nothing
    }
    let trial = MarkerTable::new(full.header().clone(), full.marker_names().to_vec(), full.times().to_vec(), positions).unwrap();
    let ik = InverseKinematics::new(&multibody, &trial, "gaps.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let mut workspace = ik.workspace();
    let mut q = ik.initial_pose();
    let frame = ik.solve_frame(1, &mut q, &mut workspace).unwrap();
    assert_eq!(frame.missing_markers, [0, 4]);
    assert!(max_difference(&frame.q, &target) < 1e-9);
    let error = ik.solve(None).unwrap_err();
    assert!(matches!(error, IkError::NoUsableMarkers { frame: 2, .. }), "{error}");
    assert!(error.to_string().contains("gaps.trc") && error.to_string().contains("frame 2"), "{error}");
}

#[test]
fn the_rms_counts_missing_markers_as_zero_errors_like_opensim() {
    let multibody = Multibody::new(&with_markers("models/joint_zoo.osim", 3)).unwrap();
    let pose = multibody.default_pose();
    let exact = synthetic_trial(&multibody, std::slice::from_ref(&pose));
    let mut positions = exact.positions().to_vec();
    positions[0] = None;
    let [x, y, z] = positions[1].unwrap();
    positions[1] = Some([x + 0.01, y, z]);
    let trial = MarkerTable::new(exact.header().clone(), exact.marker_names().to_vec(), exact.times().to_vec(), positions).unwrap();
    // Only the two affected markers count, with weight 0 for the displaced one: the pose
    // stays exact and the displaced marker is 1 cm off.
    let mut tasks: Vec<MarkerTask> = exact.marker_names().iter().map(|name| MarkerTask { name: name.clone(), weight: 1.0 }).collect();
    tasks[1].weight = 0.0;
    let ik = InverseKinematics::new(&multibody, &trial, "t.trc".as_ref(), &IkTasks { markers: tasks, coordinates: Vec::new(), coordinate_values: None }, IkSettings::default()).unwrap();
    let frame = ik.solve(None).unwrap().frames.remove(0);
    let n = exact.n_markers() as f64;
    assert!((frame.errors.max - 0.01).abs() < 1e-9);
    assert!((frame.errors.rms - (1e-4 / n).sqrt()).abs() < 1e-9);
    assert_eq!(frame.errors.worst, Some(1));
}

#[test]
fn couplers_hold_exactly_and_a_finite_weight_makes_them_goals() {
    let mut spec = ModelSpec::read(&OsimDocument::read(&common::fixture("models/leg6dof9musc.osim")).unwrap()).unwrap();
    let patella_markers = [[0.03, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.03]];
    for (k, location) in patella_markers.iter().enumerate() {
        spec.markers.push(MarkerSpec { name: format!("patella_{k}"), frame: FrameChain { name: "patella_r".into(), body: "patella_r".into(), offsets: Vec::new() }, location: *location, fixed: false });
    }
    let multibody = Multibody::new(&spec).unwrap();
    let coupler = multibody.couplers[0].clone();
    let mut target = shifted_pose(&multibody, 0.2);
    target[coupler.dependent] = coupler.dependent_value(&target) + 0.3; // patella off its coupler
    let trial = synthetic_trial(&multibody, &[target]);
    let violation = |weight: ConstraintWeight| {
        let settings = IkSettings { constraint_weight: weight, ..IkSettings::default() };
        let ik = InverseKinematics::new(&multibody, &trial, "t.trc".as_ref(), &IkTasks::every_marker(), settings).unwrap();
        let frame = ik.solve(None).unwrap().frames.remove(0);
        assert_eq!(frame.status, LeastSquaresStatus::Converged);
        (coupler.dependent_value(&frame.q) - frame.q[coupler.dependent]).abs()
    };
    assert_eq!(violation(ConstraintWeight::Infinite), 0.0);
    let (soft, firm) = (violation(ConstraintWeight::Finite(1e-7)), violation(ConstraintWeight::Finite(1.0)));
    assert!(soft > 0.25 && firm < soft && firm > 0.0, "{soft} {firm}");
}

#[test]
fn coordinate_tasks_pull_with_their_weight() {
    let multibody = Multibody::new(&with_markers("models/joint_zoo.osim", 3)).unwrap();
    let target = shifted_pose(&multibody, 0.2);
    let trial = synthetic_trial(&multibody, std::slice::from_ref(&target));
    let toe = multibody.coordinate_index("toe_flex").unwrap();
    let solve = |weight: f64| {
        let task = CoordinateTask { name: "toe_flex".into(), weight, target: CoordinateTarget::Value(target[toe] + 0.5) };
        let tasks = IkTasks { markers: Vec::new(), coordinates: vec![task], coordinate_values: None };
        let ik = InverseKinematics::new(&multibody, &trial, "t.trc".as_ref(), &tasks, IkSettings::default()).unwrap();
        ik.solve(None).unwrap().frames.remove(0).q[toe] - target[toe]
    };
    let (none, light, heavy) = (solve(0.0), solve(1e-4), solve(1e4));
    assert!(none.abs() < 1e-9);
    assert!(light > 0.0 && light < 0.5 && heavy > light && (heavy - 0.5).abs() < 1e-3, "{light} {heavy}");
}

#[test]
fn tasks_are_matched_as_opensim_matches_them() {
    let case = IkCase::subject01_walk1(&common::root());
    let (multibody, trial) = load(&case.model, &case.trial);
    let tasks = IkTasks {
        markers: vec![
            MarkerTask { name: "R.ASIS".into(), weight: 1.0 },
            MarkerTask { name: "R.Bicep".into(), weight: 1.0 },   // trial only
            MarkerTask { name: "R.Knee.Lat".into(), weight: 1.0 }, // model only
            MarkerTask { name: "Nowhere".into(), weight: 1.0 },
            MarkerTask { name: "L.ASIS".into(), weight: 1.0 },
            MarkerTask { name: "V.Sacral".into(), weight: 1.0 },
        ],
        coordinates: Vec::new(),
        coordinate_values: None,
    };
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap();
    assert_eq!(ik.marker_names(), ["R.ASIS", "L.ASIS", "V.Sacral"]);
    let missing: Vec<(&str, MissingFrom)> = ik.ignored_marker_tasks().iter().map(|i| (i.name.as_str(), i.missing_from)).collect();
    assert_eq!(missing, [("R.Bicep", MissingFrom::Model), ("R.Knee.Lat", MissingFrom::Trial), ("Nowhere", MissingFrom::ModelAndTrial)]);

    let unknown = IkTasks { markers: Vec::new(), coordinates: vec![CoordinateTask { name: "no_such".into(), weight: 1.0, target: CoordinateTarget::DefaultValue }], coordinate_values: None };
    let error = InverseKinematics::new(&multibody, &trial, &case.trial, &unknown, IkSettings::default()).unwrap_err();
    assert!(matches!(error, IkError::UnknownCoordinate { .. }) && error.to_string().contains("no_such"), "{error}");

    let none = IkTasks { markers: vec![MarkerTask { name: "R.Bicep".into(), weight: 1.0 }], coordinates: Vec::new(), coordinate_values: None };
    let error = InverseKinematics::new(&multibody, &trial, &case.trial, &none, IkSettings::default()).unwrap_err();
    assert!(matches!(error, IkError::NoMarkers { .. }), "{error}");

    let negative = IkTasks { markers: vec![MarkerTask { name: "R.ASIS".into(), weight: -1.0 }], coordinates: Vec::new(), coordinate_values: None };
    assert!(matches!(InverseKinematics::new(&multibody, &trial, &case.trial, &negative, IkSettings::default()), Err(IkError::InvalidWeight { .. })));
}

#[test]
fn time_ranges_are_clipped_to_the_trial_and_snap_to_the_nearest_frames() {
    let case = IkCase::subject01_walk1(&common::root());
    let (multibody, trial) = load(&case.model, &case.trial);
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &IkTasks::every_marker(), IkSettings::default()).unwrap();
    assert_eq!(ik.frames(None).unwrap(), 0..=150);
    assert_eq!(ik.frames(Some([0.0, 2.5])).unwrap(), 0..=150);
    assert_eq!(ik.frames(Some([-3.0, 0.02])).unwrap(), 0..=1);
    assert_eq!(ik.frames(Some([0.5, 0.6])).unwrap(), 30..=36);
    for outside in [[3.0, 4.0], [-2.0, -1.0], [1.0, 0.5]] {
        let error = ik.frames(Some(outside)).unwrap_err();
        assert!(matches!(error, IkError::TimeRange { .. }) && error.to_string().contains("subject01_walk1.trc"), "{error}");
    }
}

// ---------------------------------------------------------------- command line

#[test]
fn cli_writes_the_motion_and_the_errors() {
    let directory = tempfile::tempdir().unwrap();
    let (model, trial) = (common::fixture("golden/scale/subject01_simbody.osim"), common::fixture("subject01/subject01_walk1.trc"));
    let (motion, errors) = (directory.path().join("q.mot"), directory.path().join("err.sto"));
    let arguments = ["ik", model.to_str().unwrap(), trial.to_str().unwrap(), "--time", "0.5", "0.6", "--weights", "R.ASIS=10,L.ASIS=10", "-o", motion.to_str().unwrap(), "--errors", errors.to_str().unwrap()];
    let (code, stdout, stderr) = common::osim_tune(&arguments);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("7 frames") && stdout.contains("31 markers") && stdout.contains("worst marker"), "{stdout}");
    let table = StorageTable::read(&motion).unwrap();
    assert_eq!((table.n_rows(), table.n_columns(), table.in_degrees()), (7, 24, Some(true)));
    assert_eq!(StorageTable::read(&errors).unwrap().labels()[2], "marker_error_RMS");
}

/// `--kalman 6` smooths the walk: the poses stay within a few degrees of the per-frame IK's and
/// their second differences shrink; `--kalman-rates` gives their speeds, and `id --rates` takes
/// them (found: RMS 2.3, 3.9 and 3.0 % of the hip, knee and ankle moments' ranges from inverse
/// dynamics on splines of the smoothed angles).
#[test]
fn cli_kalman_smooths_the_walk() {
    let directory = tempfile::tempdir().unwrap();
    let (model, trial) = (common::fixture("golden/scale/subject01_simbody.osim"), common::fixture("subject01/subject01_walk1.trc"));
    let (plain, smoothed) = (directory.path().join("plain.mot"), directory.path().join("kalman.mot"));
    let rates = directory.path().join("rates.sto");
    for (extra, motion) in [(None, &plain), (Some("6"), &smoothed)] {
        let mut arguments = vec!["ik", model.to_str().unwrap(), trial.to_str().unwrap(), "--time", "0.5", "1.5", "-o", motion.to_str().unwrap()];
        arguments.extend(extra.map(|cutoff| ["--kalman", cutoff, "--kalman-rates", rates.to_str().unwrap()]).into_iter().flatten());
        let (code, stdout, stderr) = common::osim_tune(&arguments);
        assert_eq!(code, 0, "{stdout}{stderr}");
        assert_eq!(stdout.contains("Kalman-smoothed over 61 frames"), extra.is_some(), "{stdout}");
    }
    let (smoothed_file, rates_file) = (smoothed.clone(), rates.clone());
    let (plain, smoothed, rates) = (StorageTable::read(&plain).unwrap(), StorageTable::read(&smoothed).unwrap(), StorageTable::read(&rates).unwrap());
    assert_eq!((rates.n_rows(), rates.labels()[1].as_str(), rates.labels()[2].as_str()), (61, "pelvis_tilt_speed", "pelvis_tilt_acceleration"));
    // The speeds are the smoothed angles' rates (degrees in the .mot, rad/s here): central
    // differences of the smoothed knee angle agree within a few percent of its range of speeds.
    let (knee, knee_speed) = (smoothed.column("knee_angle_r").unwrap(), rates.column("knee_angle_r_speed").unwrap());
    let times = smoothed.times();
    let worst = (1..knee.len() - 1).map(|i| ((knee[i + 1] - knee[i - 1]).to_radians() / (times[i + 1] - times[i - 1]) - knee_speed[i]).abs()).fold(0.0, f64::max);
    let range = knee_speed.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(worst < 0.05 * range, "{worst} of {range}");
    let roughness = |q: &[f64]| q.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).powi(2)).sum::<f64>();
    for label in ["pelvis_tilt", "hip_flexion_r", "knee_angle_r"] {
        let (a, b) = (plain.column(label).unwrap(), smoothed.column(label).unwrap());
        assert!(max_difference(&a, &b) < 3.0, "{label}: {}°", max_difference(&a, &b));
        assert!(roughness(&b) < roughness(&a), "{label}");
    }
    // `id --rates` takes them: inverse dynamics (no loads) on the smoother's own rates, and on
    // splines of its smoothed angles, agree within a few percent of each moment's range.
    let model = model.to_str().unwrap();
    let forces = |extra: &[&str], name: &str| {
        let output = directory.path().join(name);
        let mut arguments = vec!["id", model, smoothed_file.to_str().unwrap(), "-o", output.to_str().unwrap()];
        arguments.extend_from_slice(extra);
        let (code, stdout, stderr) = common::osim_tune(&arguments);
        assert_eq!(code, 0, "{stdout}{stderr}");
        StorageTable::read(&output).unwrap()
    };
    let (given, splined) = (forces(&["--rates", rates_file.to_str().unwrap()], "given.sto"), forces(&[], "splined.sto"));
    for label in ["hip_flexion_r_moment", "knee_angle_r_moment", "ankle_angle_r_moment"] {
        let (a, b) = (given.column(label).unwrap(), splined.column(label).unwrap());
        let range = b.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v)) - b.iter().fold(f64::INFINITY, |m, v| m.min(*v));
        let rms = (a.iter().zip(&b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
        assert!(rms < 0.05 * range, "{label}: RMS {rms} N·m of a range of {range} N·m");
    }
}

/// `-o` and `--errors` in folders that do not exist yet: the folders are created, as `scale`
/// creates its output folders; a refused request creates none.
#[test]
fn cli_creates_missing_output_folders_but_not_for_a_refused_request() {
    let directory = tempfile::tempdir().unwrap();
    let (model, trial) = (common::fixture("golden/scale/subject01_simbody.osim"), common::fixture("subject01/subject01_walk1.trc"));
    let (motion, errors) = (directory.path().join("new/motion/q.mot"), directory.path().join("other/err.sto"));
    let (model, trial, motion_path, errors_path) = (model.to_str().unwrap(), trial.to_str().unwrap(), motion.to_str().unwrap(), errors.to_str().unwrap());
    let (code, _, stderr) = common::osim_tune(&["ik", model, trial, "--time", "0.5", "0.52", "--weights", "R.ASIS=heavy", "-o", motion_path, "--errors", errors_path]);
    assert_eq!(code, 2, "{stderr}");
    assert_eq!(std::fs::read_dir(directory.path()).unwrap().count(), 0, "a refused request created folders");
    let (code, _, stderr) = common::osim_tune(&["ik", model, trial, "--time", "0.5", "0.52", "-o", motion_path, "--errors", errors_path, "--marker-locations", motion_path]);
    assert!(code == 2 && stderr.contains("--marker-locations and -o name the same file"), "{stderr}");
    assert_eq!(std::fs::read_dir(directory.path()).unwrap().count(), 0, "a refused request created folders");
    let (code, stdout, stderr) = common::osim_tune(&["ik", model, trial, "--time", "0.5", "0.52", "-o", motion_path, "--errors", errors_path]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    // The trial has two frames in 0.5–0.52 s (at 0.500 and 0.517 s).
    assert_eq!(StorageTable::read(&motion).unwrap().n_rows(), 2);
    assert_eq!(StorageTable::read(&errors).unwrap().n_rows(), 2);
}

/// With OpenSim's setup (tasks, weights, 0–2.5 s) the command's .mot matches OpenSim run to
/// convergence within 0.05° and 0.1 mm.
#[test]
fn cli_with_the_opensim_setup_matches_converged_opensim() {
    let directory = tempfile::tempdir().unwrap();
    let (model, trial, setup) = (common::fixture("golden/scale/subject01_simbody.osim"), common::fixture("subject01/subject01_walk1.trc"), common::fixture("golden/ik/setup_ik_used.xml"));
    let motion = directory.path().join("q.mot");
    let arguments = ["ik", model.to_str().unwrap(), trial.to_str().unwrap(), "--setup", setup.to_str().unwrap(), "-o", motion.to_str().unwrap()];
    let (code, stdout, stderr) = common::osim_tune(&arguments);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let (ours, golden) = (StorageTable::read(&motion).unwrap(), StorageTable::read(&common::fixture("golden/ik/accuracy_1e-10/subject01_ik.mot")).unwrap());
    assert_eq!((ours.n_rows(), ours.labels()), (151, golden.labels()));
    for label in &golden.labels()[1..] {
        let tolerance = if label.ends_with("_tx") || label.ends_with("_ty") || label.ends_with("_tz") { 1e-4 } else { 0.05 };
        let worst = ours.column(label).unwrap().iter().zip(golden.column(label).unwrap()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst <= tolerance, "{label}: {worst}");
    }
}

#[test]
fn cli_refuses_bad_requests_and_writes_nothing() {
    let directory = tempfile::tempdir().unwrap();
    let (model, trial) = (common::fixture("golden/scale/subject01_simbody.osim"), common::fixture("subject01/subject01_walk1.trc"));
    let motion = directory.path().join("q.mot");
    let (model, trial, output) = (model.to_str().unwrap(), trial.to_str().unwrap(), motion.to_str().unwrap());
    let cases: [(&[&str], &str); 7] = [
        (&["--weights", "R.Bicep=2"], "is not a marker of the model"),
        (&["--kalman", "0"], "--kalman 0: expected a cutoff frequency > 0 Hz"),
        (&["--kalman-rates", "rates.sto"], "--kalman-rates needs --kalman HZ"),
        (&["--weights", "R.Knee.Lat=2"], "has no data in the trial"),
        (&["--weights", "R.ASIS=heavy"], "expected a number"),
        (&["--time", "3", "4"], "does not overlap"),
        (&["--time", "1", "0.5"], "does not overlap"),
    ];
    for (extra, message) in cases {
        let arguments: Vec<&str> = ["ik", model, trial, "-o", output].into_iter().chain(extra.iter().copied()).collect();
        let (code, _, stderr) = common::osim_tune(&arguments);
        assert_eq!(code, 2, "{extra:?}: {stderr}");
        assert!(stderr.contains(message), "{extra:?}: {stderr}");
        assert!(!motion.exists());
    }
    let (code, _, stderr) = common::osim_tune(&["ik", model, trial, "-o", trial]);
    assert_eq!(code, 2);
    assert!(stderr.contains("refusing to overwrite an input"), "{stderr}");
}

// ---------------------------------------------------------------- Kalman smoothing

/// The joint zoo (every joint type) with three markers per body moved along `q(t)`, 100 Hz.
fn kalman_case(frames: usize, motion: impl Fn(usize, f64) -> f64) -> (Multibody, Vec<Vec<f64>>) {
    let multibody = Multibody::new(&with_markers("models/joint_zoo.osim", 3)).unwrap();
    let base = shifted_pose(&multibody, 0.2);
    let poses = (0..frames).map(|f| base.iter().enumerate().map(|(c, q)| q + motion(c, f as f64 / 100.0)).collect()).collect();
    (multibody, poses)
}

/// A motion whose coordinates are quartic in time lies in the process model's null space (a
/// constant 4th derivative): from exact markers the smoother returns it unchanged (up to the
/// diffuse prior on the first frame; 4.1e-11 rad seen).
#[test]
fn kalman_smoothing_keeps_a_quartic_motion() {
    let quartic = |c: usize, t: f64| 0.02 * (c as f64 + 1.0).sqrt() * (t - 2.0 * t * t + 3.0 * t.powi(3) - 2.5 * t.powi(4));
    let (multibody, poses) = kalman_case(41, quartic);
    let trial = synthetic_trial(&multibody, &poses);
    let ik = InverseKinematics::new(&multibody, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let smoothed = ik.smooth(&ik.solve(None).unwrap(), &KalmanIkSettings::with_cutoff(6.0)).unwrap();
    let worst = smoothed.solution.frames.iter().zip(&poses).map(|(f, q)| max_difference(&f.q, q)).fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst:e}");
    // Its speeds and accelerations are the quartic's derivatives.
    let speed = |c: usize, t: f64| 0.02 * (c as f64 + 1.0).sqrt() * (1.0 - 4.0 * t + 9.0 * t * t - 10.0 * t.powi(3));
    let acceleration = |c: usize, t: f64| 0.02 * (c as f64 + 1.0).sqrt() * (-4.0 + 18.0 * t - 30.0 * t * t);
    for ((frame, u), a) in smoothed.solution.frames.iter().zip(&smoothed.speeds).zip(&smoothed.accelerations) {
        let expected_u: Vec<f64> = (0..u.len()).map(|c| speed(c, frame.time)).collect();
        let expected_a: Vec<f64> = (0..a.len()).map(|c| acceleration(c, frame.time)).collect();
        assert!(max_difference(u, &expected_u) < 1e-7 && max_difference(a, &expected_a) < 1e-5, "t = {}: {:e}, {:e}", frame.time, max_difference(u, &expected_u), max_difference(a, &expected_a));
    }
}

/// From markers with 3 mm noise, the smoothed kinematics of a 1 Hz motion lie closer to the
/// truth than the per-frame IK poses (0.38 of their RMS error seen: the smoother averages over
/// neighbouring frames).
#[test]
fn kalman_smoothing_reduces_marker_noise() {
    let wave = |c: usize, t: f64| 0.15 * (2.0 * std::f64::consts::PI * t + c as f64).sin();
    let (multibody, poses) = kalman_case(101, wave);
    let exact = synthetic_trial(&multibody, &poses);
    let trial = with_noise(&exact, 0.003, 7);
    let ik = InverseKinematics::new(&multibody, &trial, "noisy.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let solved = ik.solve(None).unwrap();
    let smoothed = ik.smooth(&solved, &KalmanIkSettings::with_cutoff(6.0)).unwrap().solution;
    let rms = |solution: &osim_tune::solvers::IkSolution| {
        let squares: Vec<f64> = solution.frames.iter().zip(&poses).flat_map(|(f, q)| f.q.iter().zip(q).map(|(a, b)| (a - b).powi(2)).collect::<Vec<_>>()).collect();
        (squares.iter().sum::<f64>() / squares.len() as f64).sqrt()
    };
    let (ik_error, smoothed_error) = (rms(&solved), rms(&smoothed));
    assert!(smoothed_error < 0.5 * ik_error, "IK {ik_error:e}, smoothed {smoothed_error:e}");
    assert!(smoothed.frames.iter().all(|f| f.iterations == 2 && f.errors.rms > 0.0));
}

/// Closed loops smoothed: linked_mechanisms (point, distance, point-on-line and weld
/// constraints and a coupler) swaying at 1 Hz — each coordinate's default value plus
/// 0.15 sin(2πt + c), assembled onto the links as OpenSim's assembler would —, its markers at
/// 100 Hz with 1 mm noise, smoothed at 6 Hz. Every smoothed pose closes the links (to 1e-10),
/// its speeds keep them (G·u) and its accelerations too (G·u̇ + Ġ·u, Ġ·u by a central
/// difference), and it puts the markers closer to where the noise-free motion has them than
/// per-frame IK does.
#[test]
fn kalman_smoothing_holds_closed_loops() {
    use osim_tune::solvers::assemble;
    let case = IkCase::linked_mechanisms(&common::root());
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&case.model).unwrap()).unwrap()).unwrap();
    let rest = assemble(&multibody, &multibody.default_pose()).unwrap();
    let poses: Vec<Vec<f64>> = (0..=60)
        .map(|k| {
            let t = k as f64 / 100.0;
            let target: Vec<f64> = rest.iter().enumerate().map(|(c, q)| q + 0.15 * (2.0 * std::f64::consts::PI * t + c as f64).sin()).collect();
            assemble(&multibody, &target).unwrap()
        })
        .collect();
    let exact = synthetic_trial(&multibody, &poses);
    let trial = with_noise(&exact, 0.001, 11);
    let ik = InverseKinematics::new(&multibody, &trial, "swaying.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let solved = ik.solve(None).unwrap();
    let smoothed = ik.smooth(&solved, &KalmanIkSettings::with_cutoff(6.0)).unwrap();
    let mut kinematics = multibody.kinematics();
    for ((frame, u), udot) in smoothed.solution.frames.iter().zip(&smoothed.speeds).zip(&smoothed.accelerations) {
        let (position, rate) = multibody.link_drift(&frame.q, u);
        assert!(position <= 1e-10 && rate <= 1e-9, "t = {}: links open by {position:e} m, {rate:e} m/s", frame.time);
        multibody.realize(&frame.q, &mut kinematics);
        let acceleration = multibody.link_accelerations(&kinematics, &frame.q, u, udot).amax();
        assert!(acceleration <= 1e-6, "t = {}: the links' accelerations {acceleration:e}", frame.time);
    }
    // Against the noise-free markers (a Ball or Free joint's angles have more than one value per
    // orientation, so poses are compared by where they put the markers).
    let mut rms = |solution: &osim_tune::solvers::IkSolution| {
        let mut squares = Vec::new();
        for (f, frame) in solution.frames.iter().enumerate() {
            multibody.realize(&frame.q, &mut kinematics);
            for m in 0..multibody.markers.len() {
                let truth = osim_tune::mechanics::Vec3::from(exact.position(f, m).unwrap());
                squares.push((kinematics.marker_location(&multibody, m) - truth).norm_squared());
            }
        }
        (squares.iter().sum::<f64>() / squares.len() as f64).sqrt()
    };
    let (ik_error, smoothed_error) = (rms(&solved), rms(&smoothed.solution));
    println!("marker RMS error against the noise-free markers: per-frame IK {ik_error:e} m, smoothed {smoothed_error:e} m");
    assert!(smoothed_error < ik_error, "IK {ik_error:e}, smoothed {smoothed_error:e}");
}

#[test]
fn kalman_smoothing_refuses_a_cutoff_of_zero() {
    let (multibody, poses) = kalman_case(6, |_, _| 0.0);
    let trial = synthetic_trial(&multibody, &poses);
    let ik = InverseKinematics::new(&multibody, &trial, "synthetic.trc".as_ref(), &IkTasks::every_marker(), IkSettings::default()).unwrap();
    let error = ik.smooth(&ik.solve(None).unwrap(), &KalmanIkSettings::with_cutoff(0.0)).unwrap_err();
    assert!(matches!(error, IkError::Smoother { .. }), "{error}");
}


/// The accuracy study's slice (`cargo xtask validate` runs more seeds and noise): on a
/// synthetic walk with 2 mm marker noise, Kalman smoothing at 6 Hz beats per-frame IK on every
/// coordinate, and its accelerations beat the ID tool's 6 Hz low-pass of per-frame IK (the
/// truth itself being 6 Hz low-passed, which favours the filter).
#[test]
fn kalman_ik_study_slice() {
    use osim_tune::validation::kalman_ik::{kalman_ik_study, STUDY_COORDINATES};
    let study = kalman_ik_study(&common::root(), 0.002, 1, 6.0, 200).unwrap();
    assert_eq!(study.frames, 151);
    for (k, name) in STUDY_COORDINATES.iter().enumerate() {
        let ([ik, _, kalman], [_, filtered, kalman_acceleration]) = (study.coordinate[k], study.acceleration[k]);
        assert!(kalman < ik, "{name}: q {kalman} vs IK {ik}");
        assert!(kalman_acceleration < filtered, "{name}: q̈ {kalman_acceleration} vs IK + 6 Hz {filtered}");
    }
}

/// `from_file` tasks need the setup's `coordinate_file`, a column in it for their coordinate and
/// finite values in it: errors name the task or the file, the coordinate and the row.
#[test]
fn from_file_tasks_without_their_values_are_refused() {
    let case = IkCase::subject01_coordinate_file(&common::root());
    let text = std::fs::read_to_string(&case.setup).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let setup = dir.path().join("setup_ik.xml");
    std::fs::write(&setup, text.replace("<coordinate_file>coordinates.mot</coordinate_file>", "<coordinate_file></coordinate_file>")).unwrap();
    let error = read_setup_tasks(&setup).unwrap_err().to_string();
    assert!(error.contains("IKCoordinateTask hip_flexion_r has value_type from_file, but the setup names no coordinate_file"), "{error}");
    std::fs::write(&setup, text.replace("<coordinate_file>coordinates.mot</coordinate_file>", "<coordinate_file>missing.mot</coordinate_file>")).unwrap();
    let error = read_setup_tasks(&setup).unwrap_err().to_string();
    assert!(error.matches("missing.mot").count() == 1 && error.contains("cannot read"), "{error}");
    let values = std::fs::read_to_string(case.setup.with_file_name("coordinates.mot")).unwrap().replace("\tknee_angle_r\t", "\tknee_elsewhere\t");
    std::fs::write(dir.path().join("coordinates.mot"), values).unwrap();
    std::fs::write(&setup, &text).unwrap();
    let (multibody, trial) = load(&case.model, &case.trial);
    let (tasks, _) = read_setup_tasks(&setup).unwrap();
    let error = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap_err().to_string();
    assert!(error.contains("coordinates.mot") && error.contains("no column for coordinate knee_angle_r"), "{error}");
    let values = std::fs::read_to_string(case.setup.with_file_name("coordinates.mot")).unwrap();
    let lines: Vec<&str> = values.lines().collect();
    let header = lines.iter().position(|l| *l == "endheader").unwrap() + 1;
    let hip = lines[header].split('\t').position(|l| l == "hip_flexion_r").unwrap();
    let mut row: Vec<&str> = lines[header + 2].split('\t').collect();
    row[hip] = "NaN";
    let broken = row.join("\t");
    let text: Vec<&str> = lines.iter().enumerate().map(|(k, l)| if k == header + 2 { broken.as_str() } else { *l }).collect();
    std::fs::write(dir.path().join("coordinates.mot"), text.join("\n") + "\n").unwrap();
    let (tasks, _) = read_setup_tasks(&setup).unwrap();
    let error = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default()).unwrap_err().to_string();
    assert!(error.contains("coordinate hip_flexion_r is NaN at row 2"), "{error}");
}

/// opensim-core's IK constraint test (8 coupler constraints, 42 weighted markers the model fits
/// to no better than ~12 cm RMS, the forearms' pronation barely seen by them), 9 frames: every
/// frame converges — its cost stationary to rounding while the steps wander along what the
/// markers do not see — and fits the markers at least as well as OpenSim 4.6 (at the setup's
/// accuracy 1e-3) in every frame.
#[test]
fn opensim_cores_constraint_test_converges_and_fits_at_least_as_well() {
    let folder = tempfile::tempdir().unwrap();
    for name in ["constraintTest_ikOnly.osim", "constraintTest.trc", "constraintTest_setup_ik.xml"] {
        std::fs::copy(common::fixture(&format!("ik_constraint_test/{name}")), folder.path().join(name)).unwrap();
    }
    let (code, stdout, stderr) = common::osim_tune(&["run", &folder.path().join("constraintTest_setup_ik.xml").to_string_lossy()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(!stderr.contains("did not converge"), "{stderr}");
    let ours = StorageTable::read(&folder.path().join("_ik_marker_errors.sto")).unwrap();
    let opensim = StorageTable::read(&common::fixture("golden/ik/constraint_test/ik_marker_errors.sto")).unwrap();
    assert_eq!(ours.times(), opensim.times());
    let (ours, opensim) = (ours.column("total_squared_error").unwrap(), opensim.column("total_squared_error").unwrap());
    for (row, (ours, opensim)) in ours.iter().zip(&opensim).enumerate() {
        // OpenSim prints 8 decimals (≈ 1e-8 relative here).
        assert!(*ours <= opensim + 1e-8, "frame {row}: ours {ours} m², OpenSim {opensim} m²");
    }
}
