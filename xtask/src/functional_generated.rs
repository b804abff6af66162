//! Held-out functional-scaling rows: noisy subjects made by the shared OpenSim 4.6 generator
//! with seeds no development run used (`oracle/gen_dynamometry_subjects.py`), in two families by
//! the model they were perturbed from: gen01–12 from the scaled subject01 model, as the public
//! subjects (σ = 5 N·m for gen01–06, 10 N·m for gen07–12), and gen13–18 from the generic
//! gait2392 model (σ = 5 N·m for gen13–15, 10 N·m for gen16–18). Each is fitted once on its own
//! noisy moments with its family's model as the prior's centre, as a lab would run it. Per family
//! and trial selection (set5, all 70 trials): fits that fail or do not converge (the posterior
//! mean, the MAP fit, Phase II alone as `--no-rest-curve` runs it, Garner & Pandy), the RMS
//! relative error of L_opt and L_ts over every muscle and subject of each estimator beside the
//! model's own, and whether the posterior mean's
//! sampled sd is calibrated: the errors in units of it (z) should be about standard normal, about
//! 5 % of them beyond 2.

use std::ops::RangeInclusive;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{estimate, DynamometryData, FitMethod, FitSettings, KneeMomentModel, MuscleParameters, SetSelection, TrialOptions};
use osim_tune::validation::functional::{relative_errors, Calibration, GroundTruth};

use crate::root;
use crate::validate::Row;

const SUBJECTS: &str = "fixtures/dynamometry/generated";

/// Subjects perturbed from one model, which is also the prior's centre of their fits.
struct Family {
    label: &'static str,
    model: &'static str,
    subjects: RangeInclusive<usize>,
}

const FAMILIES: [Family; 2] = [
    Family { label: "gen01–12 (subject01 model)", model: "fixtures/golden/scale/subject01_simbody.osim", subjects: 1..=12 },
    Family { label: "gen13–18 (generic model)", model: "models/gait2392_millard2012muscle.osim", subjects: 13..=18 },
];

/// Squared relative errors [L_opt, L_ts] summed over muscles and subjects, and their count.
#[derive(Default, Clone, Copy)]
struct Squares {
    sum: [f64; 2],
    count: usize,
}

impl Squares {
    fn add(&mut self, fitted: &[MuscleParameters], truth: &[MuscleParameters]) {
        for errors in relative_errors(fitted, truth) {
            (0..2).for_each(|i| self.sum[i] += errors[i] * errors[i]);
            self.count += 1;
        }
    }

    fn rms(&self) -> [f64; 2] {
        self.sum.map(|s| (s / self.count.max(1) as f64).sqrt())
    }
}

pub fn rows() -> Vec<Row> {
    println!("held-out OpenSim-generated subjects (σ = 5 / 10 N·m), RMS relative error over 8 muscles × the family's subjects, L_opt / L_ts:");
    let mut rows = Vec::new();
    for family in &FAMILIES {
        let spec = ModelSpec::read(&OsimDocument::read(&root().join(family.model)).expect("the base model")).expect("the base model");
        for (label, sets) in [("set5", SetSelection::Only(vec!["set5".into()])), ("all 70 trials", SetSelection::All)] {
            rows.extend(family_rows(family, &spec, label, sets));
        }
    }
    println!();
    rows
}

/// The rows of one family (its model read into `spec`) on one trial selection.
fn family_rows(family: &Family, spec: &ModelSpec, label: &str, sets: SetSelection) -> Vec<Row> {
    let root = root();
    // Name, settings, and whether the fit's sampled sd is calibrated (the posterior mean's).
    let estimators = [
        ("posterior mean", FitSettings::default(), true),
        ("MAP", FitSettings::maximum_a_posteriori(), false),
        ("Phase II alone", FitSettings { rest_curve: None, ..FitSettings::default() }, false),
        ("Garner & Pandy", FitSettings { method: FitMethod::GarnerPandy, ..FitSettings::default() }, false),
    ];
    let (mut model, mut errors, mut failed) = (Squares::default(), [Squares::default(); 4], Vec::new());
    let mut calibration = Calibration::default();
    for k in family.subjects.clone() {
        let folder = root.join(SUBJECTS).join(format!("gen{k:02}"));
        let data = DynamometryData::read(&folder, &TrialOptions { sets: sets.clone(), ..TrialOptions::default() }).expect("a generated subject");
        let knee = KneeMomentModel::new(spec, &data).expect("the knee-moment model");
        let initial = knee.nominal_parameters();
        let truth = GroundTruth::read(&folder).ok().and_then(|t| t.parameters(&initial)).expect("the subject's true parameters");
        let measured = data.measured_moments();
        model.add(&initial, &truth);
        for ((name, settings, calibrated), squares) in estimators.iter().zip(&mut errors) {
            match estimate(spec, &knee, &data, &initial, &measured, settings, &mut |_| {}) {
                Ok(fit) => {
                    squares.add(&fit.fitted, &truth);
                    if !fit.converged {
                        failed.push(format!("gen{k:02} {name}: {}", fit.status));
                    }
                    if *calibrated {
                        calibration.add(&fit.fitted, &truth, fit.sampled_sd.as_deref());
                    }
                }
                Err(e) => failed.push(format!("gen{k:02} {name}: {e}")),
            }
        }
    }
    let cell = |s: &Squares| format!("{:.2} / {:.2} %", 100.0 * s.rms()[0], 100.0 * s.rms()[1]);
    let [mean, mode, phase_two, garner_pandy] = &errors;
    println!(
        "  {} {label:<14} posterior mean {}   MAP {}   Phase II alone {}   Garner & Pandy {}   the model {}",
        family.label,
        cell(mean),
        cell(mode),
        cell(phase_two),
        cell(garner_pandy),
        cell(&model)
    );
    println!(
        "  {} {label:<14} posterior mean's error / its sampled sd: RMS {:.2}, beyond 2: {:.1} % of {} ({} muscle fits without a sampled sd)",
        family.label,
        calibration.rms(),
        100.0 * calibration.beyond_two(),
        calibration.z.len(),
        calibration.unsampled
    );
    let reference = format!("{}, {label}", family.label);
    let at = failed.join("; ");
    let mut rows = vec![
        Row { what: "generated: fits that fail or do not converge".into(), reference: reference.clone(), worst: failed.len() as f64, tolerance: 0.0, at },
        Row { what: "generated: RMS L_ts error, posterior mean".into(), reference: reference.clone(), worst: mean.rms()[1], tolerance: 0.01, at: String::new() },
        Row { what: "generated: RMS L_opt error, posterior mean / MAP's".into(), reference: reference.clone(), worst: mean.rms()[0] / mode.rms()[0], tolerance: 1.0, at: String::new() },
        Row { what: "generated: RMS L_opt error, posterior mean / model's".into(), reference: reference.clone(), worst: mean.rms()[0] / model.rms()[0], tolerance: 1.0, at: String::new() },
    ];
    rows.extend(calibration_rows(&calibration, &reference));
    rows
}

/// The sampled sd against the errors: at most 15 % of the errors beyond 2 sd (a normal error
/// has 4.6 %), and the RMS of error / sd between 1/2 and 2 (1 when calibrated).
fn calibration_rows(calibration: &Calibration, reference: &str) -> [Row; 3] {
    let what = |text: &str| format!("generated: posterior mean's error / sampled sd, {text}");
    [
        Row { what: what("share beyond 2"), reference: reference.into(), worst: calibration.beyond_two(), tolerance: 0.15, at: String::new() },
        Row { what: what("RMS (sd too small)"), reference: reference.into(), worst: calibration.rms(), tolerance: 2.0, at: String::new() },
        Row { what: what("1 / RMS (sd too large)"), reference: reference.into(), worst: 1.0 / calibration.rms(), tolerance: 2.0, at: format!("{} muscle fits without a sampled sd", calibration.unsampled) },
    ]
}
