//! The baseline of thesis ch. 6: Garner & Pandy (2003). Per estimated muscle the unknowns are
//! [L̃m_min, L̃m_max], the normalised fiber lengths at the muscle's shortest and longest
//! musculotendon length over the joint range, fitted by bounded least squares on the trial
//! moments (Levenberg–Marquardt, [`crate::solvers::LeastSquares`]).
//!
//! **Joint range** ([`JointRange`]): the knee coordinate over its model range
//! (`<range>` of the coordinate, sampled at [`RANGE_SAMPLES`] equally spaced angles, both ends
//! included), in each distinct hip/ankle posture of the trials (every other coordinate at its
//! default, couplers followed, as in [`KneeMomentModel`]). L_mt,min and L_mt,max are the
//! shortest and longest sampled path lengths over all those poses. (An extremum inside the range,
//! as `bifemlh_r`'s shortest length near −115° in gait2392, is missed by at most
//! ½·|∂²L_mt/∂q²|·(Δq/2)², below 1e-6 m with Δq = 0.5°.)
//!
//! **Map** (L̃m_min, L̃m_max) ↔ (L_opt, L_ts): the tendon is rigid (at its slack length) at both
//! extremes, L_mt = L_ts + L̃m·L_opt·cos α, and pennation follows the constant-width relation
//! L_opt sin α_opt = L_m sin α, so L_m cos α = L_opt·g(L̃m) with g(L̃) = √(L̃² − sin²α_opt)
//! exactly (no fixed-point iteration). Subtracting the two extremes:
//!
//! - L_opt = (L_mt,max − L_mt,min) / (g(L̃m_max) − g(L̃m_min)),
//! - L_ts = L_mt,min − L_opt·g(L̃m_min);
//! - inversely L̃m = √(((L_mt − L_ts)/L_opt)² + sin²α_opt) at L_mt = L_mt,min and L_mt,max,
//!   defined when L_mt,min > L_ts (a rigid tendon longer than the path has no fiber).
//!
//! α_opt (and F_max, v_max) are kept at the given values. The moments are then those of the
//! full model (elastic tendon, exact equilibrium): only the parameterisation is rigid-tendon.
//!
//! **Fit**: residuals r_t = M_model,t − M_measured,t (N·m) over all trials; bounds
//! L̃m ∈ [`GarnerPandyOptions::lower`], [`GarnerPandyOptions::upper`] (the lower bound raised
//! above sin α_opt where needed); L̃m_max > L̃m_min, L_opt > 0 and L_ts > 0 are not box bounds:
//! a point violating them has non-finite residuals and the solver backs off. The Jacobian is by
//! central differences per muscle (each variable changes one muscle's contribution only), with
//! step h = `relative_step`·max(|x|, 1); where one side is infeasible a one-sided difference is
//! used. The measured moments are an argument, so the fit can be repeated on perturbed moments
//! (see `sigma_points.rs`). The fit is a minimum when a stopping test passes or no step lowers
//! the cost any more ([`LeastSquaresStatus::at_minimum`]): the latter often on the edge
//! L_ts → 0 of the map's domain, where the moments alone leave a muscle's fiber to take up
//! the whole musculotendon length (the method's known degeneracy; the thesis' point).

use serde::Serialize;

use super::error::FunctionalError;
use super::knee_moment::{EstimatedMuscles, KneeMomentModel};
use super::parameters::MuscleParameters;
use super::trials::{root_mean_square, DynamometryData};
use crate::mechanics::{MuscleGeometry, PathEvaluation};
use crate::model::ModelSpec;
use crate::solvers::{Bounds, LeastSquares, LeastSquaresOptions, LeastSquaresProblem, LeastSquaresStatus};

use nalgebra::DMatrix;

/// Knee angles sampled over the coordinate's range (0.5° steps over gait2392's −120°…10°).
pub const RANGE_SAMPLES: usize = 261;

/// One end of a muscle's musculotendon length range and the pose where it occurs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RangeExtreme {
    /// L_mt, m.
    pub mt_length: f64,
    /// rad.
    pub knee_angle: f64,
    /// rad.
    pub hip_flexion: f64,
    /// rad.
    pub ankle_angle: f64,
}

/// The shortest and longest musculotendon length of one estimated muscle over the joint range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MusculotendonRange {
    pub muscle: String,
    pub shortest: RangeExtreme,
    pub longest: RangeExtreme,
}

/// Garner & Pandy's parameters of one muscle: normalised fiber lengths (fiber length / L_opt)
/// at the shortest and longest musculotendon length.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NormalizedFiberLengthRange {
    /// L̃m_min, at L_mt,min.
    pub minimum: f64,
    /// L̃m_max, at L_mt,max.
    pub maximum: f64,
}

/// The joint range of the estimated muscles (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointRange {
    pub knee_coordinate: String,
    /// The knee coordinate's model range [min, max], rad.
    pub knee_range: [f64; 2],
    /// The distinct (hip flexion, ankle angle) postures of the trials, rad, in trial order.
    pub postures: Vec<[f64; 2]>,
    /// One per estimated muscle, in order.
    pub muscles: Vec<MusculotendonRange>,
}

impl JointRange {
    /// The range of `data`'s estimated muscles in `model` (the model and trials of
    /// [`KneeMomentModel::new`]).
    pub fn compute(model: &ModelSpec, data: &DynamometryData) -> Result<JointRange, FunctionalError> {
        let geometry = MuscleGeometry::new(model)?;
        let multibody = &geometry.multibody;
        let coordinate = |name: &str| {
            multibody.coordinate_index(name).ok_or_else(|| FunctionalError::Model {
                model: model.file.clone(),
                what: "coordinate",
                name: name.into(),
                problem: "is not a coordinate of the model (a column of the trial files names it)".into(),
            })
        };
        let columns = &data.columns;
        let (knee, hip, ankle) = (coordinate(&columns.knee_angle)?, coordinate(&columns.hip_flexion)?, coordinate(&columns.ankle_angle)?);
        let paths = data
            .estimated_muscles
            .iter()
            .map(|name| {
                geometry.path_index(name).ok_or_else(|| FunctionalError::Model {
                    model: model.file.clone(),
                    what: "muscle",
                    name: name.clone(),
                    problem: "is not a muscle of the model (the subject file or a trial file names it)".into(),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let knee_range = multibody.coordinates[knee].range;
        let mut postures: Vec<[f64; 2]> = Vec::new();
        for trial in &data.trials {
            let posture = [trial.hip_flexion, trial.ankle_angle];
            if !postures.contains(&posture) {
                postures.push(posture);
            }
        }
        let mut evaluation = PathEvaluation::new(&geometry, &paths);
        let defaults = multibody.default_pose();
        let mut pose = defaults.clone();
        let unset = RangeExtreme { mt_length: f64::NAN, knee_angle: f64::NAN, hip_flexion: f64::NAN, ankle_angle: f64::NAN };
        let mut extremes = vec![(unset, unset); paths.len()];
        for posture in &postures {
            for i in 0..RANGE_SAMPLES {
                let fraction = i as f64 / (RANGE_SAMPLES - 1) as f64;
                let knee_angle = if i == RANGE_SAMPLES - 1 { knee_range[1] } else { knee_range[0] + fraction * (knee_range[1] - knee_range[0]) };
                pose.copy_from_slice(&defaults);
                pose[knee] = knee_angle;
                pose[hip] = posture[0];
                pose[ankle] = posture[1];
                multibody.follow_couplers(&mut pose, &[knee, hip, ankle]);
                evaluation.evaluate(&geometry, &pose);
                for (k, (shortest, longest)) in extremes.iter_mut().enumerate() {
                    let here = RangeExtreme { mt_length: evaluation.length(k), knee_angle, hip_flexion: posture[0], ankle_angle: posture[1] };
                    if shortest.mt_length.is_nan() || here.mt_length < shortest.mt_length {
                        *shortest = here;
                    }
                    if longest.mt_length.is_nan() || here.mt_length > longest.mt_length {
                        *longest = here;
                    }
                }
            }
        }
        let muscles = data
            .estimated_muscles
            .iter()
            .zip(extremes)
            .map(|(name, (shortest, longest))| MusculotendonRange { muscle: name.clone(), shortest, longest })
            .collect();
        Ok(JointRange { knee_coordinate: columns.knee_angle.clone(), knee_range, postures, muscles })
    }
}

impl MusculotendonRange {
    /// (L_opt, L_ts) in m of normalised fiber lengths `lengths` at α_opt =
    /// `pennation_angle_at_optimal` (rad), by the rigid-tendon map of the module documentation.
    /// Fails when L̃m is not above sin α_opt, L̃m_max is not above L̃m_min or L_ts would not be
    /// positive.
    pub fn parameters_of(&self, lengths: NormalizedFiberLengthRange, pennation_angle_at_optimal: f64) -> Result<(f64, f64), FunctionalError> {
        let sine_squared = pennation_angle_at_optimal.sin().powi(2);
        let projection = |normalized: f64| (normalized * normalized - sine_squared).sqrt();
        let (g_min, g_max) = (projection(lengths.minimum), projection(lengths.maximum));
        let span = self.longest.mt_length - self.shortest.mt_length;
        let optimal = span / (g_max - g_min);
        let slack = self.shortest.mt_length - optimal * g_min;
        if !(g_min > 0.0 && g_max > g_min && span > 0.0 && optimal.is_finite() && slack > 0.0) {
            return Err(self.unmappable(format!(
                "L̃m_min = {}, L̃m_max = {} (α_opt = {pennation_angle_at_optimal} rad) give L_opt = {optimal} m, L_ts = {slack} m; expected \
                 sin α_opt < L̃m_min < L̃m_max and positive lengths",
                lengths.minimum, lengths.maximum
            )));
        }
        Ok((optimal, slack))
    }

    /// `base` with L_opt and L_ts of `lengths` ([`MusculotendonRange::parameters_of`]).
    pub fn apply(&self, lengths: NormalizedFiberLengthRange, base: &MuscleParameters) -> Result<MuscleParameters, FunctionalError> {
        let (optimal, slack) = self.parameters_of(lengths, base.pennation_angle_at_optimal)?;
        let mut parameters = base.clone();
        parameters.optimal_fiber_length = optimal;
        parameters.tendon_slack_length = slack;
        Ok(parameters)
    }

    /// The normalised fiber lengths of `parameters` (the inverse map). Fails when L_mt,min is
    /// not longer than L_ts.
    pub fn normalized_fiber_lengths(&self, parameters: &MuscleParameters) -> Result<NormalizedFiberLengthRange, FunctionalError> {
        let sine_squared = parameters.pennation_angle_at_optimal.sin().powi(2);
        let (optimal, slack) = (parameters.optimal_fiber_length, parameters.tendon_slack_length);
        if !(self.shortest.mt_length > slack && optimal > 0.0) {
            return Err(self.unmappable(format!(
                "L_ts = {slack} m is not shorter than the shortest musculotendon length {} m (or L_opt = {optimal} m ≤ 0): \
                 no rigid-tendon fiber length",
                self.shortest.mt_length
            )));
        }
        let normalized = |mt_length: f64| (((mt_length - slack) / optimal).powi(2) + sine_squared).sqrt();
        Ok(NormalizedFiberLengthRange { minimum: normalized(self.shortest.mt_length), maximum: normalized(self.longest.mt_length) })
    }

    fn unmappable(&self, problem: String) -> FunctionalError {
        FunctionalError::Parameters { muscle: self.muscle.clone(), problem: format!("Garner–Pandy parameters: {problem}") }
    }
}

/// Settings of [`fit_garner_pandy`].
#[derive(Debug, Clone, PartialEq)]
pub struct GarnerPandyOptions {
    /// Lower bound of every L̃m (raised to just above sin α_opt where that is larger).
    pub lower: f64,
    /// Upper bound of every L̃m.
    pub upper: f64,
    /// Central-difference step relative to max(|L̃m|, 1).
    pub relative_step: f64,
    /// Indices of the estimated muscles to fit; `None`: all. The others keep the start values.
    pub fitted_muscles: Option<Vec<usize>>,
    /// Stopping rules. The default allows 5000 iterations: with noisy moments the fit can crawl
    /// along a curved valley for hundreds of them (580 on a held-out subject's set5, 1110 on a
    /// subject perturbed from the generic model, `gen19`) before the cost test ends it; an
    /// iteration costs well under a millisecond on set5.
    pub least_squares: LeastSquaresOptions,
}

impl Default for GarnerPandyOptions {
    fn default() -> GarnerPandyOptions {
        GarnerPandyOptions {
            lower: 0.3,
            upper: 2.0,
            relative_step: 1e-6,
            fitted_muscles: None,
            least_squares: LeastSquaresOptions { step_tolerance: 1e-10, gradient_tolerance: 1e-10, cost_tolerance: 1e-10, max_iterations: 5000 },
        }
    }
}

/// What [`fit_garner_pandy`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct GarnerPandyFit {
    /// One per estimated muscle, in order (muscles not fitted as started).
    pub parameters: Vec<MuscleParameters>,
    /// Indices of the fitted estimated muscles.
    pub fitted_muscles: Vec<usize>,
    /// [L̃m_min, L̃m_max] of each fitted muscle at the start (projected into the bounds) and at
    /// the end, parallel to `fitted_muscles`.
    pub initial_normalized_fiber_lengths: Vec<NormalizedFiberLengthRange>,
    pub normalized_fiber_lengths: Vec<NormalizedFiberLengthRange>,
    /// M_model − M_measured per trial at the start and at the end, N·m.
    pub initial_residuals: Vec<f64>,
    pub residuals: Vec<f64>,
    pub status: LeastSquaresStatus,
    pub iterations: usize,
}

impl GarnerPandyFit {
    /// Root mean square of the final residuals, N·m.
    pub fn rms(&self) -> f64 {
        root_mean_square(self.residuals.iter().copied())
    }

    /// Root mean square of the residuals at the start, N·m.
    pub fn initial_rms(&self) -> f64 {
        root_mean_square(self.initial_residuals.iter().copied())
    }
}

/// Fits [L̃m_min, L̃m_max] of the estimated muscles to `measured` (N·m, one per trial of
/// `knee`) from `start` (one per estimated muscle, in order; e.g.
/// [`KneeMomentModel::nominal_parameters`]). `range` comes from [`JointRange::compute`] for the
/// same model and trials.
///
/// Errors: sizes that do not fit, a start whose normalised fiber lengths are undefined (or,
/// once projected into the bounds, do not map back), a muscle without equilibrium at the start.
/// Non-convergence is a [`LeastSquaresStatus`] in the result.
pub fn fit_garner_pandy(
    knee: &KneeMomentModel,
    range: &JointRange,
    measured: &[f64],
    start: &[MuscleParameters],
    options: &GarnerPandyOptions,
) -> Result<GarnerPandyFit, FunctionalError> {
    let n_estimated = knee.estimated_names().count();
    let all = FunctionalError::all_muscles;
    if measured.len() != knee.trials().len() {
        return Err(all(format!("{} measured moments given; expected one per trial ({})", measured.len(), knee.trials().len())));
    }
    if range.muscles.len() != n_estimated || range.muscles.iter().zip(knee.estimated_names()).any(|(r, name)| r.muscle != name) {
        return Err(all("the joint range was computed for other estimated muscles".into()));
    }
    let fitted = options.fitted_muscles.clone().unwrap_or_else(|| (0..n_estimated).collect());
    if let Some(&e) = fitted.iter().find(|&&e| e >= n_estimated) {
        return Err(all(format!("fitted muscle index {e}; expected one below {n_estimated}")));
    }
    if !(options.lower < options.upper && options.relative_step > 0.0) {
        let (lower, upper, step) = (options.lower, options.upper, options.relative_step);
        return Err(all(format!("bounds [{lower}, {upper}] and step {step}; expected lower < upper and a positive step")));
    }
    let mut muscles = knee.estimated_muscles(start)?;
    let mut bounds = Bounds::none(2 * fitted.len());
    let mut x = vec![0.0; 2 * fitted.len()];
    for (i, &e) in fitted.iter().enumerate() {
        let lengths = range.muscles[e].normalized_fiber_lengths(&start[e])?;
        let lower = options.lower.max(start[e].pennation_angle_at_optimal.sin() + 1e-6);
        for (j, value) in [lengths.minimum, lengths.maximum].into_iter().enumerate() {
            bounds.lower[2 * i + j] = lower;
            bounds.upper[2 * i + j] = options.upper;
            x[2 * i + j] = value.clamp(lower, options.upper);
        }
    }
    // Σ F_t·r of everything not fitted, per trial.
    let mut fixed = knee.fixed_moments().to_vec();
    for e in (0..n_estimated).filter(|e| !fitted.contains(e)) {
        let k = knee.estimated_knee_index(e);
        for (t, moment) in fixed.iter_mut().enumerate() {
            *moment += knee.contribution(k, muscles.muscle(e), t)?;
        }
    }
    let decode = |x: &[f64]| -> Result<Vec<MuscleParameters>, FunctionalError> {
        let mut parameters = start.to_vec();
        for (i, &e) in fitted.iter().enumerate() {
            parameters[e] = range.muscles[e].apply(pair(x, i), &start[e])?;
        }
        Ok(parameters)
    };
    let initial_x = x.clone();
    muscles.set_all(knee, &decode(&x)?)?;
    let mut problem = GarnerPandyProblem {
        knee,
        range,
        measured,
        fitted: &fitted,
        start,
        fixed,
        muscles,
        relative_step: options.relative_step,
        contributions: vec![0.0; knee.trials().len()],
        plus: vec![0.0; knee.trials().len()],
        minus: vec![0.0; knee.trials().len()],
    };
    let mut initial_residuals = vec![0.0; measured.len()];
    problem.residuals_at(&x, &mut initial_residuals)?;
    let mut solver = LeastSquares::new(x.len(), measured.len());
    let report = solver.minimize(&mut problem, &mut x, &bounds, &options.least_squares);
    let parameters = decode(&x)?;
    let mut residuals = vec![0.0; measured.len()];
    problem.residuals_at(&x, &mut residuals)?;
    Ok(GarnerPandyFit {
        parameters,
        initial_normalized_fiber_lengths: (0..fitted.len()).map(|i| pair(&initial_x, i)).collect(),
        normalized_fiber_lengths: (0..fitted.len()).map(|i| pair(&x, i)).collect(),
        fitted_muscles: fitted,
        initial_residuals,
        residuals,
        status: report.status,
        iterations: report.iterations,
    })
}

/// The i-th fitted muscle's (L̃m_min, L̃m_max) in the variables.
fn pair(x: &[f64], i: usize) -> NormalizedFiberLengthRange {
    NormalizedFiberLengthRange { minimum: x[2 * i], maximum: x[2 * i + 1] }
}

/// The least-squares problem of [`fit_garner_pandy`]; `muscles` holds the estimated muscles
/// at the last point whose residuals were evaluated.
struct GarnerPandyProblem<'a> {
    knee: &'a KneeMomentModel,
    range: &'a JointRange,
    measured: &'a [f64],
    fitted: &'a [usize],
    start: &'a [MuscleParameters],
    /// Moments of every muscle not fitted, per trial, N·m.
    fixed: Vec<f64>,
    muscles: EstimatedMuscles,
    relative_step: f64,
    contributions: Vec<f64>,
    plus: Vec<f64>,
    minus: Vec<f64>,
}

impl GarnerPandyProblem<'_> {
    /// Sets fitted muscle i's parameters in the workspace from `lengths`.
    fn set(&mut self, i: usize, lengths: NormalizedFiberLengthRange) -> Result<(), FunctionalError> {
        let e = self.fitted[i];
        let parameters = self.range.muscles[e].apply(lengths, &self.start[e])?;
        self.muscles.set(self.knee, e, &parameters)
    }

    /// Contribution F_t·r per trial of fitted muscle i with normalised lengths `lengths` into
    /// `out`; the workspace keeps those parameters.
    fn contribution(&mut self, i: usize, lengths: NormalizedFiberLengthRange, out: &mut [f64]) -> Result<(), FunctionalError> {
        self.set(i, lengths)?;
        let e = self.fitted[i];
        let k = self.knee.estimated_knee_index(e);
        for (t, value) in out.iter_mut().enumerate() {
            *value = self.knee.contribution(k, self.muscles.muscle(e), t)?;
        }
        Ok(())
    }

    /// r(x) = M_model − M_measured.
    fn residuals_at(&mut self, x: &[f64], residuals: &mut [f64]) -> Result<(), FunctionalError> {
        residuals.copy_from_slice(&self.fixed);
        let mut contributions = std::mem::take(&mut self.contributions);
        let result: Result<(), FunctionalError> = (0..self.fitted.len()).try_for_each(|i| {
            self.contribution(i, pair(x, i), &mut contributions)?;
            residuals.iter_mut().zip(&contributions).for_each(|(r, c)| *r += c);
            Ok(())
        });
        self.contributions = contributions;
        result?;
        residuals.iter_mut().zip(self.measured).for_each(|(r, m)| *r -= m);
        Ok(())
    }

    /// Column 2i + j of ∂r/∂x by central differences (one-sided where a side is infeasible;
    /// zero where both are). Leaves the workspace at x.
    fn column(&mut self, x: &[f64], i: usize, j: usize, column: &mut [f64]) {
        let centre = pair(x, i);
        let value = x[2 * i + j];
        let h = self.relative_step * value.abs().max(1.0);
        let shifted = |delta: f64| {
            let mut lengths = centre;
            if j == 0 {
                lengths.minimum = value + delta;
            } else {
                lengths.maximum = value + delta;
            }
            lengths
        };
        let (mut plus, mut minus, mut at_centre) =
            (std::mem::take(&mut self.plus), std::mem::take(&mut self.minus), std::mem::take(&mut self.contributions));
        let plus_ok = self.contribution(i, shifted(h), &mut plus).is_ok();
        let minus_ok = self.contribution(i, shifted(-h), &mut minus).is_ok();
        // The centre's contributions only for a one-sided difference; the workspace back at x.
        let centre_ok = if plus_ok && minus_ok { self.set(i, centre).is_ok() } else { self.contribution(i, centre, &mut at_centre).is_ok() };
        for (t, c) in column.iter_mut().enumerate() {
            *c = match (plus_ok, minus_ok, centre_ok) {
                (true, true, _) => (plus[t] - minus[t]) / (2.0 * h),
                (true, false, true) => (plus[t] - at_centre[t]) / h,
                (false, true, true) => (at_centre[t] - minus[t]) / h,
                _ => 0.0,
            };
        }
        (self.plus, self.minus, self.contributions) = (plus, minus, at_centre);
    }
}

impl LeastSquaresProblem for GarnerPandyProblem<'_> {
    fn variable_count(&self) -> usize {
        2 * self.fitted.len()
    }

    fn residual_count(&self) -> usize {
        self.measured.len()
    }

    /// Non-finite residuals where the map or an equilibrium fails: the solver backs off.
    fn evaluate(&mut self, x: &[f64], residuals: &mut [f64], jacobian: Option<&mut DMatrix<f64>>) {
        if self.residuals_at(x, residuals).is_err() {
            residuals.fill(f64::NAN);
            if let Some(jacobian) = jacobian {
                jacobian.fill(f64::NAN);
            }
            return;
        }
        if let Some(jacobian) = jacobian {
            let mut column = vec![0.0; residuals.len()];
            for i in 0..self.fitted.len() {
                for j in 0..2 {
                    self.column(x, i, j, &mut column);
                    jacobian.column_mut(2 * i + j).copy_from_slice(&column);
                }
            }
        }
    }
}


#[cfg(test)]
mod tests {
    use super::*;

    fn range() -> MusculotendonRange {
        let extreme = |mt_length| RangeExtreme { mt_length, knee_angle: 0.0, hip_flexion: 0.0, ankle_angle: 0.0 };
        MusculotendonRange { muscle: "vas_lat_r".into(), shortest: extreme(0.24), longest: extreme(0.31) }
    }

    fn parameters(alpha: f64) -> MuscleParameters {
        MuscleParameters {
            name: "vas_lat_r".into(),
            optimal_fiber_length: 0.084,
            tendon_slack_length: 0.157,
            max_isometric_force: 1871.0,
            pennation_angle_at_optimal: alpha,
            max_contraction_velocity: 10.0,
        }
    }

    #[test]
    fn map_round_trips_with_and_without_pennation() {
        for alpha in [0.0, 0.087, 0.3] {
            let p = parameters(alpha);
            let lengths = range().normalized_fiber_lengths(&p).unwrap();
            let back = range().apply(lengths, &p).unwrap();
            assert!((back.optimal_fiber_length - p.optimal_fiber_length).abs() < 1e-15, "{alpha}: {back:?}");
            assert!((back.tendon_slack_length - p.tendon_slack_length).abs() < 1e-15, "{alpha}: {back:?}");
            // Rigid tendon at the extremes: L_mt = L_ts + L_m cos α with constant width.
            let width = p.optimal_fiber_length * alpha.sin();
            for (normalized, mt_length) in [(lengths.minimum, 0.24), (lengths.maximum, 0.31)] {
                let fiber = normalized * p.optimal_fiber_length;
                let along = (fiber * fiber - width * width).sqrt();
                assert!((p.tendon_slack_length + along - mt_length).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn unmappable_values_are_refused() {
        let p = parameters(0.1);
        let message = range().apply(NormalizedFiberLengthRange { minimum: 1.2, maximum: 1.1 }, &p).unwrap_err().to_string();
        assert!(message.contains("expected sin α_opt < L̃m_min < L̃m_max"), "{message}");
        assert!(range().normalized_fiber_lengths(&p.with(super::super::Parameter::TendonSlackLength, 0.25)).is_err());
    }
}
