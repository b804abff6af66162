//! `osim-tune scale MODEL TRIALS/ -o OUT.osim`: functional scaling from a dynamometry folder.
//! Writes the model with only the fitted L_opt/L_ts changed and prints the report (text, or
//! JSON with `--json`; `--report FILE` also writes the JSON).

use std::path::{Path, PathBuf};

use crate::cli::{check_outputs, create_output_folders, write_files, Failure, Outcome};
use crate::figures::{diagnosis_figures, feasible_set_figures, moment_figures};
use crate::io::atomic::write_atomically;
use crate::io::osim::OsimDocument;
use crate::model::ModelSpec;
use crate::tuning::functional::{
    apply_cause, fit, CauseEdit, DynamometryData, FeasibleSetSettings, FitMethod, FitSettings, FunctionalFit, KneeMomentModel, Parameter, PhaseTwoSettings, RestCurveSettings, SetSelection,
    TrialOptions, Verdict, DEFAULT_PRIOR_SD, FOLDS, LAPLACE, SAMPLED, STRONG_EVIDENCE, SUBJECT_FILE,
};

use super::super::args::ScaleMethodArgument;

/// What the user asked for besides the files.
pub struct Request {
    pub sets: Option<Vec<String>>,
    /// The estimated muscles, replacing the subject file's.
    pub muscles: Option<Vec<String>>,
    pub settings: FitSettings,
    pub force: bool,
    pub report: Option<PathBuf>,
    /// Where to write the model extended by the named single cause.
    pub cause_model: Option<PathBuf>,
    /// Where to draw the fit's figures.
    pub figures: Option<PathBuf>,
    pub json: bool,
}

/// Whether `folder` holds a dynamometry subject file (one with `"trial_files"`).
pub fn is_dynamometry(folder: &Path) -> bool {
    std::fs::read_to_string(folder.join(SUBJECT_FILE))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .is_some_and(|subject| subject.get("trial_files").is_some())
}

/// The functional-scaling options of the command line.
pub struct Options {
    pub method: ScaleMethodArgument,
    pub rest_tolerance: Option<f64>,
    pub rest_constraint: Option<f64>,
    pub rest_curve: bool,
    pub prior_sd: Option<f64>,
    pub no_prior: bool,
    /// The MAP fit under the prior instead of the posterior mean.
    pub map: bool,
    pub group_ratios: bool,
    pub noise_sd: Option<f64>,
    pub sigma_points: bool,
}

impl Options {
    /// The fit settings.
    pub fn settings(&self) -> FitSettings {
        let method = match self.method {
            ScaleMethodArgument::Functional => FitMethod::Functional,
            ScaleMethodArgument::GarnerPandy => FitMethod::GarnerPandy,
        };
        let feasible = FeasibleSetSettings { rest_tolerance: self.rest_tolerance.unwrap_or(FeasibleSetSettings::default().rest_tolerance), ..Default::default() };
        let phase_two = PhaseTwoSettings { rest_tolerance: self.rest_constraint, group_ratio: self.group_ratios.then_some([0.9, 1.1]), ..PhaseTwoSettings::default() };
        FitSettings {
            method,
            feasible,
            phase_two,
            rest_curve: self.rest_curve.then(|| {
                let defaults = RestCurveSettings::default();
                RestCurveSettings { posterior: defaults.posterior.filter(|_| !self.map), ..defaults }
            }),
            prior_sd: (!self.no_prior).then(|| self.prior_sd.unwrap_or(DEFAULT_PRIOR_SD)),
            noise_sd: self.noise_sd,
            sigma_points: self.sigma_points,
        }
    }
}

pub fn run(model: &Path, folder: &Path, output: &Path, request: &Request) -> Result<Outcome, Failure> {
    check_settings(&request.settings)?;
    let muscles = request.muscles.as_deref().unwrap_or_default();
    if let Some(repeated) = muscles.iter().enumerate().find(|(i, m)| muscles[..*i].contains(m)).map(|(_, m)| m) {
        return Err(format!("--muscles names {repeated} twice; expected each muscle once").into());
    }
    let sets = request.sets.clone().map_or(SetSelection::All, SetSelection::Only);
    let data = DynamometryData::read(folder, &TrialOptions { sets, estimated_muscles: request.muscles.clone(), ..Default::default() })?;
    let mut inputs: Vec<PathBuf> = vec![model.to_path_buf(), folder.join(SUBJECT_FILE)];
    inputs.extend(data.trials.iter().map(|t| t.file.clone()));
    let input_refs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    let outputs = [("-o", Some(output)), ("--report", request.report.as_deref()), ("--cause-model", request.cause_model.as_deref())];
    check_outputs(&outputs, &input_refs)?;
    let mut document = OsimDocument::read(model)?;
    let spec = ModelSpec::read(&document)?;
    let knee = KneeMomentModel::new(&spec, &data)?;
    let result = fit(&spec, &knee, &data, &request.settings, &mut |stage| eprintln!("scale: {stage}"))?;
    let report = serde_json::to_string_pretty(&result)?;
    let figures = match &request.figures {
        Some(folder) => figure_files(&result, &knee, folder)?,
        None => Vec::new(),
    };
    if request.json {
        println!("{report}");
    } else {
        print_report(&result, &data);
    }
    create_output_folders([Some(output), request.report.as_deref(), request.cause_model.as_deref()].into_iter().flatten())?;
    if let Some(file) = &request.report {
        write_atomically(file, report.as_bytes(), &input_refs)?;
    }
    if let (Some(folder), false) = (&request.figures, figures.is_empty()) {
        write_files(&figures, &inputs)?;
        eprintln!("scale: {} figures drawn in {}", figures.len(), folder.display());
    }
    if let Some(file) = &request.cause_model {
        write_cause_model(&result, model, file, &input_refs)?;
    }
    if !result.converged && !request.force {
        eprintln!("scale: the fit did not converge ({}); no model written (--force writes it anyway)", result.solver_status);
        return Ok(Outcome::NotConverged);
    }
    let changed = result.apply(&mut document)?;
    write_atomically(output, &document.xml.serialize(), &input_refs)?;
    eprintln!("scale: {changed} values changed; wrote {}", output.display());
    Ok(if result.converged { Outcome::Success } else { Outcome::NotConverged })
}

/// The fit's figures as files in `folder`: the moments and the diagnosis per trial set, the
/// feasible sets.
fn figure_files(fit: &FunctionalFit, knee: &KneeMomentModel, folder: &Path) -> Result<Vec<(PathBuf, String)>, Failure> {
    let mut figures = moment_figures(fit, knee.trials())?;
    figures.extend(diagnosis_figures(fit, knee.trials())?);
    figures.extend(feasible_set_figures(fit)?);
    Ok(figures.into_iter().map(|figure| (folder.join(figure.file_name), figure.svg)).collect())
}

/// The initial model extended by the cause the verdict names (the best candidate when it names
/// a muscle without its parameter), or a message why there is none.
fn write_cause_model(fit: &FunctionalFit, model: &Path, file: &Path, inputs: &[&Path]) -> Result<(), Failure> {
    let named = fit.cause_verdict.as_ref().filter(|v| matches!(v.verdict, Verdict::Named(_) | Verdict::MuscleNamed { .. }));
    let (Some(_), Some(best)) = (named, fit.single_causes.first()) else {
        let verdict = fit.cause_verdict.as_ref().map_or("no verdict".to_string(), |v| v.describe());
        eprintln!("scale: the verdict names no single cause ({verdict}); no cause model written");
        return Ok(());
    };
    let mut document = OsimDocument::read(model)?;
    match apply_cause(best, &fit.initial, &mut document)? {
        CauseEdit::Changed(changed) => {
            write_atomically(file, &document.xml.serialize(), inputs)?;
            eprintln!("scale: the model extended by {} ({changed} values changed); wrote {}", best.cause.describe(), file.display());
        }
        CauseEdit::NotInModel(reason) => eprintln!("scale: the named cause, {}, {reason}; no cause model written", best.cause.describe()),
    }
    Ok(())
}

fn check_settings(settings: &FitSettings) -> Result<(), Failure> {
    let fraction = |name: &str, value: Option<f64>| match value {
        Some(v) if !(v > 0.0 && v < 1.0) => Err(format!("{name} {v}: expected a fraction in (0, 1)")),
        _ => Ok(()),
    };
    fraction("--rest-tolerance", Some(settings.feasible.rest_tolerance))?;
    fraction("--rest-constraint", settings.phase_two.rest_tolerance)?;
    match (settings.noise_sd, settings.prior_sd) {
        (Some(sd), _) if !(sd > 0.0 && sd.is_finite()) => Err(format!("--noise-sd {sd}: expected a positive number of N·m").into()),
        (_, Some(tau)) if !(tau > 0.0 && tau.is_finite()) => Err(format!("--prior-sd {tau}: expected a positive relative standard deviation").into()),
        _ => Ok(()),
    }
}

fn print_report(fit: &FunctionalFit, data: &DynamometryData) {
    println!("functional scaling of {} ({} trials, method {:?})", data.folder.display(), fit.trials.len(), fit.method);
    println!("solver: {} after {} iterations{}", fit.solver_status, fit.iterations, if fit.converged { "" } else { " — NOT CONVERGED" });
    let initial_error = fit.trials.iter().map(|t| (t.initial - t.measured).abs()).fold(0.0, f64::max);
    println!("knee moment error: max {:.4} N·m, RMS {:.4} N·m (initial model: max {initial_error:.4} N·m)", fit.max_moment_error(), fit.rms_moment_error());
    if let Some(prior) = &fit.prior {
        println!("rest-curve prior: L_opt within τ = {:.0} % of the model's, against moment noise σ = {:.3} N·m ({}); estimate: the {}", 100.0 * prior.coordinate_sd, prior.noise_sd, prior.noise_source, prior.estimate);
    }
    print_residuals(fit);
    print_parameters(fit);
    print_causes(fit);
    print_sets(fit);
    print_sensitivity(fit);
    print_identifiability(fit);
    for failure in &fit.unavailable {
        println!("\nunavailable at this fit: {} ({})", failure.analysis, failure.reason);
    }
    println!("\nmoments per trial (N·m): measured, initial model, fitted model, fitted − measured");
    for t in &fit.trials {
        println!("  {:<24} {:>10.4} {:>10.4} {:>10.4} {:>+9.4}", t.trial, t.measured, t.initial, t.fitted, t.fitted - t.measured);
    }
}

fn print_residuals(fit: &FunctionalFit) {
    println!("\nwhat the models get wrong (M_mod − M_meas, N·m): RMS, mean, largest at");
    for group in &fit.residuals {
        for (model, s) in [("initial", &group.initial), ("fitted", &group.fitted)] {
            let strength = match (s.mean.abs() < 5e-4, s.too_weak) {
                (true, _) => "",
                (false, true) => " (too weak)",
                (false, false) => " (too strong)",
            };
            println!(
                "  {:<9} {:>2} trials, {model:<7} RMS {:>8.3}, mean {:>+8.3}{strength}, largest {:>+8.3} at {} ({:.1}°)",
                group.direction.key(),
                group.trials,
                s.rms,
                s.mean,
                s.largest,
                s.largest_at,
                s.largest_knee_angle_deg
            );
        }
    }
}

fn print_parameters(fit: &FunctionalFit) {
    let u = &fit.uncertainty;
    let held = if u.rest_curve.is_some() { ", rest fiber lengths held" } else { "" };
    let posterior = u.rest_curve.as_ref().and_then(|r| r.posterior.as_ref());
    let methods = u.rest_curve.as_ref().and_then(|r| r.posterior_method.as_deref()).unwrap_or(&[]);
    let mixed = methods.iter().any(|m| *m != methods[0]);
    let method = match methods.first() {
        Some(_) if mixed => format!(" ({SAMPLED}; {LAPLACE} where marked L)"),
        Some(first) => format!(" ({first})"),
        None => String::new(),
    };
    let columns = [(posterior.is_some(), format!(", posterior sd with the prior{method}")), (u.sigma_points.is_some(), ", sigma-point sd".to_string())];
    let extra: String = columns.iter().filter(|(shown, _)| *shown).map(|(_, text)| text.as_str()).collect();
    println!("\nparameters (m): old → new (change), ± Cramér–Rao sd at σ = {:.3} N·m ({}{held}){extra}", u.noise_sd, u.noise_source);
    for (e, (old, new)) in fit.initial.iter().zip(&fit.fitted).enumerate() {
        for (i, parameter) in [Parameter::OptimalFiberLength, Parameter::TendonSlackLength].into_iter().enumerate() {
            let (a, b) = (old.get(parameter), new.get(parameter));
            let cramer_rao = u.rest_curve.as_ref().map_or(u.cramer_rao.as_ref().map(|c| c[e][i]), |r| Some(r.cramer_rao[e][i]));
            let bound = match cramer_rao {
                Some(Some(sd)) => format!("± {sd:.5}"),
                Some(None) => "not identifiable".to_string(),
                None => "Cramér–Rao unavailable".to_string(),
            };
            let mark = if mixed && methods[e] == LAPLACE { " L" } else { "" };
            let prior = posterior.map_or(String::new(), |s| format!(", ± {:.5}{mark}", s[e][i]));
            let sigma = u.sigma_points.as_ref().map_or(String::new(), |s| match s[e][i] {
                sd if sd.is_finite() => format!(", ± {sd:.5}"),
                _ => ", ± n/a (negative sigma-point variance)".to_string(),
            });
            println!("  {:<12} {:<5} {a:.6} → {b:.6} ({:+.2} %) {bound}{prior}{sigma}", new.name, parameter.symbol(), 100.0 * (b / a - 1.0));
        }
    }
}

fn print_causes(fit: &FunctionalFit) {
    let noise_sd = fit.cause_verdict.as_ref().map(|v| v.noise_sd);
    let heading = if noise_sd.is_some() { " ± its standard error at the verdict's σ" } else { "" };
    println!("\nsingle causes (one deficiency changed alone from the initial model{heading}; RMS error left):");
    for cause in fit.single_causes.iter().take(3) {
        let spread = noise_sd.map_or(String::new(), |sd| format!(" {}", cause.cause.spread(cause.fitted, cause.standard_error(sd))));
        println!(
            "  {:<34} {}{spread}: RMS {:.4} → {:.4} N·m{}",
            cause.cause.describe(),
            cause.change(),
            cause.rms_before,
            cause.rms_after,
            if cause.at_minimum { "" } else { " (its fit stopped before a minimum)" }
        );
    }
    if let Some(verdict) = &fit.cause_verdict {
        println!("  verdict: {}", verdict.describe());
        println!(
            "    at σ = {} N·m ({}): 2 ln K over the initial model {}, over the runner-up {} (very strong ≥ {STRONG_EVIDENCE}); χ² left {} (≤ {:.1})",
            if verdict.noise_sd < 1e-2 { format!("{:.0e}", verdict.noise_sd) } else { format!("{:.3}", verdict.noise_sd) },
            verdict.noise_source,
            evidence(verdict.evidence_over_initial),
            evidence(verdict.evidence_over_runner_up),
            evidence(verdict.best_chi_square),
            verdict.chi_square_limit
        );
    }
    if let Some(held_out) = &fit.cause_held_out {
        println!(
            "  held out ({FOLDS} folds of alternate angles, each predicted by the best cause fitted to the other): RMS {:.4} → {:.4} N·m",
            held_out.rms_before, held_out.rms_after
        );
    }
}

/// A 2 ln K or χ² value: one decimal, or three significant digits when large.
fn evidence(value: f64) -> String {
    if value.abs() < 1e4 {
        format!("{value:.1}")
    } else {
        format!("{value:.2e}")
    }
}

fn print_sets(fit: &FunctionalFit) {
    if fit.feasible_sets.is_empty() {
        return;
    }
    println!("\nPhase I feasible sets: points kept of evaluated, L_ts/L_opt bounds, δ_max (1/m)");
    for set in &fit.feasible_sets {
        let [low, high] = set.ratio_bounds;
        println!("  {:<12} {:>4} of {:<5} ρ ∈ [{low:.3}, {high:.3}]  δ_max {:.4}", set.muscle, set.feasible.len(), set.evaluated, set.delta_max);
    }
    if let Some(start) = &fit.hot_start {
        println!("hot start: largest moment error {:.4} N·m", start.max_moment_error);
    }
    for constraint in &fit.active_constraints {
        println!("active at the solution: {constraint}");
    }
}

fn print_sensitivity(fit: &FunctionalFit) {
    let Some(sensitivity) = &fit.sensitivity else { return };
    println!("\nsensitivity (eq. 3.3–3.4, ±5 %): max over trials, N·m, and class");
    for muscle in &fit.fitted {
        let cells: Vec<String> = Parameter::ALL
            .iter()
            .filter_map(|&p| sensitivity.entry(&muscle.name, p))
            .map(|e| match (e.maximum, e.class) {
                (Some(value), Some(class)) => format!("{} {value:.0} {class:?}", e.parameter.symbol()),
                _ => format!("{} n/a", e.parameter.symbol()),
            })
            .collect();
        println!("  {:<12} {}", muscle.name, cells.join(", "));
    }
}

fn print_identifiability(fit: &FunctionalFit) {
    println!("\nidentifiability (Fisher information at the fit; relative criteria)");
    for report in &fit.identifiability {
        let id = &report.identifiability;
        println!(
            "  {:<18} rank {}/{}  log10 det {:.2}  λ_min {:.3e}  condition {:.3e}",
            report.parameterisation, id.rank, id.parameters, report.relative.log10_determinant, report.relative.min_eigenvalue, report.relative.condition_number
        );
        for p in &id.unidentifiable {
            println!("    not identifiable: {} {} ({:.0} % in the null space)", p.muscle, p.parameter.symbol(), 100.0 * p.null_space_share);
        }
    }
}
