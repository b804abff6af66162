//! The model's `ProbeSet`: `Umberger2010MuscleMetabolicsProbe`s,
//! `Bhargava2004MuscleMetabolicsProbe`s, `ActuatorForceProbe`s and `ActuatorPowerProbe`s read in
//! full (OpenSim's defaults for absent properties; a metabolics probe with a parameter out of
//! range disabled, as OpenSim disables it), other probe classes by name.

use serde::Serialize;

use super::error::ModelError;
use super::function::FunctionSpec;
use super::reader::ComponentReader;

/// A probe of the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeSpec {
    pub name: String,
    pub class: String,
    /// Disabled probes are skipped by the ProbeReporter (`enabled`, default true).
    pub enabled: bool,
    /// `value`, `integrate`, `differentiate`, `minimum`, … (default `value`).
    pub operation: String,
    /// The factor on every output (default 1).
    pub gain: f64,
    pub kind: ProbeKind,
    /// Why OpenSim disables the probe (a parameter out of range), which then reports nothing.
    pub invalid: Option<String>,
}

/// What a probe measures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum ProbeKind {
    Metabolics(MetabolicsProbeSpec),
    /// `ActuatorForceProbe`s and `ActuatorPowerProbe`s: each listed actuator's actuation or power
    /// to `exponent` (default 1), or their sum (`sum_forces_together`, `sum_powers_together`,
    /// default false);
    /// `all` (any case, first) for every actuator.
    Actuators { quantity: ActuatorQuantity, actuators: Vec<String>, summed: bool, exponent: f64 },
    /// A class not read.
    Other,
}

/// What an actuator probe reads of each actuator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum ActuatorQuantity {
    /// `getActuation`, N or N·m.
    Force,
    /// `getPower`, W.
    Power,
}

/// A muscle metabolics probe, with OpenSim's defaults.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetabolicsProbeSpec {
    pub model: MetabolicModel,
    /// Heat of shortening, basal rate and mechanical work rate counted (default true each).
    pub shortening_rate_on: bool,
    pub basal_rate_on: bool,
    pub mechanical_work_rate_on: bool,
    /// A muscle's heat rate is at least 1 W/kg (default true).
    pub enforce_minimum_heat_rate_per_muscle: bool,
    /// W per kg^exponent of the model's mass (default 1.2) and the exponent (default 1).
    pub basal_coefficient: f64,
    pub basal_exponent: f64,
    /// Scales activation, excitation and active fiber force (default 1).
    pub muscle_effort_scaling_factor: f64,
    /// Lengthening's negative work counts (default true).
    pub include_negative_mechanical_work: bool,
    /// The shortening heat raised to keep a muscle's total ≥ 0 (default true).
    pub forbid_negative_total_power: bool,
    /// Only the total, not the basal rate and each muscle's (default true).
    pub report_total_metabolics_only: bool,
    pub muscles: Vec<MetabolicMuscleSpec>,
}

/// What differs between the metabolics models.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum MetabolicModel {
    Umberger2010(UmbergerRates),
    Bhargava2004(BhargavaRates),
}

/// Umberger (2010)'s switches and coefficients.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UmbergerRates {
    /// Activation and maintenance heat, together (default on).
    pub activation_maintenance_rate_on: bool,
    /// Default 1.5, aerobic activities.
    pub aerobic_factor: f64,
    /// The slow-twitch share from the excitation, Bhargava's recruitment (default true).
    pub use_bhargava_recruitment_model: bool,
}

/// Bhargava et al. (2004)'s switches and the maintenance rate's fiber-length dependence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BhargavaRates {
    /// Activation and maintenance heat, apart (default on each).
    pub activation_rate_on: bool,
    pub maintenance_rate_on: bool,
    /// Of the normalized fiber length (default piecewise linear through (0, 0.5), (0.5, 0.5),
    /// (1, 1), (1.5, 0), (2, 0)).
    pub fiber_length_dependence: FunctionSpec,
    /// The shortening heat's constant scaled by force (default false).
    pub use_force_dependent_shortening_prop_constant: bool,
}

/// One muscle's metabolic parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetabolicMuscleSpec {
    /// The muscle's name.
    pub name: String,
    /// Pa (default 0.25e6).
    pub specific_tension: f64,
    /// kg/m³ (default 1059.7).
    pub density: f64,
    /// (default 0.5).
    pub ratio_slow_twitch_fibers: f64,
    /// kg, when given (`use_provided_muscle_mass`); else F_max / specific tension · density · L_opt.
    pub provided_muscle_mass: Option<f64>,
    /// Bhargava's activation constants of slow and fast twitch fibers (default 40, 133) and maintenance
    /// constants (default 74, 111) (W/kg).
    pub twitch_constants: [f64; 4],
}

/// The classes read in full, with the prefix of their muscle parameter set.
const METABOLICS_CLASSES: [&str; 2] = ["Umberger2010MuscleMetabolicsProbe", "Bhargava2004MuscleMetabolicsProbe"];

impl ProbeSpec {
    pub fn read(reader: ComponentReader) -> Result<ProbeSpec, ModelError> {
        let (kind, invalid) = match reader.class() {
            class if METABOLICS_CLASSES.contains(&class) => match MetabolicsProbeSpec::read(reader) {
                Ok(metabolics) => (ProbeKind::Metabolics(metabolics), None),
                Err(error) => (ProbeKind::Other, Some(error.to_string())),
            },
            "ActuatorForceProbe" => {
                (ProbeKind::Actuators { quantity: ActuatorQuantity::Force, actuators: reader.words("actuator_names"), summed: reader.boolean_or("sum_forces_together", false)?, exponent: reader.number_or("exponent", 1.0)? }, None)
            }
            "ActuatorPowerProbe" => {
                (ProbeKind::Actuators { quantity: ActuatorQuantity::Power, actuators: reader.words("actuator_names"), summed: reader.boolean_or("sum_powers_together", false)?, exponent: reader.number_or("exponent", 1.0)? }, None)
            }
            _ => (ProbeKind::Other, None),
        };
        Ok(ProbeSpec {
            name: reader.name(),
            class: reader.class().to_string(),
            enabled: reader.boolean_or("enabled", true)? && !reader.boolean_or("isDisabled", false)? && invalid.is_none(),
            operation: reader.optional_text("probe_operation").filter(|o| !o.is_empty()).unwrap_or_else(|| "value".into()),
            gain: reader.number_or("gain", 1.0)?,
            kind,
            invalid,
        })
    }
}

impl MetabolicsProbeSpec {
    fn read(reader: ComponentReader) -> Result<MetabolicsProbeSpec, ModelError> {
        let flag = |property: &str| reader.boolean_or(property, true);
        let bhargava = reader.class().starts_with("Bhargava");
        let model = if bhargava {
            let fiber_length_dependence = match reader.object_property("normalized_fiber_length_dependence_on_maintenance_rate") {
                Some(function) => FunctionSpec::read(function)?,
                None => FunctionSpec::PiecewiseLinearFunction { x: vec![0.0, 0.5, 1.0, 1.5, 2.0], y: vec![0.5, 0.5, 1.0, 0.0, 0.0] },
            };
            MetabolicModel::Bhargava2004(BhargavaRates {
                activation_rate_on: flag("activation_rate_on")?,
                maintenance_rate_on: flag("maintenance_rate_on")?,
                fiber_length_dependence,
                use_force_dependent_shortening_prop_constant: reader.boolean_or("use_force_dependent_shortening_prop_constant", false)?,
            })
        } else {
            MetabolicModel::Umberger2010(UmbergerRates {
                activation_maintenance_rate_on: flag("activation_maintenance_rate_on")?,
                aerobic_factor: reader.number_or("aerobic_factor", 1.5)?,
                use_bhargava_recruitment_model: flag("use_Bhargava_recruitment_model")?,
            })
        };
        let mut muscles = Vec::new();
        if let Some(set) = reader.child(&format!("{}_MetabolicMuscleParameterSet", reader.class())) {
            for element in reader.listed_objects(set) {
                muscles.push(MetabolicMuscleSpec::read(reader.at(element))?);
            }
        }
        Ok(MetabolicsProbeSpec {
            model,
            shortening_rate_on: flag("shortening_rate_on")?,
            basal_rate_on: flag("basal_rate_on")?,
            mechanical_work_rate_on: flag("mechanical_work_rate_on")?,
            enforce_minimum_heat_rate_per_muscle: flag("enforce_minimum_heat_rate_per_muscle")?,
            basal_coefficient: reader.number_or("basal_coefficient", 1.2)?,
            basal_exponent: reader.number_or("basal_exponent", 1.0)?,
            muscle_effort_scaling_factor: reader.number_or("muscle_effort_scaling_factor", 1.0)?,
            include_negative_mechanical_work: flag("include_negative_mechanical_work")?,
            forbid_negative_total_power: flag("forbid_negative_total_power")?,
            report_total_metabolics_only: flag("report_total_metabolics_only")?,
            muscles,
        })
    }
}

impl MetabolicMuscleSpec {
    fn read(reader: ComponentReader) -> Result<MetabolicMuscleSpec, ModelError> {
        let positive = |property: &str, default: f64, unit: &str| -> Result<f64, ModelError> {
            let value = reader.number_or(property, default)?;
            if value > 0.0 && value.is_finite() {
                Ok(value)
            } else {
                Err(reader.bad(property, &format!("a positive number ({unit})"), &value.to_string()))
            }
        };
        let ratio = reader.number_or("ratio_slow_twitch_fibers", 0.5)?;
        if !(0.0..=1.0).contains(&ratio) {
            return Err(reader.bad("ratio_slow_twitch_fibers", "a ratio between 0 and 1", &ratio.to_string()));
        }
        let provided = if reader.boolean_or("use_provided_muscle_mass", false)? { Some(positive("provided_muscle_mass", f64::NAN, "kg")?) } else { None };
        let constants = [("activation_constant_slow_twitch", 40.0), ("activation_constant_fast_twitch", 133.0), ("maintenance_constant_slow_twitch", 74.0), ("maintenance_constant_fast_twitch", 111.0)];
        let mut twitch_constants = [0.0; 4];
        for (value, (property, default)) in twitch_constants.iter_mut().zip(constants) {
            *value = reader.number_or(property, default)?;
        }
        Ok(MetabolicMuscleSpec {
            name: reader.name(),
            specific_tension: positive("specific_tension", 0.25e6, "Pa")?,
            density: positive("density", 1059.7, "kg/m³")?,
            ratio_slow_twitch_fibers: ratio,
            provided_muscle_mass: provided,
            twitch_constants,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;

    fn probes(set: &str) -> Vec<super::ProbeSpec> {
        let text = format!(r#"<OpenSimDocument Version="40000"><Model name="m"><ProbeSet><objects>{set}</objects></ProbeSet></Model></OpenSimDocument>"#);
        ModelSpec::read(&OsimDocument::parse(text, Path::new("m.osim")).unwrap()).unwrap().probes
    }

    /// OpenSim disables a metabolics probe with a parameter out of range (and reports nothing of
    /// it) rather than failing the model; other classes are kept by name.
    #[test]
    fn a_probe_out_of_range_is_disabled_and_others_are_named() {
        let read = probes(
            r#"<Umberger2010MuscleMetabolicsProbe name="u"><Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameterSet><objects>
               <Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameter name="soleus_r"><ratio_slow_twitch_fibers>1.5</ratio_slow_twitch_fibers></Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameter>
               </objects></Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameterSet></Umberger2010MuscleMetabolicsProbe>
               <Bhargava2004MuscleMetabolicsProbe name="b"><probe_operation>integrate</probe_operation><gain>2</gain></Bhargava2004MuscleMetabolicsProbe>
               <JointInternalPowerProbe name="j"/>"#,
        );
        assert!(!read[0].enabled && read[0].invalid.as_deref().is_some_and(|r| r.contains("ratio_slow_twitch_fibers")), "{:?}", read[0]);
        assert!(read[1].enabled && read[1].operation == "integrate" && read[1].gain == 2.0);
        let super::ProbeKind::Metabolics(bhargava) = &read[1].kind else { panic!("{:?}", read[1]) };
        assert!(bhargava.report_total_metabolics_only && bhargava.muscles.is_empty());
        assert!(matches!(&bhargava.model, super::MetabolicModel::Bhargava2004(rates) if !rates.use_force_dependent_shortening_prop_constant));
        assert!(read[2].enabled && read[2].kind == super::ProbeKind::Other && read[2].class == "JointInternalPowerProbe");
    }
}
