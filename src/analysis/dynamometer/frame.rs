//! One frame of the dynamometer's inverse dynamics (thesis eq. 5.3–5.7).
//!
//! The crank body is the part of the crank between the load cell and the shank's pad. Its
//! joint's reaction, with the load cell's wrench applied to it, is everything the crank needs
//! beyond gravity and the load cell: the pad's load, exerted by the tibia (eq. 5.6). Its
//! opposite loads the tibia, and the knee's reaction then gives M3D, the moment about the
//! knee's axis (eq. 5.4–5.5; the knee coordinate's generalized force, as inverse dynamics
//! defines it). Herzog's 2D estimate (eq. 5.7) scales the dynamometer's moment by the pad's
//! lever arms about the knee and the dynamometer's axis.

use crate::mechanics::{BodyLoad, JointReaction, Kinematics, Mat3, MotionState, Multibody, Vec3};

/// The model's bodies and coordinates the set-up uses ([`Multibody`] indices).
#[derive(Debug, Clone, Copy)]
pub struct DynamometerModel {
    pub crank: usize,
    pub crank_joint: usize,
    pub crank_coordinate: usize,
    pub knee_coordinate: usize,
    pub knee_joint: usize,
    /// The knee joint's child (the pad's load acts on it).
    pub shank: usize,
}

/// A line in ground: a point on it (m) and its unit direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub point: Vec3,
    pub direction: Vec3,
}

/// What one frame's inverse dynamics gives, in ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamometerFrame {
    /// M3D: the knee coordinate's generalized force, N·m.
    pub knee_moment: f64,
    /// The dynamometer's axis (Z, the crank coordinate's positive sense) through D.
    pub dynamometer_axis: Axis,
    /// The knee coordinate's axis (n) through its joint's child frame origin (r_knee).
    pub knee_axis: Axis,
    /// The crank's direction from D to the load cell (the crank body's origin), ⟂ Z.
    pub crank_direction: Vec3,
    /// F_tc: the force the tibia exerts on the crank, N.
    pub pad_force: Vec3,
    /// Its moment about D (incl. the pad's free torque), N·m.
    pub pad_moment: Vec3,
    /// The knee's reaction on the shank (muscles' and ligaments' load included): force, N, and
    /// moment about r_knee, N·m.
    pub knee_force: Vec3,
    pub knee_torque: Vec3,
    /// The shank and foot's inertial moment less their weight's, about r_knee, projected on
    /// the dynamometer's axis in the knee coordinate's sense (Herzog's limb terms), N·m.
    pub limb_moment: f64,
    /// I_ZZ·θ̈: the crank's inertial moment about the dynamometer's axis, N·m.
    pub crank_inertial_moment: f64,
    /// The shank's orientation in ground (its X anterior, Y proximal: the directions the
    /// sensitivity analysis moves the knee's axis in).
    pub shank_rotation: Mat3,
}

/// Herzog's 2D estimate at one frame (eq. 5.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HerzogEstimate {
    /// M2D, N·m (knee coordinate's sense).
    pub knee_moment: f64,
    /// d_d: from the dynamometer's axis to where F_tc's line of action crosses the crank, m.
    pub pad_distance: f64,
    /// d_k: from that point to r_knee, ⟂ Z, m.
    pub knee_distance: f64,
}

impl DynamometerModel {
    /// The frame in `state` (pose realized in `kinematics`) under gravity and `loads` (the load
    /// cell's on the crank, any others on their bodies).
    pub fn frame(&self, multibody: &Multibody, kinematics: &Kinematics, state: &MotionState, loads: &[BodyLoad]) -> DynamometerFrame {
        let free = multibody.joint_reactions(state, loads);
        let (crank, free_knee) = (&free[self.crank_joint], &free[self.knee_joint]);
        let crank_axis = &kinematics.axes[self.crank_coordinate];
        let z = crank_axis.angular.normalize();
        let dynamometer_axis = Axis { point: crank_axis.origin, direction: z };
        let knee_axis_rates = &kinematics.axes[self.knee_coordinate];
        let knee_axis = Axis { point: knee_axis_rates.origin, direction: knee_axis_rates.angular.normalize() };
        // The pad's load on the shank (the crank's reaction reversed) lies in the knee's subtree:
        // the knee must supply the crank's reaction on top of its free reaction.
        let limb_torque = moment_about(free_knee, &knee_axis.point);
        let (knee_force, knee_torque) = (free_knee.force + crank.force, limb_torque + moment_about(crank, &knee_axis.point));
        let knee_moment = knee_axis_rates.angular.dot(&knee_torque) + knee_axis_rates.linear.dot(&knee_force);
        let sense = knee_axis.direction.dot(&z).signum();
        let limb_moment = sense * z.dot(&limb_torque);
        let crank_origin = kinematics.bodies[self.crank].translation;
        DynamometerFrame {
            knee_moment,
            dynamometer_axis,
            knee_axis,
            crank_direction: perpendicular(&(crank_origin - dynamometer_axis.point), &z).normalize(),
            pad_force: crank.force,
            pad_moment: moment_about(crank, &dynamometer_axis.point),
            knee_force,
            knee_torque,
            limb_moment,
            crank_inertial_moment: self.crank_axial_inertia(multibody, kinematics, &dynamometer_axis) * state.udot[self.crank_coordinate],
            shank_rotation: kinematics.bodies[self.shank].rotation,
        }
    }

    /// The crank's moment of inertia about the dynamometer's axis, kg·m².
    fn crank_axial_inertia(&self, multibody: &Multibody, kinematics: &Kinematics, axis: &Axis) -> f64 {
        let body = &multibody.bodies[self.crank];
        let pose = &kinematics.bodies[self.crank];
        let about_center = axis.direction.dot(&(pose.rotation * body.inertia * pose.rotation.transpose() * axis.direction));
        about_center + body.mass * perpendicular(&(pose.apply(&body.mass_center) - axis.point), &axis.direction).norm_squared()
    }
}

impl DynamometerFrame {
    /// Herzog's 2D estimate from the dynamometer's moment `dynamometer_moment` (N·m,
    /// gravity-corrected as dynamometers report it, in the knee coordinate's sense: about ±Z,
    /// whichever is nearer n): the pad's moment about the dynamometer's axis (the reading plus
    /// the crank's inertial moment) times d_k/d_d, plus the limb's terms. F_tc is taken to act
    /// where its line of action crosses the crank, with no free moment about Z there (the
    /// thesis' assumption). NaN when F_tc runs along the crank.
    pub fn herzog(&self, dynamometer_moment: f64) -> HerzogEstimate {
        let Axis { point: d, direction: z } = self.dynamometer_axis;
        let along = z.dot(&self.pad_moment) / z.dot(&self.crank_direction.cross(&self.pad_force));
        let pad_point = d + along * self.crank_direction;
        let pad_distance = along.abs();
        let knee_distance = perpendicular(&(pad_point - self.knee_axis.point), &z).norm();
        let pad_moment = dynamometer_moment + self.sense() * self.crank_inertial_moment;
        HerzogEstimate { knee_moment: knee_distance / pad_distance * pad_moment + self.limb_moment, pad_distance, knee_distance }
    }

    /// +1 when the knee coordinate turns the shank about +Z rather than −Z, else −1.
    pub fn sense(&self) -> f64 {
        self.knee_axis.direction.dot(&self.dynamometer_axis.direction).signum()
    }

    /// The angle between F_tc and the crank's normal Z × e_c, rad (0: perpendicular to the
    /// crank, as 2D analyses assume).
    pub fn pad_force_angle(&self) -> f64 {
        line_angle(&self.pad_force, &self.dynamometer_axis.direction.cross(&self.crank_direction))
    }

    /// r_knee's distance from the dynamometer's axis, m.
    pub fn axis_offset(&self) -> f64 {
        perpendicular(&(self.knee_axis.point - self.dynamometer_axis.point), &self.dynamometer_axis.direction).norm()
    }

    /// The angle between the knee's and the dynamometer's axes (either sense), rad.
    pub fn axis_angle(&self) -> f64 {
        line_angle(&self.knee_axis.direction, &self.dynamometer_axis.direction)
    }

    /// M3D for the knee's axis moved to `axis` with the same reaction (eq. 5.5 at a perturbed
    /// n and r_knee), N·m.
    pub fn knee_moment_about(&self, axis: &Axis) -> f64 {
        axis.direction.dot(&(self.knee_torque + (self.knee_axis.point - axis.point).cross(&self.knee_force)))
    }
}

/// A reaction's moment about `point`.
fn moment_about(reaction: &JointReaction, point: &Vec3) -> Vec3 {
    reaction.moment + (reaction.child_origin - point).cross(&reaction.force)
}

/// The angle between the lines along `a` and `b` (either sense), rad in [0, π/2].
fn line_angle(a: &Vec3, b: &Vec3) -> f64 {
    a.cross(b).norm().atan2(a.dot(b).abs())
}

/// The part of `v` perpendicular to the unit vector `axis`.
pub(super) fn perpendicular(v: &Vec3, axis: &Vec3) -> Vec3 {
    v - axis.dot(v) * axis
}
