//! The fast slice of `cargo xtask validate`'s functional-scaling study: noise-free fits of the
//! OpenSim-generated subjects (ground truth beside them) from every 13th of the thesis' 81
//! initial guesses (train01) and from five of them (train03, among them guesses from which an
//! earlier search ended in another basin) must land within 1 % of every true L_opt and L_ts.

mod common;

use common::fixture;
use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{DynamometryData, FitSettings, KneeMomentModel, MuscleParameters, SetSelection, TrialOptions};
use osim_tune::validation::functional::{fit_errors, thesis_initial_guesses, GroundTruth, StudySubject};

/// The subject's set5 trials, the model, its ground truth and the noise-free moments
/// (`knee_moment_true_Nm`, which equal the measured ones where the subject has no noise).
fn subject(name: &str) -> (ModelSpec, DynamometryData, Vec<MuscleParameters>, Vec<f64>) {
    let spec = ModelSpec::read(&OsimDocument::read(&fixture("golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
    let folder = fixture(&format!("dynamometry/{name}"));
    let data = DynamometryData::read(&folder, &TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() }).unwrap();
    let truth = GroundTruth::read(&folder).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let parameters = truth.parameters(&knee.nominal_parameters()).unwrap();
    let moments = truth.noise_free_moments(&data.trials).unwrap();
    (spec, data, parameters, moments)
}

/// Every L_opt and L_ts within 1 % from the thesis guesses `picked` (of the 81).
fn recovers_from_guesses(name: &str, picked: &[usize]) {
    let (spec, data, truth, moments) = subject(name);
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let study = StudySubject { spec: &spec, knee: &knee, data: &data, truth: &truth };
    let guesses = thesis_initial_guesses(&truth, &data, 81);
    // The moments are noise-free even where the subject file gives a σ (train03).
    let settings = FitSettings { noise_sd: Some(0.0), ..FitSettings::default() };
    for &g in picked {
        let (errors, converged) = fit_errors(&study, &guesses[g], &moments, &settings).unwrap();
        assert!(converged, "{name}, guess {g}: not converged");
        for (p, [optimal, slack]) in truth.iter().zip(&errors) {
            assert!(optimal.abs() < 0.01 && slack.abs() < 0.01, "{name}, guess {g}, {}: L_opt {:+.2} %, L_ts {:+.2} %", p.name, 100.0 * optimal, 100.0 * slack);
        }
    }
}

#[test]
fn train01_noise_free_from_thesis_guesses() {
    recovers_from_guesses("train01", &[0, 13, 26, 39, 52, 65, 78]);
}

/// train03's fibre of vas_med_r is slack at rest (the rest length is its minimum): its (L_opt,
/// L_ts) lie on the clamped branch of the rest curve.
#[test]
fn train03_noise_free_from_thesis_guesses() {
    recovers_from_guesses("train03", &[0, 1, 10, 39, 78]);
}
