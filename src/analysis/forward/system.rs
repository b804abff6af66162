//! The right-hand side of the muscle states: ȧ from the activation dynamics, L̇_m from the
//! fiber–tendon balance at the path length of the prescribed pose (0 for a rigid tendon, whose
//! fiber length is no state), or a DeGroote muscle's df̃_T/dt, which also takes the path's
//! lengthening speed at the prescribed speeds. Time runs from 0 at the simulation's start (the
//! integrator's output model assumes non-negative times).

use std::cell::RefCell;

use ode_solvers::{DVector, System};

use super::{DrivenMuscle, PrescribedMotion};
use crate::analysis::Activations;
use crate::mechanics::muscle::MuscleError;
use crate::mechanics::{Kinematics, MuscleGeometry, PathScratch};

/// The pose buffers one evaluation needs.
struct Buffers {
    q: Vec<f64>,
    /// Generalized speeds (for the DeGroote muscles' path speeds).
    u: Vec<f64>,
    kinematics: Kinematics,
    scratch: PathScratch,
}

pub(super) struct MuscleDynamics<'a> {
    geometry: &'a MuscleGeometry,
    muscles: &'a [DrivenMuscle],
    motion: &'a PrescribedMotion,
    excitations: &'a Activations,
    /// The simulation's start, s.
    start: f64,
    /// Whether some muscle's state rate takes its path's speed (DeGroote's tendon force).
    needs_speeds: bool,
    buffers: RefCell<Buffers>,
    /// The last muscle failure (integrator time, error). Its derivative is NaN, which makes the
    /// integrator reject the step and try a shorter one; it matters only if that never succeeds.
    failure: &'a RefCell<Option<(f64, MuscleError)>>,
}

impl<'a> MuscleDynamics<'a> {
    pub(super) fn new(
        geometry: &'a MuscleGeometry,
        muscles: &'a [DrivenMuscle],
        motion: &'a PrescribedMotion,
        excitations: &'a Activations,
        start: f64,
        failure: &'a RefCell<Option<(f64, MuscleError)>>,
    ) -> MuscleDynamics<'a> {
        let multibody = &geometry.multibody;
        let n = multibody.coordinates.len();
        let buffers = Buffers { q: vec![0.0; n], u: vec![0.0; n], kinematics: multibody.kinematics(), scratch: PathScratch::default() };
        let needs_speeds = muscles.iter().any(|m| m.tendon_force_state().is_some());
        MuscleDynamics { geometry, muscles, motion, excitations, start, needs_speeds, buffers: RefCell::new(buffers), failure }
    }
}

impl System<f64, DVector<f64>> for MuscleDynamics<'_> {
    fn system(&self, x: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let time = self.start + x;
        let n = self.muscles.len();
        let mut buffers = self.buffers.borrow_mut();
        let Buffers { q, u, kinematics, scratch } = &mut *buffers;
        let multibody = &self.geometry.multibody;
        self.motion.pose(time, q);
        multibody.realize(q, kinematics);
        if self.needs_speeds {
            self.motion.speeds(time, q, u);
        }
        for (k, muscle) in self.muscles.iter().enumerate() {
            let excitation = self.excitations.at(k, time);
            let (activation, fiber_length) = match &muscle.activation {
                Some(dynamics) => {
                    dy[k] = dynamics.rate(y[k], excitation);
                    (y[k], y[n + k])
                }
                None => {
                    dy[k] = 0.0;
                    (excitation, y[n + k])
                }
            };
            if muscle.muscle.has_rigid_tendon() {
                dy[n + k] = 0.0;
                continue;
            }
            let path = &self.geometry.paths[muscle.path];
            if let Some(degroote) = muscle.tendon_force_state() {
                let (length, speed) = path.length_and_speed(multibody, kinematics, q, scratch, &path.loaded, u);
                dy[n + k] = degroote.normalized_tendon_force_rate(activation, y[n + k], length, speed);
                continue;
            }
            let length = path.length(kinematics, q, scratch);
            dy[n + k] = match muscle.muscle.fiber_velocity(activation.clamp(0.0, 1.0), fiber_length, length) {
                Ok(velocity) => velocity,
                Err(error) => {
                    *self.failure.borrow_mut() = Some((x, error));
                    f64::NAN
                }
            };
        }
    }
}
