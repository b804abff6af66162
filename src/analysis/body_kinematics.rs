//! OpenSim's `Kinematics`, `BodyKinematics` and `PointKinematics` analyses on the AnalyzeTool's
//! states: coordinate values and speeds (`_q`, `_u`); each body's mass center and orientation
//! (body-fixed X-Y-Z angles) with their velocities (`_pos_global`, `_vel_global` or
//! `_vel_bodyLocal`), the whole model's mass center last; a point's position and velocity in
//! ground or another body's frame (`_<point>_pos`, `_vel`); and, given the accelerations the
//! AnalyzeTool realizes ([`super::analyze_dynamics`]), theirs (`_dudt`, `_acc_global` or
//! `_acc_bodyLocal`, `_acc`).

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

/// `Kinematics`' `q`, `u` and, with `accelerations` (u̇ per row), `dudt` tables (rotational values
/// in degrees when `in_degrees`, as OpenSim converts only rotational coordinates).
pub fn coordinate_tables(multibody: &Multibody, states: &AnalyzeToolMotion, setup: &KinematicsSetup, accelerations: Option<&[Vec<f64>]>) -> Result<Vec<StorageTable>, KinematicsError> {
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
    let mut tables = vec![table("Coordinates", poses)?, table("Speeds", states.speeds.iter().map(Vec::as_slice).collect())?];
    if let Some(accelerations) = accelerations {
        tables.push(table("Accelerations", accelerations.iter().map(Vec::as_slice).collect())?);
    }
    Ok(tables)
}

/// `BodyKinematics`' positions, velocities and, with `accelerations` (u̇ per row), accelerations
/// tables for `bodies` (the model's bodies in its BodySet order, as `Multibody::bodies` indices).
pub fn body_tables(multibody: &Multibody, bodies: &[usize], states: &AnalyzeToolMotion, setup: &BodyKinematicsSetup, accelerations: Option<&[Vec<f64>]>) -> Result<Vec<StorageTable>, KinematicsError> {
    let (recorded, whole) = recorded_bodies(multibody, bodies, setup)?;
    let angle = if setup.in_degrees { 1f64.to_degrees() } else { 1.0 };
    let total_mass: f64 = bodies.iter().map(|&b| multibody.bodies[b].mass).sum();
    let mut rows = [Vec::new(), Vec::new(), Vec::new()];
    let zeros = vec![0.0; multibody.coordinates.len()];
    for (k, &time) in states.motion.times.iter().enumerate() {
        let udot = accelerations.map_or(zeros.as_slice(), |a| &a[k]);
        let motions = multibody.body_motions(&MotionState { q: states.motion.pose(k), u: &states.speeds[k], udot });
        let center = |b: usize| motions[b].transform.apply(&multibody.bodies[b].mass_center);
        let center_velocity = |b: usize| motions[b].point_velocity(&multibody.bodies[b].mass_center);
        let center_acceleration = |b: usize| motions[b].point_acceleration(&multibody.bodies[b].mass_center);
        let [positions, velocities, accelerations] = &mut rows;
        for row in [&mut *positions, &mut *velocities, &mut *accelerations] {
            row.push(time);
        }
        for &b in &recorded {
            let rotation = motions[b].transform.rotation;
            positions.extend(center(b).iter());
            positions.extend(body_fixed_xyz_angles(&rotation).map(|a| a * angle));
            let local = |v: Vec3| if setup.express_in_local_frame { rotation.transpose() * v } else { v };
            velocities.extend(local(center_velocity(b)).iter());
            velocities.extend(local(motions[b].angular_velocity()).iter().map(|w| w * angle));
            accelerations.extend(local(center_acceleration(b)).iter());
            accelerations.extend(local(motions[b].angular_acceleration()).iter().map(|w| w * angle));
        }
        if whole {
            let weighted = |f: &dyn Fn(usize) -> Vec3| bodies.iter().map(|&b| multibody.bodies[b].mass * f(b)).sum::<Vec3>() / total_mass;
            positions.extend(weighted(&center).iter());
            velocities.extend(weighted(&center_velocity).iter());
            accelerations.extend(weighted(&center_acceleration).iter());
        }
    }
    let mut labels = vec!["time".to_string()];
    for &b in &recorded {
        labels.extend(["X", "Y", "Z", "Ox", "Oy", "Oz"].map(|axis| format!("{}_{axis}", multibody.bodies[b].name)));
    }
    if whole {
        labels.extend(["X", "Y", "Z"].map(|axis| format!("{CENTER_OF_MASS}_{axis}")));
    }
    let names = ["Positions", "Velocities", "Accelerations"];
    let formed = if accelerations.is_some() { 3 } else { 2 };
    rows.into_iter().zip(names).take(formed).map(|(values, name)| Ok(storage(name, labels.clone(), values)?.with_in_degrees(setup.in_degrees))).collect()
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

/// `PointKinematics`' position, velocity and, with `accelerations` (u̇ per row), acceleration
/// tables: the point fixed in its body, located in ground — or in the `relative_to` body's frame,
/// where its velocity and acceleration in ground are re-expressed (not made relative), as OpenSim
/// records them — with OpenSim's labels `state_0` … `state_2`.
pub fn point_tables(multibody: &Multibody, states: &AnalyzeToolMotion, setup: &PointKinematicsSetup, accelerations: Option<&[Vec<f64>]>) -> Result<Vec<StorageTable>, KinematicsError> {
    let body_index = |name: &str| multibody.bodies.iter().position(|b| b.name == name).ok_or_else(|| KinematicsError::Unknown { class: "PointKinematics", what: "body", name: name.to_string() });
    let body = body_index(&setup.body)?;
    let relative_to = setup.relative_to.as_deref().map(body_index).transpose()?;
    let point = Vec3::from(setup.point);
    let zeros = vec![0.0; multibody.coordinates.len()];
    let mut rows = [Vec::new(), Vec::new(), Vec::new()];
    for (k, &time) in states.motion.times.iter().enumerate() {
        let udot = accelerations.map_or(zeros.as_slice(), |a| &a[k]);
        let motions = multibody.body_motions(&MotionState { q: states.motion.pose(k), u: &states.speeds[k], udot });
        let mut values = [motions[body].transform.apply(&point), motions[body].point_velocity(&point), motions[body].point_acceleration(&point)];
        if let Some(frame) = relative_to.map(|r| motions[r].transform) {
            values[0] -= frame.translation;
            values = values.map(|v| frame.rotation.transpose() * v);
        }
        for (row, value) in rows.iter_mut().zip(values) {
            row.push(time);
            row.extend(value.iter());
        }
    }
    let labels: Vec<String> = ["time", "state_0", "state_1", "state_2"].map(String::from).to_vec();
    let formed = if accelerations.is_some() { 3 } else { 2 };
    rows.into_iter().zip(["PointPosition", "PointVelocity", "PointAcceleration"]).take(formed).map(|(values, name)| Ok(storage(name, labels.clone(), values)?)).collect()
}
