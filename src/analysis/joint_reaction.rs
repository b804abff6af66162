//! OpenSim's `JointReaction` analysis (run by the `AnalyzeTool`): the loads the joints transmit
//! when the muscles and actuators exert the forces of a forces file (e.g. static optimisation's
//! `_force.sto`), with gravity and the external loads.
//!
//! Per analysed row of the AnalyzeTool's states (coordinates and their spline speeds), every
//! actuator exerts its force from the file (linearly interpolated, `Storage::getDataAtTime`):
//! a muscle its tension along its path, an actuator its actuation. The accelerations are the
//! ones these forces give (forward dynamics, as `realizeAcceleration`), not the tracked ones, so
//! any imbalance in the forces shows in the reactions as it does in OpenSim's; the forces links
//! between bodies exert to hold their loops count among the loads. Each requested
//! joint's load on its child (at the child frame origin) or on its parent (at the parent frame
//! origin) is expressed in ground or in a body, with the point where it acts.

use std::path::{Path, PathBuf};

use super::analyze_states::{AnalyzeStates, MotionInput, StatesError};
use super::external_loads::ExternalLoads;
use super::signal::linear_interpolation;
use super::static_optimization::Generator;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{AppliedForces, BodyLoad, ForwardDynamicsError, JointReaction, Kinematics, MotionState, MuscleGeometry, Multibody, PathScratch, Vec3};
use crate::model::ModelSpec;

/// Why the reactions cannot be computed.
#[derive(Debug, thiserror::Error)]
pub enum JointReactionError {
    #[error(transparent)]
    States(#[from] StatesError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{}: {problem}", file.display())]
    Forces { file: PathBuf, problem: String },
    #[error("{}: {problem}", file.display())]
    Request { file: PathBuf, problem: String },
    #[error("{}: no row lies in the time range {start}–{end} s", file.display())]
    NoFrames { file: PathBuf, start: f64, end: f64 },
    #[error("at t = {time} s: {source}")]
    Dynamics { time: f64, source: ForwardDynamicsError },
}

/// Which body of its joint a reported load acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReactionSide {
    Child,
    Parent,
}

/// One reported load: a joint ([`Multibody::joints`] index), the body it acts on and the body
/// (or ground) it is expressed in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReactionReport {
    pub joint: usize,
    pub on: ReactionSide,
    pub frame: usize,
}

/// How the analysis runs (the AnalyzeTool's and the analysis's properties).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointReactionSettings {
    /// s (see `rows_in_range`).
    pub time_range: [f64; 2],
    /// Low-pass cutoff for the coordinates, Hz (`None`: no filtering).
    pub lowpass_cutoff: Option<f64>,
    /// Record the first and last rows and every row whose index is a multiple of this.
    pub step_interval: usize,
}

/// The forces each actuator exerts, as a table read from `file`.
#[derive(Debug, Clone, Copy)]
pub struct ActuatorForces<'a> {
    pub table: &'a StorageTable,
    pub file: &'a Path,
}

/// The reported loads per analysed row, and what the inputs held that was not used.
#[derive(Debug, Clone)]
pub struct JointReactionResult {
    /// `<joint>_on_<body>_in_<frame>_{fx,fy,fz,mx,my,mz,px,py,pz}` (OpenSim's
    /// `_ReactionLoads.sto`): N, N·m, m.
    pub loads: StorageTable,
    /// Coordinates the coordinates file lacks (held at 0, as OpenSim does).
    pub missing: Vec<String>,
    /// Columns of the coordinates file that are no coordinate.
    pub ignored_columns: Vec<String>,
    /// Columns of the forces file that are no actuator of the model.
    pub unused_forces: Vec<String>,
    /// Times (s) of the rows where some actuator's force is not a number (e.g. a frame static
    /// optimisation did not solve); their loads are NaN.
    pub rows_without_forces: Vec<f64>,
}

/// The reports OpenSim's `JointReaction` makes of its `joint_names` ([`super::named_joints`]),
/// `apply_on_bodies` (`child` or `parent`) and `express_in_frame`
/// (`ground`, a body's name, `child` or `parent`); the latter two hold one entry for all joints
/// or one per joint, and are `child` and `ground` when empty. `file` is where they were given.
pub fn reaction_reports(spec: &ModelSpec, multibody: &Multibody, joints: &[String], on: &[String], frames: &[String], file: &Path) -> Result<Vec<ReactionReport>, JointReactionError> {
    let request = |problem: String| JointReactionError::Request { file: file.into(), problem };
    let joints = super::named_joints(spec, multibody, joints).map_err(|problem| request(format!("joint_names (--joints): {problem}")))?;
    let entry = |list: &[String], k: usize, default: &str, what: &str| -> Result<String, JointReactionError> {
        match list.len() {
            0 => Ok(default.into()),
            1 => Ok(list[0].clone()),
            n if n == joints.len() => Ok(list[k].clone()),
            n => Err(request(format!("{what} has {n} entries; expected 1 or one per joint ({})", joints.len()))),
        }
    };
    let mut reports = Vec::with_capacity(joints.len());
    for (k, &joint) in joints.iter().enumerate() {
        let (parent, child) = (multibody.joints[joint].parent, multibody.joints[joint].child);
        let side = entry(on, k, "child", "apply_on_bodies (--on)")?;
        let on = match side.to_ascii_lowercase().as_str() {
            "child" => ReactionSide::Child,
            "parent" => ReactionSide::Parent,
            _ => return Err(request(format!("apply_on_bodies (--on) {side:?}: expected child or parent"))),
        };
        let frame = entry(frames, k, "ground", "express_in_frame (--in)")?;
        let frame = match multibody.body_index(&frame) {
            Some(body) => body,
            None if frame.eq_ignore_ascii_case("child") => child,
            None if frame.eq_ignore_ascii_case("parent") => parent,
            None => return Err(request(format!("express_in_frame (--in) {frame:?}: expected ground, a body of the model, child or parent"))),
        };
        reports.push(ReactionReport { joint, on, frame });
    }
    Ok(reports)
}

/// What the joints carry: the model, the forces its muscles and actuators exert, and the
/// external loads.
#[derive(Debug, Clone, Copy)]
pub struct ReactionProblem<'a> {
    pub geometry: &'a MuscleGeometry,
    pub generators: &'a [Generator],
    pub forces: ActuatorForces<'a>,
    pub external: Option<&'a ExternalLoads>,
}

/// Runs the analysis along `motion` (read from `file`).
pub fn joint_reactions(problem: &ReactionProblem, motion: MotionInput, file: &Path, reports: &[ReactionReport], settings: &JointReactionSettings) -> Result<JointReactionResult, JointReactionError> {
    let ReactionProblem { geometry, generators, forces, external } = *problem;
    let multibody = &geometry.multibody;
    let mut states = AnalyzeStates::read(multibody, motion, file, settings.lowpass_cutoff)?;
    let [start, end] = settings.time_range;
    let rows = states.assembled_rows(multibody, settings.time_range, settings.step_interval, file)?.ok_or(JointReactionError::NoFrames { file: file.into(), start, end })?;
    let (columns, unused_forces) = force_columns(forces, generators)?;
    let force_times = forces.table.times();
    let mut kinematics = multibody.kinematics();
    let mut scratch = PathScratch::default();
    let mut values = Vec::with_capacity(rows.len() * (1 + 9 * reports.len()));
    let mut rows_without_forces = Vec::new();
    for &i in &rows {
        let (time, q, u) = (states.times[i], &states.q[i], &states.u[i]);
        check_time(time, &force_times, forces.file)?;
        multibody.realize(q, &mut kinematics);
        let mut applied = AppliedForces { loads: external.map(|e| e.at(time, &kinematics)).unwrap_or_default(), mobility: vec![0.0; q.len()] };
        let forces: Vec<f64> = columns.iter().map(|column| linear_interpolation(&force_times, column, time)).collect();
        if forces.iter().any(|f| !f.is_finite()) {
            rows_without_forces.push(time);
        }
        for (generator, &force) in generators.iter().zip(&forces) {
            generator.apply(geometry, &kinematics, q, &mut scratch, force, &mut applied);
        }
        let (udot, link_loads) = multibody.constrained_accelerations(&kinematics, q, u, &applied.loads, &applied.mobility).map_err(|source| JointReactionError::Dynamics { time, source })?;
        applied.loads.extend(link_loads);
        values.push(time);
        values.extend(reaction_row(multibody, &kinematics, &MotionState { q, u, udot: &udot }, &applied.loads, reports));
    }
    let loads = reaction_table(multibody, reports, values)?;
    Ok(JointReactionResult { loads, missing: states.missing, ignored_columns: states.ignored_columns, unused_forces, rows_without_forces })
}

/// The reported loads (`reports`, 9 values each) in the state `state` of the pose `kinematics`
/// holds, with the body loads `loads` applied.
pub fn reaction_row(multibody: &Multibody, kinematics: &Kinematics, state: &MotionState, loads: &[BodyLoad], reports: &[ReactionReport]) -> Vec<f64> {
    let reactions = multibody.joint_reactions(state, loads);
    reports.iter().flat_map(|report| reported(&reactions[report.joint], report, kinematics)).collect()
}

/// OpenSim's `ReactionLoads` table of `reports` from its rows `values` (time, then
/// [`reaction_row`]).
pub fn reaction_table(multibody: &Multibody, reports: &[ReactionReport], values: Vec<f64>) -> Result<StorageTable, TableError> {
    let labels = std::iter::once("time".to_string()).chain(reports.iter().flat_map(|r| labels(multibody, r))).collect();
    StorageTable::new("Joint Reaction Loads", labels, values)?
        .with_in_degrees(false)
        .with_comment("This file contains the reaction forces and moments")?
        .with_comment("applied to the specified body of a joint pair and expressed  in the specified reference frame.")?
        .with_comment("Units are S.I. units (seconds, meters, Newtons, ...)")
}

/// Each generator's force column; every generator must have one. Also returns the columns that
/// are no generator.
fn force_columns(forces: ActuatorForces, generators: &[Generator]) -> Result<(Vec<Vec<f64>>, Vec<String>), JointReactionError> {
    let problem = |problem: String| JointReactionError::Forces { file: forces.file.into(), problem };
    if forces.table.n_rows() < 2 {
        return Err(problem(format!("{} rows; at least 2 are needed to interpolate", forces.table.n_rows())));
    }
    let missing: Vec<&str> = generators.iter().filter(|g| forces.table.column_index(&g.name).is_none()).map(|g| g.name.as_str()).collect();
    if !missing.is_empty() {
        return Err(problem(format!("no column for the actuator(s) {}; every muscle and actuator of the model needs its force", missing.join(", "))));
    }
    let columns = generators.iter().map(|g| forces.table.column(&g.name).unwrap_or_default()).collect();
    let unused = forces.table.labels().iter().skip(1).filter(|l| !generators.iter().any(|g| &g.name == *l)).cloned().collect();
    Ok((columns, unused))
}

/// A row's time must lie within the forces file's times (to 1e-9 s).
fn check_time(time: f64, times: &[f64], file: &Path) -> Result<(), JointReactionError> {
    let (first, last) = (times[0], times[times.len() - 1]);
    if time < first - 1e-9 || time > last + 1e-9 {
        return Err(JointReactionError::Forces { file: file.into(), problem: format!("its times ({first}–{last} s) do not cover t = {time} s") });
    }
    Ok(())
}

/// Force, moment and point of one report, in its frame.
fn reported(reaction: &JointReaction, report: &ReactionReport, kinematics: &Kinematics) -> [f64; 9] {
    let (force, moment, point) = match report.on {
        ReactionSide::Child => (reaction.force, reaction.moment, reaction.child_origin),
        ReactionSide::Parent => {
            let (force, moment) = reaction.on_parent();
            (force, moment, reaction.parent_origin)
        }
    };
    let frame = &kinematics.bodies[report.frame];
    let express = |v: Vec3| frame.rotation.transpose() * v;
    let [f, m, p] = [express(force), express(moment), frame.inverse().apply(&point)];
    [f.x, f.y, f.z, m.x, m.y, m.z, p.x, p.y, p.z]
}

/// OpenSim's column labels of one report.
fn labels(multibody: &Multibody, report: &ReactionReport) -> Vec<String> {
    let joint = &multibody.joints[report.joint];
    let body = match report.on {
        ReactionSide::Child => joint.child,
        ReactionSide::Parent => joint.parent,
    };
    let root = format!("{}_on_{}_in_{}", joint.name, multibody.bodies[body].name, multibody.bodies[report.frame].name);
    ["fx", "fy", "fz", "mx", "my", "mz", "px", "py", "pz"].iter().map(|s| format!("{root}_{s}")).collect()
}
