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
//! integrator is Runge–Kutta–Merson); any time in between is read from its dense output. Links
//! between bodies, held at the acceleration level, drift: a step leaving them open by more than
//! the tolerance ends a stretch, the state is projected back onto them as Simbody projects it
//! and the integration goes on from there.

mod initial;
mod inputs;
mod plant;
mod system;
mod tables;

pub use initial::{initial_state, InitialSource};
pub use inputs::ForwardModel;
pub use plant::{Plant, SimulatedState, Workspace};
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
    /// Times the state was projected back onto the links between bodies.
    pub projections: usize,
    start: f64,
    /// The dense output of each stretch between projections, in time order.
    output: Vec<ContinuousOutputModel<f64, DVector<f64>>>,
}

impl Simulation {
    /// The state at `time` (s, inside the simulated range) from the integrator's dense output.
    pub fn at(&self, plant: &Plant, time: f64) -> SimulatedState {
        let x = time - self.start;
        let stretch = self.output.iter().find(|o| x <= o.bounds().1).or(self.output.last()).expect("a simulation has a stretch");
        let (first, last) = stretch.bounds();
        let y = stretch.evaluate(x.clamp(first, last)).expect("the output model covers its bounds");
        plant.unpack(time, y.as_slice())
    }
}

/// Integrates `plant` from `initial` (at `range[0]`, s) to `range[1]` with `settings` (its
/// error tolerance relative and absolute per state, its largest step and step count; the
/// smallest step is the integrator's own). After a step that leaves the links between bodies
/// open by more than the tolerance (m or m/s) the state is projected back onto them
/// ([`crate::mechanics::Multibody::project_onto_links`], as Simbody projects after its steps)
/// and the integration restarts there with the last step size.
pub fn simulate_plant(plant: &Plant, initial: &SimulatedState, range: [f64; 2], settings: &IntegratorSettings) -> Result<Simulation, SimulationError> {
    let [start, end] = range;
    if start.partial_cmp(&end) != Some(std::cmp::Ordering::Less) {
        return Err(SimulationError::TimeRange(range));
    }
    let span = end - start;
    let tolerance = settings.error_tolerance;
    let mut simulation = Simulation { times: vec![start], states: vec![initial.clone()], accepted_steps: 0, rejected_steps: 0, evaluations: 0, projections: 0, start, output: Vec::new() };
    let (mut x, mut y, mut step) = (0.0, plant.pack(initial), 0.0);
    loop {
        let remaining = u32::try_from(settings.maximum_steps).unwrap_or(u32::MAX).saturating_sub(simulation.accepted_steps + simulation.rejected_steps);
        let stretch = integrate_stretch(plant, start, [x, span], y, step, remaining, settings)?;
        simulation.accepted_steps += stretch.stats.accepted_steps;
        simulation.rejected_steps += stretch.stats.rejected_steps;
        simulation.evaluations += stretch.stats.num_eval;
        simulation.output.push(stretch.output);
        let (Some(&last), Some(last_y)) = (stretch.x.last(), stretch.y.last()) else { break };
        step = stretch.x.iter().rev().nth(1).map_or(last - x, |before| last - before);
        for (xi, yi) in stretch.x.iter().zip(&stretch.y) {
            simulation.times.push(start + xi);
            simulation.states.push(plant.unpack(start + xi, yi.as_slice()));
        }
        if last >= span * (1.0 - f64::EPSILON) {
            break;
        }
        y = plant.project(last_y.as_slice(), tolerance).map_err(|e| SimulationError::Integration { time: start + last, reason: e.to_string() })?;
        if let Some(recorded) = simulation.states.last_mut() {
            *recorded = plant.unpack(start + last, &y);
        }
        simulation.projections += 1;
        x = last;
    }
    Ok(simulation)
}

/// One stretch of the integration: its step times and states (integrator time, from 0), its
/// statistics and dense output.
struct Stretch {
    x: Vec<f64>,
    y: Vec<DVector<f64>>,
    stats: ode_solvers::dop_shared::Stats,
    output: ContinuousOutputModel<f64, DVector<f64>>,
}

/// Integrates from `y` at integrator time `from` towards `to` (integrator time runs from 0 at the
/// simulation's `start`, s), starting with step `step` (0: the integrator's own estimate) and
/// taking at most `steps`, until `to` or a step leaving the links open.
fn integrate_stretch(plant: &Plant, start: f64, [from, to]: [f64; 2], y: Vec<f64>, step: f64, steps: u32, settings: &IntegratorSettings) -> Result<Stretch, SimulationError> {
    let failure = RefCell::new(None);
    let tolerance = settings.error_tolerance;
    let dynamics = PlantDynamics::new(plant, start, &failure, tolerance);
    let mut solver = Dopri5::from_param(dynamics, from, to, to - from, DVector::from_vec(y), tolerance, tolerance, 0.9, 0.04, 0.2, 10.0, settings.maximum_step_size.min(to), step, steps, u32::MAX, ode_solvers::OutputType::Continuous);
    let mut output = ContinuousOutputModel::default();
    let outcome = solver.integrate_with_continuous_output_model(&mut output);
    let (x, y) = (solver.x_out().clone(), solver.y_out().clone());
    drop(solver);
    match (outcome, failure.into_inner()) {
        (Ok(stats), _) => Ok(Stretch { x, y, stats, output }),
        (Err(_), Some((time, reason))) => Err(SimulationError::Integration { time, reason }),
        (Err(error), None) => Err(SimulationError::Integration { time: start + integration_time(&error), reason: error.to_string() }),
    }
}

fn integration_time(error: &ode_solvers::dop_shared::IntegrationError) -> f64 {
    use ode_solvers::dop_shared::IntegrationError::*;
    match error {
        MaxNumStepReached { x, .. } | StepSizeUnderflow { x } | StiffnessDetected { x } => *x,
    }
}
