//! `DeGrooteFregly2016Muscle`: the architecture and curves of one muscle, validated as OpenSim's
//! `extendFinalizeFromProperties` does, and its length-level geometry.
//!
//! Pennation is OpenSim's own for this class, not `MuscleFixedWidthPennationModel`: the fiber
//! keeps its width w = L_opt sin α_opt, L_m = √((L_m cos α)² + w²), with no maximum pennation
//! angle and no minimum fiber length (OpenSim's 0.2 L_opt is a documented domain, not enforced).

use super::curves::DeGrooteCurves;
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;
use crate::mechanics::muscle::MuscleError;
use crate::model::{DeGrooteSpec, MuscleSpec};

/// How the tendon's compliance is integrated (`tendon_compliance_dynamics_mode`): OpenSim
/// treats every value other than `explicit` as implicit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum TendonDynamics {
    /// The normalized tendon force is a state; the fiber velocity follows from the inverse
    /// force–velocity curve, without fiber damping (forward simulation).
    Explicit,
    /// The derivative of the normalized tendon force is a variable and the fiber–tendon force
    /// balance, damping included, a residual (Moco).
    Implicit,
}

/// One `DeGrooteFregly2016Muscle` (OpenSim 4.6).
#[derive(Debug, Clone)]
pub struct DeGrooteFregly2016Muscle {
    pub(super) name: String,
    /// F_max, N.
    pub(super) max_isometric_force: f64,
    /// L_opt, m.
    pub(super) optimal_fiber_length: f64,
    /// L_ts, m.
    pub(super) tendon_slack_length: f64,
    /// v_max, L_opt per second.
    pub(super) max_contraction_velocity: f64,
    /// Rigid tendon (`ignore_tendon_compliance`): L_t = L_ts.
    pub(crate) ignore_tendon_compliance: bool,
    /// β: damping force β ṽ F_max along the fiber (ṽ normalized fiber velocity).
    pub(super) fiber_damping: f64,
    pub(super) tendon_dynamics: TendonDynamics,
    /// τ_a, s.
    activation_time_constant: f64,
    /// τ_d, s.
    deactivation_time_constant: f64,
    /// w = L_opt sin α_opt, m.
    pub(super) fiber_width: f64,
    pub(super) curves: DeGrooteCurves,
}

/// The length-level state at one path length and normalized tendon force (OpenSim's
/// `calcMuscleLengthInfoHelper`). Lengths in m.
#[derive(Debug, Clone, Copy)]
pub(super) struct LengthInfo {
    pub normalized_tendon_length: f64,
    pub tendon_length: f64,
    pub fiber_length_along_tendon: f64,
    pub fiber_length: f64,
    pub normalized_fiber_length: f64,
    pub cos_pennation_angle: f64,
    pub sin_pennation_angle: f64,
}

impl DeGrooteFregly2016Muscle {
    /// The muscle `name` from its properties; `InvalidParameter` for the values OpenSim 4.6
    /// rejects when the model is finalized (and for a non-positive F_max, L_opt, L_ts or v_max,
    /// which `MuscleSpec` already refuses when read from a file).
    pub fn new(name: &str, spec: &MuscleSpec, class: &DeGrooteSpec) -> Result<Self, MuscleError> {
        check_parameters(name, spec, class)?;
        let tendon_dynamics = match class.tendon_compliance_dynamics_mode.as_str() {
            "explicit" => TendonDynamics::Explicit,
            _ => TendonDynamics::Implicit,
        };
        Ok(DeGrooteFregly2016Muscle {
            name: name.to_string(),
            max_isometric_force: spec.max_isometric_force,
            optimal_fiber_length: spec.optimal_fiber_length,
            tendon_slack_length: spec.tendon_slack_length,
            max_contraction_velocity: spec.max_contraction_velocity,
            ignore_tendon_compliance: spec.ignore_tendon_compliance,
            fiber_damping: class.fiber_damping,
            tendon_dynamics,
            activation_time_constant: class.activation_time_constant,
            deactivation_time_constant: class.deactivation_time_constant,
            fiber_width: spec.optimal_fiber_length * spec.pennation_angle_at_optimal.sin(),
            curves: DeGrooteCurves::new(
                class.active_force_width_scale,
                class.passive_fiber_strain_at_one_norm_force,
                class.tendon_strain_at_one_norm_force,
                class.ignore_passive_fiber_force,
            ),
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn curves(&self) -> &DeGrooteCurves {
        &self.curves
    }

    /// τ_a (`activation_time_constant`), s: the time constant of rising activation.
    pub fn activation_time_constant(&self) -> f64 {
        self.activation_time_constant
    }

    /// τ_d (`deactivation_time_constant`), s: the time constant of falling activation.
    pub fn deactivation_time_constant(&self) -> f64 {
        self.deactivation_time_constant
    }

    /// w = L_opt sin α_opt (m): the fiber's constant width, the shortest possible fiber.
    /// F_max, N.
    pub fn max_isometric_force(&self) -> f64 {
        self.max_isometric_force
    }

    pub fn fiber_width(&self) -> f64 {
        self.fiber_width
    }

    /// The length-level state at path length `mt_length` (m) and normalized tendon force
    /// `normalized_tendon_force` (ignored for a rigid tendon, which stays at L_ts). The fiber
    /// length along the tendon may come out ≤ 0 (cos α ≤ 0), as in OpenSim; a fiber of zero
    /// length (w = 0 and L_mt = L_t) is given cos α = 0 and sin α = 1 instead of 0/0.
    pub(super) fn length_info(&self, mt_length: f64, normalized_tendon_force: f64) -> LengthInfo {
        let normalized_tendon_length = if self.ignore_tendon_compliance {
            1.0
        } else {
            self.curves
                .calc_tendon_force_length_inverse_curve(normalized_tendon_force)
        };
        self.length_info_at_tendon_length(mt_length, normalized_tendon_length)
    }

    /// [`Self::length_info`] with the tendon at normalized length `normalized_tendon_length`
    /// (L_t / L_ts), whatever the muscle's tendon compliance.
    pub(super) fn length_info_at_tendon_length(
        &self,
        mt_length: f64,
        normalized_tendon_length: f64,
    ) -> LengthInfo {
        let tendon_length = self.tendon_slack_length * normalized_tendon_length;
        let fiber_length_along_tendon = mt_length - tendon_length;
        let fiber_length = (fiber_length_along_tendon * fiber_length_along_tendon
            + self.fiber_width * self.fiber_width)
            .sqrt();
        let (cos_pennation_angle, sin_pennation_angle) = if fiber_length > 0.0 {
            (
                fiber_length_along_tendon / fiber_length,
                self.fiber_width / fiber_length,
            )
        } else {
            (0.0, 1.0)
        };
        LengthInfo {
            normalized_tendon_length,
            tendon_length,
            fiber_length_along_tendon,
            fiber_length,
            normalized_fiber_length: fiber_length / self.optimal_fiber_length,
            cos_pennation_angle,
            sin_pennation_angle,
        }
    }
}

/// The checks of OpenSim's `DeGrooteFregly2016Muscle::extendFinalizeFromProperties` that concern
/// properties osim-tune reads (written so that NaN fails them).
fn check_parameters(
    name: &str,
    spec: &MuscleSpec,
    class: &DeGrooteSpec,
) -> Result<(), MuscleError> {
    let positive = [
        ("max_isometric_force", spec.max_isometric_force),
        ("optimal_fiber_length", spec.optimal_fiber_length),
        ("max_contraction_velocity", spec.max_contraction_velocity),
        (
            "passive_fiber_strain_at_one_norm_force",
            class.passive_fiber_strain_at_one_norm_force,
        ),
        (
            "tendon_strain_at_one_norm_force",
            class.tendon_strain_at_one_norm_force,
        ),
        ("default_activation", class.default_activation),
        ("activation_time_constant", class.activation_time_constant),
        ("deactivation_time_constant", class.deactivation_time_constant),
    ];
    MuscleError::require_positive(name, &positive, "a positive number")?;
    if !spec.ignore_tendon_compliance {
        // A rigid tendon's L_ts may be 0, as the model reader allows.
        MuscleError::require_positive(name, &[("tendon_slack_length", spec.tendon_slack_length)], "a positive number")?;
    }
    let ranges = [
        (
            "active_force_width_scale",
            class.active_force_width_scale,
            1.0,
            f64::INFINITY,
            "a number ≥ 1",
        ),
        (
            "fiber_damping",
            class.fiber_damping,
            0.0,
            f64::INFINITY,
            "a number ≥ 0",
        ),
        (
            "default_normalized_tendon_force",
            class.default_normalized_tendon_force,
            0.0,
            5.0,
            "a number in [0, 5]",
        ),
        (
            "pennation_angle_at_optimal",
            spec.pennation_angle_at_optimal,
            0.0,
            std::f64::consts::FRAC_PI_2 - SIGNIFICANT_REAL,
            "an angle in [0, π/2) rad",
        ),
    ];
    for (property, value, lowest, highest, expected) in ranges {
        if !(value >= lowest && value <= highest && value.is_finite()) {
            return Err(MuscleError::invalid_parameter(
                name, property, value, expected,
            ));
        }
    }
    Ok(())
}
