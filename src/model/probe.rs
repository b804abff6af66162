//! The model's `ProbeSet`: `Umberger2010MuscleMetabolicsProbe`s read in full (OpenSim's defaults
//! for absent properties; one with a parameter out of range disabled, as OpenSim disables it),
//! other probe classes by name.

use serde::Serialize;

use super::error::ModelError;
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
    /// The metabolics model, `None` for another class.
    pub umberger: Option<UmbergerProbeSpec>,
    /// Why OpenSim disables the probe (a parameter out of range), which then reports nothing.
    pub invalid: Option<String>,
}

/// An `Umberger2010MuscleMetabolicsProbe`'s switches and coefficients (Umberger 2010; OpenSim's
/// defaults in brackets).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UmbergerProbeSpec {
    /// [true] each.
    pub activation_maintenance_rate_on: bool,
    pub shortening_rate_on: bool,
    pub basal_rate_on: bool,
    pub mechanical_work_rate_on: bool,
    /// A muscle's heat rate is at least 1 W/kg [true].
    pub enforce_minimum_heat_rate_per_muscle: bool,
    /// [1.5], aerobic activities.
    pub aerobic_factor: f64,
    /// W/kg^exponent of body mass [1.2] and the exponent [1].
    pub basal_coefficient: f64,
    pub basal_exponent: f64,
    /// Scales activation, excitation and active fiber force [1].
    pub muscle_effort_scaling_factor: f64,
    /// The slow-twitch share from the excitation (Bhargava et al. 2004) [true].
    pub use_bhargava_recruitment_model: bool,
    /// Lengthening's negative work counts [true].
    pub include_negative_mechanical_work: bool,
    /// The shortening heat raised to keep a muscle's total ≥ 0 [true].
    pub forbid_negative_total_power: bool,
    /// Only the total, not the basal rate and each muscle's [true].
    pub report_total_metabolics_only: bool,
    pub muscles: Vec<MetabolicMuscleSpec>,
}

/// One muscle's metabolic parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetabolicMuscleSpec {
    /// The muscle's name.
    pub name: String,
    /// Pa [0.25e6].
    pub specific_tension: f64,
    /// kg/m³ [1059.7].
    pub density: f64,
    /// [0.5].
    pub ratio_slow_twitch_fibers: f64,
    /// kg, when given (`use_provided_muscle_mass`); else F_max / specific tension · density · L_opt.
    pub provided_muscle_mass: Option<f64>,
}

impl ProbeSpec {
    pub fn read(reader: ComponentReader) -> Result<ProbeSpec, ModelError> {
        let (umberger, invalid) = match reader.class() {
            "Umberger2010MuscleMetabolicsProbe" => match UmbergerProbeSpec::read(reader) {
                Ok(umberger) => (Some(umberger), None),
                Err(error) => (None, Some(error.to_string())),
            },
            _ => (None, None),
        };
        Ok(ProbeSpec {
            name: reader.name(),
            class: reader.class().to_string(),
            enabled: reader.boolean_or("enabled", true)? && !reader.boolean_or("isDisabled", false)? && invalid.is_none(),
            operation: reader.optional_text("probe_operation").filter(|o| !o.is_empty()).unwrap_or_else(|| "value".into()),
            gain: reader.number_or("gain", 1.0)?,
            umberger,
            invalid,
        })
    }
}

impl UmbergerProbeSpec {
    fn read(reader: ComponentReader) -> Result<UmbergerProbeSpec, ModelError> {
        let flag = |property: &str| reader.boolean_or(property, true);
        let mut muscles = Vec::new();
        if let Some(set) = reader.child("Umberger2010MuscleMetabolicsProbe_MetabolicMuscleParameterSet") {
            for element in reader.listed_objects(set) {
                muscles.push(MetabolicMuscleSpec::read(reader.at(element))?);
            }
        }
        Ok(UmbergerProbeSpec {
            activation_maintenance_rate_on: flag("activation_maintenance_rate_on")?,
            shortening_rate_on: flag("shortening_rate_on")?,
            basal_rate_on: flag("basal_rate_on")?,
            mechanical_work_rate_on: flag("mechanical_work_rate_on")?,
            enforce_minimum_heat_rate_per_muscle: flag("enforce_minimum_heat_rate_per_muscle")?,
            aerobic_factor: reader.number_or("aerobic_factor", 1.5)?,
            basal_coefficient: reader.number_or("basal_coefficient", 1.2)?,
            basal_exponent: reader.number_or("basal_exponent", 1.0)?,
            muscle_effort_scaling_factor: reader.number_or("muscle_effort_scaling_factor", 1.0)?,
            use_bhargava_recruitment_model: flag("use_Bhargava_recruitment_model")?,
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
        Ok(MetabolicMuscleSpec {
            name: reader.name(),
            specific_tension: positive("specific_tension", 0.25e6, "Pa")?,
            density: positive("density", 1059.7, "kg/m³")?,
            ratio_slow_twitch_fibers: ratio,
            provided_muscle_mass: provided,
        })
    }
}
