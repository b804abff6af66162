//! The SQP iteration (see the module documentation of [`nlp`](super)).

use nalgebra::DVector;

use super::error::NlpError;
use super::hessian::HessianModel;
use super::kkt::{measure, Kkt};
use super::limits::Limits;
use super::line_search::{Correction, Counts, Search};
use super::point::Point;
use super::problem::NlpProblem;
use super::settings::{HessianMode, NlpSettings};
use super::solution::{IterationRecord, NlpMultipliers, NlpSolution, NlpStatus};
use super::steering::{direction, violation_stationarity, Direction};
use super::subproblem::{Linearisation, QpStep, Subproblem};
use crate::solvers::qp::QpSettings;

/// μ grows by this factor after each restoration step: the linearisation could not be met
/// with the step lengths μ allows (B/μ regularises the feasibility QP).
const RESTORATION_PENALTY_GROWTH: f64 = 10.0;

/// The penalty for the next iteration after an optimality step with penalty μ and QP
/// multipliers λ (Powell's update): μ is lowered towards them, to max(μ₀, 2‖λ‖∞, (μ + ‖λ‖∞)/2),
/// when the step met its linearised constraints (‖λ‖∞ < μ). A μ far above the multipliers
/// makes the merit function reject good steps along curved constraints; the steering raises it
/// again when needed.
fn relaxed_penalty(penalty: f64, step: &QpStep, settings: &NlpSettings) -> f64 {
    let largest = step.constraint_multipliers.amax();
    if largest >= penalty {
        return penalty;
    }
    penalty.min(settings.initial_penalty.max(2.0 * largest).max(0.5 * (penalty + largest)))
}

/// A sequential quadratic programming solver for one problem's sizes and bounds; its buffers
/// are reused between [`solve`](Sqp::solve) calls.
#[derive(Debug, Clone)]
pub struct Sqp {
    settings: NlpSettings,
    limits: Limits,
    subproblem: Subproblem,
    hessian: HessianModel,
    current: Point,
    trial: Point,
}

/// The state of one solve besides the iterate.
struct Progress {
    /// μ for the next QP.
    penalty: f64,
    /// μ of the last QP (recorded in the history).
    used_penalty: f64,
    lambda: DVector<f64>,
    nu: DVector<f64>,
    kkt: Option<Kkt>,
    iterations: usize,
    counts: Counts,
    history: Vec<IterationRecord>,
    exact: bool,
}

/// The step a line search follows and the merit function w·f + μ V it decreases.
struct Move<'a> {
    step: &'a DVector<f64>,
    objective_weight: f64,
    penalty: f64,
    /// The model's predicted reduction of the merit function.
    predicted: f64,
}

/// What one iteration decided.
enum Iteration {
    Continue,
    /// Retry the iteration with B = I (after a QP or line-search failure).
    Retry,
    Stop(NlpStatus),
}

impl Sqp {
    /// A solver for `problem`'s dimension, bounds and constraint bounds (read once, here).
    pub fn new<P: NlpProblem + ?Sized>(problem: &P, settings: NlpSettings) -> Result<Sqp, NlpError> {
        if let Some(name) = settings.invalid() {
            return Err(NlpError::Setting { name });
        }
        let limits = Limits::of(problem)?;
        let (n, m) = (limits.variables(), limits.constraints());
        let qp_settings = QpSettings { tolerance: settings.qp_tolerance, max_iterations: settings.qp_max_iterations, polish: true };
        Ok(Sqp {
            settings,
            subproblem: Subproblem::new(&limits, qp_settings),
            limits,
            hessian: HessianModel::new(n),
            current: Point::new(n, m),
            trial: Point::new(n, m),
        })
    }

    pub fn settings(&self) -> &NlpSettings {
        &self.settings
    }

    /// Minimises from `start` (projected onto the bounds first). Errors only for a start point
    /// of the wrong length or not finite, or a problem whose dimension differs from the one the
    /// solver was built for; every other ending is a [`NlpStatus`].
    pub fn solve<P: NlpProblem + ?Sized>(&mut self, problem: &mut P, start: &[f64]) -> Result<NlpSolution, NlpError> {
        let n = self.limits.variables();
        if problem.dimension() != n {
            return Err(NlpError::Dimension { what: "the problem", expected: n, found: problem.dimension() });
        }
        if start.len() != n {
            return Err(NlpError::Dimension { what: "the start point", expected: n, found: start.len() });
        }
        if let Some((index, &value)) = start.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(NlpError::StartPoint { index, value });
        }
        Ok(self.run(problem, start))
    }

    fn run<P: NlpProblem + ?Sized>(&mut self, problem: &mut P, start: &[f64]) -> NlpSolution {
        let (n, m) = (self.limits.variables(), self.limits.constraints());
        let exact = self.settings.hessian == HessianMode::Auto && problem.has_hessian();
        let mut progress = Progress {
            penalty: self.settings.initial_penalty,
            used_penalty: self.settings.initial_penalty,
            lambda: DVector::zeros(m),
            nu: DVector::zeros(n),
            kkt: None,
            iterations: 0,
            counts: Counts { evaluations: 1, derivatives: 0 },
            history: Vec::new(),
            exact,
        };
        self.current.x.copy_from_slice(start);
        self.limits.project(self.current.x.as_mut_slice());
        if !self.current.evaluate(problem) {
            return self.finish(NlpStatus::EvaluationFailed, progress);
        }
        progress.counts.derivatives += 1;
        if !self.current.differentiate(problem) {
            return self.finish(NlpStatus::EvaluationFailed, progress);
        }
        self.hessian.reset();
        let mut retried = false;
        loop {
            match self.iterate(problem, &mut progress, retried) {
                Iteration::Continue => retried = false,
                Iteration::Retry => retried = true,
                Iteration::Stop(status) => return self.finish(status, progress),
            }
        }
    }

    /// One SQP iteration from `self.current`.
    fn iterate<P: NlpProblem + ?Sized>(&mut self, problem: &mut P, progress: &mut Progress, retried: bool) -> Iteration {
        if progress.exact && !retried && self.hessian.exact(problem, self.current.x.as_slice(), progress.lambda.as_slice()).is_err() {
            return Iteration::Stop(NlpStatus::EvaluationFailed);
        }
        let violation = self.limits.l1_violation(self.current.constraints.iter().copied());
        let (step, restoration) = match self.direction(progress.penalty, violation) {
            Direction::Optimality { step } => (step, None),
            Direction::Restoration { step, feasibility } => (step, Some(feasibility)),
            Direction::Infeasible { step, feasibility } => {
                self.record_step(progress, &step);
                (progress.lambda, progress.nu, _) = self.violation_stationarity(&feasibility);
                return self.stop(progress, NlpStatus::LocallyInfeasible);
            }
            Direction::QpFailed if retried => return self.stop(progress, NlpStatus::QpFailed),
            Direction::QpFailed => return self.retry(),
        };
        self.record_step(progress, &step);
        if let Some(status) = self.termination(progress, &step) {
            return self.stop(progress, status);
        }
        progress.penalty = match restoration {
            Some(_) => (progress.penalty * RESTORATION_PENALTY_GROWTH).min(self.settings.max_penalty),
            None => relaxed_penalty(progress.penalty, &step, &self.settings),
        };
        let search = match &restoration {
            None => Move {
                step: &step.d,
                objective_weight: 1.0,
                penalty: step.penalty,
                predicted: -self.current.gradient.dot(&step.d) + step.penalty * (violation - step.linear_violation),
            },
            Some(feasibility) => Move { step: &feasibility.d, objective_weight: 0.0, penalty: 1.0, predicted: violation - feasibility.linear_violation },
        };
        let Some(alpha) = self.line_search(problem, progress, &search, restoration.is_none()) else {
            return if retried { self.stop(progress, NlpStatus::LineSearchFailed) } else { self.retry() };
        };
        self.advance(progress, alpha);
        Iteration::Continue
    }

    fn direction(&mut self, penalty: f64, violation: f64) -> Direction {
        let current = &self.current;
        let data = Linearisation {
            x: &current.x,
            gradient: Some(&current.gradient),
            constraints: &current.constraints,
            jacobian: &current.jacobian,
            hessian: &self.hessian.matrix,
        };
        direction(&mut self.subproblem, &self.limits, &data, penalty, violation, &self.settings)
    }

    /// The stationarity of the violation at the current point (see `steering.rs`).
    fn violation_stationarity(&self, feasibility: &QpStep) -> (DVector<f64>, DVector<f64>, f64) {
        let current = &self.current;
        let data = Linearisation {
            x: &current.x,
            gradient: None,
            constraints: &current.constraints,
            jacobian: &current.jacobian,
            hessian: &self.hessian.matrix,
        };
        violation_stationarity(&self.limits, &data, feasibility)
    }

    /// Keeps the step's penalty and multipliers and the KKT measures they give at x.
    fn record_step(&self, progress: &mut Progress, step: &QpStep) {
        progress.penalty = step.penalty;
        progress.used_penalty = step.penalty;
        progress.lambda.copy_from(&step.constraint_multipliers);
        progress.nu.copy_from(&step.bound_multipliers);
        let c = &self.current;
        progress.kkt = Some(measure(&self.limits, &c.x, &c.gradient, &c.constraints, &c.jacobian, &progress.lambda, &progress.nu));
    }

    /// Converged, a small step at a feasible point, or the iteration limit.
    fn termination(&self, progress: &Progress, step: &QpStep) -> Option<NlpStatus> {
        let kkt = progress.kkt.expect("measured before");
        let settings = &self.settings;
        let feasible = kkt.violation <= settings.feasibility_tolerance;
        if feasible && kkt.stationarity <= settings.tolerance && kkt.complementarity <= settings.tolerance {
            return Some(NlpStatus::Converged);
        }
        if feasible && self.current.objective <= settings.objective_target {
            return Some(NlpStatus::ObjectiveTarget);
        }
        if feasible && self.stalled(progress) {
            return Some(NlpStatus::ObjectiveStalled);
        }
        if feasible && step.d.amax() <= settings.step_tolerance * self.current.x.amax().max(1.0) {
            return Some(NlpStatus::AcceptableStep);
        }
        (progress.iterations >= settings.max_iterations).then_some(NlpStatus::MaxIterations)
    }

    /// Whether f moved by at most `stall_tolerance` · |f| over `stall_iterations` steps.
    fn stalled(&self, progress: &Progress) -> bool {
        let n = self.settings.stall_iterations;
        let f = self.current.objective;
        // history[k] holds iterate k; the current iterate m = history.len() is not in it yet.
        let m = progress.history.len();
        n > 0 && m >= n && (progress.history[m - n].objective - f).abs() <= self.settings.stall_tolerance * f.abs()
    }

    /// The line search along `search.step` (second-order correction only for an optimality
    /// step); `self.trial` holds the accepted point.
    fn line_search<P: NlpProblem + ?Sized>(&mut self, problem: &mut P, progress: &mut Progress, search: &Move, correctable: bool) -> Option<f64> {
        let Sqp { settings, limits, subproblem, hessian, current, trial } = self;
        let line = Search {
            limits,
            current,
            step: search.step,
            objective_weight: search.objective_weight,
            penalty: search.penalty,
            predicted: search.predicted.max(0.0),
            armijo: settings.armijo,
            max_backtracks: settings.max_backtracks,
        };
        let mut correct = |constraints: &DVector<f64>| {
            let mut shifted = constraints.clone();
            shifted.gemv(-1.0, &current.jacobian, search.step, 1.0);
            let data = Linearisation {
                x: &current.x,
                gradient: Some(&current.gradient),
                constraints: &shifted,
                jacobian: &current.jacobian,
                hessian: &hessian.matrix,
            };
            subproblem.solve(limits, &data, search.penalty).map(|corrected| corrected.d)
        };
        let correction: Option<Correction> =
            if settings.second_order_correction && correctable { Some(&mut correct) } else { None };
        line.run(problem, trial, &mut progress.counts, correction)
    }

    /// Moves to the accepted trial point: BFGS update, history, swap.
    fn advance(&mut self, progress: &mut Progress, alpha: f64) {
        let s = &self.trial.x - &self.current.x;
        if !progress.exact {
            let mut y = &self.trial.gradient - &self.current.gradient;
            y.gemv_tr(1.0, &self.trial.jacobian, &progress.lambda, 1.0);
            y.gemv_tr(-1.0, &self.current.jacobian, &progress.lambda, 1.0);
            self.hessian.bfgs_update(&s, &y);
        }
        let mut record = self.record(progress);
        record.step_norm = s.amax();
        record.step_length = alpha;
        progress.history.push(record);
        progress.iterations += 1;
        progress.kkt = None;
        std::mem::swap(&mut self.current, &mut self.trial);
    }

    fn retry(&mut self) -> Iteration {
        self.hessian.reset();
        Iteration::Retry
    }

    fn stop(&self, progress: &mut Progress, status: NlpStatus) -> Iteration {
        let record = self.record(progress);
        progress.history.push(record);
        Iteration::Stop(status)
    }

    /// The record of the current iterate (no step yet).
    fn record(&self, progress: &Progress) -> IterationRecord {
        IterationRecord {
            objective: self.current.objective,
            constraint_violation: self.limits.max_violation(self.current.constraints.as_slice()),
            kkt_error: progress.kkt.map_or(f64::NAN, |kkt| kkt.error()),
            step_norm: 0.0,
            step_length: 0.0,
            penalty: progress.used_penalty,
        }
    }

    fn finish(&self, status: NlpStatus, progress: Progress) -> NlpSolution {
        let current = &self.current;
        NlpSolution {
            status,
            x: current.x.as_slice().to_vec(),
            objective: current.objective,
            multipliers: NlpMultipliers { constraints: progress.lambda.as_slice().to_vec(), bounds: progress.nu.as_slice().to_vec() },
            iterations: progress.iterations,
            constraint_violation: self.limits.max_violation(current.constraints.as_slice()),
            kkt_error: progress.kkt.map_or(f64::NAN, |kkt| kkt.error()),
            evaluations: progress.counts.evaluations,
            derivative_evaluations: progress.counts.derivatives,
            history: progress.history,
        }
    }
}
