//! How a muscle's force follows its activation in the physiological inverse approach, and the
//! linearisation of the Hill model that keeps each solve a QP (De Groote et al. 2009; thesis
//! §3.2: "contraction dynamics imposed by a linearized Hill-model, neglecting muscle fibre
//! contraction speed").
//!
//! With [`Contraction::CompliantTendon`] a muscle pulls with F(a), its tendon force with the
//! fiber in static equilibrium (zero fiber velocity) beside its compliant tendon at the frame's
//! path length — passive fiber force included. F is nonlinear in a (the fiber shortens as the
//! tendon stretches), so the rows are linearised at the current controls a₀,
//! F(a) ≈ F(a₀) + F′(a₀)(a − a₀), F′ by central differences within the control's bounds.
//!
//! Taking the fiber velocities from the fiber lengths of the last solution instead (central
//! differences between frames) was tried: on the walk the re-solves diverge within four
//! (the velocities change by 0.3, 2 and 9 m/s), as an explicit step through the stiff
//! fiber–tendon dynamics would — that needs the fiber lengths as variables of one problem.

use std::path::Path;

use super::layout::FrameRows;
use crate::analysis::static_optimization::{FrameProblem, Generator, StaticOptimizationError};

/// How a muscle's force follows its activation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contraction {
    /// a·F₁, F₁ static optimisation's force at activation 1: a rigid tendon, the force–velocity
    /// factor at the path's speed, no passive force (OpenSim's `use_muscle_physiology`).
    RigidTendon,
    /// F(a) of the Hill model in static equilibrium with its compliant tendon (module doc),
    /// linearised and solved again at most `max_linearisations` times.
    CompliantTendon { max_linearisations: usize },
}

/// Activation step of the central differences for F′(a).
const ACTIVATION_STEP: f64 = 1e-6;

/// What the muscle forces are evaluated with: the generators, the frames at `times` (s), each
/// generator's control bounds and the motion `file` errors name.
pub(super) struct Muscles<'a> {
    pub generators: &'a [Generator],
    pub problems: &'a [FrameProblem],
    pub times: &'a [f64],
    pub bounds: (&'a [f64], &'a [f64]),
    pub file: &'a Path,
}

impl Muscles<'_> {
    /// Each frame's forces (N or N·m, per generator) at the controls `x` (frame-major, then
    /// anything else) by `contraction`.
    pub fn forces(&self, contraction: Contraction, x: &[f64]) -> Result<Vec<Vec<f64>>, StaticOptimizationError> {
        let n = self.generators.len();
        self.problems
            .iter()
            .enumerate()
            .map(|(k, problem)| {
                let a = &x[k * n..(k + 1) * n];
                match contraction {
                    Contraction::RigidTendon => Ok(a.iter().zip(&problem.unit_forces).map(|(c, f)| c * f).collect()),
                    Contraction::CompliantTendon { .. } => (0..n).map(|j| self.force(k, j, a[j])).collect(),
                }
            })
            .collect()
    }

    /// Each frame's rows with the muscle forces linearised at the controls `x` (frame-major),
    /// whose forces `forces` holds ([`Muscles::forces`]): the columns F′(a₀)·R, the right-hand
    /// side less R·(F(a₀) − F′(a₀)·a₀), R the generalized forces per unit force. Actuators stay
    /// linear.
    pub fn linearised_rows(&self, x: &[f64], forces: &[Vec<f64>]) -> Result<Vec<FrameRows>, StaticOptimizationError> {
        let n = self.generators.len();
        let mut all = Vec::with_capacity(self.problems.len());
        for (k, problem) in self.problems.iter().enumerate() {
            let mut rows = FrameRows { matrix: problem.arms.clone(), rhs: problem.rhs.clone() };
            for (j, generator) in self.generators.iter().enumerate() {
                let a = x[k * n + j];
                let (value, slope) = match generator.muscle_path() {
                    Some(_) => {
                        let [lowest, highest] = self.range(j);
                        let (low, high) = ((a - ACTIVATION_STEP).max(lowest), (a + ACTIVATION_STEP).min(highest));
                        let slope = if high > low { (self.force(k, j, high)? - self.force(k, j, low)?) / (high - low) } else { 0.0 };
                        (forces[k][j], slope)
                    }
                    None => (a * problem.unit_forces[j], problem.unit_forces[j]),
                };
                let offset = value - slope * a;
                for r in 0..rows.rhs.len() {
                    let arm = problem.arms[(r, j)];
                    rows.rhs[r] -= arm * offset;
                    rows.matrix[(r, j)] = arm * slope;
                }
            }
            all.push(rows);
        }
        Ok(all)
    }

    /// The activations muscle `j` is evaluated at: its control bounds within [0, 1].
    fn range(&self, j: usize) -> [f64; 2] {
        [self.bounds.0[j].max(0.0), self.bounds.1[j].min(1.0)]
    }

    /// The equilibrium force of generator `j` at frame `k` and control `control`, clamped to its
    /// range (the QP's solution may leave a bound by its tolerance); a failure names the muscle,
    /// the time and the motion.
    fn force(&self, k: usize, j: usize, control: f64) -> Result<f64, StaticOptimizationError> {
        let generator = &self.generators[j];
        let [lowest, highest] = self.range(j);
        let control = if generator.muscle_path().is_some() { control.clamp(lowest, highest.max(lowest)) } else { control };
        generator.equilibrium_force(control, self.problems[k].lengths[j]).map_err(|error| {
            StaticOptimizationError::Model(format!("{}: at t = {} s, {} has no static equilibrium: {error}", self.file.display(), self.times[k], generator.name))
        })
    }
}
