//! `osim-tune scale MODEL TRIALS/` with a dynamometry folder (functional scaling): the written
//! model differs from the input only in the fitted L_opt/L_ts and reproduces the measured
//! moments (and its figures draw the report's moments and feasible sets); a hidden single-muscle
//! change is named and recovered; bad input is refused.

mod common;

use std::path::{Path, PathBuf};

use common::{fixture, osim_tune, pixel_map, svg_elements, svg_points};
use osim_tune::io::osim::OsimDocument;
use osim_tune::model::ModelSpec;
use osim_tune::tuning::functional::{Direction, DynamometryData, KneeMomentModel, MuscleParameters, TrialOptions};
use osim_tune::validation::functional::hidden_slack_change;
use serde_json::Value;

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn base_model() -> PathBuf {
    fixture("golden/scale/subject01_simbody.osim")
}

fn read_knee(model: &Path, folder: &Path) -> (DynamometryData, KneeMomentModel) {
    let data = DynamometryData::read(folder, &TrialOptions::default()).unwrap();
    let spec = ModelSpec::read(&OsimDocument::read(model).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    (data, knee)
}

/// train01's set5 trials copied to `dir` (subject.json listing only set5), with `edit` applied
/// to each data row's cells (column names given) and to the subject JSON.
fn set5_copy(dir: &Path, edit_row: impl Fn(&[String], &mut [String], &str, usize), edit_subject: impl Fn(&mut Value)) {
    let source = fixture("dynamometry/train01");
    let mut subject: Value = serde_json::from_str(&std::fs::read_to_string(source.join("subject.json")).unwrap()).unwrap();
    subject["trial_files"] = serde_json::json!({"set5": subject["trial_files"]["set5"].clone()});
    edit_subject(&mut subject);
    std::fs::write(dir.join("subject.json"), serde_json::to_string_pretty(&subject).unwrap()).unwrap();
    for file in ["set5_extension.mot", "set5_flexion.mot"] {
        let text = std::fs::read_to_string(source.join(file)).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let header = lines.iter().position(|l| l.trim() == "endheader").unwrap() + 1;
        let columns: Vec<String> = lines[header].split('\t').map(|c| c.trim().to_string()).collect();
        for (row, line) in lines[header + 1..].iter_mut().enumerate() {
            let mut cells: Vec<String> = line.split('\t').map(String::from).collect();
            edit_row(&columns, &mut cells, file, row);
            *line = cells.join("\t");
        }
        std::fs::write(dir.join(file), lines.join("\n") + "\n").unwrap();
    }
}

/// A subject whose moments and rest fiber lengths come from the base model with `truth`
/// parameters (our engine), angles and activations those of train01 set5.
fn synthetic_subject(dir: &Path, truth: &[MuscleParameters]) {
    let (data, knee) = read_knee(&base_model(), &fixture("dynamometry/train01"));
    let set5: Vec<usize> = (0..data.trials.len()).filter(|&t| data.trials[t].set == "set5").collect();
    let moments = knee.moments(truth).unwrap();
    let rest = knee.rest_states(&knee.estimated_muscles(truth).unwrap()).unwrap();
    let moment_of = |file: &str, row: usize| {
        let t = set5.iter().copied().filter(|&t| data.trials[t].file.ends_with(file)).nth(row).unwrap();
        moments[t]
    };
    set5_copy(
        dir,
        |columns, cells, file, row| {
            let k = columns.iter().position(|c| c == "knee_moment").unwrap();
            cells[k] = format!("{:.6}", moment_of(file, row));
        },
        |subject| {
            for (p, state) in truth.iter().zip(&rest) {
                subject["reference_rest_fiber_length_m"][&p.name] = state.fiber_length.into();
            }
        },
    );
}

fn run_scale(folder: &Path, output: &Path, extra: &[&str]) -> (i32, String, String) {
    let model = base_model();
    let mut arguments = vec!["scale", s(&model), s(folder), "-o", s(output)];
    arguments.extend_from_slice(extra);
    osim_tune(&arguments)
}

#[test]
fn writes_only_the_fitted_lengths_and_reproduces_the_moments() {
    let dir = tempfile::tempdir().unwrap();
    let (output, report, figures) = (dir.path().join("out/train01.osim"), dir.path().join("out/report.json"), dir.path().join("figures"));
    let (code, stdout, stderr) = run_scale(&fixture("dynamometry/train01"), &output, &["--sets", "set5", "--report", s(&report), "--figures", s(&figures)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("Phase I feasible sets") && stdout.contains("identifiability"), "{stdout}");
    let model = base_model();
    let (code, differences, _) = osim_tune(&["diff", s(&model), s(&output), "--json"]);
    assert_eq!(code, 1);
    let differences: Value = serde_json::from_str(&differences).unwrap();
    let estimated = ["rect_fem_r", "vas_int_r", "vas_lat_r", "vas_med_r", "bifemlh_r", "lat_gas_r", "med_gas_r", "semimem_r"];
    let differences = differences["differences"].as_array().unwrap();
    assert!(differences.len() >= 8, "{differences:?}");
    for difference in differences {
        let path = difference["path"].as_str().unwrap();
        let parts: Vec<&str> = path.split('/').collect();
        assert!(parts.len() == 4 && parts[1] == "forceset" && estimated.contains(&parts[2]), "{path}");
        assert!(["optimal_fiber_length", "tendon_slack_length"].contains(&parts[3]), "{path}");
    }
    // The written model, evaluated afresh, reproduces the measured moments (noise-free data).
    let folder = tempfile::tempdir().unwrap();
    set5_copy(folder.path(), |_, _, _, _| {}, |_| {});
    let (data, knee) = read_knee(&output, folder.path());
    let moments = knee.moments(&knee.nominal_parameters()).unwrap();
    let worst = moments.iter().zip(data.measured_moments()).map(|(m, y)| (m - y).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-4, "largest moment error of the written model {worst} N·m");
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(report["converged"], true);
    assert_eq!(report["trials"].as_array().unwrap().len(), 10);
    // Per direction: five trials each; the initial model misses, the fitted one does not.
    for direction in report["residuals"].as_array().unwrap() {
        assert_eq!(direction["trials"], 5, "{direction}");
        assert!(direction["initial"]["rms"].as_f64().unwrap() > 1.0 && direction["fitted"]["rms"].as_f64().unwrap() < 1e-4, "{direction}");
    }
    assert_figures(&figures, &report, &data);
}

/// The figures of a set5 fit: the moments figure draws the measured moments (dots) and the
/// fitted model's (solid lines) of the report at the trials' knee angles, by one affine map; the
/// diagnosis figure the best single cause's errors with the report's RMS; each muscle's
/// feasible-set figure draws as many dots as the report has feasible points.
fn assert_figures(folder: &Path, report: &Value, data: &DynamometryData) {
    let svg = std::fs::read_to_string(folder.join("moments_set5.svg")).unwrap();
    let trials = report["trials"].as_array().unwrap();
    // Figure order: extension, then flexion, each by knee angle (the files list them so).
    let mut order: Vec<usize> = (0..trials.len()).collect();
    order.sort_by(|&a, &b| (data.trials[a].direction != Direction::Extension, data.trials[a].knee_angle).partial_cmp(&(data.trials[b].direction != Direction::Extension, data.trials[b].knee_angle)).unwrap());
    let angle = |t: usize| data.trials[t].knee_angle.to_degrees();
    let value = |t: usize, key: &str| trials[t][key].as_f64().unwrap();
    let dots: Vec<(f64, f64)> = svg_elements(&svg, "circle").iter().filter(|c| c["fill"] == "#000000").map(|c| (c["cx"].parse().unwrap(), c["cy"].parse().unwrap())).collect();
    assert_eq!(dots.len(), trials.len() + 1, "ten measured moments and the legend's dot");
    let x_map = pixel_map(&order.iter().zip(&dots).map(|(&t, d)| (angle(t), d.0)).collect::<Vec<_>>());
    let y_map = pixel_map(&order.iter().zip(&dots).map(|(&t, d)| (value(t, "measured"), d.1)).collect::<Vec<_>>());
    let fitted: Vec<(f64, f64)> = svg_elements(&svg, "polyline").iter().filter(|l| l["stroke"] == "#1F77B4").flat_map(svg_points).collect();
    let fitted = &fitted[..trials.len()];
    for (k, &t) in order.iter().enumerate() {
        let near = |pixel: (f64, f64), moment: f64| (x_map(angle(t)) - pixel.0).abs() <= 1.5 && (y_map(moment) - pixel.1).abs() <= 1.5;
        assert!(near(dots[k], value(t, "measured")), "{}: measured at {:?}", trials[t]["trial"], dots[k]);
        assert!(near(fitted[k], value(t, "fitted")), "{}: fitted at {:?}", trials[t]["trial"], fitted[k]);
    }
    // The diagnosis: the initial model's errors (squares) set the map; the best single cause's
    // line then gives back the report's RMS after it, to the pixels' resolution.
    let svg = std::fs::read_to_string(folder.join("diagnosis_set5.svg")).unwrap();
    let squares: Vec<(f64, f64)> = svg_elements(&svg, "rect").iter().filter(|r| r.get("stroke").is_some_and(|s| s == "#808080")).map(|r| {
        let at = |key: &str, size: &str| r[key].parse::<f64>().unwrap() + 0.5 * r[size].parse::<f64>().unwrap();
        (at("x", "width"), at("y", "height"))
    }).collect();
    assert_eq!(squares.len(), trials.len() + 1, "ten initial errors and the legend's square");
    let error = |t: usize, key: &str| value(t, key) - value(t, "measured");
    let y_map = pixel_map(&order.iter().zip(&squares).map(|(&t, p)| (error(t, "initial"), p.1)).collect::<Vec<_>>());
    let newton_metres_per_pixel = 1.0 / (y_map(1.0) - y_map(0.0)).abs();
    let cause: Vec<f64> = svg_elements(&svg, "polyline").iter().filter(|l| l["stroke"] == "#FF7F0E").flat_map(svg_points).take(trials.len()).map(|p| (p.1 - y_map(0.0)) / (y_map(1.0) - y_map(0.0))).collect();
    let rms = (cause.iter().map(|r| r * r).sum::<f64>() / cause.len() as f64).sqrt();
    let reported = report["single_causes"][0]["rms_after"].as_f64().unwrap();
    assert!((rms - reported).abs() <= 1.5 * newton_metres_per_pixel, "drawn RMS {rms}, reported {reported} (± {} N·m per pixel)", newton_metres_per_pixel);
    for set in report["feasible_sets"].as_array().unwrap() {
        let muscle = set["muscle"].as_str().unwrap();
        let svg = std::fs::read_to_string(folder.join(format!("feasible_{muscle}.svg"))).unwrap();
        let dots = svg_elements(&svg, "circle").iter().filter(|c| c["r"] == "2").count();
        assert_eq!(dots, set["feasible"].as_array().unwrap().len(), "{muscle}");
    }
    assert_eq!(std::fs::read_dir(folder).unwrap().count(), 2 + report["feasible_sets"].as_array().unwrap().len());
}

#[test]
fn names_and_recovers_a_hidden_tendon_slack_change() {
    let (_, knee) = read_knee(&base_model(), &fixture("dynamometry/train01"));
    let (hidden, truth) = hidden_slack_change(&knee.nominal_parameters(), 0x05ca1e);
    let dir = tempfile::tempdir().unwrap();
    synthetic_subject(dir.path(), &truth);
    let output = dir.path().join("fitted.osim");
    let (code, stdout, stderr) = run_scale(dir.path(), &output, &["--json"]);
    assert!(code == 0 || code == 1, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).unwrap();
    let best = &report["single_causes"][0];
    assert_eq!(best["muscle"], truth[hidden].name.as_str(), "{best}");
    assert_eq!(best["parameter"], "TendonSlackLength");
    let recovered = best["fitted"].as_f64().unwrap() / truth[hidden].tendon_slack_length - 1.0;
    assert!(recovered.abs() < 0.01, "recovered L_ts off by {:.3} %", 100.0 * recovered);
    // The subject file says noise-free: the verdict weighs the candidates at the moments' resolution.
    let named = &report["cause_verdict"]["verdict"]["Named"];
    assert_eq!(named["muscle"], truth[hidden].name.as_str(), "{}", report["cause_verdict"]);
    assert_eq!(named["parameter"], "TendonSlackLength");
    // Noise-free: the cause fitted to alternate angles predicts the others exactly.
    let held_out = &report["cause_held_out"];
    assert!(held_out["rms_before"].as_f64().unwrap() > 1.0 && held_out["rms_after"].as_f64().unwrap() < 1e-4, "{held_out}");
    let runner_up = report["single_causes"][1]["rms_after"].as_f64().unwrap();
    assert!(best["rms_after"].as_f64().unwrap() < 0.01 * runner_up, "the named cause must explain far more than the next: {best} vs {runner_up}");
}

fn refused(edit_row: impl Fn(&[String], &mut [String], &str, usize), edit_subject: impl Fn(&mut Value)) -> String {
    let dir = tempfile::tempdir().unwrap();
    set5_copy(dir.path(), edit_row, edit_subject);
    let output = dir.path().join("out.osim");
    let (code, _, stderr) = run_scale(dir.path(), &output, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(!output.exists(), "no model may be written");
    stderr
}

fn set_cell(columns: &[String], cells: &mut [String], column: &str, value: impl Fn(f64) -> f64) {
    let k = columns.iter().position(|c| c == column).unwrap();
    cells[k] = format!("{:.6}", value(cells[k].trim().parse::<f64>().unwrap()));
}

#[test]
fn refuses_moments_with_the_other_sign_convention() {
    let stderr = refused(|columns, cells, _, _| set_cell(columns, cells, "knee_moment", |m| -m), |_| {});
    assert!(stderr.contains("opposite sign") && stderr.contains("knee_moment"), "{stderr}");
}

#[test]
fn refuses_angles_outside_the_coordinate_range() {
    let stderr = refused(|columns, cells, file, row| if file == "set5_flexion.mot" && row == 2 { set_cell(columns, cells, "knee_angle_r", |_| -150.0) }, |_| {});
    assert!(stderr.contains("set5_flexion.mot:") && stderr.contains("knee_angle_r") && stderr.contains("range"), "{stderr}");
}

/// Angles in degrees without `inDegrees=yes` (and with `version=1`) are read in radians, as
/// OpenSim reads them: refused as out of range, the message saying how the unit is read.
#[test]
fn undeclared_degrees_are_refused_with_the_unit_rule() {
    let dir = tempfile::tempdir().unwrap();
    let trials = dir.path().join("train01");
    std::fs::create_dir(&trials).unwrap();
    for entry in std::fs::read_dir(fixture("dynamometry/train01")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, trials.join(path.file_name().unwrap())).unwrap();
    }
    let file = trials.join("set5_extension.mot");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("version=1\n") && text.contains("inDegrees=yes\n"));
    std::fs::write(&file, text.replace("inDegrees=yes\n", "")).unwrap();
    let output = dir.path().join("out.osim");
    let (code, _, stderr) = run_scale(&trials, &output, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("set5_extension.mot:") && stderr.contains("knee_angle_r") && stderr.contains("inDegrees=yes, radians where it does not say"), "{stderr}");
    assert!(!output.exists());
}

#[test]
fn refuses_too_few_angles_and_says_what_is_not_identifiable() {
    let stderr = refused(|columns, cells, _, row| set_cell(columns, cells, "knee_angle_r", |a| if row < 3 { -90.0 } else { a }), |subject| {
        subject["reference_rest_fiber_length_m"] = serde_json::json!({});
    });
    assert!(stderr.contains("not identifiable") && stderr.contains("rect_fem_r (L_opt, L_ts)"), "{stderr}");
}

/// A prior or noise level that is not a positive number is refused before any fit.
#[test]
fn refuses_a_non_positive_prior_or_noise_level() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.osim");
    for (option, value) in [("--prior-sd", "0"), ("--noise-sd", "-2")] {
        let (code, _, stderr) = run_scale(&fixture("dynamometry/train01"), &output, &[&format!("{option}={value}")]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(option) && stderr.contains("expected a positive"), "{stderr}");
        assert!(!output.exists());
    }
}

/// Garner & Pandy on train01's set5 (ten moments, sixteen unknowns) ends with bifemlh_r's fiber
/// taking up its whole musculotendon length (L_ts → 0, the edge of the method's map), where the
/// [L̃m_min, L̃m_max] Fisher information's difference step leaves the map's domain. That
/// analysis is reported as unavailable, with its reason; the fit is a minimum (no step lowers
/// the cost) and stands: exit 0, the model written, the other analyses reported — among them
/// the sigma-point spread of Garner & Pandy's own refits (as the thesis compares the methods),
/// at a nominal σ since sixteen unknowns leave ten noise-free moments no degree of freedom.
#[test]
fn garner_pandy_fit_on_the_edge_of_its_domain_is_written_with_the_analyses_it_allows() {
    let dir = tempfile::tempdir().unwrap();
    let (output, report) = (dir.path().join("gp.osim"), dir.path().join("gp.json"));
    let arguments = ["--sets", "set5", "--method", "garner-pandy", "--sigma-points", "--report", s(&report)];
    let (code, stdout, stderr) = run_scale(&fixture("dynamometry/train01"), &output, &arguments);
    assert_eq!(code, 0, "{stderr}");
    assert!(output.exists());
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let bifemlh = report["fitted"].as_array().unwrap().iter().find(|p| p["name"] == "bifemlh_r").unwrap();
    assert!(bifemlh["tendon_slack_length"].as_f64().unwrap() < 1e-3, "{bifemlh}");
    let unavailable = report["unavailable"].as_array().unwrap();
    assert_eq!(unavailable.len(), 1, "{unavailable:?}");
    assert_eq!(unavailable[0]["analysis"], "[L̃m_min, L̃m_max]");
    assert!(unavailable[0]["reason"].as_str().unwrap().contains("bifemlh_r"), "{unavailable:?}");
    assert!(stdout.contains("unavailable at this fit: [L̃m_min, L̃m_max]"), "{stdout}");
    assert!(report["sensitivity"].is_object() && report["uncertainty"]["cramer_rao"].is_array());
    assert_eq!(report["identifiability"][0]["parameterisation"], "[L_opt, L_ts]");
    assert!(report["uncertainty"]["noise_source"].as_str().unwrap().contains("no more trials than parameters"), "{}", report["uncertainty"]);
    let spread = report["uncertainty"]["sigma_points"].as_array().expect("the sigma-point sd");
    assert_eq!(spread.len(), 8);
    let finite = spread.iter().flat_map(|m| m.as_array().unwrap()).filter_map(Value::as_f64).filter(|sd| *sd > 0.0).count();
    assert!(finite > 0, "{spread:?}");
}

/// Options of the rest-curve fit's prior make no sense without the rest-curve fit, nor with no
/// prior: refused by the argument parser, nothing written.
#[test]
fn refuses_prior_options_without_the_rest_curve_fit() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.osim");
    for pair in [["--map", "--no-rest-curve"], ["--prior-sd=0.2", "--no-rest-curve"], ["--map", "--no-prior"]] {
        let (code, _, stderr) = run_scale(&fixture("dynamometry/train01"), &output, &pair);
        assert_eq!(code, 2, "{pair:?}: {stderr}");
        assert!(stderr.contains("cannot be used with"), "{pair:?}: {stderr}");
        assert!(!output.exists());
    }
}

/// A trials folder that does not exist, or a file given in its place (the subject.json itself),
/// is named as such (not as a subject.json it lacks).
#[test]
fn refuses_a_trials_folder_that_does_not_exist_or_is_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.osim");
    let missing = dir.path().join("train99");
    let (code, _, stderr) = run_scale(&missing, &output, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("train99: no such folder; expected the trials folder"), "{stderr}");
    let file = fixture("dynamometry/train01").join("subject.json");
    let (code, _, stderr) = run_scale(&file, &output, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("subject.json: a file, not a folder; expected the trials folder (the one that holds subject.json)"), "{stderr}");
    let (code, _, stderr) = run_scale(&file, &output, &["--linear"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("subject.json: a file, not a folder"), "{stderr}");
    assert!(!output.exists());
}

#[test]
fn refuses_a_model_that_lacks_an_estimated_muscle() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(base_model()).unwrap().replace("name=\"rect_fem_r\"", "name=\"rect_fem_x\"");
    let model = dir.path().join("renamed.osim");
    std::fs::write(&model, text).unwrap();
    let output = dir.path().join("out.osim");
    let (code, _, stderr) = osim_tune(&["scale", s(&model), s(&fixture("dynamometry/train01")), "-o", s(&output)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("renamed.osim") && stderr.contains("rect_fem_r"), "{stderr}");
    assert!(!output.exists());
}

/// --muscles replaces the subject file's estimated muscles (its abbreviations and rest lengths of
/// the others are then unused): hid01 hides a 2 % longer vas_lat_r tendon in the scaled model,
/// so estimating vas_lat_r and semimem_r alone recovers the truth (OpenSim's moments, printed to
/// 1e-6 N·m) and the written model differs in those two muscles only. Naming a muscle twice or
/// one that is no agonist in any trial is refused.
#[test]
fn estimates_the_muscles_given_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let (folder, output) = (fixture("dynamometry/hidden/hid01"), dir.path().join("out.osim"));
    let (code, _, stderr) = run_scale(&folder, &output, &["--sets", "set5", "--muscles", "vas_lat_r,semimem_r"]);
    assert_eq!(code, 0, "{stderr}");
    let truth: Value = serde_json::from_str(&std::fs::read_to_string(folder.join("ground_truth.json")).unwrap()).unwrap();
    let (fitted, base) = (ModelSpec::read(&OsimDocument::read(&output).unwrap()).unwrap(), ModelSpec::read(&OsimDocument::read(&base_model()).unwrap()).unwrap());
    for (force, before) in fitted.forces.iter().zip(&base.forces) {
        let (Some(muscle), Some(original)) = (&force.muscle, &before.muscle) else { continue };
        let lengths = |m: &osim_tune::model::MuscleSpec| [m.optimal_fiber_length, m.tendon_slack_length];
        if ["vas_lat_r", "semimem_r"].contains(&force.name.as_str()) {
            let expected = &truth["true_parameters"][&force.name];
            for (value, key) in lengths(muscle).iter().zip(["optimal_fiber_length", "tendon_slack_length"]) {
                assert!((value / expected[key].as_f64().unwrap() - 1.0).abs() < 1e-5, "{} {key}: {value}", force.name);
            }
        } else {
            assert_eq!(lengths(muscle), lengths(original), "{} changed", force.name);
        }
    }
    let (code, _, stderr) = run_scale(&folder, &output, &["--muscles", "vas_lat_r,vas_lat_r"]);
    assert!(code == 2 && stderr.contains("--muscles names vas_lat_r twice"), "{stderr}");
    let (code, _, stderr) = run_scale(&folder, &output, &["--muscles", "vas_lat_r,semiten_r"]);
    assert!(code == 2 && stderr.contains("semiten_r") && stderr.contains("agonist in no trial"), "{stderr}");
}

/// train03 carries σ = 5 N·m noise: no fit is exact. Phase II (the thesis' min–max fit, alone
/// with --no-rest-curve) ends where the largest error stops changing (ObjectiveStalled) or at a
/// KKT point; the rest-curve fit after it at a minimum — converged fits, written. The MAP fit
/// (`--map`) fits the noise (RMS below σ: ten trials, eight coordinates); the default posterior
/// mean weighs the basins instead and stays within 3σ of every trial, the MAP fit also within
/// the hot start's largest error.
#[test]
fn fits_noisy_moments_and_reports_the_noise_level() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("train03.osim");
    let (code, stdout, stderr) = run_scale(&fixture("dynamometry/train03"), &output, &["--sets", "set5", "--json", "--no-rest-curve"]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).unwrap();
    assert!(["Converged", "ObjectiveStalled"].contains(&report["solver_status"].as_str().unwrap()), "{}", report["solver_status"]);
    let phase_two_worst = report["trials"].as_array().unwrap().iter().map(|t| (t["fitted"].as_f64().unwrap() - t["measured"].as_f64().unwrap()).abs()).fold(0.0, f64::max);
    assert!(report["uncertainty"]["rest_curve"].is_null(), "Phase II alone holds no rest length exactly");
    let (code, stdout, stderr) = run_scale(&fixture("dynamometry/train03"), &output, &["--sets", "set5", "--json", "--map"]);
    assert_eq!(code, 0, "{stderr}");
    let map: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(map["prior"]["estimate"], "maximum a posteriori");
    let rms = |r: &Value| (r["trials"].as_array().unwrap().iter().map(|t| (t["fitted"].as_f64().unwrap() - t["measured"].as_f64().unwrap()).powi(2)).sum::<f64>() / 10.0).sqrt();
    assert!(rms(&map) < 5.0, "MAP RMS error {} N·m above σ (Phase II's largest {phase_two_worst})", rms(&map));
    let (code, stdout, stderr) = run_scale(&fixture("dynamometry/train03"), &output, &["--sets", "set5", "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).unwrap();
    let status = report["solver_status"].as_str().unwrap();
    assert!(report["converged"] == true && status.starts_with("rest curves") && status.contains("Phase II"), "{status}");
    assert_eq!(report["prior"]["estimate"], "posterior mean");
    assert_eq!(report["uncertainty"]["noise_source"], "subject file");
    assert_eq!(report["uncertainty"]["noise_sd"], 5.0);
    assert_rest_curve_uncertainty(&report);
    let worst = |r: &Value| r["trials"].as_array().unwrap().iter().map(|t| (t["fitted"].as_f64().unwrap() - t["measured"].as_f64().unwrap()).abs()).fold(0.0, f64::max);
    let hot = map["hot_start"]["max_moment_error"].as_f64().unwrap();
    assert!(worst(&map) < hot, "MAP max error {} N·m, hot start {hot} N·m", worst(&map));
    assert!(worst(&report) < 3.0 * 5.0, "posterior mean's max error {} N·m", worst(&report));
    assert!(output.exists());
}

/// With the rest lengths held, the report has one identifiable coordinate per muscle, a
/// Cramér–Rao sd for every L_opt and L_ts, and posterior sds with the default prior (τ = 0.1 in
/// s), sampled (the estimate is the posterior mean), no larger than the prior's own, sd(L_opt)
/// ≤ τ·L_opt (the tangent dL_opt/ds being L_opt unclamped, 0 clamped), nor than the Cramér–Rao
/// sd: the moments and the prior each add information (on average a posterior variance is below
/// the prior's, by the law of total variance; the Laplace sds obey both bounds exactly).
fn assert_rest_curve_uncertainty(report: &Value) {
    let on_curves = report["identifiability"].as_array().unwrap().iter().find(|r| r["parameterisation"] == "[s] on the rest curves").expect("the rest-curve parameterisation");
    assert_eq!(on_curves["identifiability"]["rank"], 8, "{on_curves}");
    let rest_curve = &report["uncertainty"]["rest_curve"];
    let posterior = rest_curve["posterior"].as_array().unwrap();
    assert!(rest_curve["posterior_method"].as_array().unwrap().iter().all(|m| m == "sampled"), "{}", rest_curve["posterior_method"]);
    for (e, fitted) in report["fitted"].as_array().unwrap().iter().enumerate() {
        assert!(rest_curve["cramer_rao"][e].as_array().unwrap().iter().all(Value::is_number), "{}", rest_curve["cramer_rao"][e]);
        let optimal = fitted["optimal_fiber_length"].as_f64().unwrap();
        let sd = posterior[e][0].as_f64().unwrap();
        assert!(sd <= 0.1 * optimal * (1.0 + 1e-9) && sd <= rest_curve["cramer_rao"][e][0].as_f64().unwrap(), "{}: posterior sd {sd} m", fitted["name"]);
    }
}

/// A slice of the xtask initial-guess study: three of the thesis' 81 guesses, each fitted
/// without failure (the full study and its accuracy table are in `cargo xtask validate`).
#[test]
fn initial_guess_study_slice_fits_every_guess() {
    use osim_tune::validation::functional::{initial_guess_study, thesis_initial_guesses, StudySubject};
    use osim_tune::tuning::functional::{FitSettings, SetSelection};
    let options = TrialOptions { sets: SetSelection::Only(vec!["set5".into()]), ..TrialOptions::default() };
    let data = DynamometryData::read(&fixture("dynamometry/train01"), &options).unwrap();
    let spec = ModelSpec::read(&OsimDocument::read(&base_model()).unwrap()).unwrap();
    let knee = KneeMomentModel::new(&spec, &data).unwrap();
    let truth_file: Value = serde_json::from_str(&std::fs::read_to_string(fixture("dynamometry/train01/ground_truth.json")).unwrap()).unwrap();
    let truth: Vec<MuscleParameters> = knee
        .nominal_parameters()
        .into_iter()
        .map(|p| {
            let t = &truth_file["true_parameters"][&p.name];
            MuscleParameters { optimal_fiber_length: t["optimal_fiber_length"].as_f64().unwrap(), tendon_slack_length: t["tendon_slack_length"].as_f64().unwrap(), ..p }
        })
        .collect();
    let guesses = thesis_initial_guesses(&truth, &data, 6);
    assert_eq!(guesses.len(), 81);
    let subject = StudySubject { spec: &spec, knee: &knee, data: &data, truth: &truth };
    let slice: Vec<Vec<MuscleParameters>> = guesses.into_iter().step_by(40).collect();
    let result = initial_guess_study(&subject, &slice, &FitSettings::default());
    assert_eq!((result.failed, result.errors.len()), (0, slice.len()), "{:?}", result.first_failure);
}
