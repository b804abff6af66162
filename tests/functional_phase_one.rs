//! Phase I of functional scaling on the public dynamometry subject train01 (set5): the true
//! parameters (ground truth beside the data, read only here) lie inside every muscle's feasible
//! set, and the hot start fits the measured moments far better than the scaled model does.

use std::path::Path;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{
    feasible_sets, hot_start, DynamometryData, FeasibleSetSettings, KneeMomentModel, MuscleParameters, SetSelection, TrialOptions,
};
use serde_json::Value;

const MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";
const SUBJECT: &str = "fixtures/dynamometry/train01";

fn set5() -> (DynamometryData, KneeMomentModel) {
    let options = TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() };
    let data = DynamometryData::read(Path::new(SUBJECT), &options).unwrap();
    let model = ModelSpec::read(&OsimDocument::read(Path::new(MODEL)).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&model, &data).unwrap();
    (data, knee)
}

fn truth(muscle: &str) -> (f64, f64) {
    let truth: Value = serde_json::from_str(&std::fs::read_to_string(Path::new(SUBJECT).join("ground_truth.json")).unwrap()).unwrap();
    let p = &truth["true_parameters"][muscle];
    (p["optimal_fiber_length"].as_f64().unwrap(), p["tendon_slack_length"].as_f64().unwrap())
}

fn max_error(moments: &[f64], measured: &[f64]) -> f64 {
    moments.iter().zip(measured).map(|(m, y)| (m - y).abs()).fold(0.0, f64::max)
}

#[test]
fn the_truth_lies_in_every_feasible_set_and_the_hot_start_fits_the_moments() {
    let (data, knee) = set5();
    let nominal = knee.nominal_parameters();
    let references: Vec<Option<f64>> = nominal.iter().map(|p| data.reference_rest_fiber_length(&p.name)).collect();
    let sets = feasible_sets(&knee, &references, &nominal, &FeasibleSetSettings::default()).unwrap();
    for set in &sets {
        let (optimal, slack) = truth(&set.muscle);
        let ratio = slack / optimal;
        assert!(set.feasible.len() >= 3 && set.outside_rest_tolerance > 0, "{set:?}");
        assert!((set.ratio_bounds[0]..=set.ratio_bounds[1]).contains(&ratio), "{}: true ρ {ratio} outside {:?}", set.muscle, set.ratio_bounds);
        let delta = set.line.delta(optimal, slack);
        assert!(delta.abs() <= set.delta_max, "{}: true δ {delta} beyond ±{}", set.muscle, set.delta_max);
        let (back_optimal, back_slack) = set.line.lengths(ratio, delta);
        assert!((back_optimal - optimal).abs() < 1e-12 && (back_slack - slack).abs() < 1e-12);
    }
    let measured = data.measured_moments();
    let start = hot_start(&knee, &sets, &nominal, &measured).unwrap();
    let nominal_error = max_error(&knee.moments(&nominal).unwrap(), &measured);
    let hot_error = max_error(&knee.moments(&start.parameters).unwrap(), &measured);
    assert!((hot_error - start.max_moment_error).abs() < 1e-9, "{hot_error} vs {}", start.max_moment_error);
    assert!(hot_error < 0.2 * nominal_error, "hot start {hot_error} N·m, scaled model {nominal_error} N·m");
    for (chosen, set) in start.parameters.iter().zip(&sets) {
        assert!(set.feasible.contains(&(chosen.optimal_fiber_length, chosen.tendon_slack_length)), "{chosen:?}");
    }
}

#[test]
fn a_rest_tolerance_no_grid_point_meets_is_reported_for_the_muscle() {
    let (data, knee) = set5();
    let nominal: Vec<MuscleParameters> = knee.nominal_parameters();
    let references: Vec<Option<f64>> = nominal.iter().map(|p| data.reference_rest_fiber_length(&p.name)).collect();
    let settings = FeasibleSetSettings { rest_tolerance: 1e-6, ..FeasibleSetSettings::default() };
    let message = feasible_sets(&knee, &references, &nominal, &settings).unwrap_err().to_string();
    assert!(message.contains("rect_fem_r") && message.contains("outside the rest-length tolerance"), "{message}");
}
