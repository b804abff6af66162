//! Single causes: which one parameter of one estimated muscle, changed alone, best explains
//! the difference between the initial model's and the measured knee moments. Each candidate
//! (L_ts, L_opt or F_max of each muscle, [`CANDIDATE_PARAMETERS`]) is fitted by one-dimensional least squares on the moments
//! (factor within [0.5, 1.5] of the model's value) and the candidates are ranked by the RMS
//! error left. A candidate that leaves almost nothing names the model deficiency; when none
//! does, the difference has more than one cause. Each fit stops where the local model sees no
//! more than 10⁻¹⁰ of the cost left to gain (with noisy moments the step test alone would crawl
//! on at steps the rounding of the moments decides).

use nalgebra::DMatrix;
use serde::Serialize;

use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::{MuscleParameters, Parameter};
use super::trials::root_mean_square;
use crate::solvers::{Bounds, LeastSquares, LeastSquaresOptions, LeastSquaresProblem};

/// Stopping rules of each candidate's fit (the cost test as in the rest-curve and Garner & Pandy
/// fits).
const CANDIDATE_FIT: LeastSquaresOptions = LeastSquaresOptions { step_tolerance: 1e-10, gradient_tolerance: 1e-14, cost_tolerance: 1e-10, max_iterations: 200 };

/// The parameters tried per estimated muscle: the two the fit estimates and the strength F_max,
/// whose change they cannot mimic across the angles.
pub const CANDIDATE_PARAMETERS: [Parameter; 3] = [Parameter::TendonSlackLength, Parameter::OptimalFiberLength, Parameter::MaxIsometricForce];

/// One candidate cause after its fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SingleCause {
    pub muscle: String,
    pub parameter: Parameter,
    /// The model's value and the fitted one (m; F_max in N).
    pub initial: f64,
    pub fitted: f64,
    /// RMS of M_mod − M_meas before and after, N·m.
    pub rms_before: f64,
    pub rms_after: f64,
    /// Whether the one-dimensional fit ended at a minimum ([`at_minimum`](crate::solvers::LeastSquaresStatus::at_minimum)).
    pub at_minimum: bool,
}

impl SingleCause {
    /// fitted / initial − 1.
    pub fn relative_change(&self) -> f64 {
        self.fitted / self.initial - 1.0
    }
}

/// Every (muscle, L_opt | L_ts) candidate fitted alone from `initial`, best first.
pub fn single_causes(model: &KneeMomentModel, initial: &[MuscleParameters], measured: &[f64]) -> Result<Vec<SingleCause>, FunctionalError> {
    let moments = model.moments(initial)?;
    let rms_before = root_mean_square(moments.iter().zip(measured).map(|(m, y)| m - y));
    let every_trial = vec![true; measured.len()];
    let mut causes = Vec::new();
    for e in 0..initial.len() {
        for parameter in CANDIDATE_PARAMETERS {
            let fit = fit_candidate(model, initial, &moments, (e, parameter), measured, &every_trial)?;
            causes.push(SingleCause {
                muscle: initial[e].name.clone(),
                parameter,
                initial: initial[e].get(parameter),
                fitted: fit.value,
                rms_before,
                rms_after: root_mean_square(fit.residuals.iter().copied()),
                at_minimum: fit.at_minimum,
            });
        }
    }
    causes.sort_by(|a, b| a.rms_after.total_cmp(&b.rms_after));
    Ok(causes)
}

/// One candidate's fit.
pub(super) struct CandidateFit {
    /// The fitted value, m.
    pub value: f64,
    /// M_mod − M_meas at it for every trial, fitted or not, N·m.
    pub residuals: Vec<f64>,
    pub at_minimum: bool,
}

/// Estimated muscle e's `parameter` fitted alone from `initial` (whose moments are `moments`;
/// factor within [0.5, 1.5]) to the trials with `fitted[t]` true.
pub(super) fn fit_candidate(
    model: &KneeMomentModel,
    initial: &[MuscleParameters],
    moments: &[f64],
    (e, parameter): (usize, Parameter),
    measured: &[f64],
    fitted: &[bool],
) -> Result<CandidateFit, FunctionalError> {
    let mut problem = Candidate::new(model, initial, e, parameter, moments, measured, fitted)?;
    let mut x = [0.0];
    let bounds = Bounds { lower: vec![0.5f64.ln()], upper: vec![1.5f64.ln()] };
    let report = LeastSquares::new(1, measured.len()).minimize(&mut problem, &mut x, &bounds, &CANDIDATE_FIT);
    let mut residuals = vec![0.0; measured.len()];
    problem.residuals(x[0], &mut residuals)?;
    Ok(CandidateFit { value: initial[e].get(parameter) * x[0].exp(), residuals, at_minimum: report.status.at_minimum() })
}

/// One muscle's parameter as ln(factor); the other muscles' contributions stay fixed.
struct Candidate<'a> {
    model: &'a KneeMomentModel,
    workspace: EstimatedMuscles,
    muscle: usize,
    parameter: Parameter,
    base: MuscleParameters,
    /// M_mod − M_meas without this muscle's contribution, N·m.
    others: Vec<f64>,
    /// Whether each trial is fitted (the others' residuals count as 0).
    fitted: Vec<bool>,
}

impl<'a> Candidate<'a> {
    fn new(
        model: &'a KneeMomentModel,
        initial: &[MuscleParameters],
        muscle: usize,
        parameter: Parameter,
        moments: &[f64],
        measured: &[f64],
        fitted: &[bool],
    ) -> Result<Candidate<'a>, FunctionalError> {
        let workspace = model.estimated_muscles(initial)?;
        let k = model.estimated_knee_index(muscle);
        let mut others = Vec::with_capacity(measured.len());
        for (t, (m, y)) in moments.iter().zip(measured).enumerate() {
            others.push(m - y - model.contribution(k, workspace.muscle(muscle), t)?);
        }
        Ok(Candidate { model, workspace, muscle, parameter, base: initial[muscle].clone(), others, fitted: fitted.to_vec() })
    }

    fn residuals(&mut self, log_factor: f64, out: &mut [f64]) -> Result<(), FunctionalError> {
        let changed = self.base.with(self.parameter, self.base.get(self.parameter) * log_factor.exp());
        self.workspace.set(self.model, self.muscle, &changed)?;
        let k = self.model.estimated_knee_index(self.muscle);
        for (t, r) in out.iter_mut().enumerate() {
            *r = self.others[t] + self.model.contribution(k, self.workspace.muscle(self.muscle), t)?;
        }
        Ok(())
    }
}

impl LeastSquaresProblem for Candidate<'_> {
    fn variable_count(&self) -> usize {
        1
    }

    fn residual_count(&self) -> usize {
        self.others.len()
    }

    /// A parameter without equilibrium somewhere gives infinite residuals (the step is refused).
    /// Trials not fitted have residual 0.
    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
        if self.residuals(x[0], residuals).is_err() {
            residuals.fill(f64::INFINITY);
        }
        if let Some(jacobian) = jacobian {
            let h = 1e-6;
            let (mut plus, mut minus) = (vec![0.0; residuals.len()], vec![0.0; residuals.len()]);
            let ok = self.residuals(x[0] + h, &mut plus).is_ok() && self.residuals(x[0] - h, &mut minus).is_ok();
            for (t, (p, m)) in plus.iter().zip(&minus).enumerate() {
                jacobian[(t, 0)] = if ok && self.fitted[t] { (p - m) / (2.0 * h) } else { 0.0 };
            }
        }
        for (r, &fitted) in residuals.iter_mut().zip(&self.fitted) {
            if !fitted {
                *r = 0.0;
            }
        }
    }
}
