//! Muscle rows of the validation table: Millard and Thelen curves, the equilibrium rows, the
//! Thelen fiber velocity and DeGrooteFregly2016 curves, equilibrium and fiber velocity against
//! OpenSim 4.6, over the full goldens when `../shared/reference` (or `$OSIM_TUNE_REFERENCE`) has
//! them, else over `fixtures/golden/muscle/` (a slice for the models of [`MUSCLE_MODELS`]; the
//! Thelen velocity and DeGroote goldens exist only there, complete).

use std::path::{Path, PathBuf};

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::HillMuscle;
use osim_tune::model::{ModelSpec, MuscleModelSpec};
use osim_tune::validation::{
    compare_degroote_curves, compare_degroote_equilibrium, compare_degroote_fiber_velocity, compare_equilibrium, compare_millard_curves,
    compare_thelen_curves, compare_thelen_fiber_velocity, EquilibriumSolution, Worst, DEGROOTE_LENGTH_TOLERANCE, FIBER_LENGTH_TOLERANCE,
};

use crate::root;
use crate::validate::Row;

/// Golden muscle folders and their models.
pub const MUSCLE_MODELS: [(&str, &str); 4] = [
    (
        "gait2392_millard2012muscle",
        "models/gait2392_millard2012muscle.osim",
    ),
    (
        "gait2392_thelen2003muscle",
        "models/gait2392_thelen2003muscle.osim",
    ),
    ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
    ("arm26", "fixtures/models/arm26.osim"),
];

/// The golden folder of `stem` that holds `file`, and how to name it.
fn golden_folder(stem: &str, file: &str) -> (PathBuf, String) {
    let reference = std::env::var_os("OSIM_TUNE_REFERENCE")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("../shared/reference"));
    let full = reference.join("muscle").join(stem);
    if full.join(file).exists() {
        (full, "OpenSim 4.6, all rows".into())
    } else if MUSCLE_MODELS.iter().any(|(s, _)| *s == stem) {
        (root().join("fixtures/golden/muscle").join(stem), "OpenSim 4.6, fixture slice".into())
    } else {
        (root().join("fixtures/golden/muscle").join(stem), "OpenSim 4.6, fixtures (all rows)".into())
    }
}

fn read_model(model: &Path) -> Result<ModelSpec, String> {
    OsimDocument::read(model).map_err(|e| e.to_string()).and_then(|d| ModelSpec::read(&d).map_err(|e| e.to_string()))
}

pub fn rows(stem: &str, model: &Path) -> Vec<Row> {
    let (folder, reference) = golden_folder(stem, "equilibrium.csv");
    let row = |what: String, worst: f64, tolerance: f64, at: String| Row {
        what,
        reference: reference.clone(),
        worst,
        tolerance,
        at,
    };
    let spec = match read_model(model) {
        Ok(spec) => spec,
        Err(e) => return vec![row(format!("muscle model, {stem}"), f64::INFINITY, 0.0, e)],
    };
    let mut rows = curve_rows(stem, &spec, &folder, &row);
    let has_millard = spec.forces.iter().any(|f| matches!(f.muscle.as_ref().map(|m| &m.model), Some(MuscleModelSpec::Millard2012(_))));
    for solution in [EquilibriumSolution::OpenSim, EquilibriumSolution::Static] {
        let label = match solution {
            EquilibriumSolution::OpenSim => "OpenSim's iteration",
            EquilibriumSolution::Static => "exact static balance",
        };
        // OpenSim's iteration is reproduced for Millard muscles only; others would repeat the
        // static rows.
        if solution == EquilibriumSolution::OpenSim && !has_millard {
            continue;
        }
        match compare_equilibrium(&spec, &folder, solution) {
            Ok(c) => {
                let n = c.fiber_length.count;
                // The exact balance may differ from OpenSim's state by OpenSim's own imbalance:
                // its rows count fiber lengths beyond the per-row allowance.
                match solution {
                    EquilibriumSolution::OpenSim => rows.push(row(format!("equilibrium fiber length (m), {stem}, {label} ({n} rows)"), c.fiber_length.error, FIBER_LENGTH_TOLERANCE, c.fiber_length.at.clone())),
                    EquilibriumSolution::Static => rows.push(row(
                        format!("equilibrium fiber length beyond OpenSim's tolerance (m), {stem}, {label} ({n} rows, raw worst {:.1e})", c.fiber_length.error),
                        c.fiber_length_excess.error,
                        0.0,
                        c.fiber_length_excess.at.clone(),
                    )),
                }
                let force_tolerance = if solution == EquilibriumSolution::Static {
                    1e-6 + c.opensim_imbalance.error
                } else {
                    1e-6
                };
                rows.push(row(
                    format!("equilibrium tendon force (N), {stem}, {label}"),
                    c.tendon_force.error,
                    force_tolerance,
                    c.tendon_force.at.clone(),
                ));
                rows.push(row(
                    format!("equilibrium rows outside tolerance, {stem}, {label}"),
                    c.outside_tolerance.len() as f64,
                    0.0,
                    c.outside_tolerance.first().cloned().unwrap_or_default(),
                ));
            }
            Err(e) => rows.push(row(
                format!("equilibrium, {stem}"),
                f64::INFINITY,
                0.0,
                e.to_string(),
            )),
        }
    }
    rows
}

/// Millard curve values and derivatives (the models share one curve set; the first muscle's), or
/// the Thelen curves of the golden's parameter sets.
fn curve_rows(
    stem: &str,
    spec: &ModelSpec,
    folder: &Path,
    row: &dyn Fn(String, f64, f64, String) -> Row,
) -> Vec<Row> {
    let Some(force) = spec.forces.iter().find(|f| f.muscle.is_some()) else {
        return Vec::new();
    };
    let muscle = match HillMuscle::from_force(force) {
        Ok(HillMuscle::Millard(m)) => *m,
        Ok(HillMuscle::Thelen(_)) => return thelen_curve_rows(stem, folder, row),
        Ok(_) => return Vec::new(),
        Err(e) => {
            return vec![row(
                format!("muscle, {stem}"),
                f64::INFINITY,
                0.0,
                e.to_string(),
            )]
        }
    };
    match compare_millard_curves(&muscle, folder) {
        Ok(c) => vec![
            row(
                format!("Millard curve values, {stem} ({} samples)", c.value.count),
                c.value.error,
                1e-10,
                c.value.at.clone(),
            ),
            row(
                format!("Millard curve slopes (relative), {stem}"),
                c.first_derivative.error,
                1e-10,
                c.first_derivative.at.clone(),
            ),
            row(
                format!("Millard curve curvatures (relative), {stem}"),
                c.second_derivative.error,
                1e-9,
                c.second_derivative.at.clone(),
            ),
        ],
        Err(e) => vec![row(
            format!("Millard curves, {stem}"),
            f64::INFINITY,
            0.0,
            e.to_string(),
        )],
    }
}

/// Thelen curve values and OpenSim's normalized fiber velocity at its force, ≤ 1e-10 absolute;
/// ∞ when a curve has no samples.
fn thelen_curve_rows(stem: &str, folder: &Path, row: &dyn Fn(String, f64, f64, String) -> Row) -> Vec<Row> {
    let c = match compare_thelen_curves(folder) {
        Ok(c) => c,
        Err(e) => return vec![row(format!("Thelen curves, {stem}"), f64::INFINITY, 0.0, e.to_string())],
    };
    let all_curves = if c.curves.len() == 4 { c.value.error } else { f64::INFINITY };
    let velocity = if c.velocity.count > 0 { c.velocity.error } else { f64::INFINITY };
    vec![
        row(format!("Thelen curve values, {stem} ({} samples, {} curves)", c.value.count, c.curves.len()), all_curves, 1e-10, c.value.at.clone()),
        row(format!("Thelen f_V inverse, ṽ at OpenSim's force, {stem}"), velocity, 1e-10, c.velocity.at.clone()),
    ]
}

/// The Thelen fiber-length derivative of gait2392 and arm26 muscles, relative to
/// max(|v|, 1e-3 m/s).
pub fn thelen_velocity_rows() -> Vec<Row> {
    let (folder, reference) = golden_folder("thelen_velocity", "fiber_velocity.csv");
    let what = "Thelen fiber velocity dL_m/dt (relative, ≥ 1e-3 m/s)".to_string();
    let specs: Result<Vec<(&str, ModelSpec)>, String> =
        MUSCLE_MODELS.iter().filter(|(stem, _)| ["gait2392_thelen2003muscle", "arm26"].contains(stem)).map(|(stem, file)| Ok((*stem, read_model(&root().join(file))?))).collect();
    let result = specs.and_then(|specs| {
        let models: Vec<(&str, &ModelSpec)> = specs.iter().map(|(stem, spec)| (*stem, spec)).collect();
        compare_thelen_fiber_velocity(&models, &folder).map_err(|e| e.to_string())
    });
    vec![worst_row(what, reference, result, 1e-9)]
}

/// A row of a `Worst` (its count in the label), or of the error that prevented the comparison.
fn worst_row(what: String, reference: String, worst: Result<Worst, String>, tolerance: f64) -> Row {
    match worst {
        Ok(w) => Row { what: format!("{what} ({} compared)", w.count), reference, worst: w.error, tolerance, at: w.at },
        Err(e) => Row { what, reference, worst: f64::INFINITY, tolerance, at: e },
    }
}

/// DeGrooteFregly2016 curves (relative to max(1, |y|)), equilibrium and fiber velocity of the
/// bench model, with the bounds of `tests/muscle_degroote.rs`.
pub fn degroote_rows() -> Vec<Row> {
    let (folder, reference) = golden_folder("degroote", "equilibrium.csv");
    let model = match read_model(&root().join("fixtures/models/degroote_bench.osim")) {
        Ok(model) => model,
        Err(e) => return vec![worst_row("DeGroote bench model".into(), reference, Err(e), 0.0)],
    };
    let mut rows = match compare_degroote_curves(&folder) {
        Ok(c) => vec![
            worst_row("DeGroote curve values (relative)".into(), reference.clone(), Ok(c.value), 1e-12),
            worst_row("DeGroote curve derivatives (relative)".into(), reference.clone(), Ok(c.derivative), 1e-12),
        ],
        Err(e) => vec![worst_row("DeGroote curves".into(), reference.clone(), Err(e.to_string()), 1e-12)],
    };
    rows.extend(degroote_equilibrium_rows(&model, &folder, &reference));
    let velocity = compare_degroote_fiber_velocity(&model, &folder).map_err(|e| e.to_string());
    rows.push(worst_row("DeGroote fiber velocity (relative, ≥ 1 m/s)".into(), reference, velocity, 1e-9));
    rows
}

/// Lengths ≤ 1e-8; tendon and fiber forces as fractions of their per-row allowance (≤ 1); the
/// rows solved, refused or left unbalanced unlike OpenSim.
fn degroote_equilibrium_rows(model: &ModelSpec, folder: &Path, reference: &str) -> Vec<Row> {
    let c = match compare_degroote_equilibrium(model, folder) {
        Ok(c) => c,
        Err(e) => return vec![worst_row("DeGroote equilibrium".into(), reference.into(), Err(e.to_string()), 0.0)],
    };
    let rows = format!("{} rows + {} refused", c.compared, c.refused);
    let mismatches = Row {
        what: "DeGroote equilibrium rows solved or refused unlike OpenSim".into(),
        reference: reference.into(),
        worst: c.mismatches.len() as f64,
        tolerance: 0.0,
        at: c.mismatches.first().cloned().unwrap_or_default(),
    };
    vec![
        worst_row(format!("DeGroote equilibrium lengths, angles, f_L, f_PE, {rows}"), reference.into(), Ok(c.lengths), DEGROOTE_LENGTH_TOLERANCE),
        worst_row("DeGroote equilibrium tendon force / max(1e-6 N, 1e-8 |F_T|)".into(), reference.into(), Ok(c.tendon_force), 1.0),
        worst_row("DeGroote equilibrium fiber forces / (that + OpenSim's imbalance)".into(), reference.into(), Ok(c.fiber_forces), 1.0),
        mismatches,
    ]
}
