//! OpenSim's ForwardTool: the model's forward dynamics integrated from an initial state under
//! its controllers' controls. The states are the free coordinates' values and speeds (neither
//! locked nor a coupler's dependent; q̇ = u, but a Ball, Free or ellipsoid joint's angles turn at
//! the rates its angular velocity gives them), each muscle's activation (its activation dynamics
//! driven by its excitation, the control) and second state (fiber length moving at the velocity
//! that balances fiber and tendon, or a DeGroote muscle's normalized tendon force); u̇ is the
//! model's forward dynamics ([`crate::mechanics::Multibody::accelerations`]) under every
//! muscle's tendon force along its path, every other actuator's control × optimal force, the
//! external loads and gravity. A Dormand–Prince 5(4) method with error control (crate
//! `ode_solvers`; relative and absolute tolerance per state) integrates them and records the
//! state after every step, as OpenSim's `Manager` does (its steps differ: OpenSim's default
//! integrator is Runge–Kutta–Merson); any time in between is read from its dense output.

mod initial;
mod inputs;
mod plant;
mod system;
mod tables;

pub use initial::{initial_state, InitialSource};
pub use inputs::ForwardModel;
pub use plant::{Plant, SimulatedState};
pub use tables::{controls_table, state_labels, state_values, states_table};

use std::cell::RefCell;

use ode_solvers::continuous_output_model::ContinuousOutputModel;
use ode_solvers::{DVector, Dopri5};

use crate::setup::IntegratorSettings;
use system::PlantDynamics;

/// Why a forward simulation cannot be set up or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum SimulationError {
    #[error("{0}")]
    Model(String),
    #[error("the initial state: {0}")]
    Initial(String),
    #[error("the time range {}–{} s is empty", .0[0], .0[1])]
    TimeRange([f64; 2]),
    #[error("the simulation stopped at {time} s: {reason}")]
    Integration { time: f64, reason: String },
}

/// The recorded simulation: the state at the start and after every integrator step.
pub struct Simulation {
    pub times: Vec<f64>,
    pub states: Vec<SimulatedState>,
    /// Integrator statistics: accepted and rejected steps, right-hand-side evaluations.
    pub accepted_steps: u32,
    pub rejected_steps: u32,
    pub evaluations: u32,
    start: f64,
    output: ContinuousOutputModel<f64, DVector<f64>>,
}

impl Simulation {
    /// The state at `time` (s, inside the simulated range) from the integrator's dense output.
    pub fn at(&self, plant: &Plant, time: f64) -> SimulatedState {
        let (first, last) = self.output.bounds();
        let y = self.output.evaluate((time - self.start).clamp(first, last)).expect("the output model covers its bounds");
        plant.unpack(time, y.as_slice())
    }
}

/// Integrates `plant` from `initial` (at `range[0]`, s) to `range[1]` with `settings` (its
/// error tolerance relative and absolute per state, its largest step and step count; the
/// smallest step is the integrator's own).
pub fn simulate_plant(plant: &Plant, initial: &SimulatedState, range: [f64; 2], settings: &IntegratorSettings) -> Result<Simulation, SimulationError> {
    let [start, end] = range;
    if start.partial_cmp(&end) != Some(std::cmp::Ordering::Less) {
        return Err(SimulationError::TimeRange(range));
    }
    let y0 = plant.pack(initial);
    let failure = RefCell::new(None);
    let dynamics = PlantDynamics::new(plant, start, &failure);
    let span = end - start;
    let tolerance = settings.error_tolerance;
    let steps = u32::try_from(settings.maximum_steps).unwrap_or(u32::MAX);
    let mut solver = Dopri5::from_param(dynamics, 0.0, span, span, DVector::from_vec(y0), tolerance, tolerance, 0.9, 0.04, 0.2, 10.0, settings.maximum_step_size.min(span), 0.0, steps, u32::MAX, ode_solvers::OutputType::Continuous);
    let mut output = ContinuousOutputModel::default();
    let outcome = solver.integrate_with_continuous_output_model(&mut output);
    let (x_out, y_out) = (solver.x_out().clone(), solver.y_out().clone());
    drop(solver);
    let stats = match (outcome, failure.into_inner()) {
        (Ok(stats), _) => stats,
        (Err(_), Some((time, reason))) => return Err(SimulationError::Integration { time, reason }),
        (Err(error), None) => return Err(SimulationError::Integration { time: start + integration_time(&error), reason: error.to_string() }),
    };
    let mut times = vec![start];
    let mut states = vec![initial.clone()];
    for (x, y) in x_out.iter().zip(&y_out) {
        times.push(start + x);
        states.push(plant.unpack(start + x, y.as_slice()));
    }
    Ok(Simulation { times, states, accepted_steps: stats.accepted_steps, rejected_steps: stats.rejected_steps, evaluations: stats.num_eval, start, output })
}

fn integration_time(error: &ode_solvers::dop_shared::IntegrationError) -> f64 {
    use ode_solvers::dop_shared::IntegrationError::*;
    match error {
        MaxNumStepReached { x, .. } | StepSizeUnderflow { x } | StiffnessDetected { x } => *x,
    }
}
