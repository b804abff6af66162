//! Phase II of functional scaling on a noisy subject whose min–max fit crawls: gen09 (σ = 10 N·m,
//! all 70 trials; OpenSim-generated, `fixtures/dynamometry/generated/`). The KKT test is never
//! met there; the relative stall test ends the solve where the remaining iterations lower the
//! largest moment error by less than the 0.1 % its pace allows.

use std::path::Path;

use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::solvers::nlp::{NlpSettings, NlpStatus};
use osim_tune::tuning::functional::{
    feasible_sets, hot_start, solve_phase_two, DynamometryData, FeasibleSetSettings, KneeMomentModel, PhaseTwo, PhaseTwoSettings, TrialOptions,
};

const MODEL: &str = "fixtures/golden/scale/subject01_simbody.osim";
const SUBJECT: &str = "fixtures/dynamometry/generated/gen09";

/// Phase II from the hot start with `settings`.
fn phase_two(settings: &PhaseTwoSettings) -> PhaseTwo {
    let data = DynamometryData::read(Path::new(SUBJECT), &TrialOptions::default()).unwrap();
    let model = ModelSpec::read(&OsimDocument::read(Path::new(MODEL)).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&model, &data).unwrap();
    let nominal = knee.nominal_parameters();
    let references: Vec<Option<f64>> = nominal.iter().map(|p| data.reference_rest_fiber_length(&p.name)).collect();
    let sets = feasible_sets(&knee, &references, &nominal, &FeasibleSetSettings::default()).unwrap();
    let measured = data.measured_moments();
    let start = hot_start(&knee, &sets, &nominal, &measured).unwrap();
    solve_phase_two(&knee, &sets, &start.parameters, &references, &measured, settings).unwrap()
}

#[test]
fn a_crawling_min_max_fit_ends_as_stalled_near_where_the_iteration_limit_would() {
    let stalled = phase_two(&PhaseTwoSettings::default());
    assert_eq!(stalled.status, NlpStatus::ObjectiveStalled, "{stalled:?}");
    assert!(stalled.converged() && stalled.iterations < 300, "{} iterations", stalled.iterations);
    let defaults = PhaseTwoSettings::default();
    let crawl = phase_two(&PhaseTwoSettings { nlp: NlpSettings { stall_iterations: 0, ..defaults.nlp }, ..defaults });
    assert_eq!(crawl.status, NlpStatus::MaxIterations, "without the stall test the fit crawls: {crawl:?}");
    let (t_stall, t_crawl) = (stalled.max_moment_error, crawl.max_moment_error);
    assert!(t_crawl <= t_stall && t_stall - t_crawl <= 1e-3 * t_crawl, "stalled at {t_stall} N·m, 300 iterations reach {t_crawl} N·m");
}
