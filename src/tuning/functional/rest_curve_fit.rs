//! The rest-curve fit: with every estimated muscle's rest fiber length taken as measured
//! exactly, each muscle moves only along its [`RestCurve`], and (L_opt, L_ts) follow from one
//! coordinate s per muscle. The moments are fitted by least squares in s:
//! 1. a global search on a tabulated surrogate of each muscle's contributions
//!    ([`rest_curve_search`](super::rest_curve_search)), which keeps the best distinct minima;
//! 2. Levenberg–Marquardt on the exact model from each distinct surrogate minimum kept, and
//!    from any extra starts (e.g. Phase II's result), each muscle's Jacobian column by central
//!    differences of its own contributions;
//! 3. the refined point with the smallest cost is the fit.
//!
//! With exact rest lengths, five angles per direction identify all 16 parameters locally, but
//! the moment error has many small basins (ten residuals for eight coordinates; the groups
//! trade passive force across directions); step 1 is what finds the right one.
//!
//! With noisy moments an optional Gaussian prior around the model's parameters
//! ([`RestCurvePrior`]) adds its residuals to the cost of all three steps: a maximum
//! a-posteriori fit. Five angles per direction leave one residual degree of freedom per group,
//! and several basins then fit the noise about equally well; the prior picks the one nearest
//! the model and shrinks what the moments do not determine.

use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::MuscleParameters;
use super::rest_curve::RestCurve;
use super::rest_curve_posterior::{posterior_mean, CoordinatePosterior, PosteriorSettings};
use super::rest_curve_search::{muscle_groups, search, ContributionTable, CoordinatePrior, SearchBudget, Surrogate};
use crate::solvers::{Bounds, LeastSquares, LeastSquaresOptions, LeastSquaresProblem, LeastSquaresStatus};
use nalgebra::DMatrix;

/// Settings of [`fit_rest_curves`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestCurveSettings {
    /// L_opt searched within this range times the origin's.
    pub span: [f64; 2],
    /// Points of each muscle's surrogate table.
    pub table_points: usize,
    /// How widely the global search looks; its `keep` minima are refined on the exact model.
    pub search: SearchBudget,
    /// Run the global search; without it only the extra starts are refined (a local fit).
    pub global_search: bool,
    /// Central-difference step in s.
    pub step: f64,
    pub least_squares: LeastSquaresOptions,
    /// With a prior, the estimate is the posterior mean sampled on the search's tables
    /// (`rest_curve_posterior.rs`); `None`: the MAP fit.
    pub posterior: Option<PosteriorSettings>,
}

impl Default for RestCurveSettings {
    fn default() -> Self {
        RestCurveSettings {
            span: [0.5, 1.5],
            table_points: 81,
            search: SearchBudget::default(),
            global_search: true,
            step: 1e-6,
            least_squares: LeastSquaresOptions { step_tolerance: 1e-8, gradient_tolerance: 1e-4, cost_tolerance: 1e-10, max_iterations: 200 },
            posterior: Some(PosteriorSettings::default()),
        }
    }
}

/// A Gaussian prior on each muscle's rest-curve coordinate around `model`'s parameters:
/// s − s(model) ~ N(0, τ²) with τ = `coordinate_sd` (the relative standard deviation of L_opt;
/// of L_ts on a clamped branch), weighed against moment noise of standard deviation `noise_sd`
/// (N·m).
#[derive(Debug, Clone, Copy)]
pub struct RestCurvePrior<'a> {
    pub model: &'a [MuscleParameters],
    pub coordinate_sd: f64,
    pub noise_sd: f64,
}

/// The outcome of [`fit_rest_curves`].
#[derive(Debug, Clone)]
pub struct RestCurveFit {
    pub parameters: Vec<MuscleParameters>,
    /// The refinement that gave the fit.
    pub status: LeastSquaresStatus,
    pub iterations: usize,
    /// Refinements run.
    pub starts: usize,
    /// M − M_meas per trial, N·m.
    pub residuals: Vec<f64>,
    /// ½ Σ (M − M_meas)² plus the prior's ½ Σ squared residuals at the refined point, N²·m².
    pub cost: f64,
    /// The prior's weight σ/τ, N·m (0 without a prior).
    pub prior_weight: f64,
    /// When the fit is the posterior mean: each muscle's posterior sd of [L_opt, L_ts] (m) from
    /// the Gibbs samples; `None` for a coordinate the grid does not resolve (it keeps the MAP
    /// value).
    pub sampled_sd: Option<Vec<Option<[f64; 2]>>>,
    /// The global search's curves and tables, kept for the posterior mean (`None` for a local
    /// fit).
    pub(crate) search: Option<SearchTables>,
}

/// The curves and contribution tables of a global search.
#[derive(Debug, Clone)]
pub(crate) struct SearchTables {
    curves: Vec<RestCurve>,
    tables: Vec<ContributionTable>,
}

impl RestCurveFit {
    /// The refinement stopped at a minimum ([`LeastSquaresStatus::at_minimum`]).
    pub fn converged(&self) -> bool {
        self.status.at_minimum()
    }
}

/// Fits the estimated muscles on their rest curves through `references` (m, one per estimated
/// muscle), with origins `origin` (the s = 0 parameters, e.g. the model's) to `measured` (N·m,
/// one per trial); `extra_starts` are refined too; `prior`, if any, joins the least squares.
pub fn fit_rest_curves(
    model: &KneeMomentModel,
    references: &[f64],
    origin: &[MuscleParameters],
    measured: &[f64],
    extra_starts: &[Vec<MuscleParameters>],
    prior: Option<RestCurvePrior>,
    settings: &RestCurveSettings,
) -> Result<RestCurveFit, FunctionalError> {
    let n = origin.len();
    if references.len() != n || measured.len() != model.trials().len() {
        return Err(FunctionalError::all_muscles(format!("{} rest lengths, {} origins and {} moments; expected one rest length per estimated muscle and one moment per trial", references.len(), n, measured.len())));
    }
    let mut workspace = model.estimated_muscles(origin)?;
    let curves = (0..n).map(|e| RestCurve::new(model, &mut workspace, e, references[e], &origin[e])).collect::<Result<Vec<_>, _>>()?;
    let ranges = curve_ranges(&curves, settings.span);
    let tables = if settings.global_search { Some(contribution_tables(model, &mut workspace, &curves, &ranges, settings)?) } else { None };
    let bounds = match &tables {
        Some(tables) => Bounds { lower: tables.iter().map(|t| t.start).collect(), upper: tables.iter().map(ContributionTable::end).collect() },
        None => Bounds { lower: ranges.iter().map(|r| r[0]).collect(), upper: ranges.iter().map(|r| r[1]).collect() },
    };
    let coordinates = |parameters: &[MuscleParameters]| -> Vec<f64> { curves.iter().zip(parameters).map(|(c, p)| c.coordinate_of(p).clamp(bounds.lower[c.e], bounds.upper[c.e])).collect() };
    let prior = coordinate_prior(&curves, prior)?;
    let extra: Vec<Vec<f64>> = extra_starts.iter().map(|p| coordinates(p)).collect();
    let mut starts: Vec<Vec<f64>> = match &tables {
        Some(tables) => {
            let held = extra.first().cloned().unwrap_or_else(|| coordinates(origin));
            let residual_base: Vec<f64> = model.fixed_moments().iter().zip(measured).map(|(f, m)| f - m).collect();
            let surrogate = Surrogate { tables, residual_base: &residual_base, prior: &prior };
            search(&surrogate, &muscle_groups(model), &held, &settings.search).into_iter().map(|m| m.s).collect()
        }
        None => Vec::new(),
    };
    starts.extend(extra);
    let prior_weight = prior.weight;
    let mut problem = CurveProblem::new(model, &curves, measured, prior, workspace, settings.step);
    let mut best: Option<(f64, Vec<f64>, LeastSquaresStatus, usize)> = None;
    let mut solver = LeastSquares::new(n, problem.residual_count());
    for mut x in starts.iter().cloned() {
        let report = solver.minimize(&mut problem, &mut x, &bounds, &settings.least_squares);
        if report.cost.is_finite() && best.as_ref().is_none_or(|b| report.cost < b.0) {
            best = Some((report.cost, x, report.status, report.iterations));
        }
    }
    let (cost, x, status, iterations) = best.ok_or_else(|| FunctionalError::all_muscles("no refinement of the rest-curve fit had finite moments"))?;
    let mut residuals = vec![0.0; problem.residual_count()];
    problem.evaluate(&x, &mut residuals, None);
    residuals.truncate(measured.len());
    let parameters = problem.parameters_at(&x).ok_or_else(|| FunctionalError::all_muscles("the rest-curve fit's point lost its equilibrium"))?;
    let search = tables.map(|tables| SearchTables { curves, tables });
    Ok(RestCurveFit { parameters, status, iterations, starts: starts.len(), residuals, cost, prior_weight, sampled_sd: None, search })
}

/// Moves the fit `fit` to `measured` (N·m, one per trial) to its posterior mean under `prior`,
/// sampled on `fit`'s search tables (`rest_curve_posterior.rs`) by chains from `fit` and from the
/// prior's centre: the curve points at the mean coordinates (`fit`'s where the grid does not
/// resolve the posterior), their residuals and the sampled sd; `fit`'s status stays. Returns
/// the posterior; `None`, with `fit` unchanged, when `fit` kept no tables or a curve has no
/// point at the mean.
pub(crate) fn move_to_posterior_mean(
    model: &KneeMomentModel,
    fit: &mut RestCurveFit,
    measured: &[f64],
    prior: RestCurvePrior,
    settings: &PosteriorSettings,
) -> Result<Option<CoordinatePosterior>, FunctionalError> {
    let Some(search) = &fit.search else { return Ok(None) };
    let coordinate_prior = coordinate_prior(&search.curves, Some(prior))?;
    let residual_base: Vec<f64> = model.fixed_moments().iter().zip(measured).map(|(f, m)| f - m).collect();
    let at_fit: Vec<f64> = search.curves.iter().zip(&fit.parameters).map(|(c, p)| c.coordinate_of(p)).collect();
    let starts = [at_fit, coordinate_prior.centre.clone()];
    let Some(posterior) = posterior_mean(&search.tables, &residual_base, &coordinate_prior, prior.noise_sd, &starts, settings) else { return Ok(None) };
    let mut workspace = model.estimated_muscles(&fit.parameters)?;
    let mut points = Vec::with_capacity(fit.parameters.len());
    for (curve, map) in search.curves.iter().zip(&fit.parameters) {
        let e = curve.e;
        let point = if posterior.resolved[e] { curve.at(model, &mut workspace, posterior.mean[e], map.tendon_slack_length) } else { Some(map.clone()) };
        points.push(point);
    }
    let points: Option<Vec<MuscleParameters>> = points.into_iter().collect();
    let Some(parameters) = points else { return Ok(None) };
    fit.residuals = model.moments(&parameters)?.iter().zip(measured).map(|(m, y)| m - y).collect();
    fit.parameters = parameters;
    fit.sampled_sd = Some(posterior.length_sd.iter().zip(&posterior.resolved).map(|(sd, resolved)| resolved.then_some(*sd)).collect());
    Ok(Some(posterior))
}

/// The prior in curve coordinates (weight 0 without one); an error for a non-positive τ or a
/// negative σ.
fn coordinate_prior(curves: &[RestCurve], prior: Option<RestCurvePrior>) -> Result<CoordinatePrior, FunctionalError> {
    let Some(prior) = prior else { return Ok(CoordinatePrior { centre: vec![0.0; curves.len()], weight: 0.0 }) };
    if !(prior.coordinate_sd > 0.0 && prior.noise_sd >= 0.0 && prior.noise_sd.is_finite()) || prior.model.len() != curves.len() {
        return Err(FunctionalError::all_muscles(format!(
            "prior τ = {}, σ = {} N·m over {} muscles; expected τ > 0, a finite σ ≥ 0 and one model muscle per estimated muscle",
            prior.coordinate_sd,
            prior.noise_sd,
            prior.model.len()
        )));
    }
    Ok(CoordinatePrior { centre: curves.iter().zip(prior.model).map(|(c, p)| c.coordinate_of(p)).collect(), weight: prior.noise_sd / prior.coordinate_sd })
}

/// Every muscle's contribution table over its range; an error for a muscle with no point.
fn contribution_tables(model: &KneeMomentModel, workspace: &mut EstimatedMuscles, curves: &[RestCurve], ranges: &[[f64; 2]], settings: &RestCurveSettings) -> Result<Vec<ContributionTable>, FunctionalError> {
    let tables: Vec<ContributionTable> = curves.iter().map(|curve| ContributionTable::compute(model, workspace, curve, ranges[curve.e], settings.table_points, settings.step)).collect();
    if let Some(curve) = curves.iter().find(|curve| tables[curve.e].points.iter().all(Option::is_none)) {
        let origin = curve.origin();
        return Err(FunctionalError::NoRestCurvePoint { muscle: origin.name.clone(), span: settings.span, optimal: origin.optimal_fiber_length, reference: curve.reference });
    }
    Ok(tables)
}

/// s within ln(span) × the origin's L_opt; where the clamped branch starts inside, s reaches far
/// enough along it for L_ts to grow to span[1] × the origin's L_ts.
fn curve_ranges(curves: &[RestCurve], span: [f64; 2]) -> Vec<[f64; 2]> {
    let (lower, upper) = (span[0].ln(), span[1].ln());
    let clamped_end = |curve: &RestCurve| -> Option<f64> {
        let (s_clamp, slack) = curve.clamp()?;
        (s_clamp < upper).then(|| s_clamp + (span[1] * curve.origin().tendon_slack_length / slack).ln())
    };
    curves.iter().map(|curve| [lower, clamped_end(curve).map_or(upper, |end| end.max(upper))]).collect()
}

/// r(s) = M(s) − M_meas per trial, then the prior's residual per muscle; each muscle's
/// contributions cached at its last s.
struct CurveProblem<'a> {
    model: &'a KneeMomentModel,
    curves: &'a [RestCurve],
    measured: &'a [f64],
    prior: CoordinatePrior,
    workspace: EstimatedMuscles,
    step: f64,
    /// Last L_ts per muscle, the next search's hint.
    slack_hints: Vec<f64>,
    /// Per muscle, the s its `contributions` are at (NaN: none yet).
    cached_s: Vec<f64>,
    contributions: Vec<Vec<f64>>,
    plus: Vec<f64>,
    minus: Vec<f64>,
}

impl<'a> CurveProblem<'a> {
    fn new(model: &'a KneeMomentModel, curves: &'a [RestCurve], measured: &'a [f64], prior: CoordinatePrior, workspace: EstimatedMuscles, step: f64) -> CurveProblem<'a> {
        let trials = measured.len();
        CurveProblem {
            model,
            curves,
            measured,
            prior,
            workspace,
            step,
            slack_hints: curves.iter().map(|c| c.origin().tendon_slack_length).collect(),
            cached_s: vec![f64::NAN; curves.len()],
            contributions: vec![vec![0.0; trials]; curves.len()],
            plus: vec![0.0; trials],
            minus: vec![0.0; trials],
        }
    }

    /// Muscle e's contributions at s into `out`; false where the curve or an equilibrium fails.
    fn contributions_at(&mut self, e: usize, s: f64, out: &mut [f64]) -> bool {
        self.curves[e].contributions(self.model, &mut self.workspace, s, &mut self.slack_hints[e], out).is_some()
    }

    /// Brings every muscle's cache to x; false where one fails.
    fn refresh(&mut self, x: &[f64]) -> bool {
        for (e, &s) in x.iter().enumerate() {
            if self.cached_s[e] != s {
                let mut out = std::mem::take(&mut self.contributions[e]);
                let ok = self.contributions_at(e, s, &mut out);
                self.contributions[e] = out;
                self.cached_s[e] = if ok { s } else { f64::NAN };
                if !ok {
                    return false;
                }
            }
        }
        true
    }

    fn parameters_at(&mut self, x: &[f64]) -> Option<Vec<MuscleParameters>> {
        x.iter().enumerate().map(|(e, &s)| self.curves[e].at(self.model, &mut self.workspace, s, self.slack_hints[e])).collect()
    }

    /// ∂c_e/∂s per trial into `column` (central, else one-sided, else zero).
    fn column(&mut self, e: usize, s: f64, column: &mut [f64]) {
        let h = self.step;
        let (mut plus, mut minus) = (std::mem::take(&mut self.plus), std::mem::take(&mut self.minus));
        let plus_ok = self.contributions_at(e, s + h, &mut plus);
        let minus_ok = self.contributions_at(e, s - h, &mut minus);
        let centre = &self.contributions[e];
        for (t, c) in column.iter_mut().enumerate() {
            *c = match (plus_ok, minus_ok) {
                (true, true) => (plus[t] - minus[t]) / (2.0 * h),
                (true, false) => (plus[t] - centre[t]) / h,
                (false, true) => (centre[t] - minus[t]) / h,
                (false, false) => 0.0,
            };
        }
        (self.plus, self.minus) = (plus, minus);
    }
}

impl LeastSquaresProblem for CurveProblem<'_> {
    fn variable_count(&self) -> usize {
        self.curves.len()
    }

    fn residual_count(&self) -> usize {
        self.measured.len() + self.curves.len()
    }

    /// Non-finite residuals where a curve point or an equilibrium fails: the solver backs off.
    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
        if !self.refresh(x) {
            residuals.fill(f64::NAN);
            return;
        }
        let (moments, priors) = residuals.split_at_mut(self.measured.len());
        moments.copy_from_slice(self.model.fixed_moments());
        for contributions in &self.contributions {
            moments.iter_mut().zip(contributions).for_each(|(r, c)| *r += c);
        }
        moments.iter_mut().zip(self.measured).for_each(|(r, m)| *r -= m);
        priors.iter_mut().enumerate().for_each(|(e, r)| *r = self.prior.residual(e, x[e]));
        if let Some(jacobian) = jacobian {
            let mut column = vec![0.0; moments.len()];
            jacobian.fill(0.0);
            for (e, &s) in x.iter().enumerate() {
                self.column(e, s, &mut column);
                jacobian.view_mut((0, e), (column.len(), 1)).copy_from_slice(&column);
                jacobian[(column.len() + e, e)] = self.prior.weight;
            }
        }
    }
}
