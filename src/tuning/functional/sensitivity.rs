//! Sensitivity of the knee moments to each parameter of each estimated muscle (thesis ch. 3,
//! eq. 3.3–3.4): MS = |(M(p + Δp) − M(p − Δp)) / 2 / (Δp / p)| per trial, with Δp = 5 % of p by
//! default, then the maximum over the trials, classed low (< 50 N·m), medium (< 100 N·m) or high.
//!
//! Only the perturbed muscle's contribution F_t·r changes, so M(+Δp) − M(−Δp) is computed as the
//! difference of that contribution (the other muscles' terms cancel exactly).
//!
//! Two cases are reported rather than computed by a formula that does not apply:
//! - α_opt = 0 (e.g. `bifemlh_r` in gait2392): a relative perturbation of zero is no
//!   perturbation and MS per *relative* change is 0/0, so the entry is
//!   [`Applicability::ZeroNominalValue`] without values. (An additive perturbation would give a
//!   number in N·m per rad, not comparable with the others.)
//! - v_max: the trials are isometric and the equilibrium static (fiber velocity 0, f_V(0)), so
//!   v_max does not enter the moments; it is perturbed like the others and its MS is exactly 0.

use serde::Serialize;

use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::{MuscleParameters, Parameter};

/// The perturbation of the thesis: ±5 % of the parameter.
pub const DEFAULT_RELATIVE_STEP: f64 = 0.05;

/// Upper bound of the low class, N·m (dynamometry, thesis ch. 3).
pub const LOW_BELOW: f64 = 50.0;

/// Upper bound of the medium class, N·m.
pub const MEDIUM_BELOW: f64 = 100.0;

/// Sensitivity class of the maximum over the trials.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub enum SensitivityClass {
    /// MS < 50 N·m.
    Low,
    /// 50 ≤ MS < 100 N·m.
    Medium,
    /// MS ≥ 100 N·m.
    High,
}

impl SensitivityClass {
    /// The class of a sensitivity `value` (N·m).
    pub fn of(value: f64) -> SensitivityClass {
        if value < LOW_BELOW {
            SensitivityClass::Low
        } else if value < MEDIUM_BELOW {
            SensitivityClass::Medium
        } else {
            SensitivityClass::High
        }
    }
}

/// Whether MS per relative change is defined for an entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Applicability {
    Applicable,
    /// The nominal value is 0 (α_opt of an unpennated muscle): nothing to perturb relatively.
    ZeroNominalValue,
}

/// The sensitivity of the knee moments to one parameter of one muscle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensitivityEntry {
    pub muscle: String,
    pub parameter: Parameter,
    /// The nominal value perturbed (SI units).
    pub nominal: f64,
    pub applicability: Applicability,
    /// MS per trial (eq. 3.3), N·m, in the model's trial order; empty when not applicable.
    pub per_trial: Vec<f64>,
    /// max over the trials (eq. 3.4), N·m; `None` when not applicable.
    pub maximum: Option<f64>,
    /// The trial (index into [`KneeMomentModel::trials`]) of the maximum (the first of ties).
    pub trial_of_maximum: Option<usize>,
    pub class: Option<SensitivityClass>,
}

/// Sensitivities of every estimated muscle × parameter, muscle-major, parameters in
/// [`Parameter::ALL`] order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensitivityTable {
    /// Δp / p.
    pub relative_step: f64,
    pub entries: Vec<SensitivityEntry>,
}

impl SensitivityTable {
    /// MS of every parameter of every estimated muscle around `parameters` (one per estimated
    /// muscle, in order) for the model's trials, with Δp = `relative_step` · p (0 < step < 1).
    pub fn compute(model: &KneeMomentModel, parameters: &[MuscleParameters], relative_step: f64) -> Result<SensitivityTable, FunctionalError> {
        if !(relative_step > 0.0 && relative_step < 1.0) {
            return Err(FunctionalError::all_muscles(format!("relative perturbation {relative_step}; expected a fraction in (0, 1)")));
        }
        let mut muscles = model.estimated_muscles(parameters)?;
        let n_trials = model.trials().len();
        let mut entries = Vec::with_capacity(parameters.len() * Parameter::ALL.len());
        let (mut plus, mut minus) = (vec![0.0; n_trials], vec![0.0; n_trials]);
        for (e, nominal) in parameters.iter().enumerate() {
            let k = model.estimated_knee_index(e);
            for parameter in Parameter::ALL {
                let p = nominal.get(parameter);
                let mut entry = SensitivityEntry {
                    muscle: nominal.name.clone(),
                    parameter,
                    nominal: p,
                    applicability: Applicability::ZeroNominalValue,
                    per_trial: Vec::new(),
                    maximum: None,
                    trial_of_maximum: None,
                    class: None,
                };
                if p == 0.0 {
                    entries.push(entry);
                    continue;
                }
                let (p_plus, p_minus) = (p * (1.0 + relative_step), p * (1.0 - relative_step));
                for (value, contributions) in [(p_plus, &mut plus), (p_minus, &mut minus)] {
                    muscles.set(model, e, &nominal.with(parameter, value))?;
                    for (t, c) in contributions.iter_mut().enumerate() {
                        *c = model.contribution(k, muscles.muscle(e), t)?;
                    }
                }
                muscles.set(model, e, nominal)?;
                // |(M+ − M−)/2 / (Δp/p)| with Δp/p from the values actually used.
                let relative = (p_plus - p_minus) / 2.0 / p;
                entry.per_trial = plus.iter().zip(&minus).map(|(m_plus, m_minus)| ((m_plus - m_minus) / 2.0 / relative).abs()).collect();
                let (trial, maximum) = entry
                    .per_trial
                    .iter()
                    .copied()
                    .enumerate()
                    .fold((0, f64::NEG_INFINITY), |best, (t, v)| if v > best.1 { (t, v) } else { best });
                entry.applicability = Applicability::Applicable;
                entry.maximum = Some(maximum);
                entry.trial_of_maximum = Some(trial);
                entry.class = Some(SensitivityClass::of(maximum));
                entries.push(entry);
            }
        }
        Ok(SensitivityTable { relative_step, entries })
    }

    /// The entry of `muscle`'s `parameter`.
    pub fn entry(&self, muscle: &str, parameter: Parameter) -> Option<&SensitivityEntry> {
        self.entries.iter().find(|e| e.muscle == muscle && e.parameter == parameter)
    }

    /// The parameter with the largest maximum MS for `muscle` (`None` for an unknown muscle).
    pub fn most_sensitive(&self, muscle: &str) -> Option<Parameter> {
        self.entries
            .iter()
            .filter(|e| e.muscle == muscle)
            .filter_map(|e| e.maximum.map(|m| (e.parameter, m)))
            .fold(None, |best: Option<(Parameter, f64)>, (p, m)| match best {
                Some((_, b)) if b >= m => best,
                _ => Some((p, m)),
            })
            .map(|(p, _)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_follow_the_thesis_thresholds() {
        assert_eq!(SensitivityClass::of(0.0), SensitivityClass::Low);
        assert_eq!(SensitivityClass::of(49.999), SensitivityClass::Low);
        assert_eq!(SensitivityClass::of(50.0), SensitivityClass::Medium);
        assert_eq!(SensitivityClass::of(99.999), SensitivityClass::Medium);
        assert_eq!(SensitivityClass::of(100.0), SensitivityClass::High);
    }
}
