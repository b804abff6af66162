//! OpenSim's `Kinematics`, `BodyKinematics` and `PointKinematics` analyses on the AnalyzeTool's
//! states: coordinate values and speeds (`_q`, `_u`); each body's mass center and orientation
//! (body-fixed X-Y-Z angles) with their velocities (`_pos_global`, `_vel_global` or
//! `_vel_bodyLocal`), the whole model's mass center last; a point's position and velocity in
//! ground or another body's frame (`_<point>_pos`, `_vel`). Their accelerations (`_dudt`,
//! `_acc_…`) are the model's forward dynamics at states a coordinates file does not give (muscle
//! states, controls) and are not formed.

use super::analyze_tool::AnalyzeToolMotion;
use super::storage;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MotionState, Multibody, Vec3};
use crate::model::{body_fixed_xyz_angles, MotionType};
use crate::setup::{BodyKinematicsSetup, KinematicsSetup, PointKinematicsSetup};

/// OpenSim's name for the whole model's mass center in a body list.
const CENTER_OF_MASS: &str = "center_of_mass";

/// Why the tables cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum KinematicsError {
    /// A listed coordinate or body the model lacks (OpenSim stops there too).
    #[error("<{class}> names {what} {name:?}, which the model does not have")]
    Unknown { class: &'static str, what: &'static str, name: String },
    #[error(transparent)]
    Table(#[from] TableError),
}

/// `Kinematics`' `q` and `u` tables (rotational values in degrees when `in_degrees`, as OpenSim
/// converts only rotational coordinates).
pub fn coordinate_tables(multibody: &Multibody, states: &AnalyzeToolMotion, setup: &KinematicsSetup) -> Result<[StorageTable; 2], KinematicsError> {
    let coordinates: Vec<usize> = if setup.coordinates.iter().any(|c| c == "all") {
        (0..multibody.coordinates.len()).collect()
    } else {
        let index = |name: &String| multibody.coordinates.iter().position(|c| &c.name == name).ok_or_else(|| KinematicsError::Unknown { class: "Kinematics", what: "coordinate", name: name.clone() });
        setup.coordinates.iter().map(index).collect::<Result<_, _>>()?
    };
    let scale = |c: usize| if setup.in_degrees && multibody.coordinates[c].motion_type == MotionType::Rotational { 1f64.to_degrees() } else { 1.0 };
    let labels: Vec<String> = std::iter::once("time".to_string()).chain(coordinates.iter().map(|&c| multibody.coordinates[c].name.clone())).collect();
    let table = |name: &str, rows: Vec<&[f64]>| {
        let values = states.motion.times.iter().zip(rows).flat_map(|(&t, row)| std::iter::once(t).chain(coordinates.iter().map(|&c| row[c] * scale(c))).collect::<Vec<_>>()).collect();
        storage(name, labels.clone(), values).map(|t| t.with_in_degrees(setup.in_degrees))
    };
    let poses = (0..states.motion.len()).map(|k| states.motion.pose(k)).collect();
    Ok([table("Coordinates", poses)?, table("Speeds", states.speeds.iter().map(Vec::as_slice).collect())?])
}

/// `BodyKinematics`' positions and velocities tables for `bodies` (the model's bodies in its
/// BodySet order, as `Multibody::bodies` indices).
pub fn body_tables(multibody: &Multibody, bodies: &[usize], states: &AnalyzeToolMotion, setup: &BodyKinematicsSetup) -> Result<[StorageTable; 2], KinematicsError> {
    let (recorded, whole) = recorded_bodies(multibody, bodies, setup)?;
    let angle = if setup.in_degrees { 1f64.to_degrees() } else { 1.0 };
    let total_mass: f64 = bodies.iter().map(|&b| multibody.bodies[b].mass).sum();
    let width = 6 * recorded.len() + if whole { 3 } else { 0 };
    let (mut positions, mut velocities) = (Vec::with_capacity(states.motion.len() * (width + 1)), Vec::with_capacity(states.motion.len() * (width + 1)));
    let zeros = vec![0.0; multibody.coordinates.len()];
    for (k, &time) in states.motion.times.iter().enumerate() {
        let motions = multibody.body_motions(&MotionState { q: states.motion.pose(k), u: &states.speeds[k], udot: &zeros });
        let center = |b: usize| motions[b].transform.apply(&multibody.bodies[b].mass_center);
        let center_velocity = |b: usize| motions[b].point_velocity(&multibody.bodies[b].mass_center);
        positions.push(time);
        velocities.push(time);
        for &b in &recorded {
            let rotation = motions[b].transform.rotation;
            positions.extend(center(b).iter());
            positions.extend(body_fixed_xyz_angles(&rotation).map(|a| a * angle));
            let (velocity, spin) = (center_velocity(b), motions[b].angular_velocity());
            let [velocity, spin] = if setup.express_in_local_frame { [rotation.transpose() * velocity, rotation.transpose() * spin] } else { [velocity, spin] };
            velocities.extend(velocity.iter());
            velocities.extend(spin.iter().map(|w| w * angle));
        }
        if whole {
            let weighted = |f: &dyn Fn(usize) -> Vec3| bodies.iter().map(|&b| multibody.bodies[b].mass * f(b)).sum::<Vec3>() / total_mass;
            positions.extend(weighted(&center).iter());
            velocities.extend(weighted(&center_velocity).iter());
        }
    }
    let mut labels = vec!["time".to_string()];
    for &b in &recorded {
        labels.extend(["X", "Y", "Z", "Ox", "Oy", "Oz"].map(|axis| format!("{}_{axis}", multibody.bodies[b].name)));
    }
    if whole {
        labels.extend(["X", "Y", "Z"].map(|axis| format!("{CENTER_OF_MASS}_{axis}")));
    }
    let table = |name: &str, values| storage(name, labels.clone(), values).map(|t| t.with_in_degrees(setup.in_degrees));
    Ok([table("Positions", positions)?, table("Velocities", velocities)?])
}

/// The bodies `setup` records and whether the whole model's mass center is recorded: `all` is
/// every body and the mass center (and ends the list), `center_of_mass` the mass center.
fn recorded_bodies(multibody: &Multibody, bodies: &[usize], setup: &BodyKinematicsSetup) -> Result<(Vec<usize>, bool), KinematicsError> {
    let (mut recorded, mut whole) = (Vec::new(), false);
    for name in &setup.bodies {
        match name.as_str() {
            "all" => return Ok((bodies.to_vec(), true)),
            CENTER_OF_MASS => whole = true,
            _ => recorded.push(bodies.iter().copied().find(|&b| &multibody.bodies[b].name == name).ok_or_else(|| KinematicsError::Unknown { class: "BodyKinematics", what: "body", name: name.clone() })?),
        }
    }
    Ok((recorded, whole))
}

/// `PointKinematics`' position and velocity tables: the point fixed in its body, located in ground
/// — or in the `relative_to` body's frame, where its velocity in ground is re-expressed (not made
/// relative), as OpenSim records them — with OpenSim's labels `state_0` … `state_2`.
pub fn point_tables(multibody: &Multibody, states: &AnalyzeToolMotion, setup: &PointKinematicsSetup) -> Result<[StorageTable; 2], KinematicsError> {
    let body_index = |name: &str| multibody.bodies.iter().position(|b| b.name == name).ok_or_else(|| KinematicsError::Unknown { class: "PointKinematics", what: "body", name: name.to_string() });
    let body = body_index(&setup.body)?;
    let relative_to = setup.relative_to.as_deref().map(body_index).transpose()?;
    let point = Vec3::from(setup.point);
    let zeros = vec![0.0; multibody.coordinates.len()];
    let (mut positions, mut velocities) = (Vec::new(), Vec::new());
    for (k, &time) in states.motion.times.iter().enumerate() {
        let motions = multibody.body_motions(&MotionState { q: states.motion.pose(k), u: &states.speeds[k], udot: &zeros });
        let mut position = motions[body].transform.apply(&point);
        let mut velocity = motions[body].point_velocity(&point);
        if let Some(frame) = relative_to.map(|r| motions[r].transform) {
            position = frame.rotation.transpose() * (position - frame.translation);
            velocity = frame.rotation.transpose() * velocity;
        }
        positions.push(time);
        positions.extend(position.iter());
        velocities.push(time);
        velocities.extend(velocity.iter());
    }
    let labels: Vec<String> = ["time", "state_0", "state_1", "state_2"].map(String::from).to_vec();
    Ok([storage("PointPosition", labels.clone(), positions)?, storage("PointVelocity", labels, velocities)?])
}
