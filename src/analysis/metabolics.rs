//! OpenSim's muscle metabolics probes on the states an AnalyzeTool forms: each muscle's metabolic
//! power (W) from its activation, excitation (the controllers' control), fiber length, velocity
//! and forces, as `computeProbeInputs` computes it — Umberger (2010) or Bhargava et al. (2004),
//! with OpenSim's options (recruitment, negative work, the non-negative total, the 1 W/kg floor)
//! — the basal rate of the whole model's mass and their total.

use super::reporters::AppliedAt;
use crate::mechanics::muscle::MuscleState;
use crate::mechanics::Function;
use crate::model::{BhargavaRates, MetabolicModel, MetabolicsProbeSpec, ModelSpec, MuscleSpec, UmbergerRates};

/// Shortening heat of slow-twitch fibers, at most (W/kg; Umberger 2003).
const MAX_SHORTENING_RATE: f64 = 100.0;

/// One muscle of a probe, on the model.
struct MetabolicMuscle<'a> {
    /// Index among the AnalyzeTool's muscle states.
    state: usize,
    name: &'a str,
    spec: &'a MuscleSpec,
    /// kg.
    mass: f64,
    ratio_slow_twitch_fibers: f64,
    /// Bhargava's activation (slow, fast) and maintenance (slow, fast) constants, W/kg.
    twitch_constants: [f64; 4],
}

/// A metabolics probe on the model's muscles.
pub(super) struct MetabolicsProbe<'a> {
    spec: &'a MetabolicsProbeSpec,
    muscles: Vec<MetabolicMuscle<'a>>,
    rates: Rates<'a>,
    /// The model's mass, kg.
    body_mass: f64,
}

/// The probe's model, Bhargava's with its fiber-length dependence compiled.
enum Rates<'a> {
    Umberger(&'a UmbergerRates),
    Bhargava(&'a BhargavaRates, Function),
}

impl<'a> MetabolicsProbe<'a> {
    /// The probe `spec` of `model` at `at`'s muscle states, or the name of a muscle the model lacks
    /// (OpenSim then disables the probe).
    pub fn new(model: &'a ModelSpec, at: &AppliedAt, spec: &'a MetabolicsProbeSpec) -> Result<MetabolicsProbe<'a>, String> {
        let rates = match &spec.model {
            MetabolicModel::Umberger2010(rates) => Rates::Umberger(rates),
            MetabolicModel::Bhargava2004(rates) => Rates::Bhargava(rates, Function::new(&rates.fiber_length_dependence)),
        };
        let body_mass = model.bodies.iter().map(|b| b.mass).sum();
        Ok(MetabolicsProbe { spec, muscles: metabolic_muscles(model, at, spec)?, rates, body_mass })
    }

    /// Its output labels: `<probe>_TOTAL`, then unless `report_total_metabolics_only` `_BASAL`
    /// and `_<muscle>`.
    pub fn labels(&self, probe: &str) -> Vec<String> {
        let mut labels = vec![format!("{probe}_TOTAL")];
        if !self.spec.report_total_metabolics_only {
            labels.push(format!("{probe}_BASAL"));
            labels.extend(self.spec.muscles.iter().map(|m| format!("{probe}_{}", m.name)));
        }
        labels
    }

    /// Its outputs at `at`'s row `row` (W): total, then the basal rate and each muscle's power
    /// (NaN where a muscle's state is not formed).
    pub fn outputs(&self, at: &AppliedAt, row: usize) -> Vec<f64> {
        let spec = self.spec;
        let time = at.states.motion.times[row];
        let basal = if spec.basal_rate_on { spec.basal_coefficient * self.body_mass.powf(spec.basal_exponent) } else { 0.0 };
        let power = |m: &MetabolicMuscle| {
            let Some(state) = at.muscles.states[row][m.state].as_ref() else { return f64::NAN };
            let excitation = at.controls.control(m.name, time);
            match &self.rates {
                Rates::Umberger(rates) => umberger_power(spec, rates, m, state, excitation),
                Rates::Bhargava(rates, dependence) => bhargava_power(spec, rates, dependence, m, state, excitation),
            }
        };
        let powers: Vec<f64> = self.muscles.iter().map(power).collect();
        let mut outputs = vec![basal + powers.iter().sum::<f64>()];
        if !spec.report_total_metabolics_only {
            outputs.push(basal);
            outputs.extend(powers);
        }
        outputs
    }
}

/// The probe's muscles on the model, or the name of one it lacks.
fn metabolic_muscles<'a>(spec: &'a ModelSpec, at: &AppliedAt, metabolics: &'a MetabolicsProbeSpec) -> Result<Vec<MetabolicMuscle<'a>>, String> {
    let mut muscles = Vec::new();
    for parameters in &metabolics.muscles {
        let muscle = spec.muscles().find(|m| m.name == parameters.name).and_then(|m| m.muscle.as_ref());
        let state = at.muscles.muscles.iter().position(|(_, name)| *name == parameters.name);
        let (Some(muscle), Some(state)) = (muscle, state) else { return Err(parameters.name.clone()) };
        let mass = parameters.provided_muscle_mass.unwrap_or(muscle.max_isometric_force / parameters.specific_tension * parameters.density * muscle.optimal_fiber_length);
        muscles.push(MetabolicMuscle { state, name: &parameters.name, spec: muscle, mass, ratio_slow_twitch_fibers: parameters.ratio_slow_twitch_fibers, twitch_constants: parameters.twitch_constants });
    }
    Ok(muscles)
}

/// One muscle's metabolic power by Umberger (2010) (W) at `state` with control `excitation`:
/// activation and maintenance heat, shortening heat and mechanical work rate (W/kg) times its
/// mass.
fn umberger_power(metabolics: &MetabolicsProbeSpec, rates: &UmbergerRates, muscle: &MetabolicMuscle, state: &MuscleState, excitation: f64) -> f64 {
    let u = metabolics;
    let &UmbergerRates { activation_maintenance_rate_on, aerobic_factor, use_bhargava_recruitment_model } = rates;
    let report = &state.report;
    let effort = u.muscle_effort_scaling_factor;
    let (activation, excitation) = (effort * report.activation, effort * excitation);
    let active_force = (effort * report.active_fiber_force).max(0.0);
    let (length, velocity) = (report.normalized_fiber_length, state.fiber_velocity);
    let normalized_velocity = velocity / muscle.spec.optimal_fiber_length;
    let f_iso = report.active_force_length_multiplier;
    let a = if excitation > activation { excitation } else { (excitation + activation) / 2.0 };
    let slow = if use_bhargava_recruitment_model { recruited_slow_share(muscle.ratio_slow_twitch_fibers, excitation) } else { muscle.ratio_slow_twitch_fibers };
    let forbid = u.forbid_negative_total_power;
    let mut maintenance = 0.0;
    if forbid || activation_maintenance_rate_on {
        let unscaled = 128.0 * (1.0 - slow) + 25.0;
        let lengthened = if length <= 1.0 { unscaled } else { 0.4 * unscaled + 0.6 * unscaled * f_iso };
        maintenance = aerobic_factor * a.powf(0.6) * lengthened;
    }
    let mut shortening = 0.0;
    if forbid || u.shortening_rate_on {
        let v_max = muscle.spec.max_contraction_velocity;
        let (alpha_fast, alpha_slow) = (153.0 / v_max, 100.0 / (v_max / 2.5));
        shortening = if normalized_velocity <= 0.0 {
            let slow_rate = (-alpha_slow * normalized_velocity).min(MAX_SHORTENING_RATE);
            let fast_rate = alpha_fast * normalized_velocity * (1.0 - slow);
            aerobic_factor * a.powi(2) * (slow_rate * slow - fast_rate)
        } else {
            let factor = if u.include_negative_mechanical_work { 4.0 } else { 0.3 };
            aerobic_factor * a * factor * alpha_slow * normalized_velocity
        };
        if length > 1.0 {
            shortening *= f_iso;
        }
    }
    let mut work = 0.0;
    if forbid || u.mechanical_work_rate_on {
        let counted = u.include_negative_mechanical_work || velocity <= 0.0;
        work = if counted { -active_force * velocity / muscle.mass } else { 0.0 };
    }
    if forbid && maintenance + shortening + work < 0.0 {
        shortening -= maintenance + shortening + work;
    }
    let mut heat = maintenance + shortening;
    let both = activation_maintenance_rate_on && u.shortening_rate_on;
    if u.enforce_minimum_heat_rate_per_muscle && both && heat < 1.0 {
        heat = 1.0;
    }
    let rates = [(both, heat), (!both && activation_maintenance_rate_on, maintenance), (!both && u.shortening_rate_on, shortening), (u.mechanical_work_rate_on, work)];
    rates.iter().filter(|(on, _)| *on).map(|(_, rate)| rate).sum::<f64>() * muscle.mass
}

/// One muscle's metabolic power by Bhargava et al. (2004) (W) at `state` with control
/// `excitation`: activation, maintenance (scaled by `dependence` of the normalized fiber length)
/// and shortening heat, and mechanical work rate.
fn bhargava_power(metabolics: &MetabolicsProbeSpec, rates: &BhargavaRates, dependence: &Function, muscle: &MetabolicMuscle, state: &MuscleState, excitation: f64) -> f64 {
    let b = metabolics;
    let &BhargavaRates { activation_rate_on, maintenance_rate_on, use_force_dependent_shortening_prop_constant, .. } = rates;
    let report = &state.report;
    let effort = b.muscle_effort_scaling_factor;
    let (activation, excitation) = (effort * report.activation, effort * excitation);
    let active_force = effort * report.active_fiber_force;
    let total_force = active_force + report.passive_fiber_force;
    let velocity = state.fiber_velocity;
    let (slow, fast) = recruitment(muscle.ratio_slow_twitch_fibers, excitation);
    let isometric_force = activation * report.active_force_length_multiplier * muscle.spec.max_isometric_force;
    let [activation_slow, activation_fast, maintenance_slow, maintenance_fast] = muscle.twitch_constants;
    let forbid = b.forbid_negative_total_power;
    let activation_heat = if forbid || activation_rate_on { muscle.mass * (activation_slow * slow + activation_fast * fast) } else { 0.0 };
    let maintenance = if forbid || maintenance_rate_on { muscle.mass * dependence.value(report.normalized_fiber_length) * (maintenance_slow * slow + maintenance_fast * fast) } else { 0.0 };
    let mut shortening = 0.0;
    if forbid || b.shortening_rate_on {
        let alpha = match (use_force_dependent_shortening_prop_constant, velocity <= 0.0) {
            (true, true) => 0.16 * isometric_force + 0.18 * total_force,
            (true, false) => 0.157 * total_force,
            (false, true) => 0.25 * total_force,
            (false, false) => 0.0,
        };
        shortening = -alpha * velocity;
    }
    let counted = b.include_negative_mechanical_work || velocity <= 0.0;
    let work = if (forbid || b.mechanical_work_rate_on) && counted { -active_force * velocity } else { 0.0 };
    if forbid && activation_heat + maintenance + shortening + work < 0.0 {
        shortening -= activation_heat + maintenance + shortening + work;
    }
    let all = activation_rate_on && maintenance_rate_on && b.shortening_rate_on;
    let mut heat = activation_heat + maintenance + shortening;
    if b.enforce_minimum_heat_rate_per_muscle && all && heat < muscle.mass {
        heat = muscle.mass;
    }
    let rates = [(all, heat), (!all && activation_rate_on, activation_heat), (!all && maintenance_rate_on, maintenance), (!all && b.shortening_rate_on, shortening), (b.mechanical_work_rate_on, work)];
    rates.iter().filter(|(on, _)| *on).map(|(_, rate)| rate).sum()
}

/// Bhargava's slow-twitch share of the recruitment at excitation u (1 at zero excitation).
fn recruited_slow_share(ratio: f64, excitation: f64) -> f64 {
    if excitation == 0.0 {
        return 1.0;
    }
    let (slow, fast) = recruitment(ratio, excitation);
    slow / (slow + fast)
}

/// The slow and fast twitch fibers' recruitment at excitation u (Bhargava et al. 2004):
/// r·sin(πu/2) and (1 − r)·(1 − cos(πu/2)), r the slow-twitch ratio.
fn recruitment(ratio: f64, excitation: f64) -> (f64, f64) {
    let angle = std::f64::consts::FRAC_PI_2 * excitation;
    (ratio * angle.sin(), (1.0 - ratio) * (1.0 - angle.cos()))
}
