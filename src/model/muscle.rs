//! Muscle properties of the Hill-type muscle classes osim-tune evaluates: the architecture every
//! `Muscle` has and the class-specific curve parameters. Absent properties take the OpenSim 4.6
//! class defaults (which differ from the values most model files carry).

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;

/// Architecture shared by all muscle classes (OpenSim `Muscle`), SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuscleSpec {
    /// F_max, N.
    pub max_isometric_force: f64,
    /// L_opt, m.
    pub optimal_fiber_length: f64,
    /// L_ts, m.
    pub tendon_slack_length: f64,
    /// α_opt, rad.
    pub pennation_angle_at_optimal: f64,
    /// v_max, optimal fiber lengths per second.
    pub max_contraction_velocity: f64,
    pub ignore_tendon_compliance: bool,
    pub ignore_activation_dynamics: bool,
    pub model: MuscleModelSpec,
}

/// The class-specific part of a muscle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum MuscleModelSpec {
    Millard2012(MillardSpec),
    Thelen2003(ThelenSpec),
    DeGrooteFregly2016(DeGrooteSpec),
}

/// `Millard2012EquilibriumMuscle` properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MillardSpec {
    /// Normalised damping coefficient β (F_max · s / L_opt per unit normalised velocity).
    pub fiber_damping: f64,
    pub default_activation: f64,
    /// The fiber-length state a model starts from, m (OpenSim's default 0.1).
    pub default_fiber_length: f64,
    pub minimum_activation: f64,
    /// τ_a, `activation_time_constant`, s.
    pub activation_time_constant: f64,
    /// τ_d, `deactivation_time_constant`, s.
    pub deactivation_time_constant: f64,
    /// rad.
    pub maximum_pennation_angle: f64,
    pub active_force_length: ActiveForceLengthCurveSpec,
    pub force_velocity: ForceVelocityCurveSpec,
    pub fiber_force_length: FiberForceLengthCurveSpec,
    pub tendon_force_length: TendonForceLengthCurveSpec,
}

/// `ActiveForceLengthCurve` (normalised fiber length → active force multiplier).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ActiveForceLengthCurveSpec {
    pub min_norm_active_fiber_length: f64,
    pub transition_norm_fiber_length: f64,
    pub max_norm_active_fiber_length: f64,
    pub shallow_ascending_slope: f64,
    pub minimum_value: f64,
}

/// `ForceVelocityCurve` (normalised fiber velocity, −1 = v_max shortening → multiplier).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceVelocityCurveSpec {
    pub concentric_slope_at_vmax: f64,
    pub concentric_slope_near_vmax: f64,
    pub isometric_slope: f64,
    pub eccentric_slope_at_vmax: f64,
    pub eccentric_slope_near_vmax: f64,
    pub max_eccentric_velocity_force_multiplier: f64,
    pub concentric_curviness: f64,
    pub eccentric_curviness: f64,
}

/// `FiberForceLengthCurve` (normalised fiber length → passive force multiplier). Unset optional
/// properties are derived by OpenSim from the strains.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FiberForceLengthCurveSpec {
    pub strain_at_zero_force: f64,
    pub strain_at_one_norm_force: f64,
    pub stiffness_at_low_force: Option<f64>,
    pub stiffness_at_one_norm_force: Option<f64>,
    pub curviness: Option<f64>,
}

/// `TendonForceLengthCurve` (normalised tendon length 1 + ε → normalised force).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TendonForceLengthCurveSpec {
    pub strain_at_one_norm_force: f64,
    pub stiffness_at_one_norm_force: Option<f64>,
    pub norm_force_at_toe_end: Option<f64>,
    pub curviness: Option<f64>,
}

/// `Thelen2003Muscle` properties (Thelen 2003 curves).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThelenSpec {
    /// Tendon strain at F_max.
    pub fmax_tendon_strain: f64,
    /// Passive fiber strain at F_max.
    pub fmax_muscle_strain: f64,
    pub kshape_active: f64,
    pub kshape_passive: f64,
    pub af: f64,
    pub flen: f64,
    pub fv_linear_extrap_threshold: f64,
    /// rad.
    pub maximum_pennation_angle: f64,
    pub default_activation: f64,
    /// The fiber-length state a model starts from, m (OpenSim's default 0.1).
    pub default_fiber_length: f64,
    pub minimum_activation: f64,
    /// τ_a, `activation_time_constant`, s.
    pub activation_time_constant: f64,
    /// τ_d, `deactivation_time_constant`, s.
    pub deactivation_time_constant: f64,
}

/// `DeGrooteFregly2016Muscle` properties (the class OpenSim Moco models use).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeGrooteSpec {
    pub active_force_width_scale: f64,
    pub fiber_damping: f64,
    pub ignore_passive_fiber_force: bool,
    pub passive_fiber_strain_at_one_norm_force: f64,
    pub tendon_strain_at_one_norm_force: f64,
    pub default_activation: f64,
    pub default_normalized_tendon_force: f64,
    pub tendon_compliance_dynamics_mode: String,
    /// τ_a, `activation_time_constant`, s.
    pub activation_time_constant: f64,
    /// τ_d, `deactivation_time_constant`, s.
    pub deactivation_time_constant: f64,
    /// b of the activation dynamics' tanh switch between τ_a and τ_d
    /// (`activation_dynamics_smoothing`).
    pub activation_dynamics_smoothing: f64,
}

/// The state a muscle class integrates besides its activation (none beside a rigid tendon).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SecondState {
    /// `fiber_length`, m (Millard, Thelen).
    FiberLength,
    /// `normalized_tendon_force` (DeGroote).
    NormalizedTendonForce,
}

impl SecondState {
    /// The state variable's name in OpenSim.
    pub fn label(self) -> &'static str {
        match self {
            SecondState::FiberLength => "fiber_length",
            SecondState::NormalizedTendonForce => "normalized_tendon_force",
        }
    }
}

/// The muscle classes with mechanics in osim-tune.
pub const MUSCLE_CLASSES: [&str; 3] = [
    "Millard2012EquilibriumMuscle",
    "Thelen2003Muscle",
    "DeGrooteFregly2016Muscle",
];

/// `default_fiber_length` when absent, m (Millard and Thelen alike: the class default
/// `optimal_fiber_length` at construction).
const DEFAULT_FIBER_LENGTH: f64 = 0.1;

/// Minimum cos α of the 4.6 defaults: `maximum_pennation_angle = acos(0.1)`.
const DEFAULT_MAXIMUM_PENNATION: f64 = 1.4706289056333368;

impl MuscleSpec {
    /// [τ_a, τ_d] (s): the class's activation and deactivation time constants.
    pub fn time_constants(&self) -> [f64; 2] {
        match &self.model {
            MuscleModelSpec::Millard2012(m) => [m.activation_time_constant, m.deactivation_time_constant],
            MuscleModelSpec::Thelen2003(t) => [t.activation_time_constant, t.deactivation_time_constant],
            MuscleModelSpec::DeGrooteFregly2016(d) => [d.activation_time_constant, d.deactivation_time_constant],
        }
    }

    /// (activation, the second state's kind and value) of the state a model starts from.
    pub fn default_state(&self) -> (f64, SecondState, f64) {
        match &self.model {
            MuscleModelSpec::Millard2012(m) => (m.default_activation, SecondState::FiberLength, m.default_fiber_length),
            MuscleModelSpec::Thelen2003(t) => (t.default_activation, SecondState::FiberLength, t.default_fiber_length),
            MuscleModelSpec::DeGrooteFregly2016(d) => (d.default_activation, SecondState::NormalizedTendonForce, d.default_normalized_tendon_force),
        }
    }

    /// Reads the muscle of a force element, or `None` when its class has no mechanics here.
    pub fn read(reader: ComponentReader) -> Result<Option<MuscleSpec>, ModelError> {
        let model = match reader.class() {
            "Millard2012EquilibriumMuscle" => {
                MuscleModelSpec::Millard2012(MillardSpec::read(reader)?)
            }
            "Thelen2003Muscle" => MuscleModelSpec::Thelen2003(ThelenSpec::read(reader)?),
            "DeGrooteFregly2016Muscle" => {
                MuscleModelSpec::DeGrooteFregly2016(DeGrooteSpec::read(reader)?)
            }
            _ => return Ok(None),
        };
        let spec = MuscleSpec {
            max_isometric_force: reader.number_or("max_isometric_force", 1000.0)?,
            optimal_fiber_length: reader.number_or("optimal_fiber_length", 0.1)?,
            tendon_slack_length: reader.number_or("tendon_slack_length", 0.2)?,
            pennation_angle_at_optimal: reader.number_or("pennation_angle_at_optimal", 0.0)?,
            max_contraction_velocity: reader.number_or("max_contraction_velocity", 10.0)?,
            ignore_tendon_compliance: reader.boolean_or("ignore_tendon_compliance", false)?,
            ignore_activation_dynamics: reader.boolean_or("ignore_activation_dynamics", false)?,
            model,
        };
        spec.check(reader)?;
        Ok(Some(spec))
    }

    /// OpenSim's own range checks on the architecture.
    fn check(&self, reader: ComponentReader) -> Result<(), ModelError> {
        let positive = [
            ("max_isometric_force", self.max_isometric_force),
            ("optimal_fiber_length", self.optimal_fiber_length),
            ("max_contraction_velocity", self.max_contraction_velocity),
        ];
        for (property, value) in positive {
            if !(value > 0.0 && value.is_finite()) {
                return Err(reader.bad(property, "a positive number", &value.to_string()));
            }
        }
        // A rigid tendon only takes up L_ts of the path, so OpenSim's models may leave it out
        // (ThoracoscapularShoulderModel's serratus anterior); a compliant one's strain needs it.
        let l_ts = self.tendon_slack_length;
        let rigid = self.ignore_tendon_compliance && !matches!(self.model, MuscleModelSpec::Thelen2003(_));
        if !(l_ts.is_finite() && (l_ts > 0.0 || (rigid && l_ts == 0.0))) {
            let expected = if rigid { "a length ≥ 0 m" } else { "a positive number (a compliant tendon's strain needs it)" };
            return Err(reader.bad("tendon_slack_length", expected, &l_ts.to_string()));
        }
        let alpha = self.pennation_angle_at_optimal;
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&alpha) {
            return Err(reader.bad(
                "pennation_angle_at_optimal",
                "an angle in [0, π/2) rad",
                &alpha.to_string(),
            ));
        }
        Ok(())
    }
}

impl MillardSpec {
    fn read(reader: ComponentReader) -> Result<MillardSpec, ModelError> {
        let curve = |class: &str| reader.child_of_class(class);
        let afl = curve("ActiveForceLengthCurve");
        let fv = curve("ForceVelocityCurve");
        let fpe = curve("FiberForceLengthCurve");
        let tfl = curve("TendonForceLengthCurve");
        Ok(MillardSpec {
            fiber_damping: reader.number_or("fiber_damping", 0.1)?,
            default_activation: reader.number_or("default_activation", 0.05)?,
            default_fiber_length: reader.number_or("default_fiber_length", DEFAULT_FIBER_LENGTH)?,
            minimum_activation: reader.number_or("minimum_activation", 0.01)?,
            activation_time_constant: reader.number_or("activation_time_constant", 0.01)?,
            deactivation_time_constant: reader.number_or("deactivation_time_constant", 0.04)?,
            maximum_pennation_angle: reader
                .number_or("maximum_pennation_angle", DEFAULT_MAXIMUM_PENNATION)?,
            active_force_length: ActiveForceLengthCurveSpec {
                min_norm_active_fiber_length: number_in(
                    afl,
                    "min_norm_active_fiber_length",
                    0.47 - 0.0259,
                )?,
                transition_norm_fiber_length: number_in(afl, "transition_norm_fiber_length", 0.73)?,
                max_norm_active_fiber_length: number_in(
                    afl,
                    "max_norm_active_fiber_length",
                    1.8123,
                )?,
                shallow_ascending_slope: number_in(afl, "shallow_ascending_slope", 0.8616)?,
                minimum_value: number_in(afl, "minimum_value", 0.1)?,
            },
            force_velocity: ForceVelocityCurveSpec {
                concentric_slope_at_vmax: number_in(fv, "concentric_slope_at_vmax", 0.0)?,
                concentric_slope_near_vmax: number_in(fv, "concentric_slope_near_vmax", 0.25)?,
                isometric_slope: number_in(fv, "isometric_slope", 5.0)?,
                eccentric_slope_at_vmax: number_in(fv, "eccentric_slope_at_vmax", 0.0)?,
                eccentric_slope_near_vmax: number_in(fv, "eccentric_slope_near_vmax", 0.15)?,
                max_eccentric_velocity_force_multiplier: number_in(
                    fv,
                    "max_eccentric_velocity_force_multiplier",
                    1.4,
                )?,
                concentric_curviness: number_in(fv, "concentric_curviness", 0.6)?,
                eccentric_curviness: number_in(fv, "eccentric_curviness", 0.9)?,
            },
            fiber_force_length: FiberForceLengthCurveSpec {
                strain_at_zero_force: number_in(fpe, "strain_at_zero_force", 0.0)?,
                strain_at_one_norm_force: number_in(fpe, "strain_at_one_norm_force", 0.7)?,
                stiffness_at_low_force: optional_in(fpe, "stiffness_at_low_force")?,
                stiffness_at_one_norm_force: optional_in(fpe, "stiffness_at_one_norm_force")?,
                curviness: optional_in(fpe, "curviness")?,
            },
            tendon_force_length: TendonForceLengthCurveSpec {
                strain_at_one_norm_force: number_in(tfl, "strain_at_one_norm_force", 0.049)?,
                stiffness_at_one_norm_force: optional_in(tfl, "stiffness_at_one_norm_force")?,
                norm_force_at_toe_end: optional_in(tfl, "norm_force_at_toe_end")?,
                curviness: optional_in(tfl, "curviness")?,
            },
        })
    }
}

impl ThelenSpec {
    fn read(reader: ComponentReader) -> Result<ThelenSpec, ModelError> {
        let (activation_time_constant, deactivation_time_constant) = time_constants(reader, (0.015, 0.050))?;
        Ok(ThelenSpec {
            fmax_tendon_strain: reader.number_or("FmaxTendonStrain", 0.04)?,
            fmax_muscle_strain: reader.number_or("FmaxMuscleStrain", 0.6)?,
            kshape_active: reader.number_or("KshapeActive", 0.45)?,
            kshape_passive: reader.number_or("KshapePassive", 5.0)?,
            af: reader.number_or("Af", 0.25)?,
            flen: reader.number_or("Flen", 1.4)?,
            fv_linear_extrap_threshold: reader.number_or("fv_linear_extrap_threshold", 0.95)?,
            maximum_pennation_angle: reader
                .number_or("maximum_pennation_angle", DEFAULT_MAXIMUM_PENNATION)?,
            default_activation: reader.number_or("default_activation", 0.05)?,
            default_fiber_length: reader.number_or("default_fiber_length", DEFAULT_FIBER_LENGTH)?,
            minimum_activation: reader.number_or("minimum_activation", 0.01)?,
            activation_time_constant,
            deactivation_time_constant,
        })
    }
}

impl DeGrooteSpec {
    fn read(reader: ComponentReader) -> Result<DeGrooteSpec, ModelError> {
        let (activation_time_constant, deactivation_time_constant) = time_constants(reader, (0.015, 0.060))?;
        Ok(DeGrooteSpec {
            active_force_width_scale: reader.number_or("active_force_width_scale", 1.0)?,
            fiber_damping: reader.number_or("fiber_damping", 0.0)?,
            ignore_passive_fiber_force: reader.boolean_or("ignore_passive_fiber_force", false)?,
            passive_fiber_strain_at_one_norm_force: reader
                .number_or("passive_fiber_strain_at_one_norm_force", 0.6)?,
            tendon_strain_at_one_norm_force: reader
                .number_or("tendon_strain_at_one_norm_force", 0.049)?,
            default_activation: reader.number_or("default_activation", 0.5)?,
            default_normalized_tendon_force: reader
                .number_or("default_normalized_tendon_force", 0.5)?,
            tendon_compliance_dynamics_mode: reader
                .optional_text("tendon_compliance_dynamics_mode")
                .unwrap_or_else(|| "explicit".into()),
            activation_time_constant,
            deactivation_time_constant,
            activation_dynamics_smoothing: reader.number_or("activation_dynamics_smoothing", 0.1)?,
        })
    }
}

/// `activation_time_constant` and `deactivation_time_constant` (s), the class's `defaults` when
/// absent; each must be a positive number, as OpenSim requires.
fn time_constants(reader: ComponentReader, defaults: (f64, f64)) -> Result<(f64, f64), ModelError> {
    let read = |property: &str, default: f64| {
        let value = reader.number_or(property, default)?;
        if value > 0.0 && value.is_finite() { Ok(value) } else { Err(reader.bad(property, "a positive time in s", &value.to_string())) }
    };
    Ok((read("activation_time_constant", defaults.0)?, read("deactivation_time_constant", defaults.1)?))
}

/// A number of an optional curve object, defaulted when the object or the property is absent.
fn number_in(
    curve: Option<ComponentReader>,
    property: &str,
    default: f64,
) -> Result<f64, ModelError> {
    curve.map_or(Ok(default), |c| c.number_or(property, default))
}

/// An optional property: absent or empty means "unset", OpenSim then derives the value.
fn optional_in(curve: Option<ComponentReader>, property: &str) -> Result<Option<f64>, ModelError> {
    match curve {
        Some(c) if c.optional_text(property).is_some_and(|t| !t.is_empty()) => {
            Ok(Some(c.number(property)?))
        }
        _ => Ok(None),
    }
}
