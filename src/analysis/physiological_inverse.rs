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
//! pull with a·F₁, F₁ static optimisation's force at activation 1 with a rigid tendon. The
//! criterion is the sum of squared controls over all frames, or (thesis ch. 7) the largest
//! muscle activation over the motion, with non-muscle actuators at their squared controls and
//! ties broken by 10⁻³ times the sum of squared activations. One sparse QP (clarabel).

use std::path::Path;

use super::analyze_states::AnalyzeStates;
use super::external_loads::ExternalLoads;
use super::static_optimization::{solved_rows, FrameProblem, Frames, Generator, StaticOptimizationError, StaticOptimizationSettings};
use crate::io::table::StorageTable;
use crate::mechanics::{MotionState, MuscleGeometry};
use crate::solvers::qp::QpSettings;
use crate::solvers::{SparseQp, SparseRow};

/// What the optimisation minimises over the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// Σ over frames and generators of the squared control.
    SumOfSquares,
    /// The largest muscle activation over the motion (thesis ch. 7).
    MinMax,
}

/// Weight of the sum of squared activations that breaks the min–max criterion's ties.
const TIE_BREAK: f64 = 1e-3;

/// How the analysis runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysiologicalInverseSettings {
    /// Time range, filtering, step interval and muscle physiology, as static optimisation's (its
    /// activation exponent is not used).
    pub frames: StaticOptimizationSettings,
    pub criterion: Criterion,
    /// Multiplies every muscle's τ_a and τ_d (1: the model's).
    pub time_constant_scale: f64,
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
    /// Largest |generalized force − inverse dynamics| over the frames, N·m or N.
    pub max_violation: f64,
    /// Largest muscle activation over the motion.
    pub max_activation: f64,
    /// Σ over frames and generators of the squared control.
    pub sum_of_squares: f64,
}

/// Runs the physiological inverse approach over the coordinates in `table` (read from `file`).
pub fn physiological_inverse(
    geometry: &MuscleGeometry,
    generators: &[Generator],
    table: &StorageTable,
    file: &Path,
    loads: Option<&ExternalLoads>,
    settings: &PhysiologicalInverseSettings,
) -> Result<PhysiologicalInverseResult, StaticOptimizationError> {
    let frames_settings = &settings.frames;
    let states = AnalyzeStates::new(&geometry.multibody, table, file, frames_settings.lowpass_cutoff)?;
    let rows = solved_rows(&states, frames_settings, file)?;
    let mut frames = Frames::new(geometry, generators, loads, frames_settings.use_muscle_physiology);
    let problems: Vec<FrameProblem> = rows
        .iter()
        .map(|&i| frames.problem(&MotionState { q: &states.q[i], u: &states.u[i], udot: &states.udot[i] }, states.times[i]))
        .collect();
    let times: Vec<f64> = rows.iter().map(|&i| states.times[i]).collect();
    let (lower, upper) = frames.bounds();
    let layout = Layout { generators: generators.len(), frames: rows.len(), criterion: settings.criterion };
    let qp = layout.problem(generators, &problems, &times, &lower, &upper, settings.time_constant_scale);
    let no_solution = |status: String| StaticOptimizationError::NoSolution { file: file.into(), problem: "physiological inverse problem", status };
    let solution = qp.solve(&QpSettings { tolerance: 1e-9, max_iterations: 400, ..QpSettings::default() }).map_err(|e| no_solution(e.to_string()))?;
    if !solution.status.is_solved() {
        return Err(no_solution(format!("{:?}", solution.status)));
    }
    layout.result(generators, &problems, &times, &solution.x, settings.time_constant_scale)
}

/// Where each control sits in the QP's variables: frame-major, then s for min–max.
struct Layout {
    generators: usize,
    frames: usize,
    criterion: Criterion,
}

impl Layout {
    fn index(&self, frame: usize, generator: usize) -> usize {
        frame * self.generators + generator
    }

    fn problem(&self, generators: &[Generator], problems: &[FrameProblem], times: &[f64], lower: &[f64], upper: &[f64], scale: f64) -> SparseQp {
        let controls = self.generators * self.frames;
        let n = controls + usize::from(self.criterion == Criterion::MinMax);
        let mut qp = SparseQp { hessian: vec![2.0; n], linear: vec![0.0; n], rows: Vec::new(), lower: vec![f64::NEG_INFINITY; n], upper: vec![f64::INFINITY; n] };
        for (k, problem) in problems.iter().enumerate() {
            for j in 0..self.generators {
                let i = self.index(k, j);
                (qp.lower[i], qp.upper[i]) = (lower[j], upper[j]);
                if self.criterion == Criterion::MinMax && generators[j].time_constants().is_some() {
                    qp.hessian[i] = 2.0 * TIE_BREAK;
                    qp.rows.push(SparseRow { entries: vec![(i, 1.0), (controls, -1.0)], lower: f64::NEG_INFINITY, upper: 0.0 });
                }
            }
            for (r, &demand) in problem.rhs.iter().enumerate() {
                let entries = (0..self.generators).map(|j| (self.index(k, j), problem.matrix[(r, j)])).filter(|&(_, a)| a != 0.0).collect();
                qp.rows.push(SparseRow { entries, lower: demand, upper: demand });
            }
        }
        if self.criterion == Criterion::MinMax {
            (qp.hessian[controls], qp.linear[controls]) = (0.0, 1.0);
        }
        for (j, generator) in generators.iter().enumerate() {
            let Some([activation, deactivation]) = generator.time_constants() else { continue };
            for k in 1..self.frames {
                let step = times[k] - times[k - 1];
                let (now, before) = (self.index(k, j), self.index(k - 1, j));
                let rise = step / (scale * activation);
                qp.rows.push(SparseRow { entries: vec![(now, 1.0 + rise), (before, -1.0)], lower: f64::NEG_INFINITY, upper: rise });
                let fall = step / (scale * deactivation);
                qp.rows.push(SparseRow { entries: vec![(now, 1.0 + fall), (before, -1.0)], lower: 0.0, upper: f64::INFINITY });
            }
        }
        qp
    }

    fn result(&self, generators: &[Generator], problems: &[FrameProblem], times: &[f64], x: &[f64], scale: f64) -> Result<PhysiologicalInverseResult, StaticOptimizationError> {
        let control = |k: usize, j: usize| x[self.index(k, j)];
        let (mut activations, mut forces, mut excitations) = (Vec::new(), Vec::new(), Vec::new());
        let (mut max_violation, mut max_activation, mut sum_of_squares) = (0.0f64, 0.0f64, 0.0);
        for (k, problem) in problems.iter().enumerate() {
            let a: Vec<f64> = (0..self.generators).map(|j| control(k, j)).collect();
            let produced = &problem.matrix * nalgebra::DVector::from_column_slice(&a);
            max_violation = produced.iter().zip(&problem.rhs).map(|(p, d)| (p - d).abs()).fold(max_violation, f64::max);
            sum_of_squares += a.iter().map(|c| c * c).sum::<f64>();
            activations.push(times[k]);
            activations.extend(&a);
            forces.push(times[k]);
            forces.extend(a.iter().zip(&problem.unit_forces).map(|(c, f)| c * f));
            excitations.push(times[k]);
            for (j, generator) in generators.iter().enumerate() {
                let Some([activation, deactivation]) = generator.time_constants() else { continue };
                max_activation = max_activation.max(a[j]);
                let rate = if k == 0 { 0.0 } else { (a[j] - control(k - 1, j)) / (times[k] - times[k - 1]) };
                excitations.push(excitation(a[j], rate, scale * activation, scale * deactivation));
            }
        }
        let names: Vec<String> = std::iter::once("time".to_string()).chain(generators.iter().map(|g| g.name.clone())).collect();
        let muscles: Vec<String> = std::iter::once("time".to_string()).chain(generators.iter().filter(|g| g.time_constants().is_some()).map(|g| g.name.clone())).collect();
        Ok(PhysiologicalInverseResult {
            activations: StorageTable::new("Physiological Inverse Approach", names.clone(), activations)?.with_in_degrees(false),
            forces: StorageTable::new("ModelForces", names, forces)?.with_in_degrees(false),
            excitations: StorageTable::new("Excitations", muscles, excitations)?.with_in_degrees(false),
            max_violation,
            max_activation,
            sum_of_squares,
        })
    }
}

/// The excitation u with ȧ = (u − a)(c₁u + c₂), c₁ = 1/τ_a − 1/τ_d, c₂ = 1/τ_d: a root of
/// c₁u² + (c₂ − c₁a)u − (c₂a + ȧ) = 0 in [0, 1]. For a > c₂/c₁ the rate is not monotone in u and
/// two excitations give the same rate; the smaller is taken. Clamped to [0, 1] against rounding.
fn excitation(a: f64, rate: f64, activation: f64, deactivation: f64) -> f64 {
    let (c1, c2) = (1.0 / activation - 1.0 / deactivation, 1.0 / deactivation);
    let (b, c) = (c2 - c1 * a, -(c2 * a + rate));
    if c1.abs() < 1e-12 {
        return (-c / b).clamp(0.0, 1.0);
    }
    let root = (b * b - 4.0 * c1 * c).max(0.0).sqrt();
    let (low, high) = {
        let (x, y) = ((-b - root) / (2.0 * c1), (-b + root) / (2.0 * c1));
        (x.min(y), x.max(y))
    };
    let tolerance = 1e-9;
    let u = if low >= -tolerance && low <= 1.0 + tolerance { low } else { high };
    u.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The excitation reproduces the rate it was computed from, and the extreme rates map to
    /// full and zero excitation.
    #[test]
    fn excitation_inverts_activation_dynamics() {
        let (ta, td) = (0.01, 0.04);
        let dynamics = |u: f64, a: f64| (u - a) * (u / ta + (1.0 - u) / td);
        for (a, u) in [(0.2, 0.7), (0.6, 0.1), (0.05, 0.05)] {
            assert!((excitation(a, dynamics(u, a), ta, td) - u).abs() < 1e-12);
        }
        assert!((excitation(0.3, (1.0 - 0.3) / ta, ta, td) - 1.0).abs() < 1e-12);
        assert!(excitation(0.3, -0.3 / td, ta, td).abs() < 1e-12);
    }
}
