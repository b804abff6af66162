//! Inverse kinematics against OpenSim 4.6's `InverseKinematicsTool` on subject01's walking
//! trial: coordinates against `subject01_walk1_ik.mot` (per coordinate, degrees or metres) and
//! marker RMS against `subject01_walk1_ik_marker_errors.sto`, with the tasks, weights and time
//! range of the setup OpenSim ran (`setup_ik_used.xml`).

use std::path::{Path, PathBuf};

use crate::io::osim::OsimDocument;
use crate::io::table::{MarkerTable, StorageTable};
use crate::mechanics::{Motion, Multibody};
use crate::model::{ModelSpec, MotionType};
use crate::setup::IkSetup;
use crate::solvers::{CoordinateValues, IkSettings, IkTasks, InverseKinematics, LeastSquaresStatus};

/// Largest coordinate difference allowed against OpenSim run at `accuracy` 1e-5, rotations
/// (degrees). OpenSim's L-BFGS stops once its gradient test passes, not at the minimum: OpenSim
/// 4.6 itself moves by up to 0.140° (lumbar_rotation at 0.583 s) between accuracy 1e-5 and
/// 1e-8, and our solution is within 6e-4° of OpenSim's at accuracy 1e-10. The tolerance covers
/// OpenSim's convergence, not ours; [`OBJECTIVE_SLACK`] checks optimality.
pub const ROTATION_TOLERANCE_DEGREES: f64 = 0.15;
/// …and translations (m); OpenSim's convergence error is ≤ 5e-5 m here.
pub const TRANSLATION_TOLERANCE_METERS: f64 = 1e-4;
/// Our objective may exceed the objective of OpenSim's pose (both evaluated by our model) by
/// this fraction: ours must be the better minimum in every frame.
pub const OBJECTIVE_SLACK: f64 = 1e-12;
/// Our marker RMS may exceed OpenSim's by this much (m). We minimise the weighted objective,
/// not the unweighted RMS, and OpenSim's unconverged poses lie off the weighted optimum, so the
/// RMS can come out a little lower in some frames (by ≤ 11.2 µm here at accuracy 1e-5, by
/// ≤ 0.02 µm against OpenSim at accuracy 1e-10).
pub const RMS_SLACK_METERS: f64 = 1.5e-5;

/// The files of one comparison.
#[derive(Debug, Clone)]
pub struct IkCase {
    pub model: PathBuf,
    pub trial: PathBuf,
    pub setup: PathBuf,
    /// OpenSim's coordinates.
    pub motion: PathBuf,
    /// OpenSim's marker errors.
    pub errors: PathBuf,
    /// Largest coordinate difference allowed: rotations (degrees) and translations (m).
    pub rotation_tolerance_degrees: f64,
    pub translation_tolerance_meters: f64,
    /// How much our objective may exceed that of OpenSim's pose, relative ([`OBJECTIVE_SLACK`]
    /// unless the case says why not).
    pub objective_slack: f64,
}

impl IkCase {
    /// subject01's walking trial in the repository at `root`.
    pub fn subject01_walk1(root: &Path) -> IkCase {
        IkCase {
            model: root.join("fixtures/golden/scale/subject01_simbody.osim"),
            trial: root.join("fixtures/subject01/subject01_walk1.trc"),
            setup: root.join("fixtures/golden/ik/setup_ik_used.xml"),
            motion: root.join("fixtures/golden/ik/subject01_walk1_ik.mot"),
            errors: root.join("fixtures/golden/ik/subject01_walk1_ik_marker_errors.sto"),
            rotation_tolerance_degrees: ROTATION_TOLERANCE_DEGREES,
            translation_tolerance_meters: TRANSLATION_TOLERANCE_METERS,
            objective_slack: OBJECTIVE_SLACK,
        }
    }

    /// The same trial against OpenSim 4.6 run to convergence (`accuracy` 1e-10,
    /// `oracle/bench_ik.py --accuracy 1e-10 --write`), held to 0.05° and 0.1 mm.
    pub fn subject01_walk1_converged(root: &Path) -> IkCase {
        let golden = root.join("fixtures/golden/ik/accuracy_1e-10");
        IkCase {
            motion: golden.join("subject01_ik.mot"),
            errors: golden.join("subject01_ik_marker_errors.sto"),
            rotation_tolerance_degrees: 0.05,
            translation_tolerance_meters: 1e-4,
            ..IkCase::subject01_walk1(root)
        }
    }

    /// The same trial with three `from_file` coordinate tasks following a `coordinate_file`
    /// (OpenSim's solution at every fourth frame, three coordinates offset by 5–8°; between its
    /// rows, quintic GCV splines), against OpenSim 4.6 at `accuracy` 1e-10 over 0.6–1.0 s
    /// (`oracle/gen_ik_coordinate_file.py`), held to 0.05° and 0.1 mm as the converged walk.
    pub fn subject01_coordinate_file(root: &Path) -> IkCase {
        let golden = root.join("fixtures/golden/ik/coordinate_file");
        IkCase {
            setup: golden.join("setup_ik.xml"),
            motion: golden.join("ik.mot"),
            errors: golden.join("ik_marker_errors.sto"),
            rotation_tolerance_degrees: 0.05,
            translation_tolerance_meters: 1e-4,
            ..IkCase::subject01_walk1(root)
        }
    }

    /// OpenSim's own constrained case (opensim-core's IK test resources): the 3.x shoulder model
    /// subject1_abdbonepin — a `ScapulothoracicJoint` and the acromioclavicular
    /// `PointConstraint` — on its trial's first second, against OpenSim 4.6 at `accuracy` 1e-10
    /// (`oracle/gen_ik_point_constraint.py`), held to 1e-4° and 1e-6 m. The objective (the
    /// markers') may exceed that of OpenSim's pose by 1e-8: OpenSim closes the constraint only
    /// to its assembly tolerance (~1e-10 m), and a pose that far off it can fit the markers
    /// that much better (6e-9 here).
    pub fn shoulder_point_constraint(root: &Path) -> IkCase {
        let (fixture, golden) = (root.join("fixtures/ik_point_constraint"), root.join("fixtures/golden/ik/point_constraint"));
        IkCase {
            model: fixture.join("subject1_abdbonepin.osim"),
            trial: fixture.join("abdbonepin_1s.trc"),
            setup: fixture.join("setup_ik.xml"),
            motion: golden.join("ik.mot"),
            errors: golden.join("ik_marker_errors.sto"),
            rotation_tolerance_degrees: 1e-4,
            translation_tolerance_meters: 1e-6,
            objective_slack: 1e-8,
        }
    }
}

impl IkCase {
    /// Every constraint class held between bodies (`oracle/gen_constraint_assembly.py`):
    /// linked_mechanisms.osim — a PointConstraint loop, a ConstantDistanceConstraint with a
    /// locked pin, a PointOnLineConstraint on a free block, a WeldConstraint between a free cap
    /// and a pinned lever, a coupler — on a synthetic 20-frame trial (1 mm noise), against
    /// OpenSim 4.6 at `accuracy` 1e-10, held to 1e-4° and 1e-6 m. The objective may exceed that
    /// of OpenSim's pose by 2e-6 (relative; 3e-12 m² absolute): OpenSim's poses leave the links
    /// open by up to 5e-9 (Simbody's position errors at its `.mot` values), enough to fit the
    /// markers that much better (1.2e-6 here).
    pub fn linked_mechanisms(root: &Path) -> IkCase {
        let (fixture, golden) = (root.join("fixtures/ik_linked_mechanisms"), root.join("fixtures/golden/ik/linked_mechanisms"));
        IkCase {
            model: fixture.join("linked_mechanisms.osim"),
            trial: fixture.join("trial.trc"),
            setup: fixture.join("setup_ik.xml"),
            motion: golden.join("ik.mot"),
            errors: golden.join("ik_marker_errors.sto"),
            rotation_tolerance_degrees: 1e-4,
            translation_tolerance_meters: 1e-6,
            objective_slack: 2e-6,
        }
    }
}

/// Which frames are solved, from where.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IkFrames {
    /// All frames of the setup's time range in order, each from our previous solution (as
    /// OpenSim runs).
    Trial,
    /// Every `n`-th frame, each started from OpenSim's solution of the frame before it (the
    /// first from the default pose): a quick, independent check of single frames.
    EveryNth(usize),
}

/// The worst difference of one coordinate.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateDifference {
    pub name: String,
    /// Degrees for rotational coordinates, metres otherwise.
    pub worst: f64,
    pub rotational: bool,
    /// Time of the worst frame (s).
    pub at: f64,
    /// The case's tolerance for this coordinate (degrees or m).
    pub tolerance: f64,
}

/// What a comparison found.
#[derive(Debug, Clone, PartialEq)]
pub struct IkComparison {
    pub frames: usize,
    /// Per coordinate, in model order.
    pub coordinates: Vec<CoordinateDifference>,
    /// max over frames of (our marker RMS − OpenSim's), m, and its time.
    pub rms_excess: f64,
    pub rms_excess_at: f64,
    /// max over frames of (OpenSim's marker RMS − ours), m: how much lower ours is.
    pub rms_improvement: f64,
    /// max over frames of (our objective − OpenSim's) / OpenSim's: ≤ 0 when every frame of
    /// ours is the better minimum.
    pub objective_excess: f64,
    /// max over frames of (OpenSim's objective − ours) / OpenSim's.
    pub objective_improvement: f64,
    /// The case's bound on `objective_excess`.
    pub objective_slack: f64,
    pub unconverged: usize,
    pub max_iterations: usize,
    pub mean_iterations: f64,
}

impl IkComparison {
    /// The coordinate furthest beyond (or nearest to) its tolerance.
    pub fn worst_coordinate(&self) -> Option<&CoordinateDifference> {
        self.coordinates.iter().max_by(|a, b| (a.worst / a.tolerance).total_cmp(&(b.worst / b.tolerance)))
    }

    /// Whether every stated tolerance holds.
    pub fn passes(&self) -> bool {
        self.unconverged == 0
            && self.rms_excess <= RMS_SLACK_METERS
            && self.objective_excess <= self.objective_slack
            && self.coordinates.iter().all(|c| c.worst <= c.tolerance)
    }
}

/// Errors reading a case or solving it.
pub type IkValidationError = Box<dyn std::error::Error>;

/// The tasks and time range (s) of an `InverseKinematicsTool` setup.
pub fn read_setup_tasks(setup: &Path) -> Result<(IkTasks, Option<[f64; 2]>), IkValidationError> {
    let setup = IkSetup::read(setup)?;
    Ok((IkTasks::from_task_set(&setup.tasks, &setup.file, CoordinateValues::read_setup_file(setup.coordinate_file.as_ref())?)?, Some([setup.time_range.start, setup.time_range.end])))
}

/// Solves `case` and compares with OpenSim's output.
pub fn compare_ik(case: &IkCase, frames: IkFrames) -> Result<IkComparison, IkValidationError> {
    let spec = ModelSpec::read(&OsimDocument::read(&case.model)?)?;
    let multibody = Multibody::new(&spec)?;
    let trial = MarkerTable::read(&case.trial)?;
    let (tasks, time_range) = read_setup_tasks(&case.setup)?;
    let ik = InverseKinematics::new(&multibody, &trial, &case.trial, &tasks, IkSettings::default())?;
    let golden = Motion::from_table(&StorageTable::read(&case.motion)?, &case.motion, &multibody, false)?;
    let golden_rms = StorageTable::read(&case.errors)?.column("marker_error_RMS").ok_or("no marker_error_RMS column")?;
    let range = ik.frames(time_range)?;
    let first = *range.start();
    if golden.len() != range.clone().count() || golden_rms.len() != golden.len() {
        return Err(format!("{}: {} rows, but the time range holds {} frames", case.motion.display(), golden.len(), range.count()).into());
    }
    let mut workspace = ik.workspace();
    let mut q = ik.initial_pose();
    let mut comparison = IkComparison {
        frames: 0,
        coordinates: multibody
            .coordinates
            .iter()
            .map(|c| {
                let rotational = c.motion_type == MotionType::Rotational;
                let tolerance = if rotational { case.rotation_tolerance_degrees } else { case.translation_tolerance_meters };
                CoordinateDifference { name: c.name.clone(), worst: 0.0, rotational, at: 0.0, tolerance }
            })
            .collect(),
        rms_excess: f64::NEG_INFINITY,
        rms_excess_at: 0.0,
        rms_improvement: 0.0,
        objective_excess: f64::NEG_INFINITY,
        objective_improvement: 0.0,
        objective_slack: case.objective_slack,
        unconverged: 0,
        max_iterations: 0,
        mean_iterations: 0.0,
    };
    let step = match frames {
        IkFrames::Trial => 1,
        IkFrames::EveryNth(n) => n.max(1),
    };
    for row in (0..golden.len()).step_by(step) {
        if let (IkFrames::EveryNth(_), true) = (frames, row > 0) {
            q.copy_from_slice(golden.pose(row - 1));
        }
        let solved = ik.solve_frame(first + row, &mut q, &mut workspace)?;
        comparison.frames += 1;
        comparison.unconverged += usize::from(solved.status != LeastSquaresStatus::Converged);
        comparison.max_iterations = comparison.max_iterations.max(solved.iterations);
        comparison.mean_iterations += solved.iterations as f64;
        for (difference, (ours, theirs)) in comparison.coordinates.iter_mut().zip(solved.q.iter().zip(golden.pose(row))) {
            let error = if difference.rotational { (ours - theirs).to_degrees().abs() } else { (ours - theirs).abs() };
            if error > difference.worst || error.is_nan() {
                difference.worst = if error.is_nan() { f64::INFINITY } else { error };
                difference.at = solved.time;
            }
        }
        let excess = solved.errors.rms - golden_rms[row];
        if excess > comparison.rms_excess {
            comparison.rms_excess = excess;
            comparison.rms_excess_at = solved.time;
        }
        comparison.rms_improvement = comparison.rms_improvement.max(-excess);
        let theirs = ik.objective(first + row, golden.pose(row), &mut workspace)?;
        let relative = (solved.objective - theirs) / theirs;
        comparison.objective_excess = comparison.objective_excess.max(relative);
        comparison.objective_improvement = comparison.objective_improvement.max(-relative);
    }
    comparison.mean_iterations /= comparison.frames.max(1) as f64;
    Ok(comparison)
}
