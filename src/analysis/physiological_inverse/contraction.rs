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

use super::layout::FrameRows;
use crate::analysis::static_optimization::{FrameProblem, Generator, StaticOptimizationError};

/// How a muscle's force follows its activation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contraction {
    /// a·F₁, F₁ static optimisation's force at activation 1: a rigid tendon, the force–velocity
    /// factor at the path's speed, no passive force (OpenSim's `use_muscle_physiology`).
    RigidTendon,
    /// F(a) of the Hill model in static equilibrium with its compliant tendon (module doc).
    CompliantTendon,
}

/// Activation step of the central differences for F′(a).
const ACTIVATION_STEP: f64 = 1e-6;

/// Each frame's forces (N or N·m) at the controls `x` (frame-major, `generators` per frame) of
/// frames `problems` at `times` (s); `file` names the motion in errors.
pub(super) fn forces(
    contraction: Contraction,
    generators: &[Generator],
    problems: &[FrameProblem],
    times: &[f64],
    x: &[f64],
    file: &std::path::Path,
) -> Result<Vec<Vec<f64>>, StaticOptimizationError> {
    let n = generators.len();
    problems
        .iter()
        .enumerate()
        .map(|(k, problem)| {
            let a = &x[k * n..(k + 1) * n];
            match contraction {
                Contraction::RigidTendon => Ok(a.iter().zip(&problem.unit_forces).map(|(c, f)| c * f).collect()),
                Contraction::CompliantTendon => {
                    generators.iter().zip(a).zip(&problem.lengths).map(|((g, &c), &length)| force(g, c, length, times[k], file)).collect()
                }
            }
        })
        .collect()
}

/// Each frame's rows with the compliant-tendon forces linearised at the controls `x`
/// (frame-major): the columns F′(a₀)·R, the right-hand side less R·(F(a₀) − F′(a₀)·a₀), R the
/// generalized forces per unit force. Actuators stay linear. `bounds` are each generator's
/// [lower, upper] control bounds.
pub(super) fn linearised_rows(
    generators: &[Generator],
    problems: &[FrameProblem],
    times: &[f64],
    x: &[f64],
    bounds: (&[f64], &[f64]),
    file: &std::path::Path,
) -> Result<Vec<FrameRows>, StaticOptimizationError> {
    let n = generators.len();
    problems
        .iter()
        .enumerate()
        .map(|(k, problem)| {
            let mut rows = FrameRows { matrix: problem.arms.clone(), rhs: problem.rhs.clone() };
            for (j, generator) in generators.iter().enumerate() {
                let a = x[k * n + j];
                let (value, slope) = match generator.muscle_path() {
                    Some(_) => {
                        let (low, high) = ((a - ACTIVATION_STEP).max(bounds.0[j].max(0.0)), (a + ACTIVATION_STEP).min(bounds.1[j].min(1.0)));
                        let at = |c: f64| force(generator, c, problem.lengths[j], times[k], file);
                        let slope = if high > low { (at(high)? - at(low)?) / (high - low) } else { 0.0 };
                        (at(a)?, slope)
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
            Ok(rows)
        })
        .collect()
}

/// `generator`'s equilibrium force at control `control` on a path of length `length` (m), at
/// `time` (s) of the motion `file`; its failure names both.
fn force(generator: &Generator, control: f64, length: f64, time: f64, file: &std::path::Path) -> Result<f64, StaticOptimizationError> {
    generator
        .equilibrium_force(control, length)
        .map_err(|error| StaticOptimizationError::Model(format!("{}: at t = {time} s, {} has no static equilibrium: {error}", file.display(), generator.name)))
}
