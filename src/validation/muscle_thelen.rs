//! `Thelen2003Muscle` against OpenSim 4.6's goldens: the curves of `curves.csv` (parameter sets in
//! `curve_sets.csv`) and the fiber-length state derivative of `fiber_velocity.csv`
//! (`getStateVariableDerivativeValue`, from `oracle/gen_thelen_velocity.py`).

use std::collections::{BTreeSet, HashMap};
use std::path::Path;

use super::geometry::Worst;
use super::golden::{GoldenError, GoldenTable};
use super::muscle::EquilibriumValidationError;
use crate::mechanics::muscle::{HillMuscle, MuscleError, Thelen2003Muscle, ThelenCurves};
use crate::model::ModelSpec;

/// Worst absolute differences of the Thelen curve samples.
#[derive(Debug, Clone, Default)]
pub struct ThelenCurveComparison {
    /// f_L, f_PE, f_SE and f_V(a, ṽ) against OpenSim's values (dimensionless).
    pub value: Worst,
    /// Our normalized fiber velocity ṽ at OpenSim's force a·f_V (with f_L = 1) against its ṽ.
    pub velocity: Worst,
    /// The curves the samples covered.
    pub curves: BTreeSet<String>,
}

/// Compares every sample of `curves.csv` in `folder` with the curves of its `curve_sets.csv`
/// parameter set. f_V is checked both ways: f_V(a, ṽ) against OpenSim's multiplier, and ṽ
/// against ours at OpenSim's force.
pub fn compare_thelen_curves(folder: &Path) -> Result<ThelenCurveComparison, GoldenError> {
    let sets = curve_sets(&GoldenTable::read(&folder.join("curve_sets.csv"))?)?;
    let table = GoldenTable::read(&folder.join("curves.csv"))?;
    let mut comparison = ThelenCurveComparison::default();
    for r in 0..table.rows.len() {
        let set = table.text_at(r, "set_id")?;
        let c = sets.get(set).ok_or_else(|| table.error_at(r, format!("no curve set {set:?}")))?;
        let (curve, a, x, value) = (table.text_at(r, "curve")?, table.number_at(r, "activation")?, table.number_at(r, "x")?, table.number_at(r, "value")?);
        let at = || format!("{curve} a = {a} x = {x}");
        let ours = match curve {
            "ThelenActiveForceLength" => c.active_force_length(x),
            "ThelenPassiveForceLength" => c.passive_force_length(x),
            "ThelenTendonForceLength" => c.tendon_force_length(x),
            "ThelenForceVelocity" => {
                comparison.velocity.update((c.normalized_fiber_velocity(a, 1.0, a * value) - x).abs(), at);
                c.force_velocity(a, x)
            }
            other => return Err(table.error_at(r, format!("unknown curve {other:?}"))),
        };
        comparison.value.update((ours - value).abs(), at);
        comparison.curves.insert(curve.into());
    }
    Ok(comparison)
}

/// The curves of each `curve_sets.csv` row (`params` = `name=value;…`) by set id.
fn curve_sets(table: &GoldenTable) -> Result<HashMap<String, ThelenCurves>, GoldenError> {
    let mut sets = HashMap::new();
    for r in 0..table.rows.len() {
        let pairs: Option<HashMap<&str, f64>> =
            table.text_at(r, "params")?.split(';').map(|pair| pair.split_once('=').and_then(|(k, v)| Some((k, v.parse().ok()?)))).collect();
        let pairs = pairs.ok_or_else(|| table.error_at(r, "params is not name=number;…".into()))?;
        let parameter = |name: &str| pairs.get(name).copied().ok_or_else(|| table.error_at(r, format!("params lack {name}")));
        let curves = ThelenCurves {
            fmax_tendon_strain: parameter("FmaxTendonStrain")?,
            fmax_muscle_strain: parameter("FmaxMuscleStrain")?,
            kshape_active: parameter("KshapeActive")?,
            kshape_passive: parameter("KshapePassive")?,
            af: parameter("Af")?,
            flen: parameter("Flen")?,
            fv_linear_extrap_threshold: parameter("fv_linear_extrap_threshold")?,
        };
        sets.insert(table.text_at(r, "set_id")?.to_string(), curves);
    }
    Ok(sets)
}

/// Every `Thelen2003Muscle` of `model` by name.
fn thelen_muscles(model: &ModelSpec) -> Result<HashMap<String, Thelen2003Muscle>, MuscleError> {
    let mut muscles = HashMap::new();
    for force in model.muscles() {
        if let HillMuscle::Thelen(muscle) = HillMuscle::from_force(force)? {
            muscles.insert(force.name.clone(), muscle);
        }
    }
    Ok(muscles)
}

/// Compares dL_m/dt (m/s) of every row of `fiber_velocity.csv` in `folder` with ours; `models`
/// names the model of the golden's `model` column. The worst is |Δ| / max(|v|, 1e-3 m/s): a
/// bound of 1e-9 on it is 1e-9 relative with 1e-12 m/s absolute near zero.
pub fn compare_thelen_fiber_velocity(models: &[(&str, &ModelSpec)], folder: &Path) -> Result<Worst, EquilibriumValidationError> {
    let table = GoldenTable::read(&folder.join("fiber_velocity.csv"))?;
    let mut muscles = HashMap::new();
    for (stem, model) in models {
        muscles.insert(stem.to_string(), thelen_muscles(model)?);
    }
    let mut worst = Worst::default();
    for r in 0..table.rows.len() {
        let (stem, name) = (table.text_at(r, "model")?, table.text_at(r, "muscle")?);
        let muscle = muscles.get(stem).and_then(|m| m.get(name)).ok_or_else(|| table.error_at(r, format!("no Thelen muscle {stem} {name}")))?;
        let (a, fiber_length, mt_length) = (table.number_at(r, "activation")?, table.number_at(r, "fiber_length")?, table.number_at(r, "mt_length")?);
        let theirs = table.number_at(r, "fiber_length_derivative")?;
        if theirs != table.number_at(r, "fiber_velocity")? {
            return Err(table.error_at(r, "fiber_length_derivative differs from fiber_velocity".into()).into());
        }
        let ours = muscle.fiber_velocity(a, fiber_length, mt_length)?;
        worst.update((ours - theirs).abs() / theirs.abs().max(1e-3), || format!("{stem} {name} a = {a} L_m = {fiber_length} L_mt = {mt_length}"));
    }
    Ok(worst)
}
