//! `DeGrooteFregly2016Muscle` against OpenSim 4.6's goldens (`fixtures/golden/muscle/degroote/`,
//! written by `oracle/gen_degroote.py` from `fixtures/models/degroote_bench.osim`): the curve
//! functions, the equilibrium of `computeInitialFiberEquilibrium` and the fiber velocity.

use std::collections::HashMap;
use std::path::Path;

use super::geometry::Worst;
use super::golden::{GoldenError, GoldenTable};
use super::muscle::EquilibriumValidationError;
use crate::mechanics::muscle::{DeGrooteCurves, DeGrooteFregly2016Muscle, EquilibriumStatus, FiberEquilibrium, MuscleError};
use crate::model::{DeGrooteSpec, ModelSpec, MuscleModelSpec, MuscleSpec};

/// Worst differences of curve samples relative to max(1, |OpenSim's|).
#[derive(Debug, Clone, Default)]
pub struct DeGrooteCurveComparison {
    pub value: Worst,
    /// Where OpenSim has a derivative; ∞ where only one side has one.
    pub derivative: Worst,
}

/// Compares every sample of `curves.csv` in `folder` with the curves of its `curve_sets.csv` set.
pub fn compare_degroote_curves(folder: &Path) -> Result<DeGrooteCurveComparison, GoldenError> {
    let sets = curve_sets(&GoldenTable::read(&folder.join("curve_sets.csv"))?)?;
    let table = GoldenTable::read(&folder.join("curves.csv"))?;
    let mut comparison = DeGrooteCurveComparison::default();
    for r in 0..table.rows.len() {
        let (set, function, x) = (table.text_at(r, "set_id")?, table.text_at(r, "function")?, table.number_at(r, "x")?);
        let curves = sets.get(set).ok_or_else(|| table.error_at(r, format!("no curve set {set:?}")))?;
        let (value, derivative) = evaluate(curves, function, x).ok_or_else(|| table.error_at(r, format!("unknown curve function {function:?}")))?;
        let at = || format!("{function} set {set} at {x}");
        let (expected, expected_derivative) = (table.number_at(r, "value")?, table.number_at(r, "derivative")?);
        comparison.value.update((value - expected).abs() / expected.abs().max(1.0), at);
        match derivative {
            Some(d) => comparison.derivative.update((d - expected_derivative).abs() / expected_derivative.abs().max(1.0), at),
            None if !expected_derivative.is_nan() => comparison.derivative.update(f64::INFINITY, || format!("{}: OpenSim has a derivative, we have none", at())),
            None => {}
        }
    }
    Ok(comparison)
}

/// The value and, where OpenSim has one, the derivative of its curve function `function` of
/// `curves` at `x`; `None` for an unknown name.
fn evaluate(c: &DeGrooteCurves, function: &str, x: f64) -> Option<(f64, Option<f64>)> {
    Some(match function {
        "calcActiveForceLengthMultiplier" => (c.calc_active_force_length_multiplier(x), Some(c.calc_active_force_length_multiplier_derivative(x))),
        "calcPassiveForceMultiplier" => (c.calc_passive_force_multiplier(x), Some(c.calc_passive_force_multiplier_derivative(x))),
        "calcPassiveForceMultiplierIntegral" => (c.calc_passive_force_multiplier_integral(x), None),
        "calcTendonForceMultiplier" => (c.calc_tendon_force_multiplier(x), Some(c.calc_tendon_force_multiplier_derivative(x))),
        "calcTendonForceMultiplierIntegral" => (c.calc_tendon_force_multiplier_integral(x), None),
        "calcTendonForceLengthInverseCurve" => (c.calc_tendon_force_length_inverse_curve(x), None),
        "calcForceVelocityMultiplier" => (DeGrooteCurves::calc_force_velocity_multiplier(x), None),
        "calcForceVelocityInverseCurve" => (DeGrooteCurves::calc_force_velocity_inverse_curve(x), None),
        _ => return None,
    })
}

/// The curves of each `curve_sets.csv` row by set id.
fn curve_sets(table: &GoldenTable) -> Result<HashMap<String, DeGrooteCurves>, GoldenError> {
    let mut sets = HashMap::new();
    for r in 0..table.rows.len() {
        let number = |name| table.number_at(r, name);
        let curves = DeGrooteCurves::new(
            number("active_force_width_scale")?,
            number("passive_fiber_strain_at_one_norm_force")?,
            number("tendon_strain_at_one_norm_force")?,
            false,
        );
        sets.insert(table.text_at(r, "set_id")?.to_string(), curves);
    }
    Ok(sets)
}

/// A DeGroote muscle of a model with the properties it was built from.
struct BenchMuscle {
    spec: MuscleSpec,
    class: DeGrooteSpec,
    muscle: DeGrooteFregly2016Muscle,
}

/// Every `DeGrooteFregly2016Muscle` of `model` by name.
fn degroote_muscles(model: &ModelSpec) -> Result<HashMap<String, BenchMuscle>, MuscleError> {
    let mut muscles = HashMap::new();
    for force in model.muscles() {
        let Some(spec) = force.muscle.clone() else { continue };
        if let MuscleModelSpec::DeGrooteFregly2016(class) = spec.model.clone() {
            let muscle = DeGrooteFregly2016Muscle::new(&force.name, &spec, &class)?;
            muscles.insert(force.name.clone(), BenchMuscle { spec, class, muscle });
        }
    }
    Ok(muscles)
}

/// The muscle a golden row names.
fn muscle_of<'a>(muscles: &'a HashMap<String, BenchMuscle>, table: &GoldenTable, r: usize) -> Result<&'a BenchMuscle, GoldenError> {
    let name = table.text_at(r, "muscle")?;
    muscles.get(name).ok_or_else(|| table.error_at(r, format!("no DeGrooteFregly2016Muscle {name:?} in the model")))
}

/// Bound on lengths (m), normalized lengths, tendon strain, pennation angle (rad), cos α and the
/// f_L and f_PE multipliers.
pub const DEGROOTE_LENGTH_TOLERANCE: f64 = 1e-8;

/// The equilibrium rows against OpenSim's.
#[derive(Debug, Clone, Default)]
pub struct DeGrooteEquilibriumComparison {
    /// Worst |Δ| of the length-level quantities (see [`DEGROOTE_LENGTH_TOLERANCE`]).
    pub lengths: Worst,
    /// Tendon force |Δ| over its allowance max(1e-6 N, 1e-8 |F_T|): ≤ 1 within.
    pub tendon_force: Worst,
    /// Active, passive and total fiber force and the fiber force along the tendon: |Δ| over the
    /// tendon force's allowance plus the row's OpenSim imbalance: ≤ 1 within.
    pub fiber_forces: Worst,
    /// Rows compared: OpenSim solved them and the path is longer than the tendon slack length.
    pub compared: usize,
    /// Rows we refuse as `Infeasible`, as we must: OpenSim threw, or its rigid tendon is longer
    /// than the path (it reports a fiber pointing backwards).
    pub refused: usize,
    /// Rows solved or refused unlike that, read back with another activation, or not static:
    /// ours with ṽ ≠ 0, f_V ≠ f_V(0) or not converged, OpenSim's with |ṽ| > 1e-6.
    pub mismatches: Vec<String>,
}

/// Compares every row of `equilibrium.csv` in `folder` with our equilibrium of the row's muscle
/// of `model` at its activation and path length.
pub fn compare_degroote_equilibrium(model: &ModelSpec, folder: &Path) -> Result<DeGrooteEquilibriumComparison, EquilibriumValidationError> {
    let table = GoldenTable::read(&folder.join("equilibrium.csv"))?;
    let muscles = degroote_muscles(model)?;
    let mut c = DeGrooteEquilibriumComparison::default();
    for r in 0..table.rows.len() {
        let bench = muscle_of(&muscles, &table, r)?;
        let (activation, mt_length, status) = (table.number_at(r, "activation")?, table.number_at(r, "mt_length")?, table.text_at(r, "status")?);
        let id = format!("{} {} a={activation}", table.text_at(r, "muscle")?, table.text_at(r, "pose_id")?);
        if table.number_at(r, "activation_readback")? != activation {
            c.mismatches.push(format!("{id}: OpenSim read back another activation"));
        }
        let solvable = status == "ok" && mt_length > bench.spec.tendon_slack_length;
        match (solvable, bench.muscle.equilibrium(activation, mt_length)) {
            (true, Ok(ours)) => {
                compare_state(&table, r, &ours, opensim_imbalance(&table, r, bench)?, &id, &mut c)?;
                c.compared += 1;
            }
            (false, Err(MuscleError::Infeasible { .. })) => c.refused += 1,
            (_, ours) => c.mismatches.push(format!("{id}: OpenSim {status}, ours {ours:?}")),
        }
    }
    Ok(c)
}

/// F_max (a f_L |f_V(ṽ) − f_V(0)| + β |ṽ|) (N): the fiber force OpenSim's explicit getters
/// attribute to the velocity its bisection leaves.
fn opensim_imbalance(table: &GoldenTable, r: usize, bench: &BenchMuscle) -> Result<f64, GoldenError> {
    let f_max = bench.spec.max_isometric_force;
    let at_rest = f_max * (table.number_at(r, "activation")? * table.number_at(r, "active_force_length_multiplier")? * DeGrooteCurves::calc_force_velocity_multiplier(0.0));
    Ok((table.number_at(r, "active_fiber_force")? - at_rest).abs() + f_max * bench.class.fiber_damping * table.number_at(r, "normalized_fiber_velocity")?.abs())
}

/// One solved row: differences, bounds and the static-state checks.
fn compare_state(
    table: &GoldenTable,
    r: usize,
    ours: &FiberEquilibrium,
    imbalance: f64,
    id: &str,
    c: &mut DeGrooteEquilibriumComparison,
) -> Result<(), GoldenError> {
    let lengths = [
        ("fiber_length", ours.fiber_length),
        ("fiber_length_along_tendon", ours.fiber_length_along_tendon),
        ("tendon_length", ours.tendon_length),
        ("normalized_fiber_length", ours.normalized_fiber_length),
        ("tendon_strain", ours.tendon_strain),
        ("pennation_angle", ours.pennation_angle),
        ("cos_pennation_angle", ours.cos_pennation_angle),
        ("active_force_length_multiplier", ours.active_force_length_multiplier),
        ("passive_force_multiplier", ours.passive_force_multiplier),
    ];
    for (what, value) in lengths {
        c.lengths.update((value - table.number_at(r, what)?).abs(), || format!("{id} {what}"));
    }
    let tendon_force = table.number_at(r, "tendon_force")?;
    let allowance = 1e-6f64.max(1e-8 * tendon_force.abs());
    c.tendon_force.update((ours.tendon_force - tendon_force).abs() / allowance, || id.to_string());
    let fiber_forces = [
        ("active_fiber_force", ours.active_fiber_force),
        ("passive_fiber_force", ours.passive_fiber_force),
        ("fiber_force", ours.fiber_force),
        ("fiber_force_along_tendon", ours.fiber_force_along_tendon),
    ];
    for (what, value) in fiber_forces {
        c.fiber_forces.update((value - table.number_at(r, what)?).abs() / (allowance + imbalance), || format!("{id} {what}"));
    }
    let opensim_velocity = table.number_at(r, "normalized_fiber_velocity")?;
    if opensim_velocity.is_nan() || opensim_velocity.abs() > 1e-6 {
        c.mismatches.push(format!("{id}: OpenSim left |ṽ| > 1e-6"));
    }
    let at_rest = DeGrooteCurves::calc_force_velocity_multiplier(0.0);
    if ours.normalized_fiber_velocity != 0.0 || ours.force_velocity_multiplier != at_rest || ours.status != EquilibriumStatus::Converged {
        c.mismatches.push(format!("{id}: our state is not static: {ours:?}"));
    }
    Ok(())
}

/// Compares the fiber velocity (m/s) of every row of `fiber_velocity.csv` in `folder` with ours
/// for the row's muscle of `model`: the worst |Δ| / max(1 m/s, |v|).
pub fn compare_degroote_fiber_velocity(model: &ModelSpec, folder: &Path) -> Result<Worst, EquilibriumValidationError> {
    let table = GoldenTable::read(&folder.join("fiber_velocity.csv"))?;
    let muscles = degroote_muscles(model)?;
    let mut worst = Worst::default();
    for r in 0..table.rows.len() {
        let muscle = &muscle_of(&muscles, &table, r)?.muscle;
        let (activation, fiber_length, mt_length) = (table.number_at(r, "activation")?, table.number_at(r, "fiber_length")?, table.number_at(r, "mt_length")?);
        let (expected, tendon_force) = (table.number_at(r, "fiber_velocity")?, table.text_at(r, "normalized_tendon_force")?);
        let ours = muscle.fiber_velocity(activation, fiber_length, mt_length)?;
        let at = || format!("{} a={activation} L_mt={mt_length} f_T={tendon_force}", muscle.name());
        worst.update((ours - expected).abs() / expected.abs().max(1.0), at);
    }
    Ok(worst)
}
