//! OpenSim's CMC tracking as RRA runs it (`CMC::computeControls` with `ActuatorForceTarget`):
//! every window T (0.001 s) the actuators' forces f that minimise
//! Σᵢ wᵢ·(q̈ᵢ(f) − q̈ᵢ*)² + s·Σⱼ (fⱼ/F_opt,ⱼ)² within the controls' bounds — the accelerations
//! those of the desired kinematics at t + T carrying the current errors (CMC's prediction of the
//! window's end, the external loads at t + T) —
//! where q̈ᵢ* = ka·q̈ᵢ,d(t + T) + kv·(q̇ᵢ,d − q̇ᵢ)(t) + kp·(qᵢ,d − qᵢ)(t) for each active `CMC_Joint`
//! task and s is 1 (or a sigmoid of a task's error against its `limit`); the forward dynamics are
//! linear in f, so this is a convex QP (clarabel; OpenSim's IPOPT or, without active bounds, its
//! least-squares solution). The control f/F_opt becomes a node at t + T of each actuator's
//! `ControlLinear` (linear between nodes), the model is integrated over the window
//! (Runge–Kutta–Merson) and the next window starts there, up to the final time less T. The
//! first node, at the initial time + 1e-8 s, comes from a solve at the desired state.

use nalgebra::{DMatrix, DVector};

use super::desired::DesiredKinematics;
use super::merson;
use super::ResidualReductionError;
use crate::analysis::controllers::Controllers;
use crate::analysis::simulation::{Plant, SimulatedState};
use crate::io::table::StorageTable;
use crate::mechanics::{AppliedForces, PathScratch};
use crate::setup::{ControlBounds, ControlLinear, ControlSet, IntegratorSettings, JointTask};
use crate::solvers::qp::{DenseQp, QpSettings};

/// CMC's window, s.
const WINDOW: f64 = 0.001;
/// The window of the first solve, at the initial state (s).
const FIRST_WINDOW: f64 = 1e-8;

/// A task on its coordinate ([`crate::mechanics::Multibody::coordinates`] index).
pub struct Task<'a> {
    pub task: &'a JointTask,
    pub coordinate: usize,
}

/// The tracked simulation: the states at the start and after every window, the controls' nodes
/// and the tasks' position errors at each window's start.
pub struct Tracking {
    pub times: Vec<f64>,
    pub states: Vec<SimulatedState>,
    /// One `ControlLinear` per actuator (`<actuator>.excitation`), nodes at the windows' ends,
    /// held at the first node's value before it.
    pub controls: ControlSet,
    /// `_pErr.sto`: qᵢ,d − qᵢ per task (rad or m).
    pub position_errors: StorageTable,
}

/// Tracks `desired` with `plant`'s actuators (ideal: control × optimal force) from `range[0]` to
/// `range[1]` − T; `limits`: each generator's control bounds (a `ControlLinear` whose bounds
/// apply, e.g. from the setup's constraints file).
pub fn track(plant: &Plant, desired: &DesiredKinematics, tasks: &[Task], limits: &[ControlLinear], range: [f64; 2], integrator: &IntegratorSettings) -> Result<Tracking, ResidualReductionError> {
    let (q, u) = desired.pose(range[0]);
    let mut state = assembled(plant, q, u);
    let names: Vec<String> = plant.generators.iter().map(|g| format!("{}.excitation", g.name)).collect();
    let mut nodes: Vec<Vec<(f64, f64)>> = vec![Vec::new(); names.len()];
    let add_nodes = |nodes: &mut Vec<Vec<(f64, f64)>>, time: f64, controls: &[f64]| {
        for (list, &x) in nodes.iter_mut().zip(controls) {
            list.push((time, x));
        }
    };
    let mut time = range[0];
    add_nodes(&mut nodes, time + FIRST_WINDOW, &window_controls(plant, desired, tasks, limits, &state, time, FIRST_WINDOW)?.0);
    let end = range[1] - WINDOW;
    let (mut times, mut states, mut errors) = (vec![time], vec![state.clone()], Vec::new());
    while time < end {
        let (controls, position_errors) = window_controls(plant, desired, tasks, limits, &state, time, WINDOW)?;
        errors.push(time);
        errors.extend(position_errors);
        let target = time + WINDOW;
        let previous: Vec<(f64, f64)> = nodes.iter().map(|list| *list.last().expect("a first node")).collect();
        add_nodes(&mut nodes, target, &controls);
        let stop = target.min(end);
        state = integrate_window(plant, &window_controllers(&names, &previous, target, &controls), &states[0].q, &state, [time, stop], integrator)?;
        time = target;
        times.push(stop);
        states.push(state.clone());
    }
    // Held, not extrapolated, before the first node: what OpenSim records at the initial time,
    // before the first window's node exists.
    let controls = ControlSet { file: "CMC".into(), controls: names.into_iter().zip(nodes).map(|(name, nodes)| ControlLinear { name, use_steps: false, extrapolate: false, nodes, bounds: ControlBounds::default() }).collect() };
    let labels = std::iter::once("time".to_string()).chain(tasks.iter().map(|t| t.task.name.clone())).collect();
    let position_errors = StorageTable::new("PositionErrors", labels, errors).map_err(|e| ResidualReductionError::Tracking { time, reason: e.to_string() })?.with_in_degrees(false);
    Ok(Tracking { times, states, controls, position_errors })
}

/// `state` at `from` (s) carried to `to` under the window's `controls`, the locked coordinates
/// held at their values in `held`.
fn integrate_window(plant: &Plant, controls: &Controllers, held: &[f64], state: &SimulatedState, [from, to]: [f64; 2], integrator: &IntegratorSettings) -> Result<SimulatedState, ResidualReductionError> {
    let failed = |(time, reason): (f64, String)| ResidualReductionError::Tracking { time, reason };
    let mut window = Plant::new(plant.spec, plant.geometry, plant.generators, plant.external, controls).map_err(|e| failed((from, e.to_string())))?;
    window.hold(held);
    let y = merson::integrate(&window, &window.pack(state), [from, to], WINDOW.min(integrator.maximum_step_size), integrator.error_tolerance, &mut window.workspace()).map_err(failed)?;
    Ok(window.unpack(to, &y))
}

/// The controls of one window: each actuator's control on the line from its last node to its
/// new one at `target`.
fn window_controllers(names: &[String], previous: &[(f64, f64)], target: f64, controls: &[f64]) -> Controllers {
    let controls = names
        .iter()
        .zip(previous.iter().zip(controls))
        .map(|(name, (&from, &x))| ControlLinear { name: name.clone(), use_steps: false, extrapolate: true, nodes: vec![from, (target, x)], bounds: ControlBounds::default() })
        .collect();
    Controllers::from_control_set(ControlSet { file: "CMC".into(), controls })
}

/// The controls (f/F_opt per generator) CMC chooses at `state` and `time` (s) for the window
/// `window` (s), and the tasks' position errors there.
fn window_controls(plant: &Plant, desired: &DesiredKinematics, tasks: &[Task], limits: &[ControlLinear], state: &SimulatedState, time: f64, window: f64) -> Result<(Vec<f64>, Vec<f64>), ResidualReductionError> {
    let failed = |reason: String| ResidualReductionError::Tracking { time, reason };
    let (base, sensitivity) = acceleration_map(plant, &predicted_state(plant, desired, state, time, window), time + window, tasks).map_err(failed)?;
    let mut position_errors = Vec::with_capacity(tasks.len());
    let mut desired_accelerations = Vec::with_capacity(tasks.len());
    let mut stress_weight: f64 = 1.0;
    for task in tasks {
        let c = task.coordinate;
        let (q, u) = desired.value_and_speed(c, time);
        let (position, speed) = (q - state.q[c], u - state.u[c]);
        let JointTask { kp, kv, ka, limit, .. } = *task.task;
        desired_accelerations.push(ka * desired.acceleration(c, time + window) + kv * speed + kp * position);
        if limit != 0.0 {
            stress_weight = stress_weight.min(sigma_down(0.1 * limit, limit, position.abs()));
        }
        position_errors.push(position);
    }
    let optimal: Vec<f64> = plant.generators.iter().map(|g| g.unit_force(false, 0.0, 0.0)).collect();
    let (lower, upper) = force_bounds(limits, &optimal, time);
    let weights = DMatrix::from_diagonal(&DVector::from_iterator(tasks.len(), tasks.iter().map(|t| t.task.weight)));
    let offset = DVector::from_iterator(tasks.len(), base.iter().zip(&desired_accelerations).map(|(a, d)| a - d));
    let stress = DMatrix::from_diagonal(&DVector::from_iterator(optimal.len(), optimal.iter().map(|f| stress_weight / (f * f))));
    let hessian = 2.0 * (sensitivity.transpose() * &weights * &sensitivity + stress);
    let linear: Vec<f64> = (2.0 * sensitivity.transpose() * &weights * offset).iter().copied().collect();
    let solved = DenseQp::new(&hessian, &linear).and_then(|qp| qp.with_bounds(&lower, &upper)).map(|qp| qp.solve(&QpSettings::default())).map_err(|e| failed(e.to_string()))?;
    if !solved.status.is_solved() {
        return Err(failed(format!("no actuator forces within the controls' bounds reach the desired accelerations ({:?})", solved.status)));
    }
    Ok((solved.x.iter().zip(&optimal).map(|(f, o)| f / o).collect(), position_errors))
}

/// The state CMC optimises at (its `CMCActuatorSubsystem`'s complete state at the window's end):
/// the desired coordinates' splines and their derivatives at `time` + `window` carrying the
/// errors of `state` at `time`.
fn predicted_state(plant: &Plant, desired: &DesiredKinematics, state: &SimulatedState, time: f64, window: f64) -> SimulatedState {
    let (now_q, now_u) = desired.path(time);
    let (q, u) = desired.path(time + window);
    let q = (0..q.len()).map(|c| q[c] + state.q[c] - now_q[c]).collect();
    let u = (0..u.len()).map(|c| u[c] + state.u[c] - now_u[c]).collect();
    assembled(plant, q, u)
}

/// The state of coordinates `q` and speeds `u` as OpenSim sets them: a locked coordinate keeps
/// its default value (`Coordinate::setValue` refuses to move it) at rest, a coupler's dependent
/// follows it.
fn assembled(plant: &Plant, mut q: Vec<f64>, mut u: Vec<f64>) -> SimulatedState {
    let multibody = &plant.geometry.multibody;
    for (c, coordinate) in multibody.coordinates.iter().enumerate().filter(|(_, c)| c.locked) {
        (q[c], u[c]) = (coordinate.default_value, 0.0);
    }
    multibody.follow_couplers(&mut q, &[]);
    SimulatedState { q, u, activations: Vec::new(), seconds: Vec::new() }
}

/// The tasks' coordinate accelerations at `state` with no actuator force, and their change per
/// unit actuation of each generator (rows: tasks; columns: generators).
fn acceleration_map(plant: &Plant, state: &SimulatedState, time: f64, tasks: &[Task]) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let multibody = &plant.geometry.multibody;
    let mut kinematics = multibody.kinematics();
    multibody.realize(&state.q, &mut kinematics);
    let loads = plant.external.map(|e| e.at(time, &kinematics)).unwrap_or_default();
    let zero = vec![0.0; state.q.len()];
    let dynamics = multibody.prepare_dynamics(&kinematics, &state.q, &state.u).map_err(|e| format!("forward dynamics: {e}"))?;
    let at = |applied: &AppliedForces| dynamics.solve(&applied.loads, &applied.mobility).map(|(udot, _)| udot).map_err(|e| format!("forward dynamics: {e}"));
    let base = at(&AppliedForces { loads: loads.clone(), mobility: zero.clone() })?;
    let mut sensitivity = DMatrix::zeros(tasks.len(), plant.generators.len());
    let mut scratch = PathScratch::default();
    for (j, generator) in plant.generators.iter().enumerate() {
        let mut applied = AppliedForces { loads: loads.clone(), mobility: zero.clone() };
        generator.apply(plant.geometry, &kinematics, &state.q, &mut scratch, 1.0, &mut applied);
        let moved = at(&applied)?;
        for (i, task) in tasks.iter().enumerate() {
            sensitivity[(i, j)] = moved[task.coordinate] - base[task.coordinate];
        }
    }
    Ok((tasks.iter().map(|t| base[t.coordinate]).collect(), sensitivity))
}

/// Each generator's force bounds at `time` (s): its control bounds times its optimal force,
/// ordered; a range under 1 N collapses onto its lower end, as CMC does.
fn force_bounds(limits: &[ControlLinear], optimal: &[f64], time: f64) -> (Vec<f64>, Vec<f64>) {
    limits
        .iter()
        .zip(optimal)
        .map(|(limit, &f)| {
            let (min, max) = limit.bounds_at(time);
            let (a, b) = (min * f, if (max - min) * f < 1.0 { min * f } else { max * f });
            (a.min(b), a.max(b))
        })
        .collect()
}

/// `ForwardTool::SigmaDn`: 1 − 1/(1 + e^(−(t − to)/τ)), falling from 1 to 0 about `to`.
fn sigma_down(tau: f64, to: f64, t: f64) -> f64 {
    1.0 - 1.0 / (1.0 + (-(t - to) / tau).exp())
}
