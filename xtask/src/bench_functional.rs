//! `cargo xtask bench`, functional scaling (issue 6) on train01 set5 (8 muscles, five angles per
//! direction): one fit (Phase I, hot start, Phase II, rest-curve fit), the same with the
//! report's analyses, and the thesis' 81-guess study (the guesses spread over the machine's
//! cores); goals < 1 s and < 60 s. Memory: the peak resident set (VmHWM) over these runs, the
//! mark reset before them (else the process's peak so far).

use std::time::Instant;

use rayon::prelude::*;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{estimate, fit, DynamometryData, FitSettings, KneeMomentModel, SetSelection, TrialOptions};
use osim_tune::validation::functional::thesis_initial_guesses;

use crate::bench::{median_seconds, print_peak_resident, reset_peak_resident};
use crate::root;

const REPEATS: usize = 5;

pub fn run() -> Result<(), Box<dyn std::error::Error>> {
    let options = TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() };
    let data = DynamometryData::read(&root().join("fixtures/dynamometry/train01"), &options)?;
    let spec = ModelSpec::read(&OsimDocument::read(&root().join("fixtures/golden/scale/subject01_simbody.osim"))?)?;
    let knee = KneeMomentModel::new(&spec, &data)?;
    let settings = FitSettings::default();
    let (initial, measured) = (knee.nominal_parameters(), data.measured_moments());
    let reset = reset_peak_resident();
    let one = median_seconds(REPEATS, || estimate(&spec, &knee, &data, &initial, &measured, &settings, &mut |_| {}).map(|_| ()))?;
    let reported = median_seconds(REPEATS, || fit(&spec, &knee, &data, &settings, &mut |_| {}).map(|_| ()))?;
    let guesses = thesis_initial_guesses(&initial, &data, 6);
    let start = Instant::now();
    guesses.par_iter().try_for_each(|guess| estimate(&spec, &knee, &data, guess, &measured, &settings, &mut |_| {}).map(|_| ()))?;
    let study = start.elapsed().as_secs_f64();
    println!("functional scaling: train01 set5 (8 muscles, {} trials)", data.trials.len());
    println!("  one fit (Phase I, II, rest curves)       {:>8.1} ms  (goal < 1 s: {})", one * 1e3, verdict(one < 1.0));
    println!("  with the report's analyses               {:>8.1} ms", reported * 1e3);
    println!("  {} initial guesses ({} threads)             {:>8.1} s   (goal < 60 s: {})", guesses.len(), rayon::current_num_threads(), study, verdict(study < 60.0));
    print_peak_resident(reset, "these runs");
    Ok(())
}

fn verdict(met: bool) -> &'static str {
    if met { "met" } else { "NOT met" }
}
