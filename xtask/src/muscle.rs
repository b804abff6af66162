//! Muscle rows of the validation table: Millard curves and the equilibrium rows against
//! OpenSim 4.6, over the full goldens when `../shared/reference` (or `$OSIM_TUNE_REFERENCE`) is
//! present, else over the slice in `fixtures/golden/muscle/`.

use std::path::{Path, PathBuf};

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::muscle::HillMuscle;
use osim_tune::model::{ModelSpec, MuscleModelSpec};
use osim_tune::validation::{
    compare_equilibrium, compare_millard_curves, EquilibriumSolution, FIBER_LENGTH_TOLERANCE,
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

fn golden_folder(stem: &str) -> (PathBuf, String) {
    let reference = std::env::var_os("OSIM_TUNE_REFERENCE")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("../shared/reference"));
    let full = reference.join("muscle").join(stem);
    if full.join("equilibrium.csv").exists() {
        (full, "OpenSim 4.6, all rows".into())
    } else {
        (
            root().join("fixtures/golden/muscle").join(stem),
            "OpenSim 4.6, fixture slice".into(),
        )
    }
}

pub fn rows(stem: &str, model: &Path) -> Vec<Row> {
    let (folder, reference) = golden_folder(stem);
    let row = |what: String, worst: f64, tolerance: f64, at: String| Row {
        what,
        reference: reference.clone(),
        worst,
        tolerance,
        at,
    };
    let spec = match OsimDocument::read(model)
        .map_err(|e| e.to_string())
        .and_then(|d| ModelSpec::read(&d).map_err(|e| e.to_string()))
    {
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

/// Millard curve values and derivatives (the models share one curve set; the first muscle's).
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
