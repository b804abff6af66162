//! The fiber velocity of a `DeGrooteFregly2016Muscle` with a compliant tendon at a given fiber
//! length: what forward simulation integrates (explicit mode) or what the implicit force balance
//! requires (implicit mode).
//!
//! The muscle's state is the normalized tendon force; a fiber length L_m > w stands for it
//! through L_m cos α = √(L_m² − w²) (the fiber pointing forwards), L_t = L_mt − L_m cos α and
//! f̃_T = f_T(L_t / L_ts). The fiber must then carry f̃_T / cos α:
//! - explicit (OpenSim's `calcFiberVelocityInfo`): f_V = (f̃_T / cos α − f_PE) / (a f_L),
//!   ṽ = f_V⁻¹(f_V) — fiber damping is left out, as OpenSim leaves it out;
//! - implicit (the root of `calcEquilibriumResidual` in the tendon-force derivative):
//!   a f_L f_V(ṽ) + f_PE + β ṽ = f̃_T / cos α, damping included; with β = 0 both agree.
//!
//! The velocity is ṽ v_max L_opt (m/s, lengthening positive), path speed 0.

use super::curves::DeGrooteCurves;
use super::muscle::TendonDynamics;
use super::DeGrooteFregly2016Muscle;
use crate::mechanics::muscle::{bracketed_newton, check_compliant_tendon, check_inputs, MuscleError};

/// The implicit solve stops when the force balance is within this (normalized force) …
const RESIDUAL_TOLERANCE: f64 = 1e-14;
/// … or the bracket on ṽ is this many ulps of its wider end wide.
const BRACKET_EPSILONS: f64 = 4.0;
const MAX_ITERATIONS: usize = 200;

impl DeGrooteFregly2016Muscle {
    /// dL_m/dt (m/s, lengthening positive) at activation `activation` ∈ [0, 1], fiber length
    /// `fiber_length` (m, > w) and path length `mt_length` (m), path speed 0; see the module
    /// documentation. `InvalidInput` for a rigid tendon (no fiber state: the fiber follows the
    /// path) and for a fiber no longer than its width; `Infeasible` when no finite velocity
    /// balances the forces (a f_L = 0 without damping, or a tendon force so far from the fiber's
    /// that ṽ = f_V⁻¹ overflows).
    pub fn fiber_velocity(
        &self,
        activation: f64,
        fiber_length: f64,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        check_compliant_tendon(&self.name, self.ignore_tendon_compliance)?;
        if !(fiber_length > self.fiber_width && fiber_length.is_finite()) {
            let expected = format!(
                "a length in m greater than the fiber width {} m",
                self.fiber_width
            );
            return Err(MuscleError::invalid_input(
                &self.name,
                "fiber length",
                fiber_length,
                &expected,
            ));
        }
        let normalized_velocity =
            self.normalized_fiber_velocity(activation, fiber_length, mt_length);
        let velocity =
            normalized_velocity * (self.max_contraction_velocity * self.optimal_fiber_length);
        if !velocity.is_finite() {
            let reason = format!(
                "no finite fiber velocity balances the tendon at fiber length {fiber_length} m \
                 (normalized velocity {normalized_velocity})"
            );
            return Err(MuscleError::Infeasible {
                muscle: self.name.clone(),
                activation,
                mt_length,
                reason,
            });
        }
        Ok(velocity)
    }

    /// ṽ = dL_m/dt / (v_max L_opt); not finite when no velocity balances the forces.
    fn normalized_fiber_velocity(&self, activation: f64, fiber_length: f64, mt_length: f64) -> f64 {
        let curves = &self.curves;
        let along_tendon =
            (fiber_length * fiber_length - self.fiber_width * self.fiber_width).sqrt();
        let normalized_tendon_length = (mt_length - along_tendon) / self.tendon_slack_length;
        let normalized_tendon_force = curves.calc_tendon_force_multiplier(normalized_tendon_length);
        let normalized_fiber_force = normalized_tendon_force / (along_tendon / fiber_length);
        let normalized_fiber_length = fiber_length / self.optimal_fiber_length;
        let active =
            activation * curves.calc_active_force_length_multiplier(normalized_fiber_length);
        let contractile =
            normalized_fiber_force - curves.calc_passive_force_multiplier(normalized_fiber_length);
        match self.tendon_dynamics {
            TendonDynamics::Implicit if self.fiber_damping > 0.0 => {
                self.damped_velocity(active, contractile)
            }
            _ => DeGrooteCurves::calc_force_velocity_inverse_curve(contractile / active),
        }
    }

    /// The ṽ with g(ṽ) = a f_L f_V(ṽ) + β ṽ − `contractile` = 0 (`active` = a f_L). g grows at
    /// least as fast as β ṽ, so the root lies between 0 and −g(0)/β; NaN if the solve fails.
    fn damped_velocity(&self, active: f64, contractile: f64) -> f64 {
        let damping = self.fiber_damping;
        let balance = |velocity: f64| {
            let value = active * DeGrooteCurves::calc_force_velocity_multiplier(velocity)
                + damping * velocity
                - contractile;
            let slope = active
                * DeGrooteCurves::calc_force_velocity_multiplier_derivative(velocity)
                + damping;
            (value, slope)
        };
        let far_end = -balance(0.0).0 / damping;
        let bracket_tolerance = BRACKET_EPSILONS * f64::EPSILON * far_end.abs();
        bracketed_newton(
            balance,
            0.0,
            far_end,
            bracket_tolerance,
            RESIDUAL_TOLERANCE,
            MAX_ITERATIONS,
        )
        .map_or(f64::NAN, |root| root.x)
    }
}
