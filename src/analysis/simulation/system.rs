//! The integrator's view of the plant: ẏ at integrator time x (from 0 at the simulation's
//! start; the output model assumes non-negative times). A derivative that cannot be formed
//! becomes NaN, which makes the integrator reject the step and try a shorter one; the failure
//! is kept and reported only if that never succeeds. After each step the integrator stops where
//! the state has drifted off the model's links between bodies by more than the tolerance, to be
//! projected back and restarted.

use std::cell::RefCell;

use ode_solvers::{DVector, System};

use super::plant::{Plant, Workspace};

pub(super) struct PlantDynamics<'a> {
    plant: &'a Plant<'a>,
    start: f64,
    work: RefCell<Workspace>,
    /// The last failure: (time in s, why).
    failure: &'a RefCell<Option<(f64, String)>>,
    /// Link drift (m, m/s) beyond which a step ends the integration.
    drift_tolerance: f64,
}

impl<'a> PlantDynamics<'a> {
    pub(super) fn new(plant: &'a Plant<'a>, start: f64, failure: &'a RefCell<Option<(f64, String)>>, drift_tolerance: f64) -> PlantDynamics<'a> {
        PlantDynamics { plant, start, work: RefCell::new(plant.workspace()), failure, drift_tolerance }
    }
}

impl System<f64, DVector<f64>> for PlantDynamics<'_> {
    fn system(&self, x: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let time = self.start + x;
        if let Err(reason) = self.plant.derivatives(time, y.as_slice(), dy.as_mut_slice(), &mut self.work.borrow_mut()) {
            *self.failure.borrow_mut() = Some((time, reason));
            dy.fill(f64::NAN);
        }
    }

    fn solout(&mut self, _x: f64, y: &DVector<f64>, _dy: &DVector<f64>) -> bool {
        self.plant.drifted(y.as_slice(), self.drift_tolerance)
    }
}
