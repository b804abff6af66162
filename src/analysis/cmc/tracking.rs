//! OpenSim's CMC tracking (`CMC::computeControls`), every window T:
//! 1. each active `CMC_Joint` task's desired acceleration
//!    q̈ᵢ* = ka·q̈ᵢ,d(t + T) + kv·(q̇ᵢ,d − q̇ᵢ)(t) + kp·(qᵢ,d − qᵢ)(t);
//! 2. the force range of each generator at t + T — its control at the bounds, the muscles' states
//!    predicted over the window ([`Predictor`]); a range under 1 N lets the root solve take the
//!    lower control only;
//! 3. the forces f at CMC's prediction of the window's end (the desired kinematics at t + T
//!    carrying the current errors, the external loads at t + T), by the target
//!    ([`super::target`]);
//! 4. the controls that give those forces at t + T (OpenSim's `RootSolver`, abscissa tolerance
//!    4e-3), a node at t + T of each control (muscles' in steps, actuators' on lines);
//! 5. the model integrated over the window (Runge–Kutta–Merson), the next window starting there,
//!    up to the final time less T.
//!
//! Without muscles' states the first node, at the initial time + 1e-8 s, comes from a solve at
//! the desired state; with them `CMC::computeInitialStates` runs first and the tracking starts
//! 0.03 s later (see [`super::initial_states`]).

use super::desired::DesiredKinematics;
use super::initial_states::{initial_states, InitialStates};
use super::merson::{self, PlantRates};
use super::predictor::{assembled, window_controls, Predictor, Prescribed};
use super::state_tasks::{state_terms, StateTracking};
use super::target::{optimal_forces, Target};
use super::CmcError;
use crate::analysis::controllers::Controllers;
use crate::analysis::simulation::{Plant, SimulatedState};
use crate::io::table::StorageTable;
use crate::setup::{ControlBounds, ControlLinear, ControlSet, IntegratorSettings, JointTask};
use crate::solvers::uncoupled_roots;

/// The window of the first solve without muscles' states, at the initial state (s).
const FIRST_WINDOW: f64 = 1e-8;
/// The root solve's tolerance on each control.
const CONTROL_TOLERANCE: f64 = 4e-3;
/// A force range (N or N·m) under which the root solve takes the lower control.
const SMALL_RANGE: f64 = 1.0;

/// A task on its coordinate ([`crate::mechanics::Multibody::coordinates`] index).
pub struct Task<'a> {
    pub task: &'a JointTask,
    pub coordinate: usize,
}

/// CMC's controller: the plant it drives, the kinematics and tasks it tracks, each generator's
/// control (a `ControlLinear` whose bounds apply and which steps or ramps between nodes) and its
/// target.
pub struct Controller<'p, 'a> {
    pub plant: &'p Plant<'a>,
    pub desired: &'p DesiredKinematics,
    pub tasks: &'p [Task<'p>],
    /// The `MuscleStateTrackingTask`s, whose terms join the target.
    pub state_tasks: &'p [StateTracking],
    pub limits: &'p [ControlLinear],
    /// Per generator, whether CMC leaves it uncontrolled (`actuators_to_exclude`): CMC's part of
    /// its control stays 0 (the other controllers', if any, drive it) and its force enters the
    /// target as given.
    pub excluded: &'p [bool],
    pub target: Target,
    /// The window T (s): 0.001 in RRA, `cmc_time_window` in CMC.
    pub window: f64,
}

/// The tracked simulation: the states at the start and after every window, the controls' nodes
/// and the tasks' position errors at each window's start.
pub struct Tracking {
    pub times: Vec<f64>,
    pub states: Vec<SimulatedState>,
    /// One `ControlLinear` per generator (`<name>.excitation`), nodes at the windows' ends,
    /// held at the first node's value before it; muscles' in steps; an excluded generator's 0.
    pub controls: ControlSet,
    /// Per generator, whether CMC left it uncontrolled.
    pub excluded: Vec<bool>,
    /// `_pErr.sto`: qᵢ,d − qᵢ per task (rad or m).
    pub position_errors: StorageTable,
    /// How CMC found the muscles' initial states (a model with muscles' states).
    pub initial: Option<InitialStates>,
}

/// One window's solution: the controls at its end and the tasks' position errors at its start,
/// with what CMC's verbose log reports of it.
#[derive(Debug, Clone)]
pub struct WindowSolution {
    pub controls: Vec<f64>,
    pub position_errors: Vec<f64>,
    /// Each controlled generator's force at the window's end under its lower and its upper
    /// control bound (N or N·m; "Min forces", "Max forces").
    pub force_range: [Vec<f64>; 2],
    /// The target's value at the forces it chose ("performance").
    pub performance: f64,
}

impl Controller<'_, '_> {
    /// Tracks the desired kinematics from `start` (the desired state at `range[0]` with the
    /// muscles' states it gives) to `range[1]` − T.
    pub fn track(&self, start: SimulatedState, range: [f64; 2], integrator: &IntegratorSettings) -> Result<Tracking, CmcError> {
        let plant = self.plant;
        let mut nodes: Vec<Vec<(f64, f64)>> = vec![Vec::new(); plant.generators.len()];
        let push = |nodes: &mut Vec<Vec<(f64, f64)>>, time: f64, controls: &[f64]| nodes.iter_mut().zip(controls).for_each(|(list, &x)| list.push((time, x)));
        let mut errors = Vec::new();
        let mut initial = None;
        let (mut time, mut state) = if plant.muscle_states(&start).is_empty() {
            let first = self.solve(&start, range[0], FIRST_WINDOW, &nodes)?;
            push(&mut nodes, range[0] + FIRST_WINDOW, &first.controls);
            (range[0], start)
        } else {
            let found = initial.insert(initial_states(self, start, range[0])?);
            errors.push(range[0]);
            errors.extend(found.last.position_errors.iter().copied());
            push(&mut nodes, found.time, &found.last.controls);
            (found.time, found.state.clone())
        };
        let end = range[1] - self.window;
        let held = state.q.clone();
        let (mut times, mut states) = (vec![time], vec![state.clone()]);
        while time < end {
            let solution = self.solve(&state, time, self.window, &nodes)?;
            errors.push(time);
            errors.extend(solution.position_errors);
            let target = time + self.window;
            let last: Vec<Option<(f64, f64)>> = nodes.iter().map(|list| list.last().copied()).collect();
            push(&mut nodes, target, &solution.controls);
            let stop = target.min(end);
            let controls = Controllers::from_control_set(ControlSet { file: "CMC".into(), controls: window_controls(plant, &self.steps(), &last, target, &solution.controls) }).and(plant.controls);
            state = integrate_window(plant, &controls, &held, &state, [time, stop], integrator)?;
            time = target;
            times.push(stop);
            states.push(state.clone());
        }
        // Held, not extrapolated, before the first node: what OpenSim records at the initial time,
        // before the first window's node exists.
        let controls = plant
            .generators
            .iter()
            .zip(self.limits.iter().zip(nodes))
            .map(|(g, (limit, nodes))| ControlLinear { name: format!("{}.excitation", g.name), use_steps: limit.use_steps, extrapolate: false, nodes, bounds: ControlBounds::default() })
            .collect();
        let labels = std::iter::once("time".to_string()).chain(self.tasks.iter().map(|t| t.task.name.clone())).collect();
        let position_errors = StorageTable::new("PositionErrors", labels, errors).map_err(|e| CmcError::Tracking { time, reason: e.to_string() })?.with_in_degrees(false);
        Ok(Tracking { times, states, controls: ControlSet { file: "CMC".into(), controls }, excluded: self.excluded.to_vec(), position_errors, initial })
    }

    /// CMC's controls at `state` and `time` (s) for a window of `window` (s), each control's
    /// last node in `nodes`.
    pub fn solve(&self, state: &SimulatedState, time: f64, window: f64, nodes: &[Vec<(f64, f64)>]) -> Result<WindowSolution, CmcError> {
        let last_nodes = nodes.iter().map(|list| list.last().copied()).collect();
        let prescribed = Prescribed { desired: self.desired, corrections: Prescribed::corrections(self.desired, state, time), held_at: None };
        let steps = self.steps();
        let predictor = Predictor { plant: self.plant, steps: &steps, prescribed, window: [time, time + window], start: self.plant.muscle_states(state), last_nodes };
        self.solve_with(&predictor, state, time)
    }

    /// The controlled generators' entries of `values` (one per generator).
    fn controlled(&self, values: &[f64]) -> Vec<f64> {
        values.iter().zip(self.excluded).filter(|(_, &excluded)| !excluded).map(|(v, _)| *v).collect()
    }

    /// `control` for every controlled generator, 0 for the excluded ones.
    pub fn uniform_controls(&self, control: f64) -> Vec<f64> {
        self.excluded.iter().map(|&excluded| if excluded { 0.0 } else { control }).collect()
    }

    /// Whether each generator's control steps between nodes (else it ramps).
    pub fn steps(&self) -> Vec<bool> {
        self.limits.iter().map(|l| l.use_steps).collect()
    }

    /// [`Controller::solve`] with the window's `predictor`.
    pub fn solve_with(&self, predictor: &Predictor, state: &SimulatedState, time: f64) -> Result<WindowSolution, CmcError> {
        let failed = |reason: String| CmcError::Tracking { time, reason };
        let end = predictor.window[1];
        let (position_errors, desired_accelerations, stress_weight) = self.task_targets(state, time, end);
        let (lower_controls, mut upper_controls): (Vec<f64>, Vec<f64>) = self.limits.iter().zip(self.excluded).map(|(l, &excluded)| if excluded { (0.0, 0.0) } else { l.bounds_at(time) }).unzip();
        let (at_lower, _) = predictor.forces(&lower_controls).map_err(failed)?;
        let (at_upper, predicted) = predictor.forces(&upper_controls).map_err(failed)?;
        for (i, upper) in upper_controls.iter_mut().enumerate() {
            if at_upper[i] - at_lower[i] < SMALL_RANGE {
                *upper = lower_controls[i];
            }
        }
        let (lower, upper): (Vec<f64>, Vec<f64>) = at_lower.iter().zip(&at_upper).map(|(&a, &b)| (a.min(b), a.max(b))).unzip();
        let state_terms = state_terms(self.state_tasks, self.plant.generators.len(), &predicted, end);
        let (forces, performance) = optimal_forces(self, &predicted, end, (&desired_accelerations, &state_terms), stress_weight, [&lower, &upper]).map_err(failed)?;
        let residual = |x: &[f64]| predictor.forces(x).map(|(f, _)| f.iter().zip(&forces).map(|(a, b)| a - b).collect());
        let controls = uncoupled_roots(residual, &lower_controls, &upper_controls, &vec![CONTROL_TOLERANCE; forces.len()]).map_err(failed)?;
        Ok(WindowSolution { controls, position_errors, force_range: [self.controlled(&at_lower), self.controlled(&at_upper)], performance })
    }

    /// The tasks' position errors at `time`, their desired accelerations with the feed-forward at
    /// `end` (s), and the stress term's weight (1, or a sigmoid of a task's error against its
    /// `limit`).
    fn task_targets(&self, state: &SimulatedState, time: f64, end: f64) -> (Vec<f64>, Vec<f64>, f64) {
        let mut position_errors = Vec::with_capacity(self.tasks.len());
        let mut desired_accelerations = Vec::with_capacity(self.tasks.len());
        let mut stress_weight: f64 = 1.0;
        for task in self.tasks {
            let c = task.coordinate;
            let (q, u) = self.desired.value_and_speed(c, time);
            let (position, speed) = (q - state.q[c], u - state.u[c]);
            let JointTask { kp, kv, ka, limit, .. } = *task.task;
            desired_accelerations.push(ka * self.desired.acceleration(c, end) + kv * speed + kp * position);
            if limit != 0.0 {
                stress_weight = stress_weight.min(sigma_down(0.1 * limit, limit, position.abs()));
            }
            position_errors.push(position);
        }
        (position_errors, desired_accelerations, stress_weight)
    }
}

/// The state at the desired kinematics' `time` (s) with muscles' states `z`.
pub fn desired_state(plant: &Plant, desired: &DesiredKinematics, time: f64, z: &[f64]) -> SimulatedState {
    let (q, u) = desired.pose(time);
    let (q, u) = assembled(plant, q, u);
    plant.with_muscle_states(q, u, z, &plant.generator_controls(time))
}

/// `state` at `from` (s) carried to `to` under the window's `controls`, the locked coordinates
/// held at their values in `held`.
fn integrate_window(plant: &Plant, controls: &Controllers, held: &[f64], state: &SimulatedState, [from, to]: [f64; 2], integrator: &IntegratorSettings) -> Result<SimulatedState, CmcError> {
    let failed = |(time, reason): (f64, String)| CmcError::Tracking { time, reason };
    let mut window = Plant::new(plant.spec, plant.geometry, plant.generators, plant.external, controls).map_err(|e| failed((from, e.to_string())))?;
    window.hold(held);
    let mut rates = PlantRates { plant: &window, work: window.workspace() };
    let y = merson::integrate(&mut rates, &window.pack(state), [from, to], [integrator.minimum_step_size, (to - from).min(integrator.maximum_step_size)], integrator.error_tolerance).map_err(failed)?;
    Ok(window.unpack(to, &y))
}

/// `ForwardTool::SigmaDn`: 1 − 1/(1 + e^(−(t − to)/τ)), falling from 1 to 0 about `to`.
fn sigma_down(tau: f64, to: f64, t: f64) -> f64 {
    1.0 - 1.0 / (1.0 + (-(t - to) / tau).exp())
}
