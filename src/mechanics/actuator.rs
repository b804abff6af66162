//! OpenSim's scalar non-muscle actuators on the compiled tree: the generalized forces of a unit
//! actuation, as each class's `computeForce` applies it (`CoordinateActuator` a mobility force,
//! `PointActuator` a force at a body point, `TorqueActuator` a torque on one body and its
//! reaction on another), projected on the coordinates' partial velocities.

use super::error::MechanicsError;
use super::inverse_dynamics::{AppliedForces, BodyLoad};
use super::kinematics::Kinematics;
use super::motion_rates::TransformRates;
use super::multibody::{Multibody, GROUND_INDEX};
use super::spatial::Vec3;
use crate::model::{ActuatorKind, ActuatorSpec};

/// An actuator compiled against a [`Multibody`].
#[derive(Debug, Clone)]
pub struct Actuator {
    pub name: String,
    action: Action,
}

/// What a unit actuation applies; directions are of unit length.
#[derive(Debug, Clone)]
enum Action {
    /// 1 (N·m or N) on the coordinate (index into [`Multibody::coordinates`]).
    Coordinate(usize),
    /// 1 N along `direction` (in ground or in the body) at `point` (m, in ground or in the body).
    Point { body: usize, point: Vec3, point_in_ground: bool, direction: Vec3, direction_in_ground: bool },
    /// 1 N·m about `axis` (in ground or in body A) on body A, −1 N·m on body B.
    Torque { body_a: usize, body_b: usize, axis: Vec3, axis_in_ground: bool },
}

impl Actuator {
    /// Compiles `spec`; an unknown coordinate or body, a `PointActuator` on ground (OpenSim looks
    /// its body up in the BodySet) or a zero direction or axis is an error naming it.
    pub fn new(spec: &ActuatorSpec, multibody: &Multibody) -> Result<Actuator, MechanicsError> {
        let invalid = |problem: String| MechanicsError::Invalid {
            file: spec.file.clone(),
            component: format!("{} {} (line {})", spec.class, spec.name, spec.line),
            problem,
        };
        let unknown = |what: &str, name: &str| invalid(format!("{what} {name:?} does not exist in the model"));
        let unit = |what: &str, v: &[f64; 3]| {
            let v = Vec3::from(*v);
            let norm = v.norm();
            if norm > 0.0 && norm.is_finite() { Ok(v / norm) } else { Err(invalid(format!("{what} {v:?} has no direction"))) }
        };
        let action = match &spec.kind {
            ActuatorKind::Coordinate { coordinate } => {
                Action::Coordinate(multibody.coordinate_index(coordinate).ok_or_else(|| unknown("coordinate", coordinate))?)
            }
            ActuatorKind::Point { body, point, point_is_global, direction, force_is_global } => Action::Point {
                body: multibody.body_index(body).filter(|&b| b != GROUND_INDEX).ok_or_else(|| invalid(format!("body {body:?} is not in the model's BodySet")))?,
                point: Vec3::from(*point),
                point_in_ground: *point_is_global,
                direction: unit("direction", direction)?,
                direction_in_ground: *force_is_global,
            },
            ActuatorKind::Torque { body_a, body_b, axis, torque_is_global } => Action::Torque {
                body_a: frame_body(multibody, body_a).ok_or_else(|| unknown("frame", body_a))?,
                body_b: frame_body(multibody, body_b).ok_or_else(|| unknown("frame", body_b))?,
                axis: unit("axis", axis)?,
                axis_in_ground: *torque_is_global,
            },
        };
        Ok(Actuator { name: spec.name.clone(), action })
    }

    /// Each coordinate's generalized force (N·m or N, [`Multibody::coordinates`] order; Simbody's
    /// generalized speeds, so a `BallJoint`'s or `FreeJoint`'s rotations get torques) of a unit
    /// actuation (1 N or 1 N·m) in the pose whose kinematics `kinematics` holds
    /// ([`Multibody::realize`]). Positive along the coordinate: it is the force's power per unit
    /// speed.
    ///
    /// # Panics
    /// If `out` does not hold one value per coordinate.
    pub fn generalized_forces(&self, multibody: &Multibody, kinematics: &Kinematics, out: &mut [f64]) {
        assert_eq!(out.len(), multibody.coordinates.len(), "one value per coordinate");
        match self.action {
            Action::Coordinate(coordinate) => {
                out.fill(0.0);
                out[coordinate] = 1.0;
            }
            Action::Point { body, point, point_in_ground, direction, direction_in_ground } => {
                let pose = &kinematics.bodies[body];
                let point = if point_in_ground { point } else { pose.apply(&point) };
                let force = if direction_in_ground { direction } else { pose.rotation * direction };
                for (c, value) in out.iter_mut().enumerate() {
                    *value = kinematics.point_partial(multibody, body, &point, c).dot(&force);
                }
            }
            Action::Torque { body_a, body_b, axis, axis_in_ground } => {
                let torque = if axis_in_ground { axis } else { kinematics.bodies[body_a].rotation * axis };
                for (c, value) in out.iter_mut().enumerate() {
                    let joint = multibody.coordinate_joint(c);
                    let turning = |body: usize| if multibody.is_moved_by(body, joint) { kinematics.axes[c].angular } else { Vec3::zeros() };
                    *value = torque.dot(&(turning(body_a) - turning(body_b)));
                }
            }
        }
    }

    /// OpenSim's `getSpeed` (m/s or rad/s) with the bodies moving as `motions`
    /// ([`Multibody::body_motions`]) at speeds `u`: a `CoordinateActuator` its coordinate's speed;
    /// a `PointActuator` the magnitude of its point's velocity in ground — the point taken in the
    /// body even when `point_is_global` (OpenSim's `calcSpeed`); a `TorqueActuator` the angular
    /// velocity of body A relative to B along the axis as written, in ground or not.
    pub fn speed(&self, motions: &[TransformRates], u: &[f64]) -> f64 {
        match self.action {
            Action::Coordinate(coordinate) => u[coordinate],
            Action::Point { body, point, .. } => motions[body].point_velocity(&point).norm(),
            Action::Torque { body_a, body_b, axis, .. } => (motions[body_a].angular_velocity() - motions[body_b].angular_velocity()).dot(&axis),
        }
    }

    /// What an actuation (N or N·m) applies in the pose `kinematics` holds: a body load
    /// (`PointActuator`, `TorqueActuator` — the torque on body A, its opposite on body B) pushed
    /// to `applied`'s loads, or a mobility force (`CoordinateActuator`) added to its own.
    pub fn apply(&self, kinematics: &Kinematics, actuation: f64, applied: &mut AppliedForces) {
        match self.action {
            Action::Coordinate(coordinate) => applied.mobility[coordinate] += actuation,
            Action::Point { body, point, point_in_ground, direction, direction_in_ground } => {
                let pose = &kinematics.bodies[body];
                let point = if point_in_ground { point } else { pose.apply(&point) };
                let direction = if direction_in_ground { direction } else { pose.rotation * direction };
                applied.loads.push(BodyLoad { body, force: actuation * direction, point, torque: Vec3::zeros() });
            }
            Action::Torque { body_a, body_b, axis, axis_in_ground } => {
                let torque = actuation * if axis_in_ground { axis } else { kinematics.bodies[body_a].rotation * axis };
                for (body, torque) in [(body_a, torque), (body_b, -torque)] {
                    applied.loads.push(BodyLoad { body, force: Vec3::zeros(), point: kinematics.bodies[body].translation, torque });
                }
            }
        }
    }
}

/// The body of a `TorqueActuator`'s frame as OpenSim looks it up: a component path
/// (`/bodyset/pelvis`, `/ground`) or a body's name.
fn frame_body(multibody: &Multibody, frame: &str) -> Option<usize> {
    let path = frame.trim_start_matches("./").trim_start_matches('/');
    multibody.body_index(path.strip_prefix("bodyset/").unwrap_or(path))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::mechanics::MotionState;
    use crate::model::ModelSpec;

    fn gait2392() -> Multibody {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/gait2392_millard2012muscle.osim");
        Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap()
    }

    fn spec(kind: ActuatorKind) -> ActuatorSpec {
        ActuatorSpec {
            name: "a".into(),
            class: "TorqueActuator".into(),
            kind,
            optimal_force: 1.0,
            min_control: f64::NEG_INFINITY,
            max_control: f64::INFINITY,
            applies_force: true,
            file: "actuators.xml".into(),
            line: 7,
        }
    }

    /// A torque between a body and itself does nothing; one on ground's path names the body.
    #[test]
    fn torque_reaction_and_frame_paths() {
        let multibody = gait2392();
        let mut kinematics = multibody.kinematics();
        multibody.realize(&multibody.default_pose(), &mut kinematics);
        let mut out = vec![f64::NAN; multibody.coordinates.len()];
        let torque = |a: &str, b: &str| ActuatorKind::Torque { body_a: a.into(), body_b: b.into(), axis: [0.0, 0.0, 2.0], torque_is_global: false };
        Actuator::new(&spec(torque("/bodyset/tibia_r", "tibia_r")), &multibody).unwrap().generalized_forces(&multibody, &kinematics, &mut out);
        assert!(out.iter().all(|&v| v == 0.0));
        Actuator::new(&spec(torque("femur_r", "/ground")), &multibody).unwrap().generalized_forces(&multibody, &kinematics, &mut out);
        let hip_flexion = multibody.coordinate_index("hip_flexion_r").unwrap();
        assert!((out[hip_flexion] - 1.0).abs() < 1e-15, "{}", out[hip_flexion]);
    }

    /// The loads `apply` gives do, per unit speed, the work `generalized_forces` says: their
    /// generalized forces (inverse dynamics with and without them, at rest) are the actuation
    /// times the unit actuation's.
    #[test]
    fn applied_loads_have_the_unit_generalized_forces() {
        let multibody = gait2392();
        let mut q = multibody.default_pose();
        q.iter_mut().enumerate().for_each(|(c, v)| *v += 0.2 * (c as f64).sin());
        let mut kinematics = multibody.kinematics();
        multibody.realize(&q, &mut kinematics);
        let zero = vec![0.0; q.len()];
        let state = MotionState { q: &q, u: &zero, udot: &zero };
        let at_rest = multibody.inverse_dynamics(&state, &[]);
        let point = ActuatorKind::Point { body: "tibia_r".into(), point: [0.01, -0.2, 0.03], point_is_global: false, direction: [0.3, 1.0, -0.2], force_is_global: false };
        let torque = ActuatorKind::Torque { body_a: "femur_r".into(), body_b: "pelvis".into(), axis: [0.2, 0.1, 1.0], torque_is_global: false };
        let coordinate = ActuatorKind::Coordinate { coordinate: "knee_angle_r".into() };
        for kind in [point, torque, coordinate] {
            let actuator = Actuator::new(&spec(kind), &multibody).unwrap();
            let mut unit = vec![0.0; q.len()];
            actuator.generalized_forces(&multibody, &kinematics, &mut unit);
            let mut applied = AppliedForces::new(q.len());
            actuator.apply(&kinematics, 3.0, &mut applied);
            let loaded = multibody.inverse_dynamics(&state, &applied.loads);
            for c in 0..q.len() {
                let applied = at_rest[c] - loaded[c] + applied.mobility[c];
                assert!((applied - 3.0 * unit[c]).abs() < 1e-12, "{}: {applied} vs {}", multibody.coordinates[c].name, 3.0 * unit[c]);
            }
        }
    }

    #[test]
    fn unknown_names_and_zero_axes_are_errors_naming_the_actuator() {
        let multibody = gait2392();
        let message = |kind| Actuator::new(&spec(kind), &multibody).unwrap_err().to_string();
        let ground = ActuatorKind::Point { body: "ground".into(), point: [0.0; 3], point_is_global: false, direction: [1.0, 0.0, 0.0], force_is_global: true };
        assert_eq!(message(ground), "actuators.xml: TorqueActuator a (line 7): body \"ground\" is not in the model's BodySet");
        let coordinate = message(ActuatorKind::Coordinate { coordinate: "knee".into() });
        assert!(coordinate.ends_with("coordinate \"knee\" does not exist in the model"), "{coordinate}");
        let zero = message(ActuatorKind::Torque { body_a: "pelvis".into(), body_b: "ground".into(), axis: [0.0; 3], torque_is_global: true });
        assert!(zero.contains("axis") && zero.contains("no direction"), "{zero}");
    }
}
