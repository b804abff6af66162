//! The physiological inverse approach (De Groote et al. 2009; thesis §3.2, ch. 7): the muscle
//! activations of a whole motion at once, each frame's muscle and actuator forces producing the
//! inverse-dynamics generalized forces as in static optimisation, and consecutive activations
//! bound by activation dynamics.
//!
//! Activation dynamics ȧ = (u − a)·(u/τ_a + (1 − u)/τ_d) with excitation u ∈ [0, 1] reach
//! ȧ = (1 − a)/τ_a at u = 1 and ȧ = −a/τ_d at u = 0; we bound ȧ between these, linearly in a
//! (for a > τ_a/(τ_d − τ_a) the rate dips below −a/τ_d at an intermediate u, so there the lower
//! bound is conservative), so with ȧ by backward differences between solved
//! frames, (a_k − a_{k−1})/Δt, the whole problem stays convex (the "nonlinear transformation of
//! variables" of De Groote et al.: the excitation is recovered from a and ȧ afterwards). Muscles
//! pull with a·F₁, F₁ static optimisation's force at activation 1 with a rigid tendon, or with
//! the Hill model's static equilibrium force beside their compliant tendons (`contraction.rs`),
//! linearised at the last solution and solved again until the linearisation holds at the
//! solution. The rows hold exactly or, with a moment weight W, as the penalty W·Σ deviation²
//! (thesis §3.2's bi-objective form); with links between bodies they run along the motions the
//! links allow, as static optimisation's do, and the deviations are reported per coordinate. The criterion is the sum of squared controls over all
//! frames, or (thesis ch. 7) the largest muscle activation over the motion, with non-muscle
//! actuators at their squared controls and ties broken by 10⁻³ times the sum of squared
//! activations. Each solve is one sparse QP (clarabel).

mod contraction;
mod layout;

use std::path::Path;

pub use contraction::Contraction;

use super::analyze_states::{AnalyzeStates, MotionInput};
use super::external_loads::ExternalLoads;
use super::inverse_dynamics;
use super::static_optimization::{solved_rows, FrameProblem, Frames, Generator, StaticOptimizationError, StaticOptimizationSettings};
use crate::io::table::StorageTable;
use crate::mechanics::{MotionState, MuscleGeometry};
use crate::solvers::qp::QpSettings;
use contraction::Muscles;
use layout::{Anchor, FrameRows, Layout};

/// What the optimisation minimises over the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// Σ over frames and generators of the squared control.
    SumOfSquares,
    /// The largest muscle activation over the motion (thesis ch. 7).
    MinMax,
}

/// A solve's variables (controls frame-major, then the min–max bound and the deviations).
type Controls = Result<Vec<f64>, StaticOptimizationError>;

/// Weight of the sum of squared activations that breaks the min–max criterion's ties.
const TIE_BREAK: f64 = 1e-3;
/// Re-solves of the linearised Hill model at most, by default.
pub const MAX_LINEARISATIONS: usize = 30;
/// The compliant-tendon solution has settled when the Hill model's generalized forces differ from
/// the linearised rows' by at most this (N·m or N; with exact rows: they meet inverse dynamics to
/// this) and no control moved by more than [`SETTLED_STEP`] in the last re-solve.
pub const SETTLED_VIOLATION: f64 = 1e-6;
pub const SETTLED_STEP: f64 = 1e-5;
/// Where the re-solves stop converging — a step larger than [`STALLED_STEP_RATIO`] times the last
/// (seen: arm26 with DeGroote muscles by min–max, whose weak tie-break lets one activation swing
/// between two values) — the proximal term ρ‖a − a₀‖² around the controls linearised at joins
/// the criterion, ρ starting at [`PROXIMAL_WEIGHT`] and doubling at each such step. It damps
/// the swing and vanishes as the controls settle. It is not used from the start: on the walk
/// it led min–max to another, worse solution of the nonconvex problem (largest activation 1
/// instead of 0.76).
const PROXIMAL_WEIGHT: f64 = 0.01;
const STALLED_STEP_RATIO: f64 = 0.9;

/// How the analysis runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysiologicalInverseSettings {
    /// Time range, filtering, step interval and muscle physiology, as static optimisation's (its
    /// activation exponent is not used).
    pub frames: StaticOptimizationSettings,
    pub criterion: Criterion,
    /// Multiplies every muscle's τ_a and τ_d (1: the model's).
    pub time_constant_scale: f64,
    pub contraction: Contraction,
    /// W (per N²·m² or N²): skeleton dynamics as a penalty W Σ (generalized force − inverse
    /// dynamics)² added to the criterion (thesis §3.2's bi-objective form) instead of exact
    /// rows; `None`: exact.
    pub moment_weight: Option<f64>,
}

/// Controls, forces and excitations per frame.
#[derive(Debug, Clone)]
pub struct PhysiologicalInverseResult {
    pub activations: StorageTable,
    /// Force of every generator (N or N·m).
    pub forces: StorageTable,
    /// Each muscle's excitation u ∈ [0, 1] from its activation and backward-difference rate (the
    /// first frame: u = a).
    pub excitations: StorageTable,
    /// Generalized force less inverse dynamics per tracked coordinate (`<coordinate>_moment`,
    /// N·m, or `_force`, N): 0 to the solver's accuracy with exact rows, what the penalty
    /// leaves with a moment weight.
    pub deviations: StorageTable,
    /// Largest |generalized force − inverse dynamics| over the frames, N·m or N.
    pub max_violation: f64,
    /// Largest muscle activation over the motion.
    pub max_activation: f64,
    /// Σ over frames and generators of the squared control.
    pub sum_of_squares: f64,
    /// Re-solves of the linearised Hill model (0 with rigid tendons).
    pub iterations: usize,
}

/// Runs the physiological inverse approach along `motion` (read from `file`).
pub fn physiological_inverse(
    geometry: &MuscleGeometry,
    generators: &[Generator],
    motion: MotionInput,
    file: &Path,
    loads: Option<&ExternalLoads>,
    settings: &PhysiologicalInverseSettings,
) -> Result<PhysiologicalInverseResult, StaticOptimizationError> {
    let frames_settings = &settings.frames;
    let mut states = AnalyzeStates::read(&geometry.multibody, motion, file, frames_settings.lowpass_cutoff)?;
    let rows = solved_rows(&mut states, &geometry.multibody, frames_settings, file)?;
    let mut frames = Frames::new(geometry, generators, loads, frames_settings.use_muscle_physiology);
    let problems: Vec<FrameProblem> = rows
        .iter()
        .map(|&i| frames.problem(&MotionState { q: &states.q[i], u: &states.u[i], udot: &states.udot[i] }, states.times[i]).along_allowed_motions())
        .collect();
    let times: Vec<f64> = rows.iter().map(|&i| states.times[i]).collect();
    let (lower, upper) = frames.bounds();
    let row_labels = frames.tracked().iter().map(|&c| inverse_dynamics::label(&geometry.multibody, c)).collect();
    let layout = Layout { generators: generators.len(), frames: rows.len(), criterion: settings.criterion, scale: settings.time_constant_scale, moment_weight: settings.moment_weight, row_labels };
    let solve = |frame_rows: &[FrameRows], anchor: Anchor| -> Controls {
        let qp = layout.problem(generators, frame_rows, &times, [&lower, &upper], anchor);
        let no_solution = |status: String| StaticOptimizationError::NoSolution { file: file.into(), problem: "physiological inverse problem", status };
        let solution = qp.solve(&QpSettings { tolerance: 1e-9, max_iterations: 400, ..QpSettings::default() }).map_err(|e| no_solution(e.to_string()))?;
        if !solution.status.is_solved() {
            return Err(no_solution(format!("{:?}", solution.status)));
        }
        Ok(solution.x)
    };
    let mut x = solve(&problems.iter().map(FrameRows::rigid).collect::<Vec<_>>(), None)?;
    let muscles = Muscles { generators, problems: &problems, times: &times, bounds: (&lower, &upper), file };
    let (iterations, forces) = match settings.contraction {
        Contraction::RigidTendon => (0, muscles.forces(settings.contraction, &x)?),
        Contraction::CompliantTendon { max_linearisations } => settle(&muscles, &solve, &mut x, max_linearisations)?,
    };
    layout.result(generators, &deviations(&problems, &forces), &times, &x, &forces, iterations)
}

/// Re-solves the problem on the Hill model linearised at the controls `x` until it settles
/// ([`SETTLED_VIOLATION`], [`SETTLED_STEP`]), damped where it stalls ([`PROXIMAL_WEIGHT`]);
/// returns the re-solves and the forces at the settled controls, or a
/// [`StaticOptimizationError::NoSolution`] after `max_linearisations`.
fn settle(muscles: &Muscles, solve: &dyn Fn(&[FrameRows], Anchor) -> Controls, x: &mut Vec<f64>, max_linearisations: usize) -> Result<(usize, Vec<Vec<f64>>), StaticOptimizationError> {
    let (generators, frames) = (muscles.generators.len(), muscles.problems.len());
    let contraction = Contraction::CompliantTendon { max_linearisations };
    let mut forces = muscles.forces(contraction, x)?;
    let (mut mismatch, mut step, mut proximal) = (f64::INFINITY, f64::INFINITY, 0.0);
    for iteration in 1..=max_linearisations {
        let linear = muscles.linearised_rows(x, &forces)?;
        let next = solve(&linear, (proximal > 0.0).then_some((x.as_slice(), proximal)))?;
        let last = step;
        step = next[..generators * frames].iter().zip(x.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        if step > STALLED_STEP_RATIO * last {
            proximal = (2.0 * proximal).max(PROXIMAL_WEIGHT);
        }
        *x = next;
        forces = muscles.forces(contraction, x)?;
        mismatch = linearisation_error(muscles.problems, &forces, &linear, x, generators);
        if mismatch <= SETTLED_VIOLATION && step <= SETTLED_STEP {
            return Ok((iteration, forces));
        }
    }
    let status = format!("the linearised Hill model has not settled after {max_linearisations} re-solves (its generalized forces off the Hill model's by {mismatch:.3e}, last step {step:.3e})");
    Err(StaticOptimizationError::NoSolution { file: muscles.file.into(), problem: "physiological inverse problem", status })
}

/// Largest difference (N·m or N) between the generalized forces of the nonlinear `forces` (per
/// frame) and of the `linear` rows at the controls `x` (frame-major, `generators` per frame).
fn linearisation_error(problems: &[FrameProblem], forces: &[Vec<f64>], linear: &[FrameRows], x: &[f64], generators: usize) -> f64 {
    let mut largest = 0.0f64;
    for (k, ((problem, f), rows)) in problems.iter().zip(forces).zip(linear).enumerate() {
        let produced = &problem.arms * nalgebra::DVector::from_column_slice(f);
        let linearised = &rows.matrix * nalgebra::DVector::from_column_slice(&x[k * generators..(k + 1) * generators]);
        for r in 0..problem.rhs.len() {
            largest = largest.max(((produced[r] - problem.rhs[r]) - (linearised[r] - rows.rhs[r])).abs());
        }
    }
    largest
}

/// R·F − inverse dynamics (N·m or N) per frame of `problems` and tracked coordinate, with
/// generator forces `forces` (per frame); with links, the part the links' forces cannot take up
/// (the rows' deviations mapped back from the allowed motions).
fn deviations(problems: &[FrameProblem], forces: &[Vec<f64>]) -> Vec<Vec<f64>> {
    problems
        .iter()
        .zip(forces)
        .map(|(problem, f)| {
            let deviation = &problem.arms * nalgebra::DVector::from_column_slice(f) - nalgebra::DVector::from_column_slice(&problem.rhs);
            match &problem.motions {
                Some(basis) => (basis * deviation).as_slice().to_vec(),
                None => deviation.as_slice().to_vec(),
            }
        })
        .collect()
}
