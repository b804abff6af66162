//! Single causes: which one model deficiency, changed alone, best explains the difference
//! between the initial model's and the measured knee moments (METHOD.md §8). The candidates
//! ([`Cause`]): L_ts, L_opt, F_max or α_opt of one estimated muscle ([`CANDIDATE_PARAMETERS`];
//! a factor within [0.5, 1.5] of the model's value, α_opt within ±[`PENNATION_CHANGE`] of it),
//! L_ts, L_opt or F_max of a muscle group together (`cause_group.rs`), the knee's axis moved
//! (`cause_axis.rs`), and the protocol's deficiencies of `cause_protocol.rs` (an offset of a
//! recorded angle, an activation level, an offset of the measured moments). Each is fitted by
//! least squares on the moments in its one variable (two for the axis) and the candidates are
//! ranked by the RMS error left; `cause_verdict.rs` says whether that names a cause. Each fit
//! stops where the local model sees no more than 10⁻¹⁰ of the cost left to gain (with noisy
//! moments the step test alone would crawl on at steps the rounding of the moments decides).

use nalgebra::DMatrix;
use serde::Serialize;

use super::cause_axis::{axis_candidate, AxisMove};
use super::cause_group::muscle_groups;
use super::cause_protocol::{protocol_candidates, MomentOffsetCandidate};
use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::{MuscleParameters, Parameter};
use super::trials::{root_mean_square, Direction, DynamometryData};
use crate::model::ModelSpec;
use crate::solvers::{Bounds, LeastSquares, LeastSquaresOptions, LeastSquaresProblem};

/// Stopping rules of each candidate's fit (the cost test as in the rest-curve and Garner & Pandy
/// fits).
const CANDIDATE_FIT: LeastSquaresOptions = LeastSquaresOptions { step_tolerance: 1e-10, gradient_tolerance: 1e-14, cost_tolerance: 1e-10, max_iterations: 200 };

/// The parameters tried per estimated muscle: the two the fit estimates, the strength F_max,
/// whose change they cannot mimic across the angles, and the pennation α_opt (the four muscle
/// properties of the thesis' sensitivity analysis but v_max, which isometric trials do not see).
pub const CANDIDATE_PARAMETERS: [Parameter; 4] = [Parameter::TendonSlackLength, Parameter::OptimalFiberLength, Parameter::MaxIsometricForce, Parameter::PennationAngleAtOptimal];

/// The parameters tried per muscle group, one factor on every member's value (a pennation
/// angle, absent in some members, has no common factor).
pub const GROUP_PARAMETERS: [Parameter; 3] = [Parameter::TendonSlackLength, Parameter::OptimalFiberLength, Parameter::MaxIsometricForce];

/// The largest change of α_opt tried, rad (20°).
pub const PENNATION_CHANGE: f64 = 0.349_065_850_398_865_9;

/// A candidate model deficiency.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind")]
pub enum Cause {
    /// One estimated muscle's parameter (value in m; F_max in N).
    Muscle { muscle: String, parameter: Parameter },
    /// The parameter of every muscle of a group (`cause_group.rs`) scaled by one factor (the
    /// value; the model's is 1).
    Group { group: String, muscles: Vec<String>, parameter: Parameter },
    /// The rotation centre of `joint` moved perpendicular to its axis by the value (mm; the
    /// model's is 0), the bones unchanged at rest (`cause_axis.rs`; the move is the fit's
    /// [`AxisMove`]).
    AxisOffset { joint: String },
    /// A constant offset of a trial coordinate: the model is posed at the recorded angle plus
    /// the value (degrees; the data's value is 0).
    AngleOffset { coordinate: String },
    /// The agonists of one direction (`None`: of every trial) activated at the value times
    /// their recorded activation (the data's value is 1).
    Activation { direction: Option<Direction> },
    /// One agonist activated at the value times its recorded activation (the data's value is 1).
    MuscleActivation { muscle: String },
    /// Every measured moment offset by the value (N·m; the data's value is 0) from the knee's.
    MomentOffset,
}

impl Cause {
    /// The muscle a muscle parameter belongs to.
    pub fn muscle(&self) -> Option<&str> {
        match self {
            Cause::Muscle { muscle, .. } => Some(muscle),
            _ => None,
        }
    }

    /// e.g. `vas_lat_r L_ts`, `knee_angle_r offset`, `extension agonists' activation`.
    pub fn describe(&self) -> String {
        match self {
            Cause::Muscle { muscle, parameter } => format!("{muscle} {}", parameter.symbol()),
            Cause::Group { group, parameter, .. } => format!("{group} {} together", parameter.symbol()),
            Cause::AxisOffset { joint } => format!("{joint} axis moved"),
            Cause::AngleOffset { coordinate } => format!("{coordinate} offset"),
            Cause::Activation { direction: Some(direction) } => format!("{} agonists' activation", direction.key()),
            Cause::Activation { direction: None } => "every trial's agonists' activation".to_string(),
            Cause::MuscleActivation { muscle } => format!("{muscle} activation"),
            Cause::MomentOffset => "measured moment offset".to_string(),
        }
    }

    /// `initial → fitted` with the change, in the cause's unit (α_opt in degrees).
    pub fn change(&self, initial: f64, fitted: f64) -> String {
        match self {
            Cause::AngleOffset { .. } => format!("{initial:+.3}° → {fitted:+.3}°"),
            Cause::MomentOffset => format!("{initial:+.3} N·m → {fitted:+.3} N·m"),
            Cause::AxisOffset { .. } => format!("{initial:.3} mm → {fitted:.3} mm"),
            Cause::Muscle { parameter: Parameter::PennationAngleAtOptimal, .. } => {
                let [initial, fitted] = [initial.to_degrees(), fitted.to_degrees()];
                format!("{initial:.3}° → {fitted:.3}° ({:+.3}°)", fitted - initial)
            }
            _ => format!("{initial:.6} → {fitted:.6} ({:+.2} %)", 100.0 * (fitted / initial - 1.0)),
        }
    }

    /// A standard error `sd` of the value `fitted`, in the unit [`Cause::change`] shows it (a
    /// muscle parameter or factor: % of the value).
    pub fn spread(&self, fitted: f64, sd: f64) -> String {
        if !sd.is_finite() {
            return "± ∞ (the moments do not fix it)".to_string();
        }
        match self {
            Cause::AngleOffset { .. } => format!("± {sd:.3}°"),
            Cause::MomentOffset => format!("± {sd:.3} N·m"),
            Cause::AxisOffset { .. } => format!("± {sd:.3} mm"),
            Cause::Muscle { parameter: Parameter::PennationAngleAtOptimal, .. } => format!("± {:.3}°", sd.to_degrees()),
            _ => format!("± {:.2} %", 100.0 * sd / fitted.abs()),
        }
    }
}

/// One candidate cause after its fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SingleCause {
    #[serde(flatten)]
    pub cause: Cause,
    /// The model's (or the data's) value and the fitted one, in the cause's unit.
    pub initial: f64,
    pub fitted: f64,
    /// RMS of M_mod − M_meas before and after, N·m.
    pub rms_before: f64,
    pub rms_after: f64,
    /// Whether the fit ended at a minimum ([`at_minimum`](crate::solvers::LeastSquaresStatus::at_minimum)).
    pub at_minimum: bool,
    /// The number of values fitted (1; 2 for an axis moved in its plane).
    pub variables: usize,
    /// An axis cause's fitted move.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis_move: Option<AxisMove>,
    /// The fitted value's standard deviation per N·m of moment noise, in the value's unit (the
    /// candidate's least-squares fit linearised at its result; an axis: its move's, mm, along the
    /// least certain direction); ∞ where the moments do not fix it.
    pub unit_noise_sd: f64,
    /// M_mod − M_meas of every trial with the cause fitted, N·m (for figures; not reported).
    #[serde(skip)]
    pub residuals: Vec<f64>,
}

impl SingleCause {
    /// The fitted value's standard error at moment noise σ (N·m), in the value's unit.
    pub fn standard_error(&self, noise_sd: f64) -> f64 {
        noise_sd * self.unit_noise_sd
    }

    /// `initial → fitted` with the change ([`Cause::change`]), and an axis move's components.
    pub fn change(&self) -> String {
        let change = self.cause.change(self.initial, self.fitted);
        match &self.axis_move {
            Some(m) => format!("{change} by ({:+.3}, {:+.3}, {:+.3}) mm in its parent frame", m.in_parent[0], m.in_parent[1], m.in_parent[2]),
            None => change,
        }
    }
}

/// Every (muscle, parameter) candidate fitted alone from `initial`, best first.
pub fn single_causes(model: &KneeMomentModel, initial: &[MuscleParameters], measured: &[f64]) -> Result<Vec<SingleCause>, FunctionalError> {
    let moments = model.moments(initial)?;
    let mut causes = muscle_causes(model, initial, &moments, measured)?;
    sort_causes(&mut causes);
    Ok(causes)
}

/// Every candidate — the muscles' and the muscle groups' parameters and the protocol's
/// deficiencies — fitted alone from `initial` on `data` (whose knee-moment model is `model`),
/// best first.
pub fn candidate_causes(spec: &ModelSpec, model: &KneeMomentModel, data: &DynamometryData, initial: &[MuscleParameters], measured: &[f64]) -> Result<Vec<SingleCause>, FunctionalError> {
    let moments = model.moments(initial)?;
    let mut causes = muscle_causes(model, initial, &moments, measured)?;
    let rms_before = initial_rms(&moments, measured);
    let every_trial = vec![true; measured.len()];
    let names: Vec<String> = initial.iter().map(|p| p.name.clone()).collect();
    for (group, members) in muscle_groups(data, &names) {
        for parameter in GROUP_PARAMETERS {
            let fit = fit_candidate(MuscleCandidate::new(model, initial, members.clone(), parameter, &moments, measured)?, &every_trial)?;
            let cause = Cause::Group { group: group.clone(), muscles: members.iter().map(|&e| names[e].clone()).collect(), parameter };
            causes.push(fit.into_cause(cause, rms_before));
        }
    }
    if let Some(candidate) = axis_candidate(spec, model, data, initial, measured)? {
        let cause = candidate.cause();
        causes.push(fit_candidate(candidate, &every_trial)?.into_cause(cause, rms_before));
    }
    for candidate in protocol_candidates(spec, model, data, initial, measured) {
        let cause = candidate.cause();
        causes.push(fit_candidate(candidate, &every_trial)?.into_cause(cause, rms_before));
    }
    causes.push(fit_candidate(MomentOffsetCandidate::new(&moments, measured), &every_trial)?.into_cause(Cause::MomentOffset, rms_before));
    sort_causes(&mut causes);
    Ok(causes)
}

fn sort_causes(causes: &mut [SingleCause]) {
    causes.sort_by(|a, b| a.rms_after.total_cmp(&b.rms_after));
}

/// RMS of the initial model's errors (its `moments` against `measured`), N·m.
pub(super) fn initial_rms(moments: &[f64], measured: &[f64]) -> f64 {
    root_mean_square(moments.iter().zip(measured).map(|(m, y)| m - y))
}

/// Each estimated muscle's candidates, from the initial model's `moments`.
fn muscle_causes(model: &KneeMomentModel, initial: &[MuscleParameters], moments: &[f64], measured: &[f64]) -> Result<Vec<SingleCause>, FunctionalError> {
    let rms_before = initial_rms(moments, measured);
    let every_trial = vec![true; measured.len()];
    let mut causes = Vec::new();
    for e in 0..initial.len() {
        for parameter in CANDIDATE_PARAMETERS {
            let fit = fit_candidate(MuscleCandidate::new(model, initial, vec![e], parameter, moments, measured)?, &every_trial)?;
            causes.push(fit.into_cause(Cause::Muscle { muscle: initial[e].name.clone(), parameter }, rms_before));
        }
    }
    Ok(causes)
}

/// A cause as a model of the moment residuals in a few variables x (one but for an axis moved in
/// its plane).
pub(super) trait Candidate {
    /// The number of variables.
    fn variables(&self) -> usize {
        1
    }
    /// M_mod − M_meas of every trial at the variables x.
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError>;
    /// The bounds on each variable; x = 0 is the unchanged model.
    fn bounds(&self) -> Vec<[f64; 2]>;
    /// The cause's value at x, in its unit.
    fn value(&self, x: &[f64]) -> f64;
    /// An axis cause's move at x.
    fn axis_move(&self, _x: &[f64]) -> Option<AxisMove> {
        None
    }
}

/// The candidate for `cause` (one of `candidate_causes`' list) on `data`.
pub(super) fn candidate_for<'a>(
    cause: &Cause,
    (spec, model, data): (&'a ModelSpec, &'a KneeMomentModel, &'a DynamometryData),
    initial: &[MuscleParameters],
    moments: &[f64],
    measured: &'a [f64],
) -> Result<Box<dyn Candidate + 'a>, FunctionalError> {
    let index = |muscle: &String| initial.iter().position(|p| &p.name == muscle).ok_or_else(|| FunctionalError::all_muscles(format!("the cause's muscle {muscle} is not estimated")));
    match cause {
        Cause::Muscle { muscle, parameter } => return Ok(Box::new(MuscleCandidate::new(model, initial, vec![index(muscle)?], *parameter, moments, measured)?)),
        Cause::Group { muscles, parameter, .. } => {
            let members = muscles.iter().map(index).collect::<Result<Vec<_>, _>>()?;
            return Ok(Box::new(MuscleCandidate::new(model, initial, members, *parameter, moments, measured)?));
        }
        Cause::MomentOffset => return Ok(Box::new(MomentOffsetCandidate::new(moments, measured))),
        Cause::AxisOffset { .. } => {
            let found = axis_candidate(spec, model, data, initial, measured)?.filter(|c| &c.cause() == cause);
            return found.map(|c| Box::new(c) as Box<dyn Candidate + 'a>).ok_or_else(|| FunctionalError::all_muscles(format!("{} is not a candidate for this model", cause.describe())));
        }
        _ => {}
    }
    protocol_candidates(spec, model, data, initial, measured)
        .into_iter()
        .find(|c| &c.cause() == cause)
        .map(|c| Box::new(c) as Box<dyn Candidate + 'a>)
        .ok_or_else(|| FunctionalError::all_muscles(format!("{} is not a candidate for these trials", cause.describe())))
}

/// One candidate's fit.
pub(super) struct CandidateFit {
    /// The unchanged and the fitted value, in the cause's unit.
    pub initial: f64,
    pub value: f64,
    /// M_mod − M_meas at it for every trial, fitted or not, N·m.
    pub residuals: Vec<f64>,
    pub at_minimum: bool,
    pub variables: usize,
    pub axis_move: Option<AxisMove>,
    pub unit_noise_sd: f64,
}

impl CandidateFit {
    /// The fit as `cause`'s entry of the ranking, from the initial model's RMS error (N·m).
    fn into_cause(self, cause: Cause, rms_before: f64) -> SingleCause {
        let rms_after = root_mean_square(self.residuals.iter().copied());
        let (variables, axis_move) = (self.variables, self.axis_move);
        SingleCause { cause, initial: self.initial, fitted: self.value, rms_before, rms_after, at_minimum: self.at_minimum, variables, axis_move, unit_noise_sd: self.unit_noise_sd, residuals: self.residuals }
    }
}

/// `candidate` fitted to the trials with `fitted[t]` true, from the unchanged model.
pub(super) fn fit_candidate<C: Candidate>(candidate: C, fitted: &[bool]) -> Result<CandidateFit, FunctionalError> {
    let limits = candidate.bounds();
    let variables = candidate.variables();
    let mut problem = Masked { candidate, fitted: fitted.to_vec() };
    let mut x = vec![0.0; variables];
    let bounds = Bounds { lower: limits.iter().map(|b| b[0]).collect(), upper: limits.iter().map(|b| b[1]).collect() };
    let report = LeastSquares::new(variables, fitted.len()).minimize(&mut problem, &mut x, &bounds, &CANDIDATE_FIT);
    let unit_noise_sd = fit_spread(&mut problem, &x);
    let mut residuals = vec![0.0; fitted.len()];
    let candidate = &mut problem.candidate;
    candidate.residuals(&x, &mut residuals)?;
    let initial = candidate.value(&vec![0.0; variables]);
    Ok(CandidateFit { initial, value: candidate.value(&x), residuals, at_minimum: report.status.at_minimum(), variables, axis_move: candidate.axis_move(&x), unit_noise_sd })
}

/// The fitted value's standard deviation per N·m of independent moment noise, linearised at the
/// fit x: the variables' covariance is σ²(JᵀJ)⁻¹ (J = ∂r/∂x over the fitted trials), the
/// value's σ²·gᵀ(JᵀJ)⁻¹g with g = ∂value/∂x (central differences); an axis move's is σ² times
/// the largest eigenvalue of (JᵀJ)⁻¹ (x are mm along orthonormal directions). ∞ where JᵀJ is
/// singular (the moments do not fix the variables) or not finite.
fn fit_spread<C: Candidate>(problem: &mut Masked<C>, x: &[f64]) -> f64 {
    let (variables, trials) = (x.len(), problem.fitted.len());
    let (mut residuals, mut jacobian) = (vec![0.0; trials], DMatrix::zeros(trials, variables));
    problem.evaluate(x, &mut residuals, Some(&mut jacobian));
    let Some(covariance) = (jacobian.transpose() * &jacobian).try_inverse().filter(|c| c.iter().all(|v| v.is_finite())) else {
        return f64::INFINITY;
    };
    if problem.candidate.axis_move(x).is_some() {
        return covariance.symmetric_eigenvalues().max().max(0.0).sqrt();
    }
    let h = 1e-6;
    let gradient = nalgebra::DVector::from_fn(variables, |k, _| {
        let mut shifted = x.to_vec();
        shifted[k] = x[k] + h;
        let plus = problem.candidate.value(&shifted);
        shifted[k] = x[k] - h;
        (plus - problem.candidate.value(&shifted)) / (2.0 * h)
    });
    (gradient.transpose() * covariance * &gradient)[(0, 0)].max(0.0).sqrt()
}

impl<C: Candidate + ?Sized> Candidate for Box<C> {
    fn variables(&self) -> usize {
        (**self).variables()
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
        (**self).residuals(x, out)
    }

    fn bounds(&self) -> Vec<[f64; 2]> {
        (**self).bounds()
    }

    fn value(&self, x: &[f64]) -> f64 {
        (**self).value(x)
    }

    fn axis_move(&self, x: &[f64]) -> Option<AxisMove> {
        (**self).axis_move(x)
    }
}

/// A candidate's least-squares problem on some trials: the others' residuals count as 0.
struct Masked<C> {
    candidate: C,
    fitted: Vec<bool>,
}

impl<C: Candidate> LeastSquaresProblem for Masked<C> {
    fn variable_count(&self) -> usize {
        self.candidate.variables()
    }

    fn residual_count(&self) -> usize {
        self.fitted.len()
    }

    /// A value without equilibrium somewhere gives infinite residuals (the step is refused).
    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
        if self.candidate.residuals(x, residuals).is_err() {
            residuals.fill(f64::INFINITY);
        }
        if let Some(jacobian) = jacobian {
            let h = 1e-6;
            let (mut plus, mut minus) = (vec![0.0; residuals.len()], vec![0.0; residuals.len()]);
            for k in 0..x.len() {
                let mut shifted = x.to_vec();
                shifted[k] = x[k] + h;
                let ok = self.candidate.residuals(&shifted, &mut plus).is_ok();
                shifted[k] = x[k] - h;
                let ok = ok && self.candidate.residuals(&shifted, &mut minus).is_ok();
                for (t, (p, m)) in plus.iter().zip(&minus).enumerate() {
                    jacobian[(t, k)] = if ok && self.fitted[t] { (p - m) / (2.0 * h) } else { 0.0 };
                }
            }
        }
        for (r, &fitted) in residuals.iter_mut().zip(&self.fitted) {
            if !fitted {
                *r = 0.0;
            }
        }
    }
}

/// The parameter of one muscle, or of a group's muscles together, as x = ln(factor) within
/// [ln 0.5, ln 1.5] — α_opt as x = its change in rad, within ±[`PENNATION_CHANGE`] and ≥ 0 —;
/// the other muscles' contributions stay fixed. Its value is the parameter's for one muscle,
/// the factor for a group.
struct MuscleCandidate<'a> {
    model: &'a KneeMomentModel,
    workspace: EstimatedMuscles,
    muscles: Vec<usize>,
    parameter: Parameter,
    bases: Vec<MuscleParameters>,
    /// M_mod − M_meas without these muscles' contributions, N·m.
    others: Vec<f64>,
}

impl<'a> MuscleCandidate<'a> {
    fn new(model: &'a KneeMomentModel, initial: &[MuscleParameters], muscles: Vec<usize>, parameter: Parameter, moments: &[f64], measured: &[f64]) -> Result<MuscleCandidate<'a>, FunctionalError> {
        let workspace = model.estimated_muscles(initial)?;
        let mut others: Vec<f64> = moments.iter().zip(measured).map(|(m, y)| m - y).collect();
        for &e in &muscles {
            let k = model.estimated_knee_index(e);
            for (t, other) in others.iter_mut().enumerate() {
                *other -= model.contribution(k, workspace.muscle(e), t)?;
            }
        }
        let bases = muscles.iter().map(|&e| initial[e].clone()).collect();
        Ok(MuscleCandidate { model, workspace, muscles, parameter, bases, others })
    }
}

impl Candidate for MuscleCandidate<'_> {
    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
        let x = x[0];
        out.copy_from_slice(&self.others);
        for (&e, base) in self.muscles.iter().zip(&self.bases) {
            self.workspace.set(self.model, e, &base.with(self.parameter, self.changed(base, x)))?;
            let k = self.model.estimated_knee_index(e);
            for (t, r) in out.iter_mut().enumerate() {
                *r += self.model.contribution(k, self.workspace.muscle(e), t)?;
            }
        }
        Ok(())
    }

    fn bounds(&self) -> Vec<[f64; 2]> {
        if self.parameter == Parameter::PennationAngleAtOptimal {
            let smallest = self.bases.iter().map(|b| b.pennation_angle_at_optimal).fold(f64::INFINITY, f64::min);
            return vec![[-smallest.min(PENNATION_CHANGE), PENNATION_CHANGE]];
        }
        vec![[0.5f64.ln(), 1.5f64.ln()]]
    }

    fn value(&self, x: &[f64]) -> f64 {
        match self.bases.as_slice() {
            [one] => self.changed(one, x[0]),
            _ => x[0].exp(),
        }
    }
}

impl MuscleCandidate<'_> {
    /// The parameter of `base` at x.
    fn changed(&self, base: &MuscleParameters, x: f64) -> f64 {
        match self.parameter {
            Parameter::PennationAngleAtOptimal => base.pennation_angle_at_optimal + x,
            parameter => base.get(parameter) * x.exp(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::tuning::functional::{SetSelection, TrialOptions};
    use rand::rngs::StdRng;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    use std::path::Path;

    #[test]
    fn a_moment_offset_is_known_to_sigma_over_root_n() {
        // r = M_mod − M_meas + x: JᵀJ = n, so the offset's sd is σ/√n exactly.
        let (moments, measured) = ([10.0, 20.0, 30.0, 40.0], [11.0, 19.5, 33.0, 41.0]);
        let fit = fit_candidate(MomentOffsetCandidate::new(&moments, &measured), &[true; 4]).unwrap();
        assert!((fit.unit_noise_sd - 0.5).abs() < 1e-9, "{}", fit.unit_noise_sd);
        let held = fit_candidate(MomentOffsetCandidate::new(&moments, &measured), &[true, false, true, false]).unwrap();
        assert!((held.unit_noise_sd - 0.5f64.sqrt()).abs() < 1e-9, "{}", held.unit_noise_sd);
    }

    /// r = A x − b with A's columns e₁ (on trials 0–3) and 2e₂ (on trials 4–5): a two-variable
    /// move, as an axis candidate is.
    struct LinearMove;

    impl Candidate for LinearMove {
        fn variables(&self) -> usize {
            2
        }

        fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
            out.copy_from_slice(&[x[0] - 1.0, x[0], x[0] + 1.0, x[0], 2.0 * x[1] - 1.0, 2.0 * x[1] + 1.0]);
            Ok(())
        }

        fn bounds(&self) -> Vec<[f64; 2]> {
            vec![[-10.0, 10.0]; 2]
        }

        fn value(&self, x: &[f64]) -> f64 {
            x[0].hypot(x[1])
        }

        fn axis_move(&self, x: &[f64]) -> Option<AxisMove> {
            Some(AxisMove { in_parent: [x[0], x[1], 0.0], in_child: [x[0], x[1], 0.0] })
        }
    }

    #[test]
    fn a_moves_spread_is_that_of_its_least_certain_direction() {
        // AᵀA = diag(4, 8): the move's sds are 1/2 along e₁ and 1/√8 along e₂.
        let fit = fit_candidate(LinearMove, &[true; 6]).unwrap();
        assert!((fit.unit_noise_sd - 0.5).abs() < 1e-9, "{}", fit.unit_noise_sd);
    }

    #[test]
    fn a_muscle_candidates_standard_error_covers_the_noise_free_fit_as_a_normals_does() {
        // 300 draws of σ = 5 N·m on an OpenSim subject's ten set5 moments: the interval of ±1 and
        // ±2 standard errors about each draw's L_ts holds the noise-free fit as often as a
        // normal's (68.3 and 95.4 %), though the draws scatter skewed (L_ts acts through the
        // tendon's nonlinear strain) and each draw's standard error differs.
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let options = TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() };
        let data = DynamometryData::read(&root.join("fixtures/dynamometry/hidden/hid01"), &options).unwrap();
        let spec = ModelSpec::read(&OsimDocument::read(&root.join("fixtures/golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
        let model = KneeMomentModel::new(&spec, &data).unwrap();
        let initial = model.nominal_parameters();
        let moments = model.moments(&initial).unwrap();
        let muscle = initial.iter().position(|p| p.name == "vas_lat_r").unwrap();
        let (sigma, noise) = (5.0, Normal::new(0.0, 5.0).unwrap());
        let fit_to = |measured: &[f64]| {
            let candidate = MuscleCandidate::new(&model, &initial, vec![muscle], Parameter::TendonSlackLength, &moments, measured).unwrap();
            fit_candidate(candidate, &vec![true; measured.len()]).unwrap()
        };
        let clean = data.measured_moments();
        let truth = fit_to(&clean).value;
        let mut rng = StdRng::seed_from_u64(7);
        let (mut values, mut errors) = (Vec::new(), Vec::new());
        for _ in 0..300 {
            let measured: Vec<f64> = clean.iter().map(|y| y + noise.sample(&mut rng)).collect();
            let fit = fit_to(&measured);
            values.push(fit.value);
            errors.push(sigma * fit.unit_noise_sd);
        }
        let coverage = |k: f64| values.iter().zip(&errors).filter(|(v, e)| (*v - truth).abs() <= k * *e).count() as f64 / values.len() as f64;
        // Binomial sd of 300 draws: 0.027 at 68.3 %, 0.012 at 95.4 % (3 sds allowed).
        assert!((0.60..=0.77).contains(&coverage(1.0)), "±1 SE holds the noise-free fit in {:.1} % of draws", 100.0 * coverage(1.0));
        assert!(coverage(2.0) >= 0.918, "±2 SE holds the noise-free fit in {:.1} % of draws", 100.0 * coverage(2.0));
    }
}
