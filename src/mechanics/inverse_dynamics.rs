//! Inverse dynamics: the generalized forces that give the model chosen accelerations, as
//! OpenSim's `InverseDynamicsSolver` computes them (constraints ignored, gravity included).
//!
//! Body velocities and accelerations come from the joints' transforms in motion
//! (`mobilizer_rates`); each body's inertial wrench, less gravity and the applied loads, is
//! projected on each generalized speed's partial velocities (Kane's equations):
//! τ_c = Σ_B ω_c·(M_B + (x_B − o_c) × F_B) + v_c·F_B over the bodies the coordinate's joint moves,
//! with F_B = m(a_cm − g) − F_ext and M_B = I·α + ω × I·ω − M_ext about the mass center.

use super::kinematics::Kinematics;
use super::motion_rates::TransformRates;
use super::multibody::{Body, Multibody, GROUND_INDEX};
use super::spatial::{Transform, Vec3};

/// A force and a torque applied to a body from outside the model (e.g. a force plate's), in
/// ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyLoad {
    /// Index into [`Multibody::bodies`].
    pub body: usize,
    /// N.
    pub force: Vec3,
    /// Where the force acts, m.
    pub point: Vec3,
    /// N·m (a free moment, in addition to the force's).
    pub torque: Vec3,
}

/// What force elements apply in one pose: body loads, and mobility forces per coordinate
/// (N·m or N, [`Multibody::coordinates`] order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AppliedForces {
    pub loads: Vec<BodyLoad>,
    pub mobility: Vec<f64>,
}

impl AppliedForces {
    /// No loads and zero mobility forces on `coordinates` coordinates.
    pub fn new(coordinates: usize) -> AppliedForces {
        AppliedForces { loads: Vec::new(), mobility: vec![0.0; coordinates] }
    }
}

/// The model's state of motion: coordinates (rad or m), Simbody's generalized speeds and their
/// rates, each in [`Multibody::coordinates`] order.
#[derive(Debug, Clone, Copy)]
pub struct MotionState<'a> {
    pub q: &'a [f64],
    pub u: &'a [f64],
    pub udot: &'a [f64],
}

/// A force at a point and a moment, in ground, that a body needs beyond what it gets.
pub(super) struct Wrench {
    pub force: Vec3,
    pub point: Vec3,
    pub moment: Vec3,
}

impl Multibody {
    /// X_GB with its time derivatives for every body (ground first) in `state`.
    ///
    /// # Panics
    /// If a slice of `state` does not hold one value per coordinate.
    pub fn body_motions(&self, state: &MotionState) -> Vec<TransformRates> {
        let n = self.coordinates.len();
        assert!(state.q.len() == n && state.u.len() == n && state.udot.len() == n, "one value per coordinate");
        let mut motions = vec![TransformRates::fixed(Transform::IDENTITY); self.bodies.len()];
        let (mut q, mut u, mut udot) = ([0.0; 6], [0.0; 6], [0.0; 6]);
        for joint in &self.joints {
            let k = joint.coordinates.len();
            for (i, &c) in joint.coordinates.iter().enumerate() {
                (q[i], u[i], udot[i]) = (state.q[c], state.u[c], state.udot[c]);
            }
            let across = joint.mobilizer.transform_rates(&q[..k], &u[..k], &udot[..k]);
            motions[joint.child] = motions[joint.parent].then_fixed(&joint.parent_frame).compose(&across).then_fixed(&joint.child_body);
        }
        motions
    }

    /// The generalized force of each coordinate (N·m or N, [`Multibody::coordinates`] order) that,
    /// with gravity and `loads`, gives the accelerations `state.udot`; constraints, locks and the
    /// model's force elements are not included.
    pub fn inverse_dynamics(&self, state: &MotionState, loads: &[BodyLoad]) -> Vec<f64> {
        let mut kinematics = self.kinematics();
        self.realize(state.q, &mut kinematics);
        self.inverse_dynamics_at(&kinematics, state, loads)
    }

    /// [`Multibody::inverse_dynamics`] with the pose already realized in `kinematics`
    /// ([`Multibody::realize`] at `state.q`).
    pub fn inverse_dynamics_at(&self, kinematics: &Kinematics, state: &MotionState, loads: &[BodyLoad]) -> Vec<f64> {
        let wrenches = self.body_wrenches(&self.body_motions(state), loads, &self.gravity);
        self.generalized_forces_of(kinematics, &wrenches)
    }

    /// Each body's inertial wrench in its motion `motions` ([`Multibody::body_motions`]) under
    /// `gravity` (m/s², in ground), less `loads`: what the body needs from its joint beyond
    /// what it gets (ground's is zero).
    pub(super) fn body_wrenches(&self, motions: &[TransformRates], loads: &[BodyLoad], gravity: &Vec3) -> Vec<Wrench> {
        let mut wrenches: Vec<Wrench> = motions.iter().zip(&self.bodies).map(|(motion, body)| inertial_wrench(motion, body, gravity)).collect();
        for load in loads {
            let wrench = &mut wrenches[load.body];
            wrench.moment -= (load.point - wrench.point).cross(&load.force) + load.torque;
            wrench.force -= load.force;
        }
        wrenches
    }

    /// Each coordinate's generalized force of `wrenches` at the pose `kinematics` holds.
    pub(super) fn generalized_forces_of(&self, kinematics: &Kinematics, wrenches: &[Wrench]) -> Vec<f64> {
        (0..self.coordinates.len()).map(|c| self.generalized_force(kinematics, wrenches, c)).collect()
    }

    /// Σ over the bodies coordinate `c`'s joint moves of the wrench's power per unit speed.
    fn generalized_force(&self, kinematics: &Kinematics, wrenches: &[Wrench], c: usize) -> f64 {
        let joint = self.coordinate_joint(c);
        let axis = &kinematics.axes[c];
        wrenches
            .iter()
            .enumerate()
            .filter(|&(b, _)| b != GROUND_INDEX && self.is_moved_by(b, joint))
            .map(|(_, w)| axis.angular.dot(&(w.moment + (w.point - axis.origin).cross(&w.force))) + axis.linear.dot(&w.force))
            .sum()
    }
}

/// m(a − g) at the mass center and I·α + ω × I·ω about it, in ground.
fn inertial_wrench(motion: &TransformRates, body: &Body, gravity: &Vec3) -> Wrench {
    let rotation = motion.transform.rotation;
    let point = motion.transform.apply(&body.mass_center);
    let inertia = rotation * body.inertia * rotation.transpose();
    let omega = motion.angular_velocity();
    let force = body.mass * (motion.point_acceleration(&body.mass_center) - gravity);
    let moment = inertia * motion.angular_acceleration() + omega.cross(&(inertia * omega));
    Wrench { force, point, moment }
}
