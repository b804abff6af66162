//! Phase II of functional scaling (thesis §6.2.3, eq. 6.15–6.24): the constrained NLP that
//! moves the hot start to the (L_opt, L_ts) of every estimated muscle whose knee moments come
//! closest to the measured ones in the ∞-norm, inside the feasible sets of Phase I.
//!
//! Variables, per estimated muscle j, ρ_j = L_ts/L_opt and δ_j (eq. 6.14, 1/m), so that
//! 1/L_opt = c1·ρ + c2 + δ on the muscle's regression line; plus the epigraph t ≥ 0 of the
//! ∞-norm (N·m). Objective t² = ‖M_mod − M_meas‖²_∞ (6.16 b), the ∞-norm written as the rows
//! −t ≤ M_mod,k − M_meas,k ≤ t.
//!
//! Where the thesis keeps the normalised fiber lengths L̃m_jk as variables and relaxes the
//! equilibrium by a slack s (6.15–6.17, for KNITRO in full space), we eliminate them: every
//! evaluation solves each muscle's static equilibrium exactly (the same solver as the
//! knee-moment model, so s = 0 and the clamped slack-fiber case of OpenSim is reproduced), and
//! the constraints on L̃m become constraints on the solved states. That leaves 2n + 1
//! variables, and each muscle's rows depend only on its own two, so a derivative costs one
//! muscle's equilibria, not the whole model's. The constraints, on each muscle's agonist trials:
//! - (6.18) tendon strain within [`PhaseTwoSettings::strain_range`];
//! - (6.19) L̃m within [`PhaseTwoSettings::operating_range`];
//! - (6.20) L̃m larger by [`PhaseTwoSettings::monotonic_gap`] where the path is longer, along a
//!   chain of trials whose path lengths differ by at least 4 gaps × L_opt (closer trials would
//!   make the gap a false claim);
//! - (6.21–6.22) ρ and δ within the feasible set's bounds (variable bounds);
//! - (6.23–6.24) optionally, the L_opt ratios of the vasti and of the gastrocnemii within
//!   [`PhaseTwoSettings::group_ratio`]; off by default, since real subjects need not obey them;
//! - optionally, the rest fiber length within ±[`PhaseTwoSettings::rest_tolerance`] of its
//!   reference (the thesis uses the reference only in Phase I).
//!
//! On noisy data the SQP (damped BFGS) can crawl along a flat valley of the min–max fit, where
//! the KKT test is never met (e.g. gen03, all 70 trials: the largest error reaches 10.157 N·m by
//! iteration 20, then falls by 10⁻⁵–10⁻³ N·m per 20 iterations, KKT measure ≈ 0.1). The
//! relative stall test [`STALLED_MOMENT_ERROR`] ends such crawls: on train01, train03 and
//! gen01–19, set5 and all trials, every run ends converged, stalled or at an acceptable step, at
//! a largest error within 0.1 % of what 300 iterations reach (before it, 5 of the 42 ended at
//! `MaxIterations`). The feasibility tolerance is the data's precision, 10⁻⁶ N·m: gen19's
//! moments have a kink where rect_fem's tendon reaches its slack length, and its iterates
//! drift 10⁻⁷–10⁻⁶ N·m outside two ∞-norm rows, which a tolerance of 10⁻⁹ counted as
//! infeasible to the iteration limit. Tried and not adopted: the exact Lagrangian Hessian
//! (finite differences, 2×2 per muscle) is indefinite (eigenvalues −109 … 1.9·10⁶), so the shift
//! that makes it positive definite turns the steps gradient-like; flipping or clipping each
//! block's negative eigenvalues ends most crawls within 40–60 iterations but stops a noise-free fit at 0.2 N·m and makes two other
//! runs fail; scaling the variables to their bounds fails more often. Convexifying the exact
//! Hessian by the augmented Lagrangian instead (W + σ Σ aᵢaᵢᵀ over the rows the last QP held
//! active) fails as well: 14 of 16 runs of a sweep ended at `MaxIterations` (BFGS: 2), and with
//! the matching gradient term the elastic QP's multipliers grew with the penalty μ and W with
//! them, so the steps shrank to 10⁻⁸ at a violated linearisation. A trust region (Sℓ∞QP) is the
//! remedy left to try. Not every stop short of an exact fit is a crawl: on noise-free train01,
//! all 70 trials, the SQP ends at a KKT point (measure 10⁻⁷) with a largest error of 1.66 N·m,
//! a local minimum of the non-convex min–max problem (set5 from the same hot start fits
//! exactly); the rest-curve fit that follows by default reaches the exact fit.

use super::error::FunctionalError;
use super::feasible_set::MuscleFeasibleSet;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::MuscleParameters;
use crate::solvers::nlp::{EvaluationError, NlpProblem, NlpSettings, NlpSolution, NlpStatus, Sqp};
use nalgebra::DMatrix;

/// Iterations over which the largest moment error t is watched for a stall (20 let a brief
/// flat stretch of a crawl end gen10's fit 1.1 % above where it went on to).
const STALL_ITERATIONS: usize = 30;

/// A fit whose largest moment error t changed by at most this fraction of itself over
/// [`STALL_ITERATIONS`] has stopped (`ObjectiveStalled`): at that pace the 300 iterations allowed
/// could lower t by at most 0.1 %, e.g. 0.01 N·m of a 10 N·m error at σ = 5 N·m. Noise-free
/// fits, whose t falls towards 0 by a steady factor, never meet it.
const STALLED_MOMENT_ERROR: f64 = 1e-4;

/// Settings of the Phase II NLP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseTwoSettings {
    /// (6.19) normalised fiber length range in the agonist trials (thesis: 0.4–1.6).
    pub operating_range: [f64; 2],
    /// (6.18) tendon strain range in the agonist trials: the tendon at least slack and at most
    /// twice the strain Millard's tendon has at F_max (0.049).
    pub strain_range: [f64; 2],
    /// (6.20) least L̃m difference between chained trials (thesis: 0.005).
    pub monotonic_gap: f64,
    /// (6.23–6.24) range of the vasti's and gastrocnemii's L_opt ratios (thesis: 0.9–1.1), or none.
    pub group_ratio: Option<[f64; 2]>,
    /// Rest fiber length within ± this fraction of its reference, or not constrained.
    pub rest_tolerance: Option<f64>,
    /// A fit whose largest moment error is below this (N·m) is exact: the solve stops there
    /// (the data's printed precision is 10⁻⁶ N·m).
    pub exact_fit: f64,
    pub nlp: NlpSettings,
}

impl Default for PhaseTwoSettings {
    fn default() -> Self {
        PhaseTwoSettings {
            operating_range: [0.4, 1.6],
            strain_range: [0.0, 0.1],
            monotonic_gap: 0.005,
            group_ratio: None,
            rest_tolerance: None,
            exact_fit: 1e-5,
            nlp: NlpSettings {
                tolerance: 1e-9,
                // The data's printed precision, 10⁻⁶ N·m; the other rows are dimensionless.
                // Tighter, a fit whose moments have a kink (a tendon at its slack length, where
                // central differences straddle it) drifts 10⁻⁷–10⁻⁶ N·m outside its ∞-norm rows
                // and never counts as feasible (gen19, all trials: MaxIterations).
                feasibility_tolerance: 1e-6,
                max_iterations: 300,
                stall_iterations: STALL_ITERATIONS,
                // f = t², so a relative change of t by ε is one of f by 2ε.
                stall_tolerance: 2.0 * STALLED_MOMENT_ERROR,
                ..NlpSettings::default()
            },
        }
    }
}

/// Muscles whose L_opt the thesis ties together (eq. 6.23–6.24), by OpenSim name without side.
pub const RATIO_GROUPS: [&[&str]; 2] = [&["vas_int", "vas_lat", "vas_med"], &["med_gas", "lat_gas"]];

/// The result of Phase II.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseTwo {
    /// How the SQP ended; see [`PhaseTwo::converged`].
    pub status: NlpStatus,
    pub parameters: Vec<MuscleParameters>,
    /// max_k |M_mod,k − M_meas,k|, N·m.
    pub max_moment_error: f64,
    pub iterations: usize,
    /// The constraints (other than the ∞-norm rows) active at the solution, described.
    pub active_constraints: Vec<String>,
}

impl PhaseTwo {
    /// Whether the SQP reached a point it can vouch for: KKT met, an exact fit, or a max error
    /// that stopped changing (the min–max optimum of a fit whose parameters are not unique —
    /// the report's identifiability says which).
    pub fn converged(&self) -> bool {
        matches!(self.status, NlpStatus::Converged | NlpStatus::ObjectiveTarget | NlpStatus::ObjectiveStalled | NlpStatus::AcceptableStep)
    }
}

/// Solves Phase II from `start` (one per estimated muscle, e.g. the hot start) inside `sets`.
/// `rest_references` gives each muscle's reference rest fiber length (m) if known.
pub fn solve_phase_two(
    model: &KneeMomentModel,
    sets: &[MuscleFeasibleSet],
    start: &[MuscleParameters],
    rest_references: &[Option<f64>],
    measured: &[f64],
    settings: &PhaseTwoSettings,
) -> Result<PhaseTwo, FunctionalError> {
    let mut problem = PhaseTwoProblem::new(model, sets, start, rest_references, measured, settings)?;
    let x0 = problem.start_point(start);
    let nlp = NlpSettings { objective_target: settings.exact_fit.powi(2), ..settings.nlp };
    let solution = Sqp::new(&problem, nlp)?.solve(&mut problem, &x0)?;
    problem.result(&solution)
}

/// One muscle evaluated at its (ρ, δ): what its rows need.
#[derive(Debug, Clone, Default)]
struct MuscleEvaluation {
    /// L_opt, m.
    optimal: f64,
    /// F_t·r per trial, N·m.
    contributions: Vec<f64>,
    /// L̃m per trial.
    normalized: Vec<f64>,
    /// Tendon strain per trial.
    strain: Vec<f64>,
    /// Rest fiber length, m (NaN when no reference constrains it).
    rest: f64,
}

/// One constraint row.
#[derive(Debug, Clone, Copy)]
enum Row {
    /// M_k − t ≤ M_meas,k.
    Above(usize),
    /// M_k + t ≥ M_meas,k.
    Below(usize),
    Operating { muscle: usize, trial: usize },
    Strain { muscle: usize, trial: usize },
    Monotonic { muscle: usize, longer: usize, shorter: usize },
    Ratio { numerator: usize, denominator: usize },
    Rest { muscle: usize, reference: f64 },
}

struct PhaseTwoProblem<'a> {
    model: &'a KneeMomentModel,
    sets: &'a [MuscleFeasibleSet],
    template: Vec<MuscleParameters>,
    workspace: EstimatedMuscles,
    measured: &'a [f64],
    rows: Vec<Row>,
    bounds: (Vec<f64>, Vec<f64>),
    settings: PhaseTwoSettings,
    /// Per muscle, whether a rest-length row needs its rest state.
    has_rest_row: Vec<bool>,
    /// The evaluation at `evaluated_at`, the last x evaluated (reused by the derivatives).
    evaluations: Vec<MuscleEvaluation>,
    evaluated_at: Vec<f64>,
}

impl<'a> PhaseTwoProblem<'a> {
    fn new(
        model: &'a KneeMomentModel,
        sets: &'a [MuscleFeasibleSet],
        start: &[MuscleParameters],
        rest_references: &[Option<f64>],
        measured: &'a [f64],
        settings: &PhaseTwoSettings,
    ) -> Result<PhaseTwoProblem<'a>, FunctionalError> {
        let workspace = model.estimated_muscles(start)?;
        let mut problem = PhaseTwoProblem {
            model,
            sets,
            template: start.to_vec(),
            workspace,
            measured,
            rows: Vec::new(),
            bounds: (Vec::new(), Vec::new()),
            settings: *settings,
            has_rest_row: rest_references.iter().map(|r| r.is_some() && settings.rest_tolerance.is_some()).collect(),
            evaluations: vec![MuscleEvaluation::default(); start.len()],
            evaluated_at: Vec::new(),
        };
        problem.build_rows(rest_references);
        Ok(problem)
    }

    fn build_rows(&mut self, rest_references: &[Option<f64>]) {
        let s = self.settings;
        let mut rows = Vec::new();
        let mut bounds = (Vec::new(), Vec::new());
        let mut push = |row: Row, low: f64, high: f64| {
            rows.push(row);
            bounds.0.push(low);
            bounds.1.push(high);
        };
        for (k, &y) in self.measured.iter().enumerate() {
            push(Row::Above(k), f64::NEG_INFINITY, y);
            push(Row::Below(k), y, f64::INFINITY);
        }
        for (e, &rest_reference) in rest_references.iter().enumerate() {
            let chain = self.monotonic_chain(e);
            for trial in chain.first().into_iter().chain(chain.last()).copied() {
                push(Row::Operating { muscle: e, trial }, s.operating_range[0], s.operating_range[1]);
                push(Row::Strain { muscle: e, trial }, s.strain_range[0], s.strain_range[1]);
            }
            for pair in chain.windows(2) {
                push(Row::Monotonic { muscle: e, longer: pair[0], shorter: pair[1] }, s.monotonic_gap, f64::INFINITY);
            }
            if let (Some(tolerance), Some(reference)) = (s.rest_tolerance, rest_reference) {
                push(Row::Rest { muscle: e, reference }, -tolerance, tolerance);
            }
        }
        if let Some([low, high]) = s.group_ratio {
            for (numerator, denominator) in self.ratio_pairs() {
                push(Row::Ratio { numerator, denominator }, low, high);
            }
        }
        self.rows = rows;
        self.bounds = bounds;
    }

    /// The agonist trials of muscle `e` from the longest path to the shortest, keeping each
    /// next one only when its path is at least 4 gaps × L_opt shorter than the last kept. The
    /// first and last are the extremes of the muscle's working range.
    fn monotonic_chain(&self, e: usize) -> Vec<usize> {
        let muscle = self.model.estimated_knee_muscle(e);
        let lengths = &muscle.mt_lengths;
        let mut agonist: Vec<usize> = (0..self.model.trials().len()).filter(|&t| self.model.trials()[t].activation(&muscle.name).is_some()).collect();
        agonist.sort_by(|&a, &b| lengths[b].total_cmp(&lengths[a]));
        let spacing = 4.0 * self.settings.monotonic_gap * self.template[e].optimal_fiber_length;
        let mut chain: Vec<usize> = agonist.first().copied().into_iter().collect();
        for &t in agonist.iter().skip(1) {
            if chain.last().is_some_and(|&last| lengths[last] - lengths[t] >= spacing) {
                chain.push(t);
            }
        }
        chain
    }

    /// Pairs of estimated muscles in one of [`RATIO_GROUPS`].
    fn ratio_pairs(&self) -> Vec<(usize, usize)> {
        let base = |name: &str| name.trim_end_matches("_r").trim_end_matches("_l").to_string();
        let names: Vec<String> = self.model.estimated_names().map(base).collect();
        let mut pairs = Vec::new();
        for group in RATIO_GROUPS {
            let members: Vec<usize> = group.iter().filter_map(|g| names.iter().position(|n| n == g)).collect();
            for (i, &a) in members.iter().enumerate() {
                pairs.extend(members[i + 1..].iter().map(|&b| (a, b)));
            }
        }
        pairs
    }

    fn start_point(&self, start: &[MuscleParameters]) -> Vec<f64> {
        let (lower, upper) = self.bounds();
        let mut x: Vec<f64> = start
            .iter()
            .zip(self.sets)
            .flat_map(|(p, set)| [p.tendon_slack_length / p.optimal_fiber_length, set.line.delta(p.optimal_fiber_length, p.tendon_slack_length)])
            .collect();
        x.push(0.0);
        for ((v, l), u) in x.iter_mut().zip(&lower).zip(&upper) {
            *v = v.clamp(*l, *u);
        }
        if let Ok(moments) = self.model.moments(&self.parameters(&x)) {
            x[self.t_index()] = max_error(&moments, self.measured);
        }
        x
    }

    fn t_index(&self) -> usize {
        2 * self.template.len()
    }

    /// The muscles' parameters at x.
    fn parameters(&self, x: &[f64]) -> Vec<MuscleParameters> {
        (0..self.template.len()).map(|e| self.muscle_parameters(e, x[2 * e], x[2 * e + 1])).collect()
    }

    fn muscle_parameters(&self, e: usize, ratio: f64, delta: f64) -> MuscleParameters {
        let (optimal, slack) = self.sets[e].line.lengths(ratio, delta);
        MuscleParameters { optimal_fiber_length: optimal, tendon_slack_length: slack, ..self.template[e].clone() }
    }

    /// Fills `out` with muscle `e`'s rows' inputs at (ρ, δ), reusing its buffers.
    fn evaluate_muscle(&mut self, e: usize, ratio: f64, delta: f64, out: &mut MuscleEvaluation) -> Result<(), FunctionalError> {
        let parameters = self.muscle_parameters(e, ratio, delta);
        self.workspace.set(self.model, e, &parameters)?;
        let k = self.model.estimated_knee_index(e);
        let arms = &self.model.estimated_knee_muscle(e).moment_arms;
        out.optimal = parameters.optimal_fiber_length;
        out.contributions.clear();
        out.normalized.clear();
        out.strain.clear();
        for (t, arm) in arms.iter().enumerate() {
            let state = self.model.state(k, self.workspace.muscle(e), t)?;
            out.contributions.push(state.tendon_force * arm);
            out.normalized.push(state.normalized_fiber_length);
            out.strain.push(state.tendon_strain);
        }
        out.rest = if self.has_rest_row[e] { self.model.rest_state(e, &self.workspace)?.fiber_length } else { f64::NAN };
        Ok(())
    }

    /// Muscle `e`'s evaluation at (ρ, δ) in place of the cached one.
    fn reevaluate_muscle(&mut self, e: usize, ratio: f64, delta: f64) -> Result<(), FunctionalError> {
        let mut evaluation = std::mem::take(&mut self.evaluations[e]);
        let outcome = self.evaluate_muscle(e, ratio, delta, &mut evaluation);
        self.evaluations[e] = evaluation;
        outcome
    }

    fn moment(&self, trial: usize) -> f64 {
        self.model.fixed_moments()[trial] + self.evaluations.iter().map(|m| m.contributions[trial]).sum::<f64>()
    }

    fn row_value(&self, row: Row, t: f64) -> f64 {
        let m = &self.evaluations;
        match row {
            Row::Above(k) => self.moment(k) - t,
            Row::Below(k) => self.moment(k) + t,
            Row::Operating { muscle, trial } => m[muscle].normalized[trial],
            Row::Strain { muscle, trial } => m[muscle].strain[trial],
            Row::Monotonic { muscle, longer, shorter } => m[muscle].normalized[longer] - m[muscle].normalized[shorter],
            Row::Ratio { numerator, denominator } => m[numerator].optimal / m[denominator].optimal,
            Row::Rest { muscle, reference } => m[muscle].rest / reference - 1.0,
        }
    }

    fn fill_rows(&self, t: f64, constraints: &mut [f64]) {
        for (c, &row) in constraints.iter_mut().zip(&self.rows) {
            *c = self.row_value(row, t);
        }
    }

    fn describe(&self, row: Row, value: f64) -> Option<String> {
        let name = |e: usize| self.model.estimated_knee_muscle(e).name.clone();
        let trial = |t: usize| self.model.trials()[t].label();
        Some(match row {
            Row::Above(_) | Row::Below(_) => return None,
            Row::Operating { muscle, trial: k } => format!("{} normalised fiber length {value:.4} in {} (eq. 6.19)", name(muscle), trial(k)),
            Row::Strain { muscle, trial: k } => format!("{} tendon strain {value:.4} in {} (eq. 6.18)", name(muscle), trial(k)),
            Row::Monotonic { muscle, longer, shorter } => {
                format!("{} fiber length step {value:.4} from {} to {} (eq. 6.20)", name(muscle), trial(longer), trial(shorter))
            }
            Row::Ratio { numerator, denominator } => format!("L_opt ratio {}/{} = {value:.4} (eq. 6.23–6.24)", name(numerator), name(denominator)),
            Row::Rest { muscle, .. } => format!("{} rest fiber length off its reference by {:.2} %", name(muscle), 100.0 * value),
        })
    }

    fn result(&mut self, solution: &NlpSolution) -> Result<PhaseTwo, FunctionalError> {
        let mut constraints = vec![0.0; self.rows.len()];
        self.evaluate(&solution.x, &mut constraints).map_err(|e| FunctionalError::all_muscles(format!("Phase II solution: {}", e.message)))?;
        let moments: Vec<f64> = (0..self.measured.len()).map(|k| self.moment(k)).collect();
        let active_constraints = self
            .rows
            .iter()
            .zip(&constraints)
            .zip(&solution.multipliers.constraints)
            .filter(|(_, &lambda)| lambda.abs() > 1e-9)
            .filter_map(|((&row, &value), _)| self.describe(row, value))
            .collect();
        Ok(PhaseTwo {
            status: solution.status,
            parameters: self.parameters(&solution.x),
            max_moment_error: max_error(&moments, self.measured),
            iterations: solution.iterations,
            active_constraints,
        })
    }
}

fn max_error(moments: &[f64], measured: &[f64]) -> f64 {
    moments.iter().zip(measured).map(|(m, y)| (m - y).abs()).fold(0.0, f64::max)
}

fn evaluation_error(error: FunctionalError) -> EvaluationError {
    EvaluationError::new(error.to_string())
}

impl NlpProblem for PhaseTwoProblem<'_> {
    fn dimension(&self) -> usize {
        2 * self.template.len() + 1
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lower = Vec::with_capacity(self.dimension());
        let mut upper = Vec::with_capacity(self.dimension());
        for set in self.sets {
            lower.extend([set.ratio_bounds[0], -set.delta_max]);
            upper.extend([set.ratio_bounds[1], set.delta_max]);
        }
        lower.push(0.0);
        upper.push(f64::INFINITY);
        (lower, upper)
    }

    fn constraint_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.bounds.clone()
    }

    fn evaluate(&mut self, x: &[f64], constraints: &mut [f64]) -> Result<f64, EvaluationError> {
        self.evaluated_at.clear();
        for e in 0..self.template.len() {
            self.reevaluate_muscle(e, x[2 * e], x[2 * e + 1]).map_err(evaluation_error)?;
        }
        self.evaluated_at.extend_from_slice(x);
        let t = x[self.t_index()];
        self.fill_rows(t, constraints);
        Ok(t * t)
    }

    /// Central differences per muscle: each of its two variables moves only its own rows'
    /// inputs, so only its equilibria are recomputed; t enters linearly (exact). The cached
    /// evaluation is reused when it is at x (the solver evaluates a point before
    /// differentiating it).
    fn derivatives(&mut self, x: &[f64], gradient: &mut [f64], jacobian: &mut DMatrix<f64>) -> Result<(), EvaluationError> {
        if self.evaluated_at != x {
            self.evaluate(x, &mut vec![0.0; self.rows.len()])?;
        }
        let t = x[self.t_index()];
        // Invalid while muscles are shifted; restored once every one is back at x.
        let evaluated_at = std::mem::take(&mut self.evaluated_at);
        let (mut plus, mut minus) = (vec![0.0; self.rows.len()], vec![0.0; self.rows.len()]);
        for i in 0..self.t_index() {
            let (e, h) = (i / 2, 1e-6 * x[i].abs().max(1.0));
            let kept = self.evaluations[e].clone();
            let shifted = |sign: f64, out: &mut [f64], this: &mut Self| -> Result<(), EvaluationError> {
                let (mut ratio, mut delta) = (x[2 * e], x[2 * e + 1]);
                if i % 2 == 0 { ratio += sign * h } else { delta += sign * h }
                this.reevaluate_muscle(e, ratio, delta).map_err(evaluation_error)?;
                this.fill_rows(t, out);
                Ok(())
            };
            shifted(1.0, &mut plus, self)?;
            shifted(-1.0, &mut minus, self)?;
            self.evaluations[e] = kept;
            for (r, (p, m)) in plus.iter().zip(&minus).enumerate() {
                jacobian[(r, i)] = (p - m) / (2.0 * h);
            }
        }
        self.evaluated_at = evaluated_at;
        let ti = self.t_index();
        for (r, row) in self.rows.iter().enumerate() {
            jacobian[(r, ti)] = match row {
                Row::Above(_) => -1.0,
                Row::Below(_) => 1.0,
                _ => 0.0,
            };
        }
        gradient.fill(0.0);
        gradient[ti] = 2.0 * t;
        Ok(())
    }
}
