//! OpenSim's `StaticOptimization` (run by the `AnalyzeTool`): per frame, the controls a of the
//! muscles and actuators that minimise Σ |aᵢ|ᵖ (p the activation exponent, 2 by default) while their forces (aᵢ·Fᵢ, Fᵢ a muscle's active
//! force at activation 1 with a rigid tendon, or an actuator's optimal force; passive fiber
//! forces are not applied) produce the tracked accelerations with gravity and the external
//! loads, each control within its bounds.
//!
//! OpenSim constrains the forward-dynamics accelerations of the unconstrained coordinates to the
//! tracked ones; that is the same as requiring the generalized forces to equal inverse dynamics
//! at those accelerations along each unconstrained coordinate's coupling vector (`frames.rs`),
//! (and, with links between bodies, along each motion the links allow: their forces take up the
//! rest), which is what we solve:
//! for p = 2 a convex QP (clarabel, polished on its active set), else a conic programme on power
//! cones (`solvers::minimise_power_sum`), to the optimum. OpenSim solves it with IPOPT to its
//! convergence criterion (default 1e-4), so its controls sit within about that of ours.

mod frames;
mod generators;

use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, DVector};

pub(super) use frames::{FrameProblem, Frames};
pub use generators::{force_generators, generators, Generator};

use super::analyze_states::{AnalyzeStates, MotionInput, StatesError};
use super::external_loads::ExternalLoads;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MotionState, Multibody, MuscleGeometry};
use crate::solvers::minimise_power_sum;
use crate::solvers::qp::{DenseQp, QpSettings};

/// Why static optimisation cannot run.
#[derive(Debug, thiserror::Error)]
pub enum StaticOptimizationError {
    #[error("{0}")]
    Model(String),
    #[error(transparent)]
    States(#[from] StatesError),
    /// The solver found no solution (infeasible bounds, or it stopped short).
    #[error("{}: the {problem} has no solution ({status})", file.display())]
    NoSolution { file: PathBuf, problem: &'static str, status: String },
    #[error("{}: no row lies in the time range {start}–{end} s", file.display())]
    NoFrames { file: PathBuf, start: f64, end: f64 },
    #[error(transparent)]
    Table(#[from] TableError),
}

/// How the analysis runs (OpenSim's AnalyzeTool and StaticOptimization properties).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticOptimizationSettings {
    /// s: from the row at or before the start to the row at or before the end.
    pub time_range: [f64; 2],
    /// Low-pass cutoff for the coordinates, Hz (`None`: no filtering).
    pub lowpass_cutoff: Option<f64>,
    /// Solve the first and last rows and every row whose index is a multiple of this.
    pub step_interval: usize,
    /// Muscle forces from their curves (else F_max).
    pub use_muscle_physiology: bool,
    /// p of the objective Σ|aᵢ|ᵖ (> 1; OpenSim's default 2).
    pub activation_exponent: f64,
}

/// A frame whose QP has no solution within the bounds (its controls are written as NaN).
#[derive(Debug, Clone, PartialEq)]
pub struct FrameFailure {
    /// s.
    pub time: f64,
    /// How the solver ended.
    pub status: String,
}

/// Controls and forces per solved frame.
#[derive(Debug, Clone)]
pub struct StaticOptimizationResult {
    /// Control of every generator (`<name>_activation.sto` in OpenSim).
    pub activations: StorageTable,
    /// Force of every generator (N or N·m), then the external loads' records (`_force.sto`).
    pub forces: StorageTable,
    pub failures: Vec<FrameFailure>,
    /// Largest |generalized force − inverse dynamics| over the solved frames, N·m or N (with
    /// links, along an orthonormal basis of the motions they allow).
    pub max_violation: f64,
    /// The largest |G·u̇ + Ġ·u| of the tracked motion over the solved frames (m/s² or rad/s²; 0
    /// without links between bodies): how far its accelerations break the links
    /// ([`Multibody::link_accelerations`](crate::mechanics::Multibody::link_accelerations)); the
    /// controls then give the nearest accelerations that keep them.
    pub link_acceleration_error: f64,
    /// Coordinates the file lacks (held at 0, as OpenSim does).
    pub missing: Vec<String>,
    pub ignored_columns: Vec<String>,
    /// Other controls (e.g. OpenSim's) judged on our problem, per frame they have.
    pub reference: Vec<ReferenceFrame>,
}

/// Another solution's controls at one frame, judged on our problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceFrame {
    /// s.
    pub time: f64,
    /// max |Σ aⱼ·Fⱼ·Rⱼ − τ_ID|, N·m or N.
    pub violation: f64,
    /// How far its controls leave their bounds (0 when within).
    pub bound_violation: f64,
    /// Its Σ|a|ᵖ and ours.
    pub objective: f64,
    pub our_objective: f64,
}

/// Controls of another solution (a table with a column per generator, e.g. OpenSim's
/// `_activation.sto`) to judge on our problem at the frames whose times it has.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceControls<'a> {
    pub table: &'a StorageTable,
    pub file: &'a Path,
}

/// Runs static optimisation along `motion` (read from `file`).
pub fn static_optimization(
    geometry: &MuscleGeometry,
    generators: &[Generator],
    motion: MotionInput,
    file: &Path,
    loads: Option<&ExternalLoads>,
    settings: &StaticOptimizationSettings,
    reference: Option<ReferenceControls>,
) -> Result<StaticOptimizationResult, StaticOptimizationError> {
    let mut states = AnalyzeStates::read(&geometry.multibody, motion, file, settings.lowpass_cutoff)?;
    let rows = solved_rows(&mut states, &geometry.multibody, settings, file)?;
    let columns = reference.map(|r| reference_columns(r, generators)).transpose()?;
    let mut frames = Frames::new(geometry, generators, loads, settings.use_muscle_physiology);
    let bounds = frames.bounds();
    let mut judged = Vec::new();
    let (mut activations, mut forces) = (Vec::new(), Vec::new());
    let (mut failures, mut max_violation, mut link_acceleration_error) = (Vec::new(), 0.0f64, 0.0f64);
    for &i in &rows {
        let time = states.times[i];
        let state = MotionState { q: &states.q[i], u: &states.u[i], udot: &states.udot[i] };
        let other = reference.zip(columns.as_ref()).and_then(|(r, columns)| r.table.rows().find(|row| (row[0] - time).abs() <= 1e-9).map(|row| columns.iter().map(|&c| row[c]).collect::<Vec<f64>>()));
        let solved = solve(&mut frames, &bounds, settings.activation_exponent, &state, time, other.as_deref());
        judged.extend(solved.reference);
        link_acceleration_error = link_acceleration_error.max(solved.link_acceleration_error);
        match solved.failure {
            Some(status) => failures.push(FrameFailure { time, status }),
            None => max_violation = max_violation.max(solved.violation),
        }
        activations.push(time);
        activations.extend(&solved.controls);
        forces.push(time);
        forces.extend(solved.controls.iter().zip(&solved.unit_forces).map(|(a, f)| a * f));
        if let Some(loads) = loads {
            forces.extend(loads.record_values(time, frames.kinematics()));
        }
    }
    let names: Vec<String> = std::iter::once("time".to_string()).chain(generators.iter().map(|g| g.name.clone())).collect();
    let mut force_labels = names.clone();
    force_labels.extend(loads.map(ExternalLoads::record_labels).unwrap_or_default());
    Ok(StaticOptimizationResult {
        activations: StorageTable::new("Static Optimization", names, activations)?.with_in_degrees(false).with_comment("This file contains static optimization results.")?,
        forces: StorageTable::new("ModelForces", force_labels, forces)?.with_in_degrees(false),
        failures,
        max_violation,
        link_acceleration_error,
        missing: states.missing,
        ignored_columns: states.ignored_columns,
        reference: judged,
    })
}

/// The rows the AnalyzeTool solves in `settings.time_range`, their poses assembled onto the
/// links between bodies ([`AnalyzeStates::assembled_rows`]).
pub(in crate::analysis) fn solved_rows(states: &mut AnalyzeStates, multibody: &Multibody, settings: &StaticOptimizationSettings, file: &Path) -> Result<Vec<usize>, StaticOptimizationError> {
    let [start, end] = settings.time_range;
    states.assembled_rows(multibody, settings.time_range, settings.step_interval, file)?.ok_or(StaticOptimizationError::NoFrames { file: file.into(), start, end })
}

/// The column of each generator in the reference table; a missing one is an error.
fn reference_columns(reference: ReferenceControls, generators: &[Generator]) -> Result<Vec<usize>, StaticOptimizationError> {
    generators
        .iter()
        .map(|g| reference.table.column_index(&g.name).ok_or_else(|| StaticOptimizationError::Model(format!("{}: no column {} to compare", reference.file.display(), g.name))))
        .collect()
}

/// One frame's solution.
struct Solved {
    controls: Vec<f64>,
    /// Each generator's force at control 1.
    unit_forces: Vec<f64>,
    violation: f64,
    failure: Option<String>,
    reference: Option<ReferenceFrame>,
    link_acceleration_error: f64,
}

/// min Σ|a|ᵖ subject to Σ aⱼ·Fⱼ·Rⱼ = τ_ID on the tracked coordinates, a within bounds, at one
/// frame; `other`: another solution's controls there, to judge.
/// `bounds`: every generator's (min_control, max_control).
fn solve(frames: &mut Frames, bounds: &(Vec<f64>, Vec<f64>), exponent: f64, state: &MotionState, time: f64, other: Option<&[f64]>) -> Solved {
    let FrameProblem { matrix, rhs, unit_forces, link_acceleration_error, .. } = frames.problem(state, time).along_allowed_motions();
    let n = unit_forces.len();
    let (lower, upper) = bounds;
    let solved = if exponent == 2.0 {
        let (hessian, linear) = (DMatrix::from_diagonal_element(n, n, 2.0), vec![0.0; n]);
        let qp = DenseQp::new(&hessian, &linear).and_then(|qp| qp.with_equalities(&matrix, &rhs)).and_then(|qp| qp.with_bounds(lower, upper));
        qp.map(|qp| qp.solve(&QpSettings::default())).map(|s| (s.status, s.x))
    } else {
        minimise_power_sum(exponent, &matrix, &rhs, lower, upper, &QpSettings::default()).map(|s| (s.status, s.x))
    };
    let (status, x) = match solved {
        Ok(solved) => solved,
        Err(e) => return Solved { controls: vec![f64::NAN; n], unit_forces, violation: f64::INFINITY, failure: Some(e.to_string()), reference: None, link_acceleration_error },
    };
    let violation = |controls: &[f64]| (&matrix * DVector::from_column_slice(controls) - DVector::from_column_slice(&rhs)).amax();
    let objective = |controls: &[f64]| controls.iter().map(|a| a.abs().powf(exponent)).sum::<f64>();
    let reference = other.map(|a| ReferenceFrame {
        time,
        violation: violation(a),
        bound_violation: a.iter().zip(lower).zip(upper).map(|((a, l), u)| (l - a).max(a - u).max(0.0)).fold(0.0, f64::max),
        objective: objective(a),
        our_objective: objective(&x),
    });
    let failure = (!status.is_solved()).then(|| format!("{status:?}"));
    let controls = if failure.is_some() { vec![f64::NAN; n] } else { x };
    Solved { violation: violation(&controls), controls, unit_forces, failure, reference, link_acceleration_error }
}
