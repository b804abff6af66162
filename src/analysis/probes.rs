//! OpenSim's `ProbeReporter` on the states an AnalyzeTool forms: each enabled probe of the model's
//! `ProbeSet`, in its order, times its gain — muscle metabolics ([`super::metabolics`]) and
//! actuator force and power probes (each listed actuator's actuation or power to the exponent, or
//! their sum). Probes OpenSim disables (a muscle or actuator the model lacks, a parameter out of
//! range) report nothing and are noted; other classes and operations but `value` (the
//! AnalyzeTool holds no probe states to integrate) leave the table out.

use super::metabolics::MetabolicsProbe;
use super::reporters::{actuation_row, AppliedAt, ReporterError};
use crate::io::table::StorageTable;
use crate::model::{ActuatorQuantity, ModelSpec, ProbeKind, ProbeSpec};

/// A probe the reporter evaluates.
enum Reported<'a> {
    Metabolics(MetabolicsProbe<'a>),
    /// The generators' indices, what is read of them, summed or not, the exponent.
    Actuators { generators: Vec<usize>, quantity: ActuatorQuantity, summed: bool, exponent: f64 },
}

/// The `probes` table; `notes` gets the probes OpenSim disables.
pub fn probe_table(spec: &ModelSpec, at: &AppliedAt, notes: &mut Vec<String>) -> Result<StorageTable, ReporterError> {
    let mut probes = Vec::new();
    for probe in &spec.probes {
        if let Some(reason) = &probe.invalid {
            notes.push(format!("ProbeReporter: probe {} is disabled, as OpenSim disables it: {reason}", probe.name));
        }
        if !probe.enabled {
            continue;
        }
        if probe.operation != "value" {
            return Err(ReporterError::NotFormed(format!("probe {}'s probe_operation {:?}: the AnalyzeTool holds no probe states to {} (only `value` is reported)", probe.name, probe.operation, probe.operation)));
        }
        match reported(spec, at, probe)? {
            Ok(reported) => probes.push((probe, reported)),
            Err(missing) => notes.push(format!("ProbeReporter: probe {} is disabled, as OpenSim disables it: {missing}", probe.name)),
        }
    }
    let mut labels = vec!["time".to_string()];
    for (probe, reported) in &probes {
        labels.extend(probe_labels(probe, reported, at));
    }
    let mut values = Vec::new();
    for (row, &time) in at.states.motion.times.iter().enumerate() {
        values.push(time);
        // The actuation is formed once per row, and only for an actuator probe.
        let mut actuation = None;
        for (probe, reported) in &probes {
            let outputs = match reported {
                Reported::Metabolics(metabolics) => metabolics.outputs(at, row),
                Reported::Actuators { generators, quantity, summed, exponent } => {
                    let actuation = actuation.get_or_insert_with(|| actuation_row(at, row));
                    let read = if *quantity == ActuatorQuantity::Force { &actuation.forces } else { &actuation.powers };
                    let each = generators.iter().map(|&g| read[g].powf(*exponent));
                    if *summed { vec![each.sum()] } else { each.collect() }
                }
            };
            values.extend(outputs.iter().map(|v| probe.gain * v));
        }
    }
    Ok(StorageTable::new("ModelProbes", labels, values)?.with_in_degrees(false))
}

/// `probe` on the model, or what the model lacks for it (OpenSim then disables it); an error for
/// a class the reporter does not evaluate.
fn reported<'a>(spec: &'a ModelSpec, at: &AppliedAt, probe: &'a ProbeSpec) -> Result<Result<Reported<'a>, String>, ReporterError> {
    match &probe.kind {
        ProbeKind::Metabolics(metabolics) => Ok(MetabolicsProbe::new(spec, at, metabolics).map(Reported::Metabolics).map_err(|m| format!("the model has no muscle {m}"))),
        ProbeKind::Actuators { quantity, actuators, summed, exponent } => {
            let all = actuators.first().is_some_and(|a| a.eq_ignore_ascii_case("all"));
            let found: Result<Vec<usize>, String> = if all {
                Ok((0..at.generators.len()).collect())
            } else {
                actuators.iter().map(|name| at.generators.iter().position(|g| &g.name == name).ok_or_else(|| format!("the model has no actuator {name}"))).collect()
            };
            Ok(found.map(|generators| Reported::Actuators { generators, quantity: *quantity, summed: *summed, exponent: *exponent }))
        }
        ProbeKind::Other => Err(ReporterError::NotFormed(format!(
            "probe {} is a {}; osim-tune's ProbeReporter reports Umberger2010 and Bhargava2004 MuscleMetabolicsProbes, ActuatorForceProbes and ActuatorPowerProbes",
            probe.name, probe.class
        ))),
    }
}

/// The output labels of `probe`: a metabolics probe's, `<probe>_Summed`, or `<probe>_<actuator>`.
fn probe_labels(probe: &ProbeSpec, reported: &Reported, at: &AppliedAt) -> Vec<String> {
    match reported {
        Reported::Metabolics(metabolics) => metabolics.labels(&probe.name),
        Reported::Actuators { summed: true, .. } => vec![format!("{}_Summed", probe.name)],
        Reported::Actuators { generators, .. } => generators.iter().map(|&g| format!("{}_{}", probe.name, at.generators[g].name)).collect(),
    }
}
