//! The five Hill-model parameters of a muscle (thesis eq. 2.3–2.14), as functional scaling
//! estimates and perturbs them, with the model's values as the nominal set.

use serde::Serialize;

use super::error::FunctionalError;
use crate::model::MuscleSpec;

/// One of the five parameters, named as the OpenSim property.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Parameter {
    /// L_ts, m.
    TendonSlackLength,
    /// L_opt, m.
    OptimalFiberLength,
    /// F_max, N.
    MaxIsometricForce,
    /// α_opt, rad.
    PennationAngleAtOptimal,
    /// v_max, optimal fiber lengths per second.
    MaxContractionVelocity,
}

impl Parameter {
    /// All five, in the thesis' order of sensitivity (L_ts, L_opt, F_max, α_opt, v_max).
    pub const ALL: [Parameter; 5] = [
        Parameter::TendonSlackLength,
        Parameter::OptimalFiberLength,
        Parameter::MaxIsometricForce,
        Parameter::PennationAngleAtOptimal,
        Parameter::MaxContractionVelocity,
    ];

    /// The OpenSim property name, e.g. `tendon_slack_length`.
    pub fn property(self) -> &'static str {
        match self {
            Parameter::TendonSlackLength => "tendon_slack_length",
            Parameter::OptimalFiberLength => "optimal_fiber_length",
            Parameter::MaxIsometricForce => "max_isometric_force",
            Parameter::PennationAngleAtOptimal => "pennation_angle_at_optimal",
            Parameter::MaxContractionVelocity => "max_contraction_velocity",
        }
    }

    /// The thesis' symbol: `L_ts`, `L_opt`, `F_max`, `α_opt`, `v_max`.
    pub fn symbol(self) -> &'static str {
        match self {
            Parameter::TendonSlackLength => "L_ts",
            Parameter::OptimalFiberLength => "L_opt",
            Parameter::MaxIsometricForce => "F_max",
            Parameter::PennationAngleAtOptimal => "α_opt",
            Parameter::MaxContractionVelocity => "v_max",
        }
    }
}

/// A muscle's Hill-model parameters (SI units, OpenSim property names).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuscleParameters {
    pub name: String,
    /// L_opt, m.
    pub optimal_fiber_length: f64,
    /// L_ts, m.
    pub tendon_slack_length: f64,
    /// F_max, N.
    pub max_isometric_force: f64,
    /// α_opt, rad.
    pub pennation_angle_at_optimal: f64,
    /// v_max, L_opt/s.
    pub max_contraction_velocity: f64,
}

impl MuscleParameters {
    /// The values of a model's muscle.
    pub fn from_spec(name: &str, spec: &MuscleSpec) -> MuscleParameters {
        MuscleParameters {
            name: name.to_string(),
            optimal_fiber_length: spec.optimal_fiber_length,
            tendon_slack_length: spec.tendon_slack_length,
            max_isometric_force: spec.max_isometric_force,
            pennation_angle_at_optimal: spec.pennation_angle_at_optimal,
            max_contraction_velocity: spec.max_contraction_velocity,
        }
    }

    pub fn get(&self, parameter: Parameter) -> f64 {
        match parameter {
            Parameter::TendonSlackLength => self.tendon_slack_length,
            Parameter::OptimalFiberLength => self.optimal_fiber_length,
            Parameter::MaxIsometricForce => self.max_isometric_force,
            Parameter::PennationAngleAtOptimal => self.pennation_angle_at_optimal,
            Parameter::MaxContractionVelocity => self.max_contraction_velocity,
        }
    }

    pub fn set(&mut self, parameter: Parameter, value: f64) {
        match parameter {
            Parameter::TendonSlackLength => self.tendon_slack_length = value,
            Parameter::OptimalFiberLength => self.optimal_fiber_length = value,
            Parameter::MaxIsometricForce => self.max_isometric_force = value,
            Parameter::PennationAngleAtOptimal => self.pennation_angle_at_optimal = value,
            Parameter::MaxContractionVelocity => self.max_contraction_velocity = value,
        }
    }

    /// A copy with `parameter` set to `value`.
    pub fn with(&self, parameter: Parameter, value: f64) -> MuscleParameters {
        let mut changed = self.clone();
        changed.set(parameter, value);
        changed
    }

    /// `spec` with these five values (everything else, the curves included, unchanged).
    pub fn apply_to(&self, spec: &MuscleSpec) -> MuscleSpec {
        MuscleSpec {
            optimal_fiber_length: self.optimal_fiber_length,
            tendon_slack_length: self.tendon_slack_length,
            max_isometric_force: self.max_isometric_force,
            pennation_angle_at_optimal: self.pennation_angle_at_optimal,
            max_contraction_velocity: self.max_contraction_velocity,
            ..spec.clone()
        }
    }

    /// OpenSim's range checks: positive finite lengths, force and velocity; α_opt in [0, π/2).
    pub fn check(&self) -> Result<(), FunctionalError> {
        for parameter in Parameter::ALL {
            let value = self.get(parameter);
            let ok = match parameter {
                Parameter::PennationAngleAtOptimal => (0.0..std::f64::consts::FRAC_PI_2).contains(&value),
                _ => value > 0.0 && value.is_finite(),
            };
            if !ok {
                let expected = match parameter {
                    Parameter::PennationAngleAtOptimal => "an angle in [0, π/2) rad",
                    _ => "a positive finite number",
                };
                return Err(FunctionalError::Parameters {
                    muscle: self.name.clone(),
                    problem: format!("{} = {value}; expected {expected}", parameter.property()),
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> MuscleParameters {
        MuscleParameters {
            name: "vas_lat_r".into(),
            optimal_fiber_length: 0.097,
            tendon_slack_length: 0.18,
            max_isometric_force: 1871.0,
            pennation_angle_at_optimal: 0.087,
            max_contraction_velocity: 10.0,
        }
    }

    #[test]
    fn get_returns_what_set_stored() {
        let mut p = example();
        for (k, parameter) in Parameter::ALL.into_iter().enumerate() {
            p.set(parameter, k as f64 + 0.5);
        }
        for (k, parameter) in Parameter::ALL.into_iter().enumerate() {
            assert_eq!(p.get(parameter), k as f64 + 0.5);
        }
    }

    #[test]
    fn check_refuses_out_of_range_values() {
        assert!(example().check().is_ok());
        let message = example().with(Parameter::TendonSlackLength, -0.1).check().unwrap_err().to_string();
        assert_eq!(message, "parameters of muscle \"vas_lat_r\": tendon_slack_length = -0.1; expected a positive finite number");
        assert!(example().with(Parameter::PennationAngleAtOptimal, 1.6).check().is_err());
        assert!(example().with(Parameter::OptimalFiberLength, f64::NAN).check().is_err());
    }
}
