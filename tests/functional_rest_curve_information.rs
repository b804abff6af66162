//! The Fisher information on the rest curves against the fit it describes: to first order the
//! least-squares estimate moves by (JᵀJ)⁻¹Jᵀε when the moments move by ε, and a Gaussian prior
//! of sd τ centred at c moves it by (JᵀJ/σ² + I/τ²)⁻¹(c − s)/τ². Small changes keep the
//! second-order terms below the tolerances (stated per test).

mod common;

use common::{fixture, true_parameters};
use nalgebra::{DMatrix, DVector};
use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{
    fit_rest_curves, DynamometryData, KneeMomentModel, MuscleParameters, RestCurve, RestCurveInformation, RestCurvePrior, RestCurveSettings, SetSelection, TrialOptions,
};

struct Subject {
    knee: KneeMomentModel,
    truth: Vec<MuscleParameters>,
    references: Vec<f64>,
}

fn train01_set5() -> Subject {
    let spec = ModelSpec::read(&OsimDocument::read(&fixture("golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
    let data = DynamometryData::read(&fixture("dynamometry/train01"), &TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() }).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let truth = true_parameters(&fixture("dynamometry/train01"), knee.nominal_parameters());
    let references = truth.iter().map(|p| data.reference_rest_fiber_length(&p.name).unwrap()).collect();
    Subject { knee, truth, references }
}

/// The local rest-curve fit from the truth (no global search), run to the equilibria's precision.
fn local_fit(subject: &Subject, measured: &[f64], prior: Option<RestCurvePrior>) -> Vec<MuscleParameters> {
    let mut settings = RestCurveSettings { global_search: false, ..RestCurveSettings::default() };
    settings.least_squares.cost_tolerance = 1e-16;
    settings.least_squares.gradient_tolerance = 1e-12;
    settings.least_squares.step_tolerance = 1e-12;
    fit_rest_curves(&subject.knee, &subject.references, &subject.truth, measured, std::slice::from_ref(&subject.truth), prior, &settings).unwrap().parameters
}

/// Each fitted muscle's coordinate on the curve through the truth (s = 0 at the truth).
fn coordinates(subject: &Subject, fitted: &[MuscleParameters]) -> Vec<f64> {
    let mut workspace = subject.knee.estimated_muscles(&subject.truth).unwrap();
    (0..fitted.len())
        .map(|e| {
            let curve = RestCurve::new(&subject.knee, &mut workspace, e, subject.references[e], &subject.truth[e]).unwrap();
            curve.coordinate_of(&fitted[e]) - curve.coordinate_of(&subject.truth[e])
        })
        .collect()
}

/// Moments moved by ε (±3·10⁻⁴ N·m, alternating) move the estimate by (JᵀJ)⁻¹Jᵀε to within
/// 4 % of the largest move plus 10⁻⁶. The second-order terms grow fast along the weakly
/// identified gastrocnemius directions (at ε = 0.002 N·m they are 20 %), and the equilibria's
/// precision limits the fit to about 10⁻⁶ in s. The
/// Cramér–Rao sd is |dL/ds|·σ√(JᵀJ)⁻¹_ii, and dL_opt/ds = L_opt where the curve does not clamp.
#[test]
fn jacobian_predicts_the_least_squares_response() {
    let subject = train01_set5();
    let sigma = 5.0;
    let information = RestCurveInformation::new(&subject.knee, &subject.truth, &subject.references, sigma).unwrap();
    let j: &DMatrix<f64> = &information.fisher.jacobian;
    let epsilon = DVector::from_iterator(j.nrows(), (0..j.nrows()).map(|t| if t % 2 == 0 { 3e-4 } else { -3e-4 }));
    let normal = j.tr_mul(j).try_inverse().unwrap();
    let predicted = &normal * j.tr_mul(&epsilon);
    let clean = subject.knee.moments(&subject.truth).unwrap();
    let measured: Vec<f64> = clean.iter().zip(epsilon.iter()).map(|(m, e)| m + e).collect();
    let moved = coordinates(&subject, &local_fit(&subject, &measured, None));
    let largest = predicted.amax();
    for (e, (got, want)) in moved.iter().zip(predicted.iter()).enumerate() {
        assert!((got - want).abs() <= 0.04 * largest + 1e-6, "{}: Δs {got:.3e}, first order {want:.3e}", subject.truth[e].name);
    }
    for (e, bounds) in information.cramer_rao().iter().enumerate() {
        let sd_s = sigma * normal[(e, e)].sqrt();
        let [optimal, slack] = information.tangents[e];
        assert!((bounds[0].unwrap() - optimal.abs() * sd_s).abs() <= 1e-9 * optimal.abs() * sd_s, "{}: sd L_opt", subject.truth[e].name);
        assert!((bounds[1].unwrap() - slack.abs() * sd_s).abs() <= 1e-9 * slack.abs() * sd_s, "{}: sd L_ts", subject.truth[e].name);
        if optimal != 0.0 {
            assert!((optimal / subject.truth[e].optimal_fiber_length - 1.0).abs() < 1e-6, "{}: dL_opt/ds {optimal}, expected L_opt", subject.truth[e].name);
        }
    }
}

/// A prior centred 0.1 % above the true L_opt (τ = 0.1, σ = 5 N·m) on noise-free moments moves
/// the MAP estimate by the predicted pull, to within 4 % of the largest pull plus 10⁻⁶ (at 1 %
/// the second-order terms reach 8 %).
#[test]
fn prior_pull_predicts_the_map_estimate() {
    let subject = train01_set5();
    let (tau, sigma) = (0.1, 5.0);
    let centre: Vec<MuscleParameters> = subject
        .truth
        .iter()
        .map(|p| MuscleParameters { optimal_fiber_length: 1.001 * p.optimal_fiber_length, ..p.clone() })
        .collect();
    let information = RestCurveInformation::new(&subject.knee, &subject.truth, &subject.references, sigma).unwrap();
    let pull: Vec<[f64; 2]> = information
        .prior_pull(tau, sigma, &centre)
        .unwrap()
        .iter()
        .zip(&subject.truth)
        .map(|(m, p)| [m[0] / p.optimal_fiber_length, m[1] / p.tendon_slack_length])
        .collect();
    let clean = subject.knee.moments(&subject.truth).unwrap();
    let fitted = local_fit(&subject, &clean, Some(RestCurvePrior { model: &centre, coordinate_sd: tau, noise_sd: sigma }));
    let largest = pull.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(largest > 1e-4, "the prior should pull the estimate (largest {largest:.2e})");
    for ((got, want), truth) in fitted.iter().zip(&pull).zip(&subject.truth) {
        let moved = [got.optimal_fiber_length / truth.optimal_fiber_length - 1.0, got.tendon_slack_length / truth.tendon_slack_length - 1.0];
        for i in 0..2 {
            assert!((moved[i] - want[i]).abs() <= 0.04 * largest + 1e-6, "{} [{i}]: moved {:.4e}, predicted {:.4e}", truth.name, moved[i], want[i]);
        }
    }
    let posterior = information.posterior(tau, sigma).unwrap();
    let bounds = information.cramer_rao();
    for (e, (p, b)) in posterior.iter().zip(&bounds).enumerate() {
        assert!(p[0] <= b[0].unwrap() && p[0] <= tau * subject.truth[e].optimal_fiber_length * (1.0 + 1e-9), "{}: the posterior sd is below both the bound and the prior", subject.truth[e].name);
    }
}
