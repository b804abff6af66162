//! First-order activation dynamics as OpenSim's `MuscleFirstOrderActivationDynamicModel`
//! (used by `Millard2012EquilibriumMuscle` and `Thelen2003Muscle`):
//! ȧ = (u − a)/τ with τ = τ_a (0.5 + 1.5 a) when u > a, else τ_d / (0.5 + 1.5 a), and a clamped
//! to [a_min, 1] before it enters.

use crate::model::{MuscleModelSpec, MuscleSpec};

/// τ_a, τ_d (s) and the minimum activation of one muscle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstOrderActivation {
    pub activation_time_constant: f64,
    pub deactivation_time_constant: f64,
    pub minimum_activation: f64,
}

impl FirstOrderActivation {
    /// The dynamics of a Millard or Thelen muscle with properties `spec` and minimum
    /// activation `minimum_activation`; `None` for DeGroote–Fregly muscles, whose activation
    /// dynamics are smoothed differently.
    pub fn of(spec: &MuscleSpec, minimum_activation: f64) -> Option<FirstOrderActivation> {
        if matches!(spec.model, MuscleModelSpec::DeGrooteFregly2016(_)) {
            return None;
        }
        let [tau_a, tau_d] = spec.time_constants();
        Some(FirstOrderActivation { activation_time_constant: tau_a, deactivation_time_constant: tau_d, minimum_activation })
    }

    /// ȧ (1/s) at activation `activation` and excitation `excitation`.
    pub fn rate(&self, activation: f64, excitation: f64) -> f64 {
        let a = activation.clamp(self.minimum_activation, 1.0);
        let tau = if excitation > a {
            self.activation_time_constant * (0.5 + 1.5 * a)
        } else {
            self.deactivation_time_constant / (0.5 + 1.5 * a)
        };
        (excitation - a) / tau
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// First principles: the rate vanishes at u = a, activates with τ_a(0.5 + 1.5a) and
    /// deactivates with τ_d/(0.5 + 1.5a), and sees activations below the minimum as the minimum.
    #[test]
    fn rates_follow_the_first_order_law() {
        let dynamics = FirstOrderActivation { activation_time_constant: 0.01, deactivation_time_constant: 0.04, minimum_activation: 0.01 };
        assert_eq!(dynamics.rate(0.3, 0.3), 0.0);
        assert!((dynamics.rate(0.2, 0.8) - 0.6 / (0.01 * 0.8)).abs() < 1e-12);
        assert!((dynamics.rate(0.6, 0.1) - (-0.5) * 1.4 / 0.04).abs() < 1e-12);
        assert_eq!(dynamics.rate(0.0, 0.5), dynamics.rate(0.01, 0.5));
    }
}
