//! Held-out functional-scaling rows: twelve noisy subjects made by the shared OpenSim 4.6
//! generator with seeds no development run used (`oracle/gen_dynamometry_subjects.py`; σ = 5 N·m
//! for gen01–06, 10 N·m for gen07–12), each fitted once on its own noisy moments with the
//! bundled model as the prior's centre, as a lab would run it. Per estimator (the default
//! posterior mean, the MAP fit) and trial selection (set5, all 70 trials): the RMS relative
//! error of L_opt and L_ts over every muscle and subject, beside the model's own; and whether
//! the posterior mean's sampled sd is calibrated: the errors in units of it (z) should be about
//! standard normal, about 5 % of them beyond 2.

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{estimate, DynamometryData, FitSettings, KneeMomentModel, MuscleParameters, SetSelection, TrialOptions};
use osim_tune::validation::functional::{relative_errors, Calibration, GroundTruth};

use crate::root;
use crate::validate::Row;

const SUBJECTS: &str = "fixtures/dynamometry/generated";
const MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";
const COUNT: usize = 12;

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
    let root = root();
    let spec = ModelSpec::read(&OsimDocument::read(&root.join(MODEL)).expect("the base model")).expect("the base model");
    let map = FitSettings::maximum_a_posteriori();
    let mut rows = Vec::new();
    println!("held-out OpenSim-generated subjects gen01–gen12 (σ = 5 / 10 N·m), RMS relative error over 8 muscles × 12 subjects, L_opt / L_ts:");
    for (label, sets) in [("set5", SetSelection::Only(vec!["set5".into()])), ("all 70 trials", SetSelection::All)] {
        let (mut model, mut mean, mut mode, mut failed) = (Squares::default(), Squares::default(), Squares::default(), Vec::new());
        let mut calibration = Calibration::default();
        for k in 1..=COUNT {
            let folder = root.join(SUBJECTS).join(format!("gen{k:02}"));
            let data = DynamometryData::read(&folder, &TrialOptions { sets: sets.clone(), ..TrialOptions::default() }).expect("a generated subject");
            let knee = KneeMomentModel::new(&spec, &data).expect("the knee-moment model");
            let initial = knee.nominal_parameters();
            let truth = GroundTruth::read(&folder).ok().and_then(|t| t.parameters(&initial)).expect("the subject's true parameters");
            let measured = data.measured_moments();
            model.add(&initial, &truth);
            for (settings, squares) in [(&FitSettings::default(), &mut mean), (&map, &mut mode)] {
                match estimate(&spec, &knee, &data, &initial, &measured, settings, &mut |_| {}) {
                    Ok(fit) => {
                        squares.add(&fit.fitted, &truth);
                        if settings.rest_curve.is_some_and(|r| r.posterior.is_some()) {
                            calibration.add(&fit.fitted, &truth, fit.sampled_sd.as_deref());
                        }
                    }
                    Err(e) => failed.push(format!("gen{k:02}: {e}")),
                }
            }
        }
        let cell = |s: &Squares| format!("{:.2} / {:.2} %", 100.0 * s.rms()[0], 100.0 * s.rms()[1]);
        println!("  {label:<14} posterior mean {}   MAP {}   the model {}", cell(&mean), cell(&mode), cell(&model));
        println!(
            "  {label:<14} posterior mean's error / its sampled sd: RMS {:.2}, beyond 2: {:.1} % of {} ({} muscle fits without a sampled sd)",
            calibration.rms(),
            100.0 * calibration.beyond_two(),
            calibration.z.len(),
            calibration.unsampled
        );
        let reference = format!("gen01–12, {label}");
        let at = failed.join("; ");
        rows.push(Row { what: "generated: fits that fail".into(), reference: reference.clone(), worst: failed.len() as f64, tolerance: 0.0, at });
        rows.push(Row { what: "generated: RMS L_ts error, posterior mean".into(), reference: reference.clone(), worst: mean.rms()[1], tolerance: 0.01, at: String::new() });
        rows.push(Row { what: "generated: RMS L_opt error, posterior mean / MAP's".into(), reference: reference.clone(), worst: mean.rms()[0] / mode.rms()[0], tolerance: 1.0, at: String::new() });
        rows.push(Row { what: "generated: RMS L_opt error, posterior mean / model's".into(), reference: reference.clone(), worst: mean.rms()[0] / model.rms()[0], tolerance: 1.0, at: String::new() });
        rows.extend(calibration_rows(&calibration, &reference));
    }
    println!();
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
