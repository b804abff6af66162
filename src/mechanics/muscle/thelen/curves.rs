//! The force–length curves of OpenSim's `Thelen2003Muscle` (`calcfal`, `calcfpe`, `calcfse` and
//! their derivatives), written in the same floating-point order as OpenSim so values agree to
//! the last bits. The force–velocity relation is in `force_velocity.rs`.

use crate::mechanics::muscle::MuscleError;
use crate::model::ThelenSpec;

/// Exponential shape factor of the tendon toe region (`kToe`).
const TOE_SHAPE: f64 = 3.0;
/// Normalized tendon force at the end of the toe region (`Ftoe`).
const TOE_FORCE: f64 = 33.0 / 100.0;

/// The four curves of one `Thelen2003Muscle` parameter set. Fields are the OpenSim properties
/// (dimensionless); lengths are normalized (fiber by L_opt, tendon by L_ts), forces by F_max.
#[derive(Debug, Clone, PartialEq)]
pub struct ThelenCurves {
    /// `FmaxTendonStrain`: tendon strain at F_max.
    pub fmax_tendon_strain: f64,
    /// `FmaxMuscleStrain`: passive fiber strain at F_max.
    pub fmax_muscle_strain: f64,
    /// `KshapeActive`: width (variance) of the Gaussian active force–length curve.
    pub kshape_active: f64,
    /// `KshapePassive`: exponential shape of the passive force–length curve.
    pub kshape_passive: f64,
    /// `Af`: force–velocity shape factor.
    pub af: f64,
    /// `Flen`: eccentric force–velocity asymptote (multiple of the isometric force).
    pub flen: f64,
    /// `fv_linear_extrap_threshold`: fraction of the eccentric asymptote beyond which the
    /// force–velocity relation is extrapolated linearly.
    pub fv_linear_extrap_threshold: f64,
}

impl ThelenCurves {
    /// The curves of `muscle`'s parameters, with the checks of OpenSim's
    /// `Thelen2003Muscle::extendFinalizeFromProperties` (plus finiteness, and
    /// `fv_linear_extrap_threshold < 1`: at 1 or more OpenSim's eccentric branch divides by
    /// zero where the force reaches `Flen · a · f_L`).
    pub fn new(muscle: &str, spec: &ThelenSpec) -> Result<ThelenCurves, MuscleError> {
        let positive = [
            ("FmaxTendonStrain", spec.fmax_tendon_strain),
            ("FmaxMuscleStrain", spec.fmax_muscle_strain),
            ("KshapeActive", spec.kshape_active),
            ("KshapePassive", spec.kshape_passive),
            ("Af", spec.af),
        ];
        for (property, value) in positive {
            require(muscle, property, value, value > 0.0, "a positive number")?;
        }
        require(
            muscle,
            "Flen",
            spec.flen,
            spec.flen > 1.0,
            "a number greater than 1",
        )?;
        let threshold = spec.fv_linear_extrap_threshold;
        let in_range = threshold > 1.0 / spec.flen && threshold < 1.0;
        require(
            muscle,
            "fv_linear_extrap_threshold",
            threshold,
            in_range,
            "a number in (1/Flen, 1)",
        )?;
        Ok(ThelenCurves {
            fmax_tendon_strain: spec.fmax_tendon_strain,
            fmax_muscle_strain: spec.fmax_muscle_strain,
            kshape_active: spec.kshape_active,
            kshape_passive: spec.kshape_passive,
            af: spec.af,
            flen: spec.flen,
            fv_linear_extrap_threshold: threshold,
        })
    }

    /// eToe = 99 e₀ e³ / (166 e³ − 67), the tendon strain where the exponential toe region
    /// ends and the linear region begins (the value that makes f_SE C¹ there).
    pub fn toe_strain(&self) -> f64 {
        let t1 = TOE_SHAPE.exp();
        (99.0 * self.fmax_tendon_strain * t1) / (166.0 * t1 - 67.0)
    }

    /// klin = 0.67 / (e₀ − eToe), the slope of the linear tendon region.
    fn linear_stiffness(&self) -> f64 {
        (67.0 / 100.0) / (self.fmax_tendon_strain - self.toe_strain())
    }

    /// f_L(l̃_m) = exp(−(l̃_m − 1)² / KshapeActive), the active force–length multiplier at
    /// normalized fiber length l̃_m (`calcfal`).
    pub fn active_force_length(&self, normalized_fiber_length: f64) -> f64 {
        let x = (normalized_fiber_length - 1.0) * (normalized_fiber_length - 1.0);
        (-x / self.kshape_active).exp()
    }

    /// df_L/dl̃_m (`calcDfalDlceN`).
    pub fn active_force_length_derivative(&self, normalized_fiber_length: f64) -> f64 {
        let stretch = normalized_fiber_length - 1.0;
        let inverse_shape = 1.0 / self.kshape_active;
        -2.0 * stretch * inverse_shape * (-(stretch * stretch) * inverse_shape).exp()
    }

    /// f_PE(l̃_m) = (exp(KshapePassive (l̃_m − 1) / FmaxMuscleStrain) − 1) / (exp(KshapePassive) − 1)
    /// for l̃_m > 1, else 0: the passive force multiplier (`calcfpe`).
    pub fn passive_force_length(&self, normalized_fiber_length: f64) -> f64 {
        if normalized_fiber_length <= 1.0 {
            return 0.0;
        }
        let kpe = self.kshape_passive;
        let growth = (kpe * (normalized_fiber_length - 1.0) / self.fmax_muscle_strain).exp();
        (growth - 1.0) / (kpe.exp() - 1.0)
    }

    /// df_PE/dl̃_m (`calcDfpeDlceN`); 0 at and below l̃_m = 1.
    pub fn passive_force_length_derivative(&self, normalized_fiber_length: f64) -> f64 {
        if normalized_fiber_length <= 1.0 {
            return 0.0;
        }
        let kpe = self.kshape_passive;
        let inverse_strain = 1.0 / self.fmax_muscle_strain;
        let growth = (kpe * (normalized_fiber_length - 1.0) * inverse_strain).exp();
        kpe * inverse_strain * growth / (kpe.exp() - 1.0)
    }

    /// f_SE(l̃_t), the normalized tendon force at normalized tendon length l̃_t = 1 + ε
    /// (`calcfse`): 0 when slack (ε ≤ 0), Ftoe (exp(kToe ε / eToe) − 1) / (exp(kToe) − 1) in the
    /// toe (0 < ε ≤ eToe), Ftoe + klin (ε − eToe) beyond.
    pub fn tendon_force_length(&self, normalized_tendon_length: f64) -> f64 {
        let strain = normalized_tendon_length - 1.0;
        let toe_strain = self.toe_strain();
        if strain > toe_strain {
            self.linear_stiffness() * (strain - toe_strain) + TOE_FORCE
        } else if strain > 0.0 {
            (TOE_FORCE / (TOE_SHAPE.exp() - 1.0)) * ((TOE_SHAPE * strain / toe_strain).exp() - 1.0)
        } else {
            0.0
        }
    }

    /// df_SE/dl̃_t (`calcDfseDtlN`).
    pub fn tendon_force_length_derivative(&self, normalized_tendon_length: f64) -> f64 {
        let strain = normalized_tendon_length - 1.0;
        let toe_strain = self.toe_strain();
        if strain > toe_strain {
            self.linear_stiffness()
        } else if strain > 0.0 {
            (TOE_FORCE / (TOE_SHAPE.exp() - 1.0))
                * (TOE_SHAPE / toe_strain)
                * (TOE_SHAPE * strain / toe_strain).exp()
        } else {
            0.0
        }
    }
}

/// `Ok` when `valid` holds for a finite `value`, else OpenSim's rejection of the property.
fn require(
    muscle: &str,
    property: &str,
    value: f64,
    valid: bool,
    expected: &str,
) -> Result<(), MuscleError> {
    if valid && value.is_finite() {
        Ok(())
    } else {
        Err(MuscleError::invalid_parameter(
            muscle, property, value, expected,
        ))
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The parameter set of gait2392 and arm26 (`curve_sets.csv`).
    pub fn gait2392_spec() -> ThelenSpec {
        ThelenSpec {
            fmax_tendon_strain: 0.033,
            fmax_muscle_strain: 0.6,
            kshape_active: 0.5,
            kshape_passive: 4.0,
            af: 0.3,
            flen: 1.8,
            fv_linear_extrap_threshold: 0.95,
            maximum_pennation_angle: 0.1f64.acos(),
            default_activation: 0.05,
            default_fiber_length: 0.1,
            minimum_activation: 0.01,
            activation_time_constant: 0.01,
            deactivation_time_constant: 0.04,
        }
    }

    pub fn gait2392_curves() -> ThelenCurves {
        ThelenCurves::new("test", &gait2392_spec()).unwrap()
    }

    /// Central difference of `f` at `x` with step `h`.
    pub fn central_difference(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
        (f(x + h) - f(x - h)) / (2.0 * h)
    }

    #[test]
    fn identities_at_the_reference_points() {
        let c = gait2392_curves();
        assert_eq!(c.active_force_length(1.0), 1.0);
        assert_eq!(c.active_force_length_derivative(1.0), 0.0);
        assert_eq!(c.passive_force_length(1.0), 0.0);
        // 1 + ε − 1 ≠ ε in floating point: a few ulps of ε times slopes ≤ 52.
        assert!((c.passive_force_length(1.0 + c.fmax_muscle_strain) - 1.0).abs() < 1e-13);
        assert_eq!(c.tendon_force_length(1.0), 0.0);
        assert!((c.tendon_force_length(1.0 + c.toe_strain()) - TOE_FORCE).abs() < 1e-13);
        assert!((c.tendon_force_length(1.0 + c.fmax_tendon_strain) - 1.0).abs() < 1e-13);
    }

    #[test]
    fn the_tendon_curve_is_c1_at_the_end_of_the_toe() {
        let c = gait2392_curves();
        let knot = 1.0 + c.toe_strain();
        let toe_slope = c.tendon_force_length_derivative(knot);
        let linear_slope = c.tendon_force_length_derivative(knot + 1e-12);
        assert!(
            (toe_slope - linear_slope).abs() < 1e-9 * linear_slope,
            "{toe_slope} vs {linear_slope}"
        );
    }

    /// Analytic derivatives against central differences (h = 1e-6, agreement 1e-7 relative
    /// to max(1, |f′|): the O(h²) truncation of these exponentials is below 1e-9), away from the
    /// kinks at l̃_m = 1 (passive) and ε = 0 (tendon).
    #[test]
    fn derivatives_match_central_differences() {
        let c = gait2392_curves();
        let h = 1e-6;
        let check = |name: &str, f: &dyn Fn(f64) -> f64, df: &dyn Fn(f64) -> f64, x: f64| {
            let numeric = central_difference(f, x, h);
            let analytic = df(x);
            assert!(
                (numeric - analytic).abs() <= 1e-7 * analytic.abs().max(1.0),
                "{name} at {x}: {analytic} vs {numeric}"
            );
        };
        for i in 0..=180 {
            let x = 0.2 + 0.01 * f64::from(i);
            check(
                "f_L",
                &|x| c.active_force_length(x),
                &|x| c.active_force_length_derivative(x),
                x,
            );
            if (x - 1.0).abs() > 2.0 * h {
                check(
                    "f_PE",
                    &|x| c.passive_force_length(x),
                    &|x| c.passive_force_length_derivative(x),
                    x,
                );
            }
        }
        for i in 0..=100 {
            let x = 0.99 + 0.001 * f64::from(i);
            if (x - 1.0).abs() > 2.0 * h && (x - 1.0 - c.toe_strain()).abs() > 2.0 * h {
                check(
                    "f_SE",
                    &|x| c.tendon_force_length(x),
                    &|x| c.tendon_force_length_derivative(x),
                    x,
                );
            }
        }
    }

    /// A property name and an edit making it invalid.
    type Invalidation = (&'static str, fn(&mut ThelenSpec));

    #[test]
    fn rejects_what_opensim_rejects() {
        let cases: [Invalidation; 9] = [
            ("FmaxTendonStrain", |s| s.fmax_tendon_strain = 0.0),
            ("FmaxMuscleStrain", |s| s.fmax_muscle_strain = -0.1),
            ("KshapeActive", |s| s.kshape_active = 0.0),
            ("KshapePassive", |s| s.kshape_passive = f64::NAN),
            ("Af", |s| s.af = 0.0),
            ("Flen", |s| s.flen = 1.0),
            ("fv_linear_extrap_threshold", |s| {
                s.fv_linear_extrap_threshold = 1.0 / 1.8
            }),
            ("fv_linear_extrap_threshold", |s| {
                s.fv_linear_extrap_threshold = 1.0
            }),
            ("Af", |s| s.af = f64::INFINITY),
        ];
        for (property, edit) in cases {
            let mut spec = gait2392_spec();
            edit(&mut spec);
            match ThelenCurves::new("m", &spec) {
                Err(MuscleError::InvalidParameter { property: p, .. }) => assert_eq!(p, property),
                other => panic!("{property}: {other:?}"),
            }
        }
    }
}
