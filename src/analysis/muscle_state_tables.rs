//! The tables OpenSim's `MuscleAnalysis` forms from the muscles' states: fiber and tendon
//! lengths and velocities, forces, powers, and the moments r·F_t about the listed coordinates.

use super::muscle_states::MuscleStates;
use super::storage;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::muscle::MuscleState;

/// A quantity OpenSim's Muscle API reports for a state.
type Quantity = fn(&MuscleState) -> f64;

/// MuscleAnalysis' state tables in the order it forms them, by table name.
const QUANTITIES: [(&str, Quantity); 17] = [
    ("PennationAngle", |s| s.report.pennation_angle),
    ("FiberLength", |s| s.report.fiber_length),
    ("NormalizedFiberLength", |s| s.report.normalized_fiber_length),
    ("TendonLength", |s| s.report.tendon_length),
    ("FiberVelocity", |s| s.fiber_velocity),
    ("NormFiberVelocity", |s| s.report.normalized_fiber_velocity),
    ("PennationAngularVelocity", |s| s.pennation_angular_velocity),
    ("TendonForce", |s| s.report.tendon_force),
    ("FiberForce", |s| s.report.fiber_force),
    ("ActiveFiberForce", |s| s.report.active_fiber_force),
    ("PassiveFiberForce", |s| s.report.passive_fiber_force),
    ("ActiveFiberForceAlongTendon", |s| s.report.active_fiber_force * s.report.cos_pennation_angle),
    ("PassiveFiberForceAlongTendon", |s| s.report.passive_fiber_force * s.report.cos_pennation_angle),
    ("FiberActivePower", |s| s.fiber_active_power),
    ("FiberPassivePower", |s| s.fiber_passive_power),
    ("TendonPower", |s| s.tendon_power),
    ("MuscleActuatorPower", MuscleState::muscle_power),
];

/// The state tables of `muscles` (names in `states`; NaN where a state was not evaluated, as
/// OpenSim writes it) at `times` (s), then `Moment_<coordinate>` = MomentArm × TendonForce for
/// each `MomentArm_<coordinate>` table of `moment_arms` (same rows and columns).
pub fn muscle_state_tables(states: &MuscleStates, times: &[f64], muscles: &[String], moment_arms: &[&StorageTable]) -> Result<Vec<StorageTable>, TableError> {
    let columns: Vec<usize> = muscles.iter().filter_map(|m| states.muscles.iter().position(|(_, name)| name == m)).collect();
    let labels: Vec<String> = std::iter::once("time".to_string()).chain(columns.iter().map(|&k| states.muscles[k].1.clone())).collect();
    let value = |row: usize, k: usize, quantity: Quantity| states.states[row][k].as_ref().map_or(f64::NAN, quantity);
    let table = |name: &str, quantity: Quantity| {
        let values = times.iter().enumerate().flat_map(|(row, &t)| std::iter::once(t).chain(columns.iter().map(move |&k| value(row, k, quantity)))).collect();
        storage(name, labels.clone(), values)
    };
    let mut tables = QUANTITIES.iter().map(|&(name, quantity)| table(name, quantity)).collect::<Result<Vec<_>, _>>()?;
    let tendon_force: Quantity = |s| s.report.tendon_force;
    for arms in moment_arms {
        let name = arms.name().replacen("MomentArm_", "Moment_", 1);
        let values = arms
            .rows()
            .enumerate()
            .flat_map(|(row, r)| std::iter::once(r[0]).chain(columns.iter().enumerate().map(move |(i, &k)| r[i + 1] * value(row, k, tendon_force))))
            .collect();
        tables.push(storage(&name, labels.clone(), values)?);
    }
    Ok(tables)
}
