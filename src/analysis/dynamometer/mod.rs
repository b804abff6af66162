//! Thesis ch. 5, an extended dynamometer set-up: the knee moment about the knee's (functional)
//! axis, M3D, by 3D inverse dynamics of crank, shank and foot with a 6-D load cell in the
//! crank, beside the dynamometer's own moment (Mdyn) and Herzog's 2D estimate (M2D); how far
//! the axes are apart, whether the pad pushes perpendicular to the crank, and how much M3D
//! moves with the model's uncertain parameters (table 5.1).
//!
//! The crank is a body of the model on a one-coordinate joint that turns it about a fixed
//! axis in ground (a `PinJoint` to ground: the dynamometer's axis); its origin is the load
//! cell. The load cell's wrench on the crank comes as an `ExternalForce` applied to it.

mod agreement;
mod frame;
mod plateau;
mod sensitivity;
mod summary;

use std::path::{Path, PathBuf};

pub use agreement::{agreement, Agreement};
pub use frame::{Axis, DynamometerFrame, DynamometerModel, HerzogEstimate};
pub use plateau::{isometric_contraction, plateau, IsometricContraction};
pub use sensitivity::{Perturbations, SensitivityRow};
pub use summary::{Agreements, DynamometerSummary, Spread, PERPENDICULAR_TOLERANCE};

use super::external_loads::{interpolate, ExternalLoads};
use sensitivity::sensitivity;
use super::sampled_motion::SampledMotion;
use super::splined_motion::{SplinedMotion, SplinedMotionError};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Function, MotionState, Multibody, Vec3, GROUND_INDEX};
use crate::model::MotionType;

/// Why the dynamometer's inverse dynamics cannot run.
#[derive(Debug, thiserror::Error)]
pub enum DynamometerError {
    #[error("{}: {problem}", file.display())]
    Model { file: PathBuf, problem: String },
    #[error("{}: {problem}", file.display())]
    Data { file: PathBuf, problem: String },
    #[error(transparent)]
    Motion(#[from] SplinedMotionError),
}

/// The dynamometer's own moment, a column of a table, as a function of time.
pub struct MeasuredMoment {
    pub file: PathBuf,
    pub column: String,
    /// +1, or −1 when the column is about the axis' other sense.
    pub sign: f64,
    span: [f64; 2],
    function: Function,
}

impl MeasuredMoment {
    /// Column `column` of `table` (read from `file`), interpolated as OpenSim interpolates
    /// external loads.
    pub fn new(table: &StorageTable, file: &Path, column: &str, sign: f64) -> Result<MeasuredMoment, DynamometerError> {
        let data = |problem: String| DynamometerError::Data { file: file.into(), problem };
        let index = table.labels().iter().position(|l| l == column).filter(|&i| i > 0).ok_or_else(|| data(format!("has no column {column:?} (the dynamometer's moment)")))?;
        let times = table.times();
        let values: Vec<f64> = table.rows().map(|row| row[index]).collect();
        if let Some(row) = values.iter().position(|v| !v.is_finite()) {
            return Err(data(format!("column {column:?}, row {}: the dynamometer's moment is not a number", row + 1)));
        }
        let function = interpolate(&times, &values).map_err(|e| data(e.to_string()))?;
        Ok(MeasuredMoment { file: file.into(), column: column.into(), sign, span: [times[0], times[times.len() - 1]], function })
    }
}

/// How the analysis runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamometerSettings {
    /// s; clipped to the coordinates' times.
    pub time_range: [f64; 2],
    pub perturbations: Perturbations,
}

/// The analysis along a trial.
pub struct DynamometerResult {
    pub times: Vec<f64>,
    pub frames: Vec<DynamometerFrame>,
    /// Mdyn in the knee coordinate's sense, when measured.
    pub dynamometer: Option<Vec<f64>>,
    /// M2D, when Mdyn was measured.
    pub herzog: Option<Vec<HerzogEstimate>>,
    pub sensitivity: Vec<SensitivityRow>,
    /// Coordinates held at their default value (not in the file).
    pub defaulted: Vec<String>,
}

impl DynamometerModel {
    /// Finds the crank body `crank` and the knee coordinate `knee` in `multibody`.
    pub fn new(multibody: &Multibody, crank: &str, knee: &str) -> Result<DynamometerModel, DynamometerError> {
        let problem = |problem: String| DynamometerError::Model { file: multibody.file.clone(), problem };
        let crank_body = multibody.body_index(crank).filter(|&b| b != GROUND_INDEX).ok_or_else(|| problem(format!("the crank {crank:?} is not a body of the model")))?;
        let crank_joint = multibody.bodies[crank_body].joint.expect("a body other than ground has a joint");
        let joint = &multibody.joints[crank_joint];
        let rotational = |c: usize| multibody.coordinates[c].motion_type == MotionType::Rotational;
        if joint.parent != GROUND_INDEX || joint.coordinates.len() != 1 || !rotational(joint.coordinates[0]) || !turns_about_fixed_axis(multibody, joint.coordinates[0]) {
            return Err(problem(format!("the crank's joint {:?} must turn it about an axis fixed in ground (a PinJoint to ground: the dynamometer's axis)", joint.name)));
        }
        let arm = crank_arm(multibody, crank_body, joint.coordinates[0]);
        if arm < MIN_CRANK_ARM {
            return Err(problem(format!(
                "the crank {crank:?}'s origin (the load cell) lies {arm:.1e} m from the dynamometer's axis; it must lie on the crank, off the axis (the crank's direction, Herzog's lever arms and the pad force's angle are measured from it)"
            )));
        }
        let knee_coordinate = multibody.coordinate_index(knee).ok_or_else(|| problem(format!("the knee coordinate {knee:?} is not a coordinate of the model")))?;
        if !rotational(knee_coordinate) {
            return Err(problem(format!("the knee coordinate {knee:?} is not rotational")));
        }
        let knee_joint = multibody.coordinate_joint(knee_coordinate);
        if multibody.is_moved_by(crank_body, knee_joint) {
            return Err(problem(format!("the crank {crank:?} hangs below the knee's joint {:?}; it must hang on ground", multibody.joints[knee_joint].name)));
        }
        let shank = multibody.joints[knee_joint].child;
        Ok(DynamometerModel { crank: crank_body, crank_joint, crank_coordinate: joint.coordinates[0], knee_coordinate, knee_joint, shank })
    }
}

/// The least distance of the load cell (the crank's origin) from the dynamometer's axis, m.
const MIN_CRANK_ARM: f64 = 1e-3;

/// The distance of `body`'s origin from the axis of `coordinate` (its joint's), m, in the
/// default pose.
fn crank_arm(multibody: &Multibody, body: usize, coordinate: usize) -> f64 {
    let mut kinematics = multibody.kinematics();
    multibody.realize(&multibody.default_pose(), &mut kinematics);
    let axis = kinematics.axes[coordinate];
    frame::perpendicular(&(kinematics.bodies[body].translation - axis.origin), &axis.angular.normalize()).norm()
}

/// Whether the coordinate turns its body about one line at two values (a pin's axis).
fn turns_about_fixed_axis(multibody: &Multibody, coordinate: usize) -> bool {
    let mut kinematics = multibody.kinematics();
    let mut q = multibody.default_pose();
    let mut lines = Vec::new();
    for step in [0.0, 0.7] {
        q[coordinate] += step;
        multibody.realize(&q, &mut kinematics);
        let axis = kinematics.axes[coordinate];
        lines.push((axis.angular, axis.origin, axis.linear));
    }
    let (a, p, v) = lines[0];
    let (b, r, w) = lines[1];
    let close = |x: Vec3| x.norm() < 1e-9;
    close(v) && close(w) && close(a - b) && close((r - p).cross(&a.normalize()))
}

/// Runs the dynamometer's inverse dynamics along `motion` with the load cell in `loads`.
pub fn dynamometer_analysis(
    multibody: &Multibody,
    model: &DynamometerModel,
    motion: &SplinedMotion,
    loads: &ExternalLoads,
    measured: Option<&MeasuredMoment>,
    settings: &DynamometerSettings,
) -> Result<DynamometerResult, DynamometerError> {
    let motion = model.measured_motion(multibody, motion, settings.time_range)?;
    let frames = frames_of(multibody, model, &motion, loads);
    let dynamometer = measured.map(|m| dynamometer_moments(m, &motion.times, &frames)).transpose()?;
    let herzog = dynamometer.as_ref().map(|d| d.iter().zip(&frames).map(|(&m, f)| f.herzog(m)).collect());
    let sensitivity = sensitivity(multibody, model, &frames, &settings.perturbations, |perturbed| frames_of(perturbed, model, &motion, loads));
    Ok(DynamometerResult { times: motion.times, frames, dynamometer, herzog, sensitivity, defaulted: motion.defaulted })
}

impl DynamometerModel {
    /// The load cell's file `file` (read as `loads`) must load the crank.
    pub fn check_load_cell(&self, multibody: &Multibody, loads: &ExternalLoads, file: &Path) -> Result<(), DynamometerError> {
        if loads.loads_body(self.crank) {
            return Ok(());
        }
        let problem = format!("no ExternalForce is applied to the crank {:?}; the load cell's wrench on the crank is what the analysis needs", multibody.bodies[self.crank].name);
        Err(DynamometerError::Data { file: file.into(), problem })
    }

    /// `motion`'s frames within `range` (s), sampled once for every run along them; refused
    /// when the crank's or the knee's coordinate is not in its file.
    fn measured_motion(&self, multibody: &Multibody, motion: &SplinedMotion, range: [f64; 2]) -> Result<SampledMotion, DynamometerError> {
        for c in [self.crank_coordinate, self.knee_coordinate] {
            let name = &multibody.coordinates[c].name;
            if motion.defaulted.contains(name) {
                return Err(DynamometerError::Data { file: motion.file().into(), problem: format!("has no column for {name}; the crank's and the knee's motion must be measured") });
            }
        }
        Ok(motion.sample(multibody, range)?)
    }
}

/// The frames of `motion`.
fn frames_of(multibody: &Multibody, model: &DynamometerModel, motion: &SampledMotion, loads: &ExternalLoads) -> Vec<DynamometerFrame> {
    let mut kinematics = multibody.kinematics();
    motion
        .times
        .iter()
        .zip(&motion.states)
        .map(|(&time, state)| {
            multibody.realize(&state.q, &mut kinematics);
            let applied = loads.at(time, &kinematics);
            model.frame(multibody, &kinematics, &MotionState { q: &state.q, u: &state.u, udot: &state.udot }, &applied)
        })
        .collect()
}

/// Below this cosine between the series of Mdyn and M3D, Mdyn is taken to have the other sign
/// convention (opposite series give −1; a mere mismatch stays well above −0.5).
const OPPOSED: f64 = 0.5;

/// Mdyn at `times` in the knee coordinate's sense; refused outside its table's times and when
/// it clearly opposes M3D (the other sign convention).
fn dynamometer_moments(measured: &MeasuredMoment, times: &[f64], frames: &[DynamometerFrame]) -> Result<Vec<f64>, DynamometerError> {
    let data = |problem: String| DynamometerError::Data { file: measured.file.clone(), problem };
    let [first, last] = measured.span;
    if let Some(time) = times.iter().find(|&&t| t < first || t > last) {
        return Err(data(format!("the dynamometer's moment spans {first}–{last} s, but the trial has a frame at {time} s; choose --time within it")));
    }
    let moments: Vec<f64> = times.iter().zip(frames).map(|(&t, f)| measured.sign * measured.function.value(t) * f.sense()).collect();
    let knee: Vec<f64> = frames.iter().map(|f| f.knee_moment).collect();
    let cosine = dot(&moments, &knee) / (dot(&moments, &moments) * dot(&knee, &knee)).sqrt();
    if cosine < -OPPOSED {
        return Err(data(format!(
            "column {:?} opposes the knee moment M3D the load cell gives (cosine of the two series {cosine:.2}): the other sign convention. If the dynamometer reports the moment about the other sense of its axis, pass --dynamometer-sign -1; if the load cell's columns are the load on the sensor rather than on the crank, negate them",
            measured.column
        )));
    }
    Ok(moments)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl DynamometerResult {
    /// The per-frame table: M3D (`<knee>_moment`), Mdyn and M2D with its lever arms (when
    /// measured), F_tc and its moment about D, its angle to the crank's normal, the knee's
    /// reaction, and the axes' offset and angle; in ground, N, N·m, m and degrees.
    pub fn table(&self, multibody: &Multibody, model: &DynamometerModel) -> Result<StorageTable, TableError> {
        let knee = &multibody.coordinates[model.knee_coordinate].name;
        let mut labels = vec!["time".to_string(), format!("{knee}_moment")];
        if self.herzog.is_some() {
            labels.extend(["dynamometer_moment", "herzog_moment", "herzog_pad_distance", "herzog_knee_distance"].map(String::from));
        }
        for (prefix, axes) in [("pad_force", "xyz"), ("pad_moment", "xyz"), ("knee_force", "xyz"), ("knee_torque", "xyz")] {
            labels.extend(axes.chars().map(|a| format!("{prefix}_{a}")));
        }
        labels.extend(["pad_force_angle_deg", "knee_axis_offset", "knee_axis_angle_deg"].map(String::from));
        let mut values = Vec::with_capacity(self.times.len() * labels.len());
        for (i, (time, frame)) in self.times.iter().zip(&self.frames).enumerate() {
            values.extend([*time, frame.knee_moment]);
            if let (Some(dynamometer), Some(herzog)) = (&self.dynamometer, &self.herzog) {
                values.extend([dynamometer[i], herzog[i].knee_moment, herzog[i].pad_distance, herzog[i].knee_distance]);
            }
            for v in [frame.pad_force, frame.pad_moment, frame.knee_force, frame.knee_torque] {
                values.extend(v.iter());
            }
            values.extend([frame.pad_force_angle().to_degrees(), frame.axis_offset(), frame.axis_angle().to_degrees()]);
        }
        Ok(StorageTable::new("Dynamometer Inverse Dynamics", labels, values)?.with_in_degrees(false))
    }
}
