//! Whether the single-cause ranking (`cause.rs`) names the model deficiency, weighed against the
//! moment noise: the ranking always has a best candidate, but with noisy moments it may be no
//! better than the initial model, than other candidates, or not enough on its own.
//!
//! With Gaussian moment noise of sd σ, a candidate leaving the residual sum of squares
//! SSR = n·RMS² has −2 ln(likelihood) = SSR/σ² + const, so the evidence for candidate a over b
//! is 2 ln K = (SSR_b − SSR_a)/σ², minus ln n per extra parameter (the Schwarz/BIC
//! approximation of the Bayes factor K). [`STRONG_EVIDENCE`] is Kass & Raftery's (1995)
//! "very strong" (2 ln K > 10). In order:
//! 1. [`Verdict::NoEffect`]: the best candidate is not very strongly better than the initial
//!    model (no change, as many parameters fewer as the candidate fits: one, two for an axis
//!    moved in its plane);
//! 2. [`Verdict::NotSingle`]: it leaves more than noise, SSR/σ² above the 99 % quantile of
//!    χ²(n − k) for its k parameters: no one cause explains the moments;
//! 3. [`Verdict::Named`]: it beats every other candidate very strongly;
//!    [`Verdict::MuscleNamed`]: it beats every candidate of the other muscles, not its
//!    muscle's other parameter; else [`Verdict::Ambiguous`], listing the candidates within
//!    [`STRONG_EVIDENCE`] of it.

use serde::Serialize;

use super::cause::{Cause, SingleCause};
use super::parameters::Parameter;

/// 2 ln K of Kass & Raftery's "very strong" evidence.
pub const STRONG_EVIDENCE: f64 = 10.0;

/// Moments agreeing to this (N·m) are taken as exact: σ is never taken smaller (OpenSim's
/// moments are printed to 10⁻⁶ N·m and reproduced to about that).
pub const MOMENT_RESOLUTION: f64 = 1e-5;

/// The standard normal's 0.99 quantile, for the χ² quantile of the goodness-of-fit test.
const NORMAL_QUANTILE_99: f64 = 2.326_347_874_040_841;

/// What the single-cause ranking says, at the noise σ it was weighed against.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CauseVerdict {
    pub verdict: Verdict,
    /// σ, N·m, and where it came from (the report's σ; the moments' rounding when the fit was exact).
    pub noise_sd: f64,
    pub noise_source: String,
    /// 2 ln K of the best candidate over the initial model (with its k·ln n penalty) and over the
    /// runner-up.
    pub evidence_over_initial: f64,
    pub evidence_over_runner_up: f64,
    /// SSR/σ² of the best candidate and the 99 % quantile of χ²(n − k) it is held to.
    pub best_chi_square: f64,
    pub chi_square_limit: f64,
}

/// The verdict proper.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Verdict {
    NoEffect,
    NotSingle,
    Named(Cause),
    /// The muscle, and its parameters that explain the moments alike (best first).
    MuscleNamed { muscle: String, parameters: Vec<Parameter> },
    /// The candidates within [`STRONG_EVIDENCE`] of the best, best first.
    Ambiguous { candidates: Vec<Cause> },
}

impl CauseVerdict {
    /// A sentence for the report.
    pub fn describe(&self) -> String {
        match &self.verdict {
            Verdict::NoEffect => "no single change is supported beyond the noise".to_string(),
            Verdict::NotSingle => "no single parameter explains the moments: more than one cause (see the full fit)".to_string(),
            Verdict::Named(cause) => format!("named: {}", cause.describe()),
            Verdict::MuscleNamed { muscle, parameters } => {
                format!("named: {muscle} (its {} explain the moments alike)", parameters.iter().map(|p| p.symbol()).collect::<Vec<_>>().join(" and "))
            }
            Verdict::Ambiguous { candidates } => {
                format!("not resolved between {}", candidates.iter().map(Cause::describe).collect::<Vec<_>>().join(", "))
            }
        }
    }
}

/// What is known of the moment noise σ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoiseLevel {
    /// Given, from the subject file, or estimated from the fit (N·m).
    Estimated(f64),
    /// The moments are noise-free (the subject file says so, or the full fit reproduced them):
    /// σ is [`MOMENT_RESOLUTION`].
    Exact,
    /// Nothing estimates it (no more trials than the fit's parameters): the best candidate's
    /// residuals, √(SSR/(n − k)), stand in for it, so its χ² test cannot fail.
    Unknown,
}

/// The verdict on `causes` (best first, as [`single_causes`](super::single_causes) returns
/// them; `None` for fewer than two) from n = `trials` moments; σ is raised to
/// [`MOMENT_RESOLUTION`], and `noise_source` says where a known σ came from.
pub fn cause_verdict(causes: &[SingleCause], trials: usize, noise: NoiseLevel, noise_source: &str) -> Option<CauseVerdict> {
    let (best, runner_up) = (causes.first()?, causes.get(1)?);
    let degrees = trials.saturating_sub(best.variables).max(1);
    let (noise_sd, noise_source) = match noise {
        NoiseLevel::Estimated(sd) => (sd, noise_source),
        NoiseLevel::Exact => (0.0, noise_source),
        NoiseLevel::Unknown => (best.rms_after * (trials as f64 / degrees as f64).sqrt(), "the best candidate's residuals (no noise estimate)"),
    };
    let noise_sd = noise_sd.max(MOMENT_RESOLUTION);
    let n = trials as f64;
    let chi_square = |rms: f64| n * rms * rms / (noise_sd * noise_sd);
    let evidence = |other: &SingleCause| chi_square(other.rms_after) - chi_square(best.rms_after) - (best.variables as f64 - other.variables as f64) * n.ln();
    let evidence_over_initial = chi_square(best.rms_before) - chi_square(best.rms_after) - best.variables as f64 * n.ln();
    let best_chi_square = chi_square(best.rms_after);
    let chi_square_limit = chi_square_quantile_99(degrees);
    let close: Vec<&SingleCause> = causes[1..].iter().filter(|c| evidence(c) < STRONG_EVIDENCE).collect();
    let verdict = if evidence_over_initial < STRONG_EVIDENCE {
        Verdict::NoEffect
    } else if best_chi_square > chi_square_limit {
        Verdict::NotSingle
    } else if close.is_empty() {
        Verdict::Named(best.cause.clone())
    } else if let Some(parameters) = same_muscle(best, &close) {
        Verdict::MuscleNamed { muscle: best.cause.muscle().unwrap_or_default().to_string(), parameters }
    } else {
        Verdict::Ambiguous { candidates: std::iter::once(best).chain(close).map(|c| c.cause.clone()).collect() }
    };
    Some(CauseVerdict {
        verdict,
        noise_sd,
        noise_source: noise_source.to_string(),
        evidence_over_initial,
        evidence_over_runner_up: evidence(runner_up),
        best_chi_square,
        chi_square_limit,
    })
}

/// The parameters of `best` and `close` (best first) when all are parameters of one muscle.
fn same_muscle(best: &SingleCause, close: &[&SingleCause]) -> Option<Vec<Parameter>> {
    let muscle = best.cause.muscle()?;
    std::iter::once(best)
        .chain(close.iter().copied())
        .map(|c| match &c.cause {
            Cause::Muscle { muscle: m, parameter } if m == muscle => Some(*parameter),
            _ => None,
        })
        .collect()
}

/// The 0.99 quantile of χ²(k) by Wilson & Hilferty's (1931) cube-root normal approximation,
/// k·(1 − 2/(9k) + z·√(2/(9k)))³ (relative error below 0.5 % for k ≥ 2).
fn chi_square_quantile_99(k: usize) -> f64 {
    let k = k as f64;
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + NORMAL_QUANTILE_99 * a.sqrt()).powi(3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cause(muscle: &str, parameter: Parameter, rms_after: f64) -> SingleCause {
        SingleCause { cause: Cause::Muscle { muscle: muscle.into(), parameter }, initial: 1.0, fitted: 1.0, rms_before: 10.0, rms_after, at_minimum: true, variables: 1, axis_move: None, unit_noise_sd: 0.1, residuals: Vec::new() }
    }

    #[test]
    fn a_two_parameter_cause_pays_for_its_second_parameter() {
        let axis = SingleCause { cause: Cause::AxisOffset { joint: "knee".into() }, variables: 2, ..cause("a", Parameter::TendonSlackLength, 1.0) };
        // n = 20, σ = 1: 20·(1.28² − 1) = 12.8 ahead of a one-parameter candidate, less ln 20 = 3.0:
        // below 10, not named.
        let causes = [axis, cause("b", Parameter::TendonSlackLength, 1.28)];
        let verdict = cause_verdict(&causes, 20, NoiseLevel::Estimated(1.0), "given").unwrap();
        assert!((verdict.evidence_over_runner_up - (20.0 * (1.28f64.powi(2) - 1.0) - 20f64.ln())).abs() < 1e-12, "{verdict:?}");
        assert!((verdict.evidence_over_initial - (20.0 * 99.0 - 2.0 * 20f64.ln())).abs() < 1e-9, "{verdict:?}");
        assert!(matches!(verdict.verdict, Verdict::Ambiguous { .. }), "{verdict:?}");
    }

    #[test]
    fn the_chi_square_quantile_matches_the_tables() {
        // 0.99 quantiles of χ²(k), the regularised incomplete gamma function inverted.
        for (k, table) in [(2, 9.210), (9, 21.666), (30, 50.892), (69, 99.228)] {
            let approx = chi_square_quantile_99(k);
            assert!((approx / table - 1.0).abs() < 5e-3, "k {k}: {approx} vs {table}");
        }
    }

    #[test]
    fn a_cause_far_ahead_of_the_rest_is_named() {
        let causes = [cause("a", Parameter::TendonSlackLength, 1.0), cause("a", Parameter::OptimalFiberLength, 1.5), cause("b", Parameter::TendonSlackLength, 2.0)];
        // n = 20, σ = 1: 2 ln K over the runner-up 20·(2.25 − 1) = 25.
        let verdict = cause_verdict(&causes, 20, NoiseLevel::Estimated(1.0), "given").unwrap();
        assert_eq!(verdict.verdict, Verdict::Named(Cause::Muscle { muscle: "a".into(), parameter: Parameter::TendonSlackLength }));
        assert!((verdict.evidence_over_runner_up - 25.0).abs() < 1e-12);
    }

    #[test]
    fn close_candidates_of_one_muscle_name_the_muscle_and_of_two_muscles_name_neither() {
        let one = [cause("a", Parameter::TendonSlackLength, 1.0), cause("a", Parameter::OptimalFiberLength, 1.1), cause("b", Parameter::TendonSlackLength, 2.0)];
        assert_eq!(cause_verdict(&one, 20, NoiseLevel::Estimated(1.0), "given").unwrap().verdict, Verdict::MuscleNamed { muscle: "a".into(), parameters: vec![Parameter::TendonSlackLength, Parameter::OptimalFiberLength] });
        let two = [cause("a", Parameter::TendonSlackLength, 1.0), cause("b", Parameter::OptimalFiberLength, 1.1), cause("a", Parameter::OptimalFiberLength, 2.0)];
        let candidates = vec![Cause::Muscle { muscle: "a".into(), parameter: Parameter::TendonSlackLength }, Cause::Muscle { muscle: "b".into(), parameter: Parameter::OptimalFiberLength }];
        let expected = Verdict::Ambiguous { candidates };
        assert_eq!(cause_verdict(&two, 20, NoiseLevel::Estimated(1.0), "given").unwrap().verdict, expected);
    }

    #[test]
    fn too_little_gain_is_no_effect_and_too_much_left_is_not_single() {
        // Gain 20·(100 − 99)/σ² = 20 at σ = 1 (no effect at σ = 2: 5 − ln 20 < 10) …
        let small = [cause("a", Parameter::TendonSlackLength, 99f64.sqrt()), cause("b", Parameter::TendonSlackLength, 10.0)];
        assert_eq!(cause_verdict(&small, 20, NoiseLevel::Estimated(2.0), "given").unwrap().verdict, Verdict::NoEffect);
        // … and at σ = 1 the best leaves χ² = 1980 against a limit near 36.
        assert_eq!(cause_verdict(&small, 20, NoiseLevel::Estimated(1.0), "given").unwrap().verdict, Verdict::NotSingle);
    }
}
