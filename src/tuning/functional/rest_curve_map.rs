//! The rest-curve fit as the estimator runs it after Phase II, and the moment noise σ its
//! prior is weighed against (`rest_curve_fit.rs`: the prior on each curve coordinate):
//!
//! - without a prior (τ unset), or on noise-free moments — σ given at most
//!   [`NEGLIGIBLE_NOISE`], or the fit without prior reproducing the moments so that the
//!   marginal likelihood finds σ at most that — the least-squares fit; unless it reproduces
//!   the moments, its global search is run again around it until the cost stops falling
//!   ([`RestCurveProblem::recentred`]);
//! - σ given (option or subject file): the fit under the prior with that σ;
//! - else σ from the marginal likelihood of the moments under the prior (its posterior mean,
//!   `noise_evidence.rs`), linearised first at the fit without prior, then at each MAP estimate,
//!   which is refitted locally with the new σ until σ changes by less than
//!   [`EVIDENCE_TOLERANCE`] (an evidence fixed point after MacKay; at most [`EVIDENCE_ROUNDS`]
//!   refits, reported when σ has not settled).
//!   A fit without prior leaves few degrees of freedom for σ (set5: ten trials, eight
//!   coordinates); the marginal likelihood also counts the directions the prior holds.
//!
//! Under the prior the estimate is the posterior mean of the curve coordinates
//! (`rest_curve_posterior.rs`) at the final σ, unless the settings ask for the MAP fit (or the
//! mean cannot be sampled: then the MAP fit, said so in the progress).

use serde::Serialize;

use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::rest_curve_fit::{fit_rest_curves, move_to_posterior_mean, RestCurveFit, RestCurvePrior, RestCurveSettings};
use super::rest_curve_information::RestCurveInformation;

/// σ (N·m) below which moments count as noise-free (dynamometers resolve about 0.1 N·m): the
/// prior is then not used.
pub const NEGLIGIBLE_NOISE: f64 = 1e-3;
/// Relative change of σ at which the evidence fixed point stops.
pub const EVIDENCE_TOLERANCE: f64 = 0.01;
/// Local refits of the evidence fixed point at most.
pub const EVIDENCE_ROUNDS: usize = 10;
/// Global searches re-centred on the fit at most, and the relative fall of the cost that counts
/// as a gain (below it the re-centred search found the same minimum).
pub const RECENTRED_SEARCHES: usize = 3;
pub const RECENTRED_GAIN: f64 = 1e-6;
/// The source of a σ estimated with the prior.
const MARGINAL_LIKELIHOOD: &str = "marginal likelihood";
/// The estimates under the prior.
const POSTERIOR_MEAN: &str = "posterior mean";
const MAXIMUM_A_POSTERIORI: &str = "maximum a posteriori";

/// The Gaussian prior a rest-curve fit used: relative sd τ of L_opt around the model's, moment
/// noise σ (N·m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AppliedPrior {
    pub coordinate_sd: f64,
    pub noise_sd: f64,
    /// Where σ came from: "given", "subject file" or "marginal likelihood" (under the prior).
    pub noise_source: &'static str,
    /// "posterior mean" or "maximum a posteriori".
    pub estimate: &'static str,
}

/// What the rest-curve fit works on: the trials' model, the held rest fiber lengths (m, one per
/// estimated muscle), the curves' origins (s = 0), the measured moments (N·m, one per trial)
/// and the prior's centre (the model's parameters).
pub struct RestCurveProblem<'a> {
    pub knee: &'a KneeMomentModel,
    pub references: &'a [f64],
    pub origin: &'a [MuscleParameters],
    pub measured: &'a [f64],
    pub centre: &'a [MuscleParameters],
    pub settings: &'a RestCurveSettings,
}

/// The rest-curve estimate from Phase II's parameters `phase_two`, with noise σ `noise` (N·m,
/// and its source) when known and the prior's τ `prior_sd` when one is used (module doc);
/// returns the fit and the prior it used.
pub fn fit_on_rest_curves(
    problem: &RestCurveProblem,
    phase_two: &[MuscleParameters],
    noise: Option<(f64, &'static str)>,
    prior_sd: Option<f64>,
    progress: &mut dyn FnMut(&str),
) -> Result<(RestCurveFit, Option<AppliedPrior>), FunctionalError> {
    let mut starts = vec![phase_two.to_vec()];
    if let (Some((noise_sd, noise_source)), Some(coordinate_sd)) = (noise, prior_sd) {
        if noise_sd > NEGLIGIBLE_NOISE {
            let prior = AppliedPrior { coordinate_sd, noise_sd, noise_source, estimate: MAXIMUM_A_POSTERIORI };
            let map = problem.fit(&starts, Some(prior), true, progress)?;
            return problem.posterior(map, prior, progress);
        }
    }
    let plain = problem.fit(&starts, None, true, progress)?;
    let plain = problem.recentred(plain, progress)?;
    let Some(coordinate_sd) = prior_sd else { return Ok((plain, None)) };
    let noise_sd = match noise {
        Some((sd, _)) => sd,
        None => problem.evidence(&plain, coordinate_sd)?,
    };
    if noise_sd <= NEGLIGIBLE_NOISE {
        return Ok((plain, None));
    }
    starts.insert(0, plain.parameters);
    let prior = AppliedPrior { coordinate_sd, noise_sd, noise_source: MARGINAL_LIKELIHOOD, estimate: MAXIMUM_A_POSTERIORI };
    let (map, prior) = evidence_fixed_point(problem, &starts, prior, progress)?;
    problem.posterior(map, prior, progress)
}

/// The MAP fit from `starts` (global search) with σ re-estimated at each estimate and refitted
/// locally until it settles; the fit keeps the global search's tables.
fn evidence_fixed_point(
    problem: &RestCurveProblem,
    starts: &[Vec<MuscleParameters>],
    mut prior: AppliedPrior,
    progress: &mut dyn FnMut(&str),
) -> Result<(RestCurveFit, AppliedPrior), FunctionalError> {
    progress(&format!("rest curves: σ = {:.3} N·m by the marginal likelihood under the prior; again with the prior", prior.noise_sd));
    let mut curves = problem.fit(starts, Some(prior), true, progress)?;
    let search = curves.search.take();
    for _ in 0..EVIDENCE_ROUNDS {
        let noise_sd = problem.evidence(&curves, prior.coordinate_sd)?;
        if (noise_sd - prior.noise_sd).abs() <= EVIDENCE_TOLERANCE * prior.noise_sd || noise_sd <= NEGLIGIBLE_NOISE {
            return Ok((RestCurveFit { search, ..curves }, prior));
        }
        prior.noise_sd = noise_sd;
        progress(&format!("rest curves: σ = {noise_sd:.3} N·m at the estimate; refitted from it"));
        curves = problem.fit(std::slice::from_ref(&curves.parameters), Some(prior), false, progress)?;
    }
    progress(&format!("rest curves: σ has not settled within {EVIDENCE_ROUNDS} refits; the estimate is taken at σ = {:.3} N·m", prior.noise_sd));
    Ok((RestCurveFit { search, ..curves }, prior))
}

/// Whether `fit`'s moments are within [`NEGLIGIBLE_NOISE`] of the measured ones (RMS).
fn reproduced(fit: &RestCurveFit) -> bool {
    let squares: f64 = fit.residuals.iter().map(|r| r * r).sum();
    squares <= NEGLIGIBLE_NOISE.powi(2) * fit.residuals.len() as f64
}

impl RestCurveProblem<'_> {
    /// The rest-curve fit from `starts` (with the global search when `global_search`).
    fn fit(&self, starts: &[Vec<MuscleParameters>], prior: Option<AppliedPrior>, global_search: bool, progress: &mut dyn FnMut(&str)) -> Result<RestCurveFit, FunctionalError> {
        let settings = RestCurveSettings { global_search: global_search && self.settings.global_search, ..*self.settings };
        let prior = prior.map(|p| RestCurvePrior { model: self.centre, coordinate_sd: p.coordinate_sd, noise_sd: p.noise_sd });
        let curves = fit_rest_curves(self.knee, self.references, self.origin, self.measured, starts, prior, &settings)?;
        progress(&format!(
            "rest curves: {:?} after {} iterations ({} starts, prior weight {:.3} N·m), largest moment error {:.3e} N·m",
            curves.status,
            curves.iterations,
            curves.starts,
            curves.prior_weight,
            curves.residuals.iter().fold(0.0, |m: f64, r| m.max(r.abs()))
        ));
        Ok(curves)
    }

    /// The global search again with the curves' origins at `fit` (its tables and starts centred
    /// there), while that lowers the cost by more than [`RECENTRED_GAIN`], at most
    /// [`RECENTRED_SEARCHES`] times, and not once the fit reproduces the moments to within
    /// [`NEGLIGIBLE_NOISE`] (RMS). A search centred elsewhere samples other basins: from a
    /// guess 25 % off, the search around it can miss the truth that the search around its own
    /// result finds. Where no search can run around the fit (a curve without a point in the
    /// span about it, [`FunctionalError::NoRestCurvePoint`]), the fit stands, and the progress
    /// says so; any other error of the search is returned.
    fn recentred(&self, mut fit: RestCurveFit, progress: &mut dyn FnMut(&str)) -> Result<RestCurveFit, FunctionalError> {
        if !self.settings.global_search {
            return Ok(fit);
        }
        for _ in 0..RECENTRED_SEARCHES {
            if reproduced(&fit) {
                break;
            }
            let again = match fit_rest_curves(self.knee, self.references, &fit.parameters, self.measured, std::slice::from_ref(&fit.parameters), None, self.settings) {
                Ok(again) => again,
                Err(error @ FunctionalError::NoRestCurvePoint { .. }) => {
                    progress(&format!("rest curves: no search around the fit ({error}); the fit stands"));
                    break;
                }
                Err(error) => return Err(error),
            };
            if again.cost >= (1.0 - RECENTRED_GAIN) * fit.cost {
                break;
            }
            progress(&format!("rest curves: the search around the fit found a lower cost ({:.3e} → {:.3e} N²·m²)", fit.cost, again.cost));
            fit = again;
        }
        Ok(fit)
    }

    /// The estimate from the MAP fit `map` under `prior`: its posterior mean when the settings
    /// ask for one and it can be sampled, else `map` itself.
    fn posterior(&self, mut map: RestCurveFit, prior: AppliedPrior, progress: &mut dyn FnMut(&str)) -> Result<(RestCurveFit, Option<AppliedPrior>), FunctionalError> {
        let Some(settings) = &self.settings.posterior else { return Ok((map, Some(prior))) };
        let curve_prior = RestCurvePrior { model: self.centre, coordinate_sd: prior.coordinate_sd, noise_sd: prior.noise_sd };
        match move_to_posterior_mean(self.knee, &mut map, self.measured, curve_prior, settings)? {
            Some(posterior) => {
                progress(&format!("rest curves: posterior mean from {} Gibbs samples at σ = {:.3} N·m", posterior.samples, prior.noise_sd));
                Ok((map, Some(AppliedPrior { estimate: POSTERIOR_MEAN, ..prior })))
            }
            None => {
                progress("rest curves: the posterior mean could not be sampled (no table or no curve point at the mean); the estimate is the MAP fit");
                Ok((map, Some(prior)))
            }
        }
    }

    /// σ by the marginal likelihood under a prior of sd τ = `coordinate_sd`, linearised at `curves`.
    fn evidence(&self, curves: &RestCurveFit, coordinate_sd: f64) -> Result<f64, FunctionalError> {
        let information = RestCurveInformation::new(self.knee, &curves.parameters, self.references, 1.0)?;
        Ok(information.noise_by_evidence(&curves.residuals, coordinate_sd, self.centre))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tuning::functional::test_data::{subject01, train01};
    use crate::tuning::functional::{SetSelection, TrialOptions};

    /// A search around the fit that finds a rest curve without a point in its span (rect_fem's
    /// rest fiber length 10 m: no L_ts gives it) leaves the fit as it is and says so; any other
    /// error of the search (here, one moment short) is returned.
    #[test]
    fn a_recentred_search_that_cannot_run_leaves_the_fit() {
        let data = train01(&TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() });
        let knee = KneeMomentModel::new(&subject01(), &data).unwrap();
        let model = knee.nominal_parameters();
        let references: Vec<f64> = model.iter().map(|p| data.reference_rest_fiber_length(&p.name).unwrap()).collect();
        let measured: Vec<f64> = data.measured_moments().iter().map(|m| m + 3.0).collect();
        let settings = RestCurveSettings::default();
        let fit = fit_rest_curves(&knee, &references, &model, &measured, &[], None, &settings).unwrap();
        let mut unreachable = references.clone();
        unreachable[0] = 10.0;
        let error = fit_rest_curves(&knee, &unreachable, &fit.parameters, &measured, &[], None, &settings).unwrap_err();
        assert!(matches!(&error, FunctionalError::NoRestCurvePoint { muscle, .. } if muscle == "rect_fem_r"), "{error}");

        let problem = RestCurveProblem { knee: &knee, references: &unreachable, origin: &model, measured: &measured, centre: &model, settings: &settings };
        let mut said = Vec::new();
        let kept = problem.recentred(fit.clone(), &mut |line: &str| said.push(line.to_string())).unwrap();
        assert_eq!(kept.parameters, fit.parameters);
        assert!(said.iter().any(|line| line.contains("no search around the fit") && line.contains("rect_fem_r")), "{said:?}");

        let short = RestCurveProblem { measured: &measured[1..], ..problem };
        assert!(matches!(short.recentred(fit, &mut |_: &str| {}), Err(FunctionalError::Parameters { .. })));
    }
}
