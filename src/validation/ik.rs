//! Inverse kinematics against OpenSim 4.6's `InverseKinematicsTool` on subject01's walking
//! trial: coordinates against `subject01_walk1_ik.mot` (per coordinate, degrees or metres) and
//! marker RMS against `subject01_walk1_ik_marker_errors.sto`, with the tasks, weights and time
//! range of the setup OpenSim ran (`setup_ik_used.xml`, read minimally here).

use std::path::{Path, PathBuf};

use crate::io::osim::OsimDocument;
use crate::io::table::{MarkerTable, StorageTable};
use crate::io::xml::Document;
use crate::mechanics::{Motion, Multibody};
use crate::model::{ModelSpec, MotionType};
use crate::solvers::{CoordinateTarget, CoordinateTask, IkSettings, IkTasks, InverseKinematics, LeastSquaresStatus, MarkerTask};

/// Largest coordinate difference allowed: 0.05° for rotations…
pub const ROTATION_TOLERANCE_DEGREES: f64 = 0.05;
/// …and 0.1 mm for translations.
pub const TRANSLATION_TOLERANCE_METERS: f64 = 1e-4;
/// Our marker RMS may exceed OpenSim's by this much (m): the rounding of OpenSim's file (8
/// decimals) plus 1 µm. Our solution minimises the weighted objective more tightly than
/// OpenSim's L-BFGS, which need not lower the unweighted RMS in every frame.
pub const RMS_SLACK_METERS: f64 = 1e-6;

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
}

impl CoordinateDifference {
    pub fn tolerance(&self) -> f64 {
        if self.rotational { ROTATION_TOLERANCE_DEGREES } else { TRANSLATION_TOLERANCE_METERS }
    }
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
    pub unconverged: usize,
    pub max_iterations: usize,
    pub mean_iterations: f64,
}

impl IkComparison {
    /// The coordinate furthest beyond (or nearest to) its tolerance.
    pub fn worst_coordinate(&self) -> Option<&CoordinateDifference> {
        self.coordinates.iter().max_by(|a, b| (a.worst / a.tolerance()).total_cmp(&(b.worst / b.tolerance())))
    }

    /// Whether every stated tolerance holds.
    pub fn passes(&self) -> bool {
        self.unconverged == 0 && self.rms_excess <= RMS_SLACK_METERS && self.coordinates.iter().all(|c| c.worst <= c.tolerance())
    }
}

/// Errors reading a case or solving it.
pub type IkValidationError = Box<dyn std::error::Error>;

/// The tasks and time range of an `InverseKinematicsTool` setup: `IKMarkerTask`s and
/// `IKCoordinateTask`s with `apply` true (`default_value` and `manual_value` targets), and
/// `time_range`.
pub fn read_setup_tasks(setup: &Path) -> Result<(IkTasks, Option<[f64; 2]>), IkValidationError> {
    let document = Document::read(setup)?;
    let text = |id, tag: &str| document.child(id, tag).and_then(|c| document.text(c)).map(|t| t.trim().to_string());
    let number = |id, tag: &str, default: f64| -> Result<f64, IkValidationError> {
        match text(id, tag) {
            None => Ok(default),
            Some(t) => t.parse().map_err(|_| format!("{}:{}: <{tag}> {t:?} is not a number", setup.display(), document.line(id)).into()),
        }
    };
    let mut tasks = IkTasks::default();
    let mut time_range = None;
    for id in document.ids() {
        let name = document.name(id).unwrap_or_default().to_string();
        let applied = text(id, "apply").is_none_or(|a| a == "true");
        match document.tag(id) {
            "IKMarkerTask" if applied => tasks.markers.push(MarkerTask { name, weight: number(id, "weight", 0.0)? }),
            "IKCoordinateTask" if applied => {
                let target = match text(id, "value_type").as_deref() {
                    Some("manual_value") => CoordinateTarget::Value(number(id, "value", 0.0)?),
                    None | Some("default_value") => CoordinateTarget::DefaultValue,
                    Some(other) => return Err(format!("{}:{}: value_type {other} is not supported", setup.display(), document.line(id)).into()),
                };
                tasks.coordinates.push(CoordinateTask { name, weight: number(id, "weight", 0.0)?, target });
            }
            "time_range" => {
                let values: Vec<f64> = document.text(id).unwrap_or_default().split_whitespace().filter_map(|v| v.parse().ok()).collect();
                if let [start, end] = values[..] {
                    time_range = Some([start, end]);
                }
            }
            _ => {}
        }
    }
    Ok((tasks, time_range))
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
            .map(|c| CoordinateDifference { name: c.name.clone(), worst: 0.0, rotational: c.motion_type == MotionType::Rotational, at: 0.0 })
            .collect(),
        rms_excess: f64::NEG_INFINITY,
        rms_excess_at: 0.0,
        rms_improvement: 0.0,
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
    }
    comparison.mean_iterations /= comparison.frames.max(1) as f64;
    Ok(comparison)
}
