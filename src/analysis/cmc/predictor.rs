//! CMC's actuator force predictor (`VectorFunctionForActuators` on the `CMCActuatorSubsystem`):
//! the muscles' states integrated alone over a window (Runge–Kutta–Merson, accuracy 5e-6, steps
//! of at most 1 ms), the coordinates following the desired kinematics' splines plus the errors at
//! the window's start — or held where they are at the start while the muscles settle —, each
//! control moving from its last node to a trial value at the window's end (muscles in a step,
//! actuators on a line), the model's other controllers adding theirs; the generators' forces at
//! the window's end.

use super::desired::DesiredKinematics;
use super::merson::{self, Rates};
use crate::analysis::simulation::{Plant, SimulatedState, Workspace};
use crate::setup::{ControlBounds, ControlLinear};

/// The predictor's integration accuracy and longest step (s), as `VectorFunctionForActuators`.
const ACCURACY: f64 = 5e-6;
const MAX_STEP: f64 = 1e-3;

/// The window's kinematics: the desired coordinates' splines at time t plus the errors at the
/// window's start (`CMCActuatorSubsystem`'s corrections), or at a held time.
pub struct Prescribed<'p> {
    pub desired: &'p DesiredKinematics,
    /// q − q_d and u − q̇_d at the window's start (rad or m, rad/s or m/s).
    pub corrections: [Vec<f64>; 2],
    /// The coordinates held at their values of this time (s) instead of following the splines.
    pub held_at: Option<f64>,
}

impl Prescribed<'_> {
    /// The corrections of `state` at `time` (s): its errors from the desired trajectories.
    pub fn corrections(desired: &DesiredKinematics, state: &SimulatedState, time: f64) -> [Vec<f64>; 2] {
        let (q, u) = desired.path(time);
        [state.q.iter().zip(&q).map(|(a, b)| a - b).collect(), state.u.iter().zip(&u).map(|(a, b)| a - b).collect()]
    }

    /// The coordinates and speeds at `time` (s), set as OpenSim sets them (locked coordinates at
    /// their defaults, couplers' dependents following).
    pub fn pose(&self, plant: &Plant, time: f64) -> (Vec<f64>, Vec<f64>) {
        let (q, u) = self.desired.path(self.held_at.unwrap_or(time));
        let [dq, du] = &self.corrections;
        assembled(plant, q.iter().zip(dq).map(|(a, b)| a + b).collect(), u.iter().zip(du).map(|(a, b)| a + b).collect())
    }
}

/// The state of coordinates `q` and speeds `u` as OpenSim sets them: a locked coordinate keeps
/// its default value (`Coordinate::setValue` refuses to move it) at rest, a coupler's dependent
/// follows it.
pub fn assembled(plant: &Plant, mut q: Vec<f64>, mut u: Vec<f64>) -> (Vec<f64>, Vec<f64>) {
    let multibody = &plant.geometry.multibody;
    for (c, coordinate) in multibody.coordinates.iter().enumerate().filter(|(_, c)| c.locked) {
        (q[c], u[c]) = (coordinate.default_value, 0.0);
    }
    multibody.follow_couplers(&mut q, &[]);
    (q, u)
}

/// One window's predictor: the muscles' states `start` at `window[0]`, each generator's last
/// control node and whether its control steps (`steps`) or ramps.
pub struct Predictor<'p, 'a> {
    pub plant: &'p Plant<'a>,
    pub steps: &'p [bool],
    pub prescribed: Prescribed<'p>,
    pub window: [f64; 2],
    pub start: Vec<f64>,
    pub last_nodes: Vec<Option<(f64, f64)>>,
}

impl Predictor<'_, '_> {
    /// The generators' forces (N or N·m) at the window's end under trial controls `x`, and the
    /// complete state there.
    pub fn forces(&self, x: &[f64]) -> Result<(Vec<f64>, SimulatedState), String> {
        let plant = self.plant;
        let controls = self.controls(x);
        let [from, to] = self.window;
        let mut subsystem = ActuatorSubsystem { plant, prescribed: &self.prescribed, controls: &controls, work: plant.workspace() };
        let z = if self.start.is_empty() {
            Vec::new()
        } else {
            merson::integrate(&mut subsystem, &self.start, [from, to], [0.0, MAX_STEP], ACCURACY).map_err(|(time, reason)| format!("the muscles' states cannot be predicted at {time} s: {reason}"))?
        };
        let at_end = model_controls(plant, &controls, to, self.prescribed.held_at.unwrap_or(to));
        let (q, u) = self.prescribed.pose(plant, to);
        let state = plant.with_muscle_states(q, u, &z, &at_end);
        let forces = plant.actuations(to, &state, &at_end, &mut subsystem.work)?;
        Ok((forces, state))
    }

    /// Each generator's control over the window: from its last node to `x` at the window's end
    /// (constant at `x` without a last node).
    fn controls(&self, x: &[f64]) -> Vec<ControlLinear> {
        window_controls(self.plant, self.steps, &self.last_nodes, self.window[1], x)
    }
}

/// Each generator's control from its last node to `x` at `end` (s), in a step where `steps` says
/// (CMC gives muscles piecewise-constant controls unless a constraints file's control says
/// otherwise), else on a line.
pub fn window_controls(plant: &Plant, steps: &[bool], last_nodes: &[Option<(f64, f64)>], end: f64, x: &[f64]) -> Vec<ControlLinear> {
    plant
        .generators
        .iter()
        .zip(steps.iter().zip(last_nodes.iter().zip(x)))
        .map(|(generator, (&use_steps, (last, &x)))| {
            let nodes = last.iter().copied().chain(std::iter::once((end, x))).collect();
            ControlLinear { name: format!("{}.excitation", generator.name), use_steps, extrapolate: true, nodes, bounds: ControlBounds::default() }
        })
        .collect()
}

/// The model's controls: CMC's `controls` at `time` plus the model's and the tool's other
/// controllers' at `model_time` (s) — the subsystem's time, or the held time while the
/// coordinates are held (`CMCActuatorSubsystem` poses the complete state there).
fn model_controls(plant: &Plant, controls: &[ControlLinear], time: f64, model_time: f64) -> Vec<f64> {
    let mut sum = plant.generator_controls(model_time);
    for (u, c) in sum.iter_mut().zip(controls) {
        *u += c.value(time);
    }
    sum
}

/// The muscles' states moved by their own dynamics along the prescribed kinematics.
struct ActuatorSubsystem<'s, 'p, 'a> {
    plant: &'s Plant<'a>,
    prescribed: &'s Prescribed<'p>,
    controls: &'s [ControlLinear],
    work: Workspace,
}

impl Rates for ActuatorSubsystem<'_, '_, '_> {
    fn rates(&mut self, time: f64, z: &[f64], dz: &mut [f64]) -> Result<(), String> {
        let controls = model_controls(self.plant, self.controls, time, self.prescribed.held_at.unwrap_or(time));
        let (q, u) = self.prescribed.pose(self.plant, time);
        let state = self.plant.with_muscle_states(q, u, z, &controls);
        self.plant.muscle_state_rates(time, &state, &controls, dz, &mut self.work)
    }

    fn coordinates(&self) -> usize {
        0
    }
}
