//! Joint reaction loads: the force and moment a joint's parent body transmits to its child, as
//! Simbody's `calcMobilizerReactionForces` defines them — everything the child's subtree needs
//! beyond the loads applied to it, Σ over the subtree of (m(a − g), I·α + ω × I·ω) less the
//! applied body loads. Mobility forces (actuators on coordinates, lock and coupler forces) apply
//! no body load, so those of the joint itself end up in its reaction and those inside the
//! subtree cancel.

use super::inverse_dynamics::{BodyLoad, MotionState};
use super::motion_rates::TransformRates;
use super::multibody::Multibody;
use super::spatial::Vec3;

/// One joint's reaction, in ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointReaction {
    /// On the child (N); the parent gets its opposite.
    pub force: Vec3,
    /// On the child about `child_origin` (N·m).
    pub moment: Vec3,
    /// The joint's child frame origin (Simbody's M), m.
    pub child_origin: Vec3,
    /// The joint's parent frame origin (Simbody's F), m.
    pub parent_origin: Vec3,
    /// The point the load on the parent is taken about (m): `parent_origin`, or the child origin
    /// where OpenSim reads it there ([`crate::mechanics::Mobilizer::parent_reaction_at_child_origin`]).
    pub parent_moment_point: Vec3,
}

impl JointReaction {
    /// The load on the parent: the opposite force, and the opposite moment about
    /// `parent_moment_point`.
    pub fn on_parent(&self) -> (Vec3, Vec3) {
        let moment = self.moment + (self.child_origin - self.parent_moment_point).cross(&self.force);
        (-self.force, -moment)
    }
}

impl Multibody {
    /// Every joint's reaction ([`Multibody::joints`] order) in the state of motion `state`
    /// (its u̇ the accelerations the forces give, e.g. [`Multibody::accelerations`]) under
    /// gravity and the body `loads`.
    pub fn joint_reactions(&self, state: &MotionState, loads: &[BodyLoad]) -> Vec<JointReaction> {
        let motions = self.body_motions(state);
        // Per body: force and moment about the ground origin, then summed over its subtree.
        let mut subtree: Vec<(Vec3, Vec3)> = self.body_wrenches(&motions, loads, &self.gravity).iter().map(|w| (w.force, w.moment + w.point.cross(&w.force))).collect();
        for joint in self.joints.iter().rev() {
            let (force, moment) = subtree[joint.child];
            subtree[joint.parent].0 += force;
            subtree[joint.parent].1 += moment;
        }
        self.joints
            .iter()
            .enumerate()
            .map(|(j, joint)| {
                let (force, moment) = subtree[joint.child];
                let (child_origin, parent_origin) = self.joint_origins(&motions, j);
                let parent_moment_point = if joint.mobilizer.parent_reaction_at_child_origin() { child_origin } else { parent_origin };
                JointReaction { force, moment: moment - child_origin.cross(&force), child_origin, parent_origin, parent_moment_point }
            })
            .collect()
    }

    /// The ground locations of joint `j`'s child and parent frame origins, bodies placed by
    /// `motions`.
    fn joint_origins(&self, motions: &[TransformRates], j: usize) -> (Vec3, Vec3) {
        let joint = &self.joints[j];
        let child = motions[joint.child].transform.compose(&joint.child_body.inverse());
        let parent = motions[joint.parent].transform.compose(&joint.parent_frame);
        (child.translation, parent.translation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;
    use approx::assert_relative_eq;
    use std::path::Path;

    /// First principles on gait2392 at rest in its default pose: the ground–pelvis joint
    /// carries the whole body's weight, vertically, and its moment about the pelvis origin is
    /// the weight's, acting at the whole-body mass center; the moment of a pin joint about its
    /// own axis is the generalized force inverse dynamics gives it.
    #[test]
    fn static_reactions_carry_the_weight() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/gait2392_thelen2003muscle.osim");
        let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap();
        let q = multibody.default_pose();
        let zero = vec![0.0; q.len()];
        let state = MotionState { q: &q, u: &zero, udot: &zero };
        let reactions = multibody.joint_reactions(&state, &[]);
        let mut kinematics = multibody.kinematics();
        multibody.realize(&q, &mut kinematics);
        let mass: f64 = multibody.bodies.iter().map(|b| b.mass).sum();
        let center = multibody.bodies.iter().zip(&kinematics.bodies).map(|(b, x)| b.mass * x.apply(&b.mass_center)).sum::<Vec3>() / mass;
        let weight = mass * multibody.gravity;
        let root = &reactions[0];
        assert_relative_eq!(root.force, -weight, epsilon = 1e-9);
        assert_relative_eq!(root.moment, -(center - root.child_origin).cross(&weight), epsilon = 1e-9);
        let forces = multibody.inverse_dynamics(&state, &[]);
        let knee = multibody.coordinate_index("knee_angle_r").unwrap();
        let joint = multibody.coordinate_joint(knee);
        let axis = kinematics.axes[knee];
        let reaction = &reactions[joint];
        let about_axis = reaction.moment + (reaction.child_origin - axis.origin).cross(&reaction.force);
        assert_relative_eq!(axis.angular.dot(&about_axis) + axis.linear.dot(&reaction.force), forces[knee], epsilon = 1e-9);
    }

    #[test]
    fn the_parent_gets_the_opposite_load() {
        let reaction = JointReaction { force: Vec3::new(1.0, 2.0, 3.0), moment: Vec3::new(0.1, 0.0, 0.0), child_origin: Vec3::new(0.0, 1.0, 0.0), parent_origin: Vec3::zeros(), parent_moment_point: Vec3::zeros() };
        let (force, moment) = reaction.on_parent();
        assert_relative_eq!(force, -reaction.force);
        // The parent's moment about its origin: −(m + r × f) with r from F to M.
        assert_relative_eq!(moment, -(reaction.moment + Vec3::new(0.0, 1.0, 0.0).cross(&reaction.force)));
    }
}
