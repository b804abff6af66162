//! `CMC::computeInitialStates`: where CMC starts a model with muscles' states. At the initial
//! time the coordinates are held while the muscles settle for 0.2 s under controls of 0.01, twice;
//! then CMC's controls for a first window of 0.03 s are solved (twice, the muscles settling under
//! the first solution in between) and the predictor's state at the window's end — the desired
//! kinematics there, the muscles' states integrated under those controls — is where the tracking
//! starts, 0.03 s after the initial time, with those controls as its first nodes.

use super::predictor::{Predictor, Prescribed};
use super::tracking::Controller;
use super::CmcError;
use crate::analysis::simulation::SimulatedState;

/// How long the muscles settle with the coordinates held (s).
const SETTLING: f64 = 0.2;
/// The controls they settle under first.
const SETTLING_CONTROL: f64 = 0.01;
/// The first window (s): the tracking starts this much after the initial time.
pub const FIRST_WINDOW: f64 = 0.03;

/// Where the tracking starts.
pub struct InitialStates {
    pub time: f64,
    pub state: SimulatedState,
    /// The first window's controls (the tracking's first nodes).
    pub controls: Vec<f64>,
    /// The tasks' position errors at the initial time.
    pub position_errors: Vec<f64>,
}

/// CMC's initial states from `start`, the desired state at `time` (s) with the muscles' states
/// the model starts with.
pub fn initial_states(controller: &Controller, start: SimulatedState, time: f64) -> Result<InitialStates, CmcError> {
    let plant = controller.plant;
    let desired = controller.desired;
    let n = plant.generators.len();
    let failed = |reason: String| CmcError::Tracking { time, reason };
    let corrections = Prescribed::corrections(desired, &start, time);
    let predictor = |z: Vec<f64>, window: f64, held: bool| Predictor {
        plant,
        prescribed: Prescribed { desired, corrections: corrections.clone(), held_at: held.then_some(time) },
        window: [time, time + window],
        start: z,
        last_nodes: vec![None; n],
    };
    let settled = |z: Vec<f64>, controls: &[f64]| predictor(z, SETTLING, true).forces(controls).map(|(_, state)| plant.muscle_states(&state)).map_err(failed);
    let mut z = plant.muscle_states(&start);
    for _ in 0..2 {
        z = settled(z, &vec![SETTLING_CONTROL; n])?;
    }
    let with_states = |z: &[f64]| plant.with_muscle_states(start.q.clone(), start.u.clone(), z, &plant.generator_controls(time));
    let mut solution = controller.solve_with(&predictor(z.clone(), FIRST_WINDOW, false), &with_states(&z), time)?;
    z = settled(z, &solution.controls)?;
    solution = controller.solve_with(&predictor(z.clone(), FIRST_WINDOW, false), &with_states(&z), time)?;
    let (_, state) = predictor(z, FIRST_WINDOW, false).forces(&solution.controls).map_err(failed)?;
    Ok(InitialStates { time: time + FIRST_WINDOW, state, controls: solution.controls, position_errors: solution.position_errors })
}
