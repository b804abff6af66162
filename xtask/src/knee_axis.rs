//! Functional knee axis rows of the validation table: the 50-seed synthetic study (issue 7) for
//! GaL and SARA, with least-squares and Kalman-smoothed poses, marker noise only and with
//! soft-tissue artefact. Prints the study's table (mean / max errors) and adds one row per goal.

use std::time::Instant;

use osim_tune::tuning::knee_axis::{AxisMethod, KalmanSettings, PoseMethod};
use osim_tune::validation::knee_axis::{axis_study, Condition, StudySummary, SyntheticKneeSettings};

use crate::validate::Row;

/// Seeds of the study.
const SEEDS: std::ops::Range<u64> = 0..50;

pub fn rows() -> Vec<Row> {
    let poses = [("least squares", PoseMethod::LeastSquares), ("Kalman", PoseMethod::KalmanSmoother(KalmanSettings::default()))];
    let started = Instant::now();
    let mut summaries = Vec::new();
    for condition in [Condition::Noise, Condition::SoftTissue] {
        for (label, pose) in &poses {
            summaries.extend(axis_study(&SyntheticKneeSettings::new(0, condition), pose, SEEDS).into_iter().map(|s| (*label, s)));
        }
    }
    print_study(&summaries, started.elapsed().as_secs_f64());
    summaries.iter().flat_map(|(label, summary)| summary_rows(label, summary)).collect()
}

fn print_study(summaries: &[(&str, StudySummary)], seconds: f64) {
    println!("knee axis, synthetic study ({} seeds each, {seconds:.1} s): errors against the generating axis", SEEDS.end - SEEDS.start);
    println!(
        "{:<12} {:<8} {:<14} {:>18} {:>18} {:>18}  failed",
        "condition", "method", "poses", "transversal ° mean/max", "frontal ° mean/max", "sagittal mm mean/max"
    );
    for (label, s) in summaries {
        println!(
            "{:<12} {:<8} {:<14} {:>9.2} /{:>7.2} {:>9.2} /{:>7.2} {:>9.2} /{:>7.2}  {}",
            condition_name(s.condition),
            method_name(s.method),
            label,
            s.mean.transversal.to_degrees(),
            s.max.transversal.to_degrees(),
            s.mean.frontal.to_degrees(),
            s.max.frontal.to_degrees(),
            s.mean.sagittal * 1e3,
            s.max.sagittal * 1e3,
            s.failures
        );
        if let Some(failure) = &s.first_failure {
            println!("    first failure: {failure}");
        }
    }
    println!();
}

/// One row per goal (values in degrees or millimetres), and one for failed fits.
fn summary_rows(label: &str, summary: &StudySummary) -> Vec<Row> {
    let name = format!("knee axis {} {}, {label}", method_name(summary.method), condition_name(summary.condition));
    let reference = "generating axis, 50 seeds".to_owned();
    let mut rows = vec![Row {
        what: format!("{name}: failed fits"),
        reference: reference.clone(),
        worst: summary.failures as f64,
        tolerance: 0.0,
        at: summary.first_failure.clone().unwrap_or_default(),
    }];
    for (what, value, goal) in summary.goals() {
        let (value, goal, unit) = if what.ends_with("(m)") { (value * 1e3, goal * 1e3, "mm") } else { (value.to_degrees(), goal.to_degrees(), "°") };
        let what = format!("{name}: {}({unit})", what.replace("(rad)", "").replace("(m)", ""));
        rows.push(Row { what, reference: reference.clone(), worst: value, tolerance: goal, at: String::new() });
    }
    rows
}

fn condition_name(condition: Condition) -> &'static str {
    match condition {
        Condition::Noise => "noise",
        Condition::SoftTissue => "soft tissue",
    }
}

fn method_name(method: AxisMethod) -> &'static str {
    match method {
        AxisMethod::Gal => "GaL",
        AxisMethod::Sara => "SARA",
    }
}
