//! Activation dynamics of OpenSim's muscles:
//! - `MuscleFirstOrderActivationDynamicModel` (`Millard2012EquilibriumMuscle`,
//!   `Thelen2003Muscle`): ȧ = (u − a)/τ with τ = τ_a (0.5 + 1.5 a) when u > a, else
//!   τ_d / (0.5 + 1.5 a), and a clamped to [a_min, 1] before it enters;
//! - `DeGrooteFregly2016Muscle`'s smoothed switch: with f = ½ tanh(b (u − a)) and
//!   z = 0.5 + 1.5 a, ȧ = [(f + ½)/(τ_a z) + (½ − f) z/τ_d] (u − a), a unclamped.
//!   (OpenSim 4.6 reads τ_a, τ_d and b into function-local statics, so every DeGroote muscle of a
//!   process uses the first one's; here each muscle uses its own.)

use crate::model::{MuscleModelSpec, MuscleSpec};

/// A muscle's activation dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActivationDynamics {
    FirstOrder(FirstOrderActivation),
    /// DeGroote–Fregly 2016: τ_a, τ_d (s) and the tanh steepness b.
    Smoothed { activation_time_constant: f64, deactivation_time_constant: f64, smoothing: f64 },
}

impl ActivationDynamics {
    /// The dynamics of a muscle with properties `spec` and minimum activation
    /// `minimum_activation` (used by the first-order law only).
    pub fn of(spec: &MuscleSpec, minimum_activation: f64) -> ActivationDynamics {
        match &spec.model {
            MuscleModelSpec::DeGrooteFregly2016(d) => ActivationDynamics::Smoothed {
                activation_time_constant: d.activation_time_constant,
                deactivation_time_constant: d.deactivation_time_constant,
                smoothing: d.activation_dynamics_smoothing,
            },
            _ => {
                let [tau_a, tau_d] = spec.time_constants();
                ActivationDynamics::FirstOrder(FirstOrderActivation { activation_time_constant: tau_a, deactivation_time_constant: tau_d, minimum_activation })
            }
        }
    }

    /// ȧ (1/s) at activation `activation` and excitation `excitation`.
    pub fn rate(&self, activation: f64, excitation: f64) -> f64 {
        match *self {
            ActivationDynamics::FirstOrder(first_order) => first_order.rate(activation, excitation),
            ActivationDynamics::Smoothed { activation_time_constant, deactivation_time_constant, smoothing } => {
                let z = 0.5 + 1.5 * activation;
                let f = 0.5 * (smoothing * (excitation - activation)).tanh();
                ((f + 0.5) / (activation_time_constant * z) + (0.5 - f) * z / deactivation_time_constant) * (excitation - activation)
            }
        }
    }
}

/// τ_a, τ_d (s) and the minimum activation of one muscle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstOrderActivation {
    pub activation_time_constant: f64,
    pub deactivation_time_constant: f64,
    pub minimum_activation: f64,
}

impl FirstOrderActivation {
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

    /// First principles: the smoothed law vanishes at u = a and, far from it (tanh → ±1),
    /// activates with τ_a z and deactivates with τ_d / z; at b (u − a) = atanh(0.2) the two
    /// rates mix 0.6 : 0.4.
    #[test]
    fn the_smoothed_law_switches_by_tanh() {
        let dynamics = ActivationDynamics::Smoothed { activation_time_constant: 0.015, deactivation_time_constant: 0.06, smoothing: 10.0 };
        assert_eq!(dynamics.rate(0.3, 0.3), 0.0);
        let (a, u) = (0.2, 0.9);
        let z = 0.5 + 1.5 * a;
        assert!((dynamics.rate(a, u) - (u - a) / (0.015 * z)).abs() / ((u - a) / (0.015 * z)) < 1e-5);
        let (a, u) = (0.8, 0.05);
        let z = 0.5 + 1.5 * a;
        assert!((dynamics.rate(a, u) - (u - a) * z / 0.06).abs() / ((u - a) * z / 0.06).abs() < 1e-5);
        let (a, u) = (0.4, 0.4 + 0.2f64.atanh() / 10.0);
        let z = 0.5 + 1.5 * a;
        let mixed = (0.6 / (0.015 * z) + 0.4 * z / 0.06) * (u - a);
        assert!((dynamics.rate(a, u) - mixed).abs() < 1e-12 * mixed.abs());
    }
}
