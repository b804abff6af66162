//! RRA's mass-center adjustment (`RRATool::adjustCOMToReduceResiduals`): the residual actuators'
//! forces by OpenSim's `InverseDynamics` analysis at every desired-kinematics row of a time range
//! — the actuators' forces f minimising Σ (f/F_opt)² while giving the rows' accelerations —
//! averaged over time (trapezoids, divided by the range), then the chosen body's mass center
//! moved by dx = MZ/W, dz = −MX/W (W its weight; each at most 0.1 m) and each body's mass change
//! recommended in proportion to its mass so that the model's weight gains FY.

use std::path::Path;

use nalgebra::DMatrix;

use crate::analysis::analyze_states::AnalyzeStates;
use crate::analysis::external_loads::ExternalLoads;
use crate::analysis::static_optimization::{FrameProblem, Frames, Generator};
use crate::mechanics::{MotionState, MuscleGeometry};
use crate::model::ModelSpec;
use crate::solvers::qp::{DenseQp, QpSettings};

use super::ResidualReductionError;

/// The residual actuators' names, in the order of [`Residuals`]' components.
pub const RESIDUALS: [&str; 6] = ["FX", "FY", "FZ", "MX", "MY", "MZ"];
/// Largest mass-center move per axis, m.
const COM_LIMIT: f64 = 0.1;

/// Time averages of the residual actuators FX, FY, FZ (N) and MX, MY, MZ (N·m); 0 for one the
/// model lacks.
pub type Residuals = [f64; 6];

/// The mass-center move and the recommended masses.
#[derive(Debug, Clone, PartialEq)]
pub struct MassAdjustment {
    pub body: String,
    /// Moves subtracted from the mass center's x and z, m.
    pub dx: f64,
    pub dz: f64,
    /// The body's mass center before and after, m.
    pub mass_center: [[f64; 3]; 2],
    /// FY/g: the recommended change of the model's mass, kg.
    pub total_mass_change: f64,
    /// Every body's name, mass and recommended mass, kg.
    pub masses: Vec<(String, f64, f64)>,
}

/// The residuals averaged over the rows of `states` in `range` (s) (`Storage::findIndex`
/// semantics: from the row at or before its start to the row at or before its end).
pub fn average_residuals(geometry: &MuscleGeometry, generators: &[Generator], loads: Option<&ExternalLoads>, states: &mut AnalyzeStates, range: [f64; 2], file: &Path) -> Result<Residuals, ResidualReductionError> {
    let rows = states.assembled_rows(&geometry.multibody, range, 1, file)?.ok_or(ResidualReductionError::NoRows { file: file.into(), range })?;
    let columns: [Option<usize>; 6] = RESIDUALS.map(|name| generators.iter().position(|g| g.name == name));
    let mut frames = Frames::new(geometry, generators, loads, false);
    let mut samples = Vec::with_capacity(rows.len());
    for &i in &rows {
        let state = MotionState { q: &states.q[i], u: &states.u[i], udot: &states.udot[i] };
        let forces = least_stress_forces(frames.problem(&state, states.times[i]).along_allowed_motions(), states.times[i])?;
        samples.push((states.times[i], columns.map(|c| c.map_or(0.0, |c| forces[c]))));
    }
    Ok(time_average(&samples))
}

/// The forces (N or N·m) minimising Σ (f/F_opt)² = Σ x² under the frame's equalities — OpenSim's
/// `InverseDynamics` analysis (`dgglse`), with no bounds.
fn least_stress_forces(problem: FrameProblem, time: f64) -> Result<Vec<f64>, ResidualReductionError> {
    let FrameProblem { matrix, rhs, unit_forces, .. } = problem;
    let n = unit_forces.len();
    let solved = DenseQp::new(&DMatrix::from_diagonal_element(n, n, 2.0), &vec![0.0; n]).and_then(|qp| qp.with_equalities(&matrix, &rhs)).map(|qp| qp.solve(&QpSettings::default()));
    match solved {
        Ok(solution) if solution.status.is_solved() => Ok(solution.x.iter().zip(&unit_forces).map(|(x, f)| x * f).collect()),
        Ok(solution) => Err(ResidualReductionError::InverseDynamics { time, reason: format!("{:?}", solution.status) }),
        Err(error) => Err(ResidualReductionError::InverseDynamics { time, reason: error.to_string() }),
    }
}

/// `Storage::computeAverage`: each component's trapezoidal area over the samples' times divided
/// by their span (0 with a single sample).
pub fn time_average(samples: &[(f64, Residuals)]) -> Residuals {
    let (Some(first), Some(last)) = (samples.first(), samples.last()) else { return [0.0; 6] };
    let span = last.0 - first.0;
    if span <= 0.0 {
        return [0.0; 6];
    }
    let mut area = [0.0; 6];
    for pair in samples.windows(2) {
        let (dt, a, b) = (pair[1].0 - pair[0].0, &pair[0].1, &pair[1].1);
        for k in 0..6 {
            area[k] += 0.5 * dt * (a[k] + b[k]);
        }
    }
    area.map(|a| a / span)
}

/// The mass-center move of `body` (of `spec`, gravity `gravity` m/s²) that cancels the average
/// moments `residuals` and the masses that would cancel FY.
pub fn mass_adjustment(spec: &ModelSpec, body: &str, gravity: [f64; 3], residuals: &Residuals) -> Result<MassAdjustment, ResidualReductionError> {
    let adjusted = spec.bodies.iter().find(|b| b.name == body).ok_or_else(|| ResidualReductionError::NoBody(body.into()))?;
    let weight = gravity[1].abs() * adjusted.mass;
    if weight <= 0.0 {
        return Err(ResidualReductionError::Weightless(body.into()));
    }
    let dx = (residuals[5] / weight).clamp(-COM_LIMIT, COM_LIMIT);
    let dz = (-residuals[3] / weight).clamp(-COM_LIMIT, COM_LIMIT);
    let before = adjusted.mass_center;
    let after = [before[0] - dx, before[1], before[2] - dz];
    let total_mass_change = residuals[1] / gravity[1];
    let total: f64 = spec.bodies.iter().map(|b| b.mass).sum();
    let masses = spec.bodies.iter().map(|b| (b.name.clone(), b.mass, b.mass + total_mass_change * b.mass / total)).collect();
    Ok(MassAdjustment { body: body.into(), dx, dz, mass_center: [before, after], total_mass_change, masses })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Trapezoids: a line averages to its mid value, whatever the spacing.
    #[test]
    fn averages_are_trapezoidal_areas_over_the_span() {
        let line = |t: f64| [t, 2.0 * t, 0.0, 1.0, -t, 3.0];
        let samples: Vec<(f64, Residuals)> = [0.0, 0.1, 0.4, 1.0].iter().map(|&t| (t, line(t))).collect();
        let average = time_average(&samples);
        let expected = line(0.5);
        for k in 0..6 {
            assert!((average[k] - expected[k]).abs() < 1e-15, "{k}");
        }
        assert_eq!(time_average(&samples[..1]), [0.0; 6]);
    }
}
