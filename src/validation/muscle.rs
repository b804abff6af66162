//! Muscle mechanics against OpenSim 4.6's goldens (`muscle/<model>/` of the reference data):
//! Millard curve values and derivatives, and the equilibrium rows of `equilibrium.csv`.

use std::collections::HashMap;
use std::path::Path;

use super::geometry::Worst;
use super::golden::{GoldenError, GoldenTable};
use crate::mechanics::muscle::{
    force_velocity_inverse, FiberEquilibrium, HillMuscle, Millard2012Muscle,
    MuscleError, SmoothSegmentedFunction,
};
use crate::model::{ForceVelocityCurveSpec, ModelSpec};

/// Worst differences of curve samples: values absolute, derivatives relative to max(1, |golden|).
#[derive(Debug, Clone, Default)]
pub struct CurveComparison {
    pub value: Worst,
    pub first_derivative: Worst,
    pub second_derivative: Worst,
}

/// The class-default `ForceVelocityInverseCurve` OpenSim 4.6 constructs (the golden's set 0).
pub fn default_force_velocity_inverse() -> SmoothSegmentedFunction {
    let shape = ForceVelocityCurveSpec {
        concentric_slope_at_vmax: 0.1,
        concentric_slope_near_vmax: 0.25,
        isometric_slope: 5.0,
        eccentric_slope_at_vmax: 0.1,
        eccentric_slope_near_vmax: 0.15,
        max_eccentric_velocity_force_multiplier: 1.4,
        concentric_curviness: 0.6,
        eccentric_curviness: 0.9,
    };
    force_velocity_inverse(&shape).expect("OpenSim's defaults are valid")
}

/// Compares the curves of `muscle` (all muscles of a golden model share one set) with
/// `curves.csv` in `folder`.
pub fn compare_millard_curves(
    muscle: &Millard2012Muscle,
    folder: &Path,
) -> Result<CurveComparison, GoldenError> {
    let table = GoldenTable::read(&folder.join("curves.csv"))?;
    let inverse = default_force_velocity_inverse();
    let (curve, x, value) = (
        table.column("curve")?,
        table.column("x")?,
        table.column("value")?,
    );
    let (d1, d2) = (table.column("d1")?, table.column("d2")?);
    let mut comparison = CurveComparison::default();
    for r in 0..table.rows.len() {
        let name = table.rows[r][curve].as_str();
        let function = match name {
            "ActiveForceLengthCurve" => &muscle.curves.active_force_length,
            "FiberForceLengthCurve" => &muscle.curves.fiber_force_length,
            "TendonForceLengthCurve" => &muscle.curves.tendon_force_length,
            "ForceVelocityCurve" => &muscle.curves.force_velocity,
            "ForceVelocityInverseCurve" => &inverse,
            other => return Err(table.error_at(r, format!("unknown curve {other:?}"))),
        };
        let at = table.number(r, x)?;
        let here = || format!("{name} at {at}");
        let ours = [
            function.value(at),
            function.derivative(at),
            function.second_derivative(at),
        ];
        let golden = [
            table.number(r, value)?,
            table.number(r, d1)?,
            table.number(r, d2)?,
        ];
        comparison.value.update((ours[0] - golden[0]).abs(), here);
        comparison
            .first_derivative
            .update((ours[1] - golden[1]).abs() / golden[1].abs().max(1.0), here);
        comparison
            .second_derivative
            .update((ours[2] - golden[2]).abs() / golden[2].abs().max(1.0), here);
    }
    Ok(comparison)
}

/// Which of our solutions is compared with OpenSim's `equilibrateMuscles` state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EquilibriumSolution {
    /// The exact static balance (`HillMuscle::equilibrium`). OpenSim stops at its own solver
    /// tolerance, so each row's force tolerance widens by that row's static imbalance.
    Static,
    /// OpenSim's iteration reproduced (Millard only; other classes fall back to `Static`).
    OpenSim,
}

/// Worst differences over the compared rows, and the rows outside their tolerance.
#[derive(Debug, Clone, Default)]
pub struct EquilibriumComparison {
    /// m, raw difference.
    pub fiber_length: Worst,
    /// m, beyond the row's allowance: `FIBER_LENGTH_TOLERANCE`, plus for `Static` twice
    /// OpenSim's imbalance over the balance's stiffness |∂(F_m cos α − F_t)/∂L_m| (OpenSim's
    /// tolerance maps to long fiber-length differences where tendon and fiber are both soft).
    pub fiber_length_excess: Worst,
    /// rad.
    pub pennation_angle: Worst,
    /// m.
    pub tendon_length: Worst,
    /// N, beyond the row's allowance (max(1e-6 N, 1e-8 relative), plus OpenSim's static
    /// imbalance for `Static`): ≤ 0 means within tolerance.
    pub tendon_force_excess: Worst,
    /// N, raw difference.
    pub tendon_force: Worst,
    /// N: active and passive fiber force.
    pub fiber_forces: Worst,
    /// Largest OpenSim static imbalance seen, N.
    pub opensim_imbalance: Worst,
    /// Rows with a fiber length off by more than the solution's tolerance or a force beyond its
    /// allowance.
    pub outside_tolerance: Vec<String>,
}

/// Fiber length agreement with OpenSim's own state, m.
pub const FIBER_LENGTH_TOLERANCE: f64 = 1e-8;
/// Fiber length agreement of the exact static balance with OpenSim's state where the balance's
/// stiffness is not available (DeGroote), m.
pub const STATIC_FIBER_LENGTH_TOLERANCE: f64 = 1e-7;

/// One golden row's reported state.
struct GoldenRow {
    id: String,
    activation: f64,
    mt_length: f64,
    values: HashMap<&'static str, f64>,
}

const FIELDS: [&str; 11] = [
    "force_velocity_multiplier",
    "fiber_length",
    "pennation_angle",
    "tendon_length",
    "tendon_force",
    "active_fiber_force",
    "passive_fiber_force",
    "fiber_force",
    "cos_pennation_angle",
    "active_force_length_multiplier",
    "passive_force_multiplier",
];

/// Compares every row of `equilibrium.csv` in `folder` with our solution for the row's muscle,
/// activation and path length (the golden `mt_length`, which equals our path length to 1e-15 m
/// — the geometry conformance tests check that).
pub fn compare_equilibrium(
    model: &ModelSpec,
    folder: &Path,
    solution: EquilibriumSolution,
) -> Result<EquilibriumComparison, EquilibriumValidationError> {
    let table = GoldenTable::read(&folder.join("equilibrium.csv"))?;
    let muscles = build_muscles(model)?;
    let mut comparison = EquilibriumComparison::default();
    for r in 0..table.rows.len() {
        let row = golden_row(&table, r)?;
        let muscle_name = table.rows[r][table.column("muscle")?].clone();
        let (max_force, muscle) = muscles
            .get(&muscle_name)
            .ok_or_else(|| table.error_at(r, format!("muscle {muscle_name:?} is not in the model")))?;
        let ours = solve(muscle, solution, row.activation, row.mt_length)?;
        let length_allowance = length_allowance(muscle, solution, &row, &ours, *max_force);
        compare_row(
            &row,
            &ours,
            *max_force,
            solution,
            length_allowance,
            &mut comparison,
        );
    }
    Ok(comparison)
}

fn solve(
    muscle: &HillMuscle,
    solution: EquilibriumSolution,
    activation: f64,
    mt_length: f64,
) -> Result<FiberEquilibrium, MuscleError> {
    match (solution, muscle) {
        (EquilibriumSolution::OpenSim, HillMuscle::Millard(m)) => {
            m.opensim_equilibrium(activation, mt_length)
        }
        _ => muscle.equilibrium(activation, mt_length),
    }
}

/// The fiber-length allowance of one row (see `EquilibriumComparison::fiber_length_excess`).
fn length_allowance(
    muscle: &HillMuscle,
    solution: EquilibriumSolution,
    row: &GoldenRow,
    ours: &FiberEquilibrium,
    max_force: f64,
) -> f64 {
    if solution == EquilibriumSolution::OpenSim {
        return FIBER_LENGTH_TOLERANCE;
    }
    let (a, l, h) = (row.activation, ours.fiber_length, 1e-7 * ours.fiber_length);
    let balance = |fiber_length| muscle.static_force_residual(a, fiber_length, row.mt_length);
    match (balance(l + h), balance(l - h)) {
        (Some(up), Some(down)) if up != down => {
            FIBER_LENGTH_TOLERANCE
                + 2.0 * opensim_imbalance(row, max_force) * (2.0 * h) / (up - down).abs()
        }
        _ => STATIC_FIBER_LENGTH_TOLERANCE,
    }
}

fn build_muscles(model: &ModelSpec) -> Result<HashMap<String, (f64, HillMuscle)>, MuscleError> {
    let mut muscles = HashMap::new();
    for force in model.forces.iter().filter(|f| f.muscle.is_some()) {
        let max_force = force.muscle.as_ref().map_or(0.0, |m| m.max_isometric_force);
        muscles.insert(
            force.name.clone(),
            (max_force, HillMuscle::from_force(force)?),
        );
    }
    Ok(muscles)
}

fn golden_row(table: &GoldenTable, r: usize) -> Result<GoldenRow, GoldenError> {
    let number = |name: &str| -> Result<f64, GoldenError> { table.number(r, table.column(name)?) };
    let mut values = HashMap::new();
    for field in FIELDS {
        values.insert(field, number(field)?);
    }
    let id = format!(
        "{} {} a={}",
        table.rows[r][0], table.rows[r][1], table.rows[r][2]
    );
    Ok(GoldenRow {
        id,
        activation: number("activation_readback")?,
        mt_length: number("mt_length")?,
        values,
    })
}

/// How far OpenSim's reported state is from the static balance, N: F_max (a f_L + f_PE) cos α −
/// F_t with OpenSim's own multipliers. 0 for rows whose fiber OpenSim reports force-free
/// (clamped at its minimum length): those must match as they are.
fn opensim_imbalance(row: &GoldenRow, max_force: f64) -> f64 {
    let v = &row.values;
    if v["fiber_force"] == 0.0 {
        return 0.0;
    }
    let static_fiber_force = max_force
        * (row.activation * v["active_force_length_multiplier"] + v["passive_force_multiplier"]);
    (static_fiber_force * v["cos_pennation_angle"] - v["tendon_force"]).abs()
}

fn compare_row(
    row: &GoldenRow,
    ours: &FiberEquilibrium,
    max_force: f64,
    solution: EquilibriumSolution,
    length_tolerance: f64,
    c: &mut EquilibriumComparison,
) {
    let v = &row.values;
    let at = || row.id.clone();
    let imbalance = opensim_imbalance(row, max_force);
    c.opensim_imbalance.update(imbalance, at);
    let widen = if solution == EquilibriumSolution::Static {
        imbalance
    } else {
        0.0
    };
    let allowance = 1e-6_f64.max(1e-8 * v["tendon_force"].abs()) + widen;
    let force_error = (ours.tendon_force - v["tendon_force"]).abs();
    let length_error = (ours.fiber_length - v["fiber_length"]).abs();
    c.fiber_length.update(length_error, at);
    c.fiber_length_excess
        .update(length_error - length_tolerance, at);
    c.pennation_angle
        .update((ours.pennation_angle - v["pennation_angle"]).abs(), at);
    c.tendon_length
        .update((ours.tendon_length - v["tendon_length"]).abs(), at);
    c.tendon_force.update(force_error, at);
    c.tendon_force_excess.update(force_error - allowance, at);
    let fiber = (ours.active_fiber_force - v["active_fiber_force"])
        .abs()
        .max((ours.passive_fiber_force - v["passive_fiber_force"]).abs());
    c.fiber_forces.update(fiber, at);
    // OpenSim's active force carries its f_V ≠ 1 and its passive force the fiber damping.
    let velocity_terms = (v["active_fiber_force"] * (1.0 - 1.0 / v["force_velocity_multiplier"]))
        .abs()
        + (v["passive_fiber_force"] - max_force * v["passive_force_multiplier"]).abs();
    let fiber_allowance = allowance
        + if solution == EquilibriumSolution::Static {
            velocity_terms
        } else {
            0.0
        };
    if length_error > length_tolerance || force_error > allowance || fiber > fiber_allowance {
        c.outside_tolerance.push(format!(
            "{}: fiber length off by {length_error:e} m (allowance {length_tolerance:e} m), tendon force by {force_error:e} N, fiber forces by {fiber:e} N (allowance {allowance:e} N)",
            row.id
        ));
    }
}

/// Reading goldens or building muscles failed.
#[derive(Debug, thiserror::Error)]
pub enum EquilibriumValidationError {
    #[error(transparent)]
    Golden(#[from] GoldenError),
    #[error(transparent)]
    Muscle(#[from] MuscleError),
}
