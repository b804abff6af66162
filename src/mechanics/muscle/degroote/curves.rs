//! The curves of OpenSim 4.6's `DeGrooteFregly2016Muscle` (De Groote et al. 2016, with
//! OpenSim's modified constants), evaluated in the same operation order as OpenSim's inline
//! header functions so that values agree to the last bits.
//!
//! Arguments are normalized: fiber length L_m / L_opt, tendon length L_t / L_ts, fiber velocity
//! dL_m/dt / (v_max L_opt) (−1 = maximum shortening), forces / F_max (tension positive).

/// b1·exp(−½ (x − b2)² / (b3 + b4 x)²): one term of the active force–length curve.
#[derive(Debug, Clone, Copy, PartialEq)]
struct GaussianLike {
    b1: f64,
    b2: f64,
    b3: f64,
    b4: f64,
}

/// The three terms of the active force–length curve (OpenSim's b11 … b43; b11 makes f_L(1) = 1).
const ACTIVE_FORCE_LENGTH_TERMS: [GaussianLike; 3] = [
    GaussianLike {
        b1: 0.8150671134243542,
        b2: 1.055033428970575,
        b3: 0.162384573599574,
        b4: 0.063303448465465,
    },
    GaussianLike {
        b1: 0.433004984392647,
        b2: 0.716775413397760,
        b3: -0.029947116970696,
        b4: 0.200356847296188,
    },
    GaussianLike {
        b1: 0.1,
        b2: 1.0,
        b3: 0.353553390593274,
        b4: 0.0,
    },
];

/// Exponential shape factor of the passive force–length curve (OpenSim's kPE).
const PASSIVE_SHAPE: f64 = 4.0;

/// Tendon curve c1·exp(k_T (l̃_T − c2)) − c3 (OpenSim's c1, c2, c3; c2 = 1 and c1 = c3 make
/// it pass through (1, 0)).
const C1: f64 = 0.200;
const C2: f64 = 1.0;
const C3: f64 = 0.200;

/// Force–velocity curve d1·ln(d2 ṽ + d3 + √((d2 ṽ + d3)² + 1)) + d4 (OpenSim's d1 … d4; d1 and
/// d4 make it pass through (−1, 0) and (0, 1)).
const D1: f64 = -0.3211346127989808;
const D2: f64 = -8.149;
const D3: f64 = -0.374;
const D4: f64 = 0.8825327733249912;

/// The curves of one `DeGrooteFregly2016Muscle`: active force–length (widened by
/// `active_force_width_scale`), passive force–length (`passive_fiber_strain_at_one_norm_force`,
/// zero when `ignore_passive_fiber_force`), tendon force–length
/// (`tendon_strain_at_one_norm_force`), force–velocity and their inverses, derivatives and
/// integrals as OpenSim's `calc*` member functions expose them.
#[derive(Debug, Clone, PartialEq)]
pub struct DeGrooteCurves {
    active_force_width_scale: f64,
    /// e0: passive fiber strain at which the passive force is F_max.
    passive_fiber_strain_at_one_norm_force: f64,
    ignore_passive_fiber_force: bool,
    /// k_T = ln((1 + c3) / c1) / (1 + e_T − c2), OpenSim's `getTendonStiffnessParameter`.
    tendon_stiffness_parameter: f64,
}

impl DeGrooteCurves {
    /// The passive force–length curve is 0 at this normalized fiber length (and negative
    /// below); OpenSim's `getMinNormalizedFiberLength` (not enforced by OpenSim).
    pub const MIN_NORMALIZED_FIBER_LENGTH: f64 = 0.2;
    /// The bracket of OpenSim's equilibrium solver (`getMin/MaxNormalizedTendonForce`).
    pub const MIN_NORMALIZED_TENDON_FORCE: f64 = 0.0;
    pub const MAX_NORMALIZED_TENDON_FORCE: f64 = 5.0;

    /// Curves for the given properties (validated by the muscle: scale ≥ 1, strains > 0).
    pub fn new(
        active_force_width_scale: f64,
        passive_fiber_strain_at_one_norm_force: f64,
        tendon_strain_at_one_norm_force: f64,
        ignore_passive_fiber_force: bool,
    ) -> DeGrooteCurves {
        DeGrooteCurves {
            active_force_width_scale,
            passive_fiber_strain_at_one_norm_force,
            ignore_passive_fiber_force,
            tendon_stiffness_parameter: ((1.0 + C3) / C1).ln()
                / (1.0 + tendon_strain_at_one_norm_force - C2),
        }
    }

    /// k_T, the exponent of the tendon curve per unit normalized tendon length.
    pub fn tendon_stiffness_parameter(&self) -> f64 {
        self.tendon_stiffness_parameter
    }

    /// The argument of the unscaled active curve: the fiber length moved away from 1 by
    /// 1 / `active_force_width_scale`.
    fn scaled_fiber_length(&self, normalized_fiber_length: f64) -> f64 {
        (normalized_fiber_length - 1.0) / self.active_force_width_scale + 1.0
    }

    /// f_L(l̃_m): active force–length multiplier, 1 at l̃_m = 1.
    pub fn calc_active_force_length_multiplier(&self, normalized_fiber_length: f64) -> f64 {
        let x = self.scaled_fiber_length(normalized_fiber_length);
        let [first, second, third] = ACTIVE_FORCE_LENGTH_TERMS;
        first.value(x) + second.value(x) + third.value(x)
    }

    /// df_L/dl̃_m.
    pub fn calc_active_force_length_multiplier_derivative(
        &self,
        normalized_fiber_length: f64,
    ) -> f64 {
        let x = self.scaled_fiber_length(normalized_fiber_length);
        let [first, second, third] = ACTIVE_FORCE_LENGTH_TERMS;
        (1.0 / self.active_force_width_scale)
            * (first.derivative(x) + second.derivative(x) + third.derivative(x))
    }

    /// exp(kPE (l̃_min − 1) / e0): the exponential at l̃_min = 0.2, where f_PE is zero.
    fn passive_offset(&self) -> f64 {
        (PASSIVE_SHAPE * (Self::MIN_NORMALIZED_FIBER_LENGTH - 1.0)
            / self.passive_fiber_strain_at_one_norm_force)
            .exp()
    }

    /// f_PE(l̃_m): passive force–length multiplier, 0 at l̃_m = 0.2 (negative below), 1 at
    /// l̃_m = 1 + e0; 0 everywhere when `ignore_passive_fiber_force`.
    pub fn calc_passive_force_multiplier(&self, normalized_fiber_length: f64) -> f64 {
        if self.ignore_passive_fiber_force {
            return 0.0;
        }
        let e0 = self.passive_fiber_strain_at_one_norm_force;
        let offset = self.passive_offset();
        let denominator = PASSIVE_SHAPE.exp() - offset;
        ((PASSIVE_SHAPE * (normalized_fiber_length - 1.0) / e0).exp() - offset) / denominator
    }

    /// df_PE/dl̃_m.
    pub fn calc_passive_force_multiplier_derivative(&self, normalized_fiber_length: f64) -> f64 {
        if self.ignore_passive_fiber_force {
            return 0.0;
        }
        let e0 = self.passive_fiber_strain_at_one_norm_force;
        let offset = self.passive_offset();
        (PASSIVE_SHAPE * ((PASSIVE_SHAPE * (normalized_fiber_length - 1.0)) / e0).exp())
            / (e0 * (PASSIVE_SHAPE.exp() - offset))
    }

    /// ∫ f_PE from l̃_min = 0.2 to l̃_m (fiber potential energy / (F_max L_opt)).
    pub fn calc_passive_force_multiplier_integral(&self, normalized_fiber_length: f64) -> f64 {
        if self.ignore_passive_fiber_force {
            return 0.0;
        }
        let e0 = self.passive_fiber_strain_at_one_norm_force;
        let temp1 = e0 + PASSIVE_SHAPE * normalized_fiber_length
            - PASSIVE_SHAPE * Self::MIN_NORMALIZED_FIBER_LENGTH;
        let temp2 = (PASSIVE_SHAPE * (normalized_fiber_length - 1.0) / e0).exp();
        let temp3 = self.passive_offset();
        let numerator = PASSIVE_SHAPE.exp() * temp1 - e0 * temp2;
        let denominator = PASSIVE_SHAPE * (temp3 - PASSIVE_SHAPE.exp());
        (temp1 / PASSIVE_SHAPE) + (numerator / denominator)
    }

    /// f_T(l̃_T): normalized tendon force, 0 at l̃_T = 1, 1 at 1 + e_T, tending to −c3 = −0.2
    /// for a short tendon.
    pub fn calc_tendon_force_multiplier(&self, normalized_tendon_length: f64) -> f64 {
        C1 * (self.tendon_stiffness_parameter * (normalized_tendon_length - C2)).exp() - C3
    }

    /// df_T/dl̃_T = k_T (f_T + c3).
    pub fn calc_tendon_force_multiplier_derivative(&self, normalized_tendon_length: f64) -> f64 {
        let k_t = self.tendon_stiffness_parameter;
        C1 * k_t * (k_t * (normalized_tendon_length - C2)).exp()
    }

    /// ∫ f_T from l̃_T(f_T = 0) = 1 to l̃_T (tendon potential energy / (F_max L_ts)).
    pub fn calc_tendon_force_multiplier_integral(&self, normalized_tendon_length: f64) -> f64 {
        let k_t = self.tendon_stiffness_parameter;
        let min_normalized_tendon_length =
            self.calc_tendon_force_length_inverse_curve(Self::MIN_NORMALIZED_TENDON_FORCE);
        let temp1 =
            (k_t * normalized_tendon_length).exp() - (k_t * min_normalized_tendon_length).exp();
        let temp2 = C1 * (-C2 * k_t).exp() / k_t;
        let temp3 = C3 * (normalized_tendon_length - min_normalized_tendon_length);
        temp1 * temp2 - temp3
    }

    /// l̃_T(f̃_T): the tendon length of a normalized tendon force (f̃_T > −0.2; 1 at 0).
    pub fn calc_tendon_force_length_inverse_curve(&self, normalized_tendon_force: f64) -> f64 {
        ((1.0 / C1) * (normalized_tendon_force + C3)).ln() / self.tendon_stiffness_parameter + C2
    }

    /// dl̃_T/dt from df̃_T/dt at tendon length l̃_T (normalized tendon velocity, 1/s).
    pub fn calc_tendon_force_length_inverse_curve_derivative(
        &self,
        normalized_tendon_force_derivative: f64,
        normalized_tendon_length: f64,
    ) -> f64 {
        let k_t = self.tendon_stiffness_parameter;
        normalized_tendon_force_derivative
            / (C1 * k_t * (k_t * (normalized_tendon_length - C2)).exp())
    }

    /// f_V(ṽ): force–velocity multiplier; 0 at ṽ = −1, 1 (to rounding) at 0, ≈ 1.794 at +1.
    pub fn calc_force_velocity_multiplier(normalized_fiber_velocity: f64) -> f64 {
        let temp_v = D2 * normalized_fiber_velocity + D3;
        let temp_log_argument = temp_v + (square(temp_v) + 1.0).sqrt();
        D1 * temp_log_argument.ln() + D4
    }

    /// df_V/dṽ = d1 d2 / √((d2 ṽ + d3)² + 1) > 0 (not exposed by OpenSim).
    pub fn calc_force_velocity_multiplier_derivative(normalized_fiber_velocity: f64) -> f64 {
        let temp_v = D2 * normalized_fiber_velocity + D3;
        D1 * D2 / (square(temp_v) + 1.0).sqrt()
    }

    /// ṽ(f_V): the inverse of the force–velocity curve, defined for every multiplier.
    pub fn calc_force_velocity_inverse_curve(force_velocity_multiplier: f64) -> f64 {
        ((1.0 / D1 * (force_velocity_multiplier - D4)).sinh() - D3) / D2
    }
}

impl GaussianLike {
    fn value(self, x: f64) -> f64 {
        self.b1 * (-0.5 * square(x - self.b2) / square(self.b3 + self.b4 * x)).exp()
    }

    /// d/dx; 0 where the exponential has underflowed (including the zero width at
    /// x = −b3/b4, where OpenSim's formula gives 0/0).
    fn derivative(self, x: f64) -> f64 {
        let width = self.b3 + self.b4 * x;
        let exponential = (-square(self.b2 - x) / (2.0 * square(width))).exp();
        if exponential == 0.0 {
            return 0.0;
        }
        (self.b1 * exponential * (self.b2 - x) * (self.b3 + self.b2 * self.b4))
            / (width * width * width)
    }
}

fn square(x: f64) -> f64 {
    x * x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_curves() -> DeGrooteCurves {
        DeGrooteCurves::new(1.0, 0.6, 0.049, false)
    }

    #[test]
    fn curves_pass_through_their_design_points() {
        let curves = default_curves();
        assert!((curves.calc_active_force_length_multiplier(1.0) - 1.0).abs() < 1e-15);
        assert_eq!(
            curves.calc_passive_force_multiplier(DeGrooteCurves::MIN_NORMALIZED_FIBER_LENGTH),
            0.0
        );
        assert!((curves.calc_passive_force_multiplier(1.6) - 1.0).abs() < 1e-15);
        assert_eq!(curves.calc_tendon_force_multiplier(1.0), 0.0);
        assert!((curves.calc_tendon_force_multiplier(1.049) - 1.0).abs() < 1e-14);
        assert!(DeGrooteCurves::calc_force_velocity_multiplier(-1.0).abs() < 1e-15);
        assert!((DeGrooteCurves::calc_force_velocity_multiplier(0.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn the_width_scale_stretches_the_active_curve_about_its_peak() {
        let wide = DeGrooteCurves::new(2.0, 0.6, 0.049, false);
        let curves = default_curves();
        for x in [0.3, 0.7, 1.2, 1.6] {
            let stretched = 1.0 + 2.0 * (x - 1.0);
            assert_eq!(
                wide.calc_active_force_length_multiplier(stretched),
                curves.calc_active_force_length_multiplier(x)
            );
        }
    }

    #[test]
    fn inverses_undo_their_curves() {
        let curves = default_curves();
        for force in [0.0, 0.01, 0.5, 1.0, 4.9] {
            let length = curves.calc_tendon_force_length_inverse_curve(force);
            assert!(
                (curves.calc_tendon_force_multiplier(length) - force).abs() < 1e-13 * (1.0 + force),
                "{force}"
            );
        }
        for velocity in [-1.0, -0.4, 0.0, 0.3, 1.0] {
            let multiplier = DeGrooteCurves::calc_force_velocity_multiplier(velocity);
            assert!(
                (DeGrooteCurves::calc_force_velocity_inverse_curve(multiplier) - velocity).abs()
                    < 1e-13,
                "{velocity}"
            );
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let curves = DeGrooteCurves::new(1.4, 0.5, 0.06, false);
        let h = 1e-6;
        let check = |f: &dyn Fn(f64) -> f64, df: &dyn Fn(f64) -> f64, x: f64| {
            let numeric = (f(x + h) - f(x - h)) / (2.0 * h);
            assert!(
                (numeric - df(x)).abs() <= 1e-7 * (1.0 + df(x).abs()),
                "x = {x}: {numeric} vs {}",
                df(x)
            );
        };
        for x in [0.1, 0.45, 0.8, 1.0, 1.3, 1.9] {
            check(
                &|x| curves.calc_active_force_length_multiplier(x),
                &|x| curves.calc_active_force_length_multiplier_derivative(x),
                x,
            );
            check(
                &|x| curves.calc_passive_force_multiplier(x),
                &|x| curves.calc_passive_force_multiplier_derivative(x),
                x,
            );
            check(
                &|x| curves.calc_passive_force_multiplier_integral(x),
                &|x| curves.calc_passive_force_multiplier(x),
                x,
            );
        }
        for x in [0.97, 1.0, 1.03, 1.08] {
            check(
                &|x| curves.calc_tendon_force_multiplier(x),
                &|x| curves.calc_tendon_force_multiplier_derivative(x),
                x,
            );
            check(
                &|x| curves.calc_tendon_force_multiplier_integral(x),
                &|x| curves.calc_tendon_force_multiplier(x),
                x,
            );
        }
        for v in [-1.2, -0.5, 0.0, 0.4, 1.1] {
            check(
                &DeGrooteCurves::calc_force_velocity_multiplier,
                &DeGrooteCurves::calc_force_velocity_multiplier_derivative,
                v,
            );
        }
    }

    #[test]
    fn the_active_derivative_is_finite_where_a_term_has_zero_width() {
        let second = ACTIVE_FORCE_LENGTH_TERMS[1];
        let zero_width = -second.b3 / second.b4;
        assert_eq!(second.derivative(zero_width), 0.0);
        assert!(default_curves()
            .calc_active_force_length_multiplier_derivative(zero_width)
            .is_finite());
    }

    #[test]
    fn ignoring_passive_force_zeroes_the_passive_curve() {
        let curves = DeGrooteCurves::new(1.0, 0.6, 0.049, true);
        assert_eq!(curves.calc_passive_force_multiplier(1.7), 0.0);
        assert_eq!(curves.calc_passive_force_multiplier_derivative(1.7), 0.0);
        assert_eq!(curves.calc_passive_force_multiplier_integral(1.7), 0.0);
    }
}
