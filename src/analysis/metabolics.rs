//! OpenSim's `ProbeReporter` of the model's `Umberger2010MuscleMetabolicsProbe`s on the states an
//! AnalyzeTool forms: each muscle's metabolic power (W) from its activation, excitation (the
//! controllers' control), fiber length, velocity and active force, as
//! `Umberger2010MuscleMetabolicsProbe::computeProbeInputs` computes it (Umberger 2010, with
//! OpenSim's options: Bhargava's recruitment, negative work, the non-negative total, the 1 W/kg
//! floor), the basal rate of the whole model's mass, their total, times the probe's gain.

use super::reporters::{AppliedAt, ReporterError};
use crate::io::table::StorageTable;
use crate::mechanics::muscle::MuscleState;
use crate::model::{ModelSpec, MuscleSpec, ProbeSpec, UmbergerProbeSpec};

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
}

/// A muscle's state as the probe reads it.
struct MuscleInputs {
    activation: f64,
    excitation: f64,
    /// N, along the fiber.
    active_fiber_force: f64,
    normalized_fiber_length: f64,
    /// m/s, lengthening positive.
    fiber_velocity: f64,
    active_force_length_multiplier: f64,
}

/// The `probes` table: per enabled probe its outputs (`<probe>_TOTAL`, then unless
/// `report_total_metabolics_only` `_BASAL` and `_<muscle>`), in the ProbeSet's order; `notes`
/// gets the probes OpenSim disables (reporting nothing).
pub fn probe_table(spec: &ModelSpec, at: &AppliedAt, notes: &mut Vec<String>) -> Result<StorageTable, ReporterError> {
    let body_mass: f64 = spec.bodies.iter().map(|b| b.mass).sum();
    let mut probes = Vec::new();
    for probe in &spec.probes {
        if let Some(reason) = &probe.invalid {
            notes.push(format!("ProbeReporter: probe {} is disabled, as OpenSim disables it: {reason}", probe.name));
        }
        if !probe.enabled {
            continue;
        }
        let Some(umberger) = &probe.umberger else {
            return Err(ReporterError::NotFormed(format!("probe {} is a {}; osim-tune's ProbeReporter reports Umberger2010MuscleMetabolicsProbes", probe.name, probe.class)));
        };
        if probe.operation != "value" {
            return Err(ReporterError::NotFormed(format!("probe {}'s probe_operation {:?}: the AnalyzeTool holds no probe states to {} (only `value` is reported)", probe.name, probe.operation, probe.operation)));
        }
        match metabolic_muscles(spec, at, umberger) {
            Ok(muscles) => probes.push((probe, umberger, muscles)),
            Err(missing) => notes.push(format!("ProbeReporter: probe {} is disabled, as OpenSim disables it: the model has no muscle {missing}", probe.name)),
        }
    }
    let mut labels = vec!["time".to_string()];
    for (probe, umberger, _) in &probes {
        labels.push(format!("{}_TOTAL", probe.name));
        if !umberger.report_total_metabolics_only {
            labels.push(format!("{}_BASAL", probe.name));
            labels.extend(umberger.muscles.iter().map(|m| format!("{}_{}", probe.name, m.name)));
        }
    }
    let mut values = Vec::new();
    for (row, &time) in at.states.motion.times.iter().enumerate() {
        values.push(time);
        for (probe, umberger, muscles) in &probes {
            let inputs = muscles.iter().map(|m| at.muscles.states[row][m.state].as_ref().map(|s| inputs(s, at.controls.control(m.name, time)))).collect::<Vec<_>>();
            values.extend(umberger_outputs(probe, umberger, muscles, &inputs, body_mass));
        }
    }
    Ok(StorageTable::new("ModelProbes", labels, values)?.with_in_degrees(false))
}

/// The probe's muscles on the model, or the name of one it lacks.
fn metabolic_muscles<'a>(spec: &'a ModelSpec, at: &AppliedAt, umberger: &'a UmbergerProbeSpec) -> Result<Vec<MetabolicMuscle<'a>>, String> {
    let mut muscles = Vec::new();
    for parameters in &umberger.muscles {
        let muscle = spec.muscles().find(|m| m.name == parameters.name).and_then(|m| m.muscle.as_ref());
        let state = at.muscles.muscles.iter().position(|(_, name)| *name == parameters.name);
        let (Some(muscle), Some(state)) = (muscle, state) else { return Err(parameters.name.clone()) };
        let mass = parameters.provided_muscle_mass.unwrap_or(muscle.max_isometric_force / parameters.specific_tension * parameters.density * muscle.optimal_fiber_length);
        muscles.push(MetabolicMuscle { state, name: &parameters.name, spec: muscle, mass, ratio_slow_twitch_fibers: parameters.ratio_slow_twitch_fibers });
    }
    Ok(muscles)
}

/// What the probe reads of a muscle at `state` with control `excitation`.
fn inputs(state: &MuscleState, excitation: f64) -> MuscleInputs {
    let report = &state.report;
    MuscleInputs {
        activation: report.activation,
        excitation,
        active_fiber_force: report.active_fiber_force,
        normalized_fiber_length: report.normalized_fiber_length,
        fiber_velocity: state.fiber_velocity,
        active_force_length_multiplier: report.active_force_length_multiplier,
    }
}

/// The probe's outputs at one row (W): total, then unless only the total is reported the basal
/// rate and each muscle's power (NaN where a muscle's state is not formed).
fn umberger_outputs(probe: &ProbeSpec, umberger: &UmbergerProbeSpec, muscles: &[MetabolicMuscle], inputs: &[Option<MuscleInputs>], body_mass: f64) -> Vec<f64> {
    let basal = if umberger.basal_rate_on { umberger.basal_coefficient * body_mass.powf(umberger.basal_exponent) } else { 0.0 };
    let powers: Vec<f64> = muscles.iter().zip(inputs).map(|(m, i)| i.as_ref().map_or(f64::NAN, |i| muscle_power(umberger, m, i))).collect();
    let mut outputs = vec![basal + powers.iter().sum::<f64>()];
    if !umberger.report_total_metabolics_only {
        outputs.push(basal);
        outputs.extend(&powers);
    }
    outputs.iter().map(|v| probe.gain * v).collect()
}

/// One muscle's metabolic power (W): activation and maintenance heat, shortening heat and
/// mechanical work rate (W/kg) times its mass.
fn muscle_power(umberger: &UmbergerProbeSpec, muscle: &MetabolicMuscle, inputs: &MuscleInputs) -> f64 {
    let u = umberger;
    let effort = u.muscle_effort_scaling_factor;
    let (activation, excitation) = (effort * inputs.activation, effort * inputs.excitation);
    let active_force = (effort * inputs.active_fiber_force).max(0.0);
    let (length, velocity) = (inputs.normalized_fiber_length, inputs.fiber_velocity);
    let normalized_velocity = velocity / muscle.spec.optimal_fiber_length;
    let f_iso = inputs.active_force_length_multiplier;
    let a = if excitation > activation { excitation } else { (excitation + activation) / 2.0 };
    let slow = slow_twitch_share(u, muscle.ratio_slow_twitch_fibers, excitation);
    let forbid = u.forbid_negative_total_power;
    let mut maintenance = 0.0;
    if forbid || u.activation_maintenance_rate_on {
        let unscaled = 128.0 * (1.0 - slow) + 25.0;
        let lengthened = if length <= 1.0 { unscaled } else { 0.4 * unscaled + 0.6 * unscaled * f_iso };
        maintenance = u.aerobic_factor * a.powf(0.6) * lengthened;
    }
    let mut shortening = 0.0;
    if forbid || u.shortening_rate_on {
        let v_max = muscle.spec.max_contraction_velocity;
        let (alpha_fast, alpha_slow) = (153.0 / v_max, 100.0 / (v_max / 2.5));
        shortening = if normalized_velocity <= 0.0 {
            let slow_rate = (-alpha_slow * normalized_velocity).min(MAX_SHORTENING_RATE);
            let fast_rate = alpha_fast * normalized_velocity * (1.0 - slow);
            u.aerobic_factor * a.powi(2) * (slow_rate * slow - fast_rate)
        } else {
            let factor = if u.include_negative_mechanical_work { 4.0 } else { 0.3 };
            u.aerobic_factor * a * factor * alpha_slow * normalized_velocity
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
    let both = u.activation_maintenance_rate_on && u.shortening_rate_on;
    if u.enforce_minimum_heat_rate_per_muscle && both && heat < 1.0 {
        heat = 1.0;
    }
    let rates = [(both, heat), (!both && u.activation_maintenance_rate_on, maintenance), (!both && u.shortening_rate_on, shortening), (u.mechanical_work_rate_on, work)];
    rates.iter().filter(|(on, _)| *on).map(|(_, rate)| rate).sum::<f64>() * muscle.mass
}

/// The slow-twitch share: the muscle's ratio, or with Bhargava's recruitment model the share of
/// the slow fibers' recruitment r·sin(πu/2) in all (1 at zero excitation).
fn slow_twitch_share(umberger: &UmbergerProbeSpec, ratio: f64, excitation: f64) -> f64 {
    if !umberger.use_bhargava_recruitment_model {
        return ratio;
    }
    if excitation == 0.0 {
        return 1.0;
    }
    let angle = std::f64::consts::FRAC_PI_2 * excitation;
    let (slow, fast) = (ratio * angle.sin(), (1.0 - ratio) * (1.0 - angle.cos()));
    slow / (slow + fast)
}
