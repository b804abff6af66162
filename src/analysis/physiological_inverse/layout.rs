//! The physiological inverse approach's sparse QP: every frame's controls in one vector
//! (frame-major, then the min–max bound s), each frame's generalized-force rows, the bounds
//! activation dynamics set between consecutive frames, and the tables read back from a solution.

use nalgebra::DMatrix;

use super::{Criterion, PhysiologicalInverseResult, TIE_BREAK};
use crate::analysis::static_optimization::{FrameProblem, Generator, StaticOptimizationError};
use crate::io::table::StorageTable;
use crate::solvers::{SparseQp, SparseRow};

/// One frame's rows `matrix` a = `rhs` (N·m or N; columns: generators, per unit control).
pub(super) struct FrameRows {
    pub matrix: DMatrix<f64>,
    pub rhs: Vec<f64>,
}

impl FrameRows {
    /// Static optimisation's rows: each muscle pulls with a·F₁.
    pub fn rigid(problem: &FrameProblem) -> FrameRows {
        FrameRows { matrix: problem.matrix.clone(), rhs: problem.rhs.clone() }
    }
}

/// The controls a proximal term ρ‖a − anchor‖² pulls towards, and ρ; `None`: no such term.
pub(super) type Anchor<'a> = Option<(&'a [f64], f64)>;

/// Where each control sits in the QP's variables: frame-major, then s for min–max, then (with
/// a moment weight W) each frame's row deviations e = rhs − rows·a, frame-major; `scale`
/// multiplies every muscle's time constants.
pub(super) struct Layout {
    pub generators: usize,
    pub frames: usize,
    pub criterion: Criterion,
    pub scale: f64,
    /// W (per N²·m² or N²): the rows are met in the objective's W Σ e² instead of exactly.
    pub moment_weight: Option<f64>,
    /// Each row's label, its coordinate's generalized force as inverse dynamics names it.
    pub row_labels: Vec<String>,
}

impl Layout {
    pub fn index(&self, frame: usize, generator: usize) -> usize {
        frame * self.generators + generator
    }

    /// Controls over all frames.
    pub fn controls(&self) -> usize {
        self.generators * self.frames
    }

    /// The QP over `rows` (one per frame at `times`, s), each control within [`lower`, `upper`];
    /// with an `anchor` (controls, weight ρ) the proximal term ρ‖a − anchor‖² joins the criterion.
    pub fn problem(&self, generators: &[Generator], rows: &[FrameRows], times: &[f64], [lower, upper]: [&[f64]; 2], anchor: Anchor) -> SparseQp {
        let scale = self.scale;
        let controls = self.controls();
        let deviations = usize::from(self.moment_weight.is_some()) * rows.iter().map(|r| r.rhs.len()).sum::<usize>();
        let first_deviation = controls + usize::from(self.criterion == Criterion::MinMax);
        let n = first_deviation + deviations;
        let mut qp = SparseQp { hessian: vec![2.0; n], linear: vec![0.0; n], rows: Vec::new(), lower: vec![f64::NEG_INFINITY; n], upper: vec![f64::INFINITY; n] };
        let mut deviation = first_deviation..n;
        if let Some(weight) = self.moment_weight {
            qp.hessian[first_deviation..].fill(2.0 * weight);
        }
        if let Some((anchor, weight)) = anchor {
            for (i, &a) in anchor[..controls].iter().enumerate() {
                qp.hessian[i] += 2.0 * weight;
                qp.linear[i] -= 2.0 * weight * a;
            }
        }
        for (k, frame) in rows.iter().enumerate() {
            for j in 0..self.generators {
                let i = self.index(k, j);
                (qp.lower[i], qp.upper[i]) = (lower[j], upper[j]);
                if self.criterion == Criterion::MinMax && generators[j].time_constants().is_some() {
                    qp.hessian[i] = 2.0 * TIE_BREAK;
                    qp.rows.push(SparseRow { entries: vec![(i, 1.0), (controls, -1.0)], lower: f64::NEG_INFINITY, upper: 0.0 });
                }
            }
            for (r, &demand) in frame.rhs.iter().enumerate() {
                let mut entries: Vec<(usize, f64)> = (0..self.generators).map(|j| (self.index(k, j), frame.matrix[(r, j)])).filter(|&(_, a)| a != 0.0).collect();
                entries.extend(deviation.next().map(|e| (e, 1.0)));
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

    /// The tables of controls `x`, with `forces` (per frame, per generator; N or N·m) what the
    /// generators apply at them, `deviations` (per frame, per row; N·m or N) their generalized
    /// forces less inverse dynamics and `iterations` the linearised re-solves behind them.
    pub fn result(
        &self,
        generators: &[Generator],
        deviations: &[Vec<f64>],
        times: &[f64],
        x: &[f64],
        forces: &[Vec<f64>],
        iterations: usize,
    ) -> Result<PhysiologicalInverseResult, StaticOptimizationError> {
        let scale = self.scale;
        let control = |k: usize, j: usize| x[self.index(k, j)];
        let (mut activation_rows, mut force_rows, mut excitations, mut deviation_rows) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut max_activation, mut sum_of_squares) = (0.0f64, 0.0);
        for k in 0..self.frames {
            let a: Vec<f64> = (0..self.generators).map(|j| control(k, j)).collect();
            sum_of_squares += a.iter().map(|c| c * c).sum::<f64>();
            activation_rows.push(times[k]);
            activation_rows.extend(&a);
            force_rows.push(times[k]);
            force_rows.extend(&forces[k]);
            deviation_rows.push(times[k]);
            deviation_rows.extend(&deviations[k]);
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
            activations: StorageTable::new("Physiological Inverse Approach", names.clone(), activation_rows)?.with_in_degrees(false),
            forces: StorageTable::new("ModelForces", names, force_rows)?.with_in_degrees(false),
            excitations: StorageTable::new("Excitations", muscles, excitations)?.with_in_degrees(false),
            deviations: StorageTable::new("Generalized forces less inverse dynamics", std::iter::once("time".to_string()).chain(self.row_labels.iter().cloned()).collect(), deviation_rows)?.with_in_degrees(false),
            max_violation: deviations.iter().flatten().fold(0.0, |m: f64, d| m.max(d.abs())),
            max_activation,
            sum_of_squares,
            iterations,
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
