//! `CMC::computeInitialStates`: where CMC starts a model with muscles' states. At the initial
//! time the coordinates are held while the muscles settle for 0.2 s under CMC's controls of 0.01
//! (an excluded generator's 0; other controllers add theirs), twice; then CMC's controls for a
//! first window of 0.03 s are solved (twice, the muscles settling under the first solution in
//! between) and the predictor's state at the window's end — the desired kinematics there, the
//! muscles' states integrated under those controls — is where the tracking starts, 0.03 s after
//! the initial time, with those controls as its first nodes.

use super::predictor::{Predictor, Prescribed};
use super::tracking::{Controller, WindowSolution};
use super::CmcError;
use crate::analysis::simulation::SimulatedState;

/// How long the muscles settle with the coordinates held (s).
const SETTLING: f64 = 0.2;
/// The controls they settle under first.
const SETTLING_CONTROL: f64 = 0.01;
/// The first window (s): the tracking starts this much after the initial time.
pub const FIRST_WINDOW: f64 = 0.03;

/// Where the tracking starts, and how CMC got there.
#[derive(Debug, Clone)]
pub struct InitialStates {
    pub time: f64,
    pub state: SimulatedState,
    /// The muscles' states it started from (the model's default state's, OpenSim's "guess").
    pub guess: Vec<f64>,
    /// The muscles' states after each settling under controls of 0.01 ([`crate::analysis::Plant::muscle_states`]
    /// order).
    pub settled: [Vec<f64>; 2],
    /// The first window's two solutions; the last one's controls are the tracking's first nodes.
    pub first: WindowSolution,
    pub last: WindowSolution,
}

/// CMC's initial states from `start`, the desired state at `time` (s) with the muscles' states
/// the model starts with.
pub fn initial_states(controller: &Controller, start: SimulatedState, time: f64) -> Result<InitialStates, CmcError> {
    let plant = controller.plant;
    let desired = controller.desired;
    let n = plant.generators.len();
    let failed = |reason: String| CmcError::Tracking { time, reason };
    let corrections = Prescribed::corrections(desired, &start, time);
    let steps = controller.steps();
    let predictor = |z: Vec<f64>, window: f64, held: bool| Predictor {
        plant,
        steps: &steps,
        prescribed: Prescribed { desired, corrections: corrections.clone(), held_at: held.then_some(time) },
        window: [time, time + window],
        start: z,
        last_nodes: vec![None; n],
    };
    let settled = |z: Vec<f64>, controls: &[f64]| predictor(z, SETTLING, true).forces(controls).map(|(_, state)| plant.muscle_states(&state)).map_err(failed);
    let guess = plant.muscle_states(&start);
    let settling = controller.uniform_controls(SETTLING_CONTROL);
    let once = settled(guess.clone(), &settling)?;
    let twice = settled(once.clone(), &settling)?;
    let with_states = |z: &[f64]| plant.with_muscle_states(start.q.clone(), start.u.clone(), z, &plant.generator_controls(time));
    let first = controller.solve_with(&predictor(twice.clone(), FIRST_WINDOW, false), &with_states(&twice), time)?;
    let z = settled(twice.clone(), &first.controls)?;
    let last = controller.solve_with(&predictor(z.clone(), FIRST_WINDOW, false), &with_states(&z), time)?;
    let (_, state) = predictor(z, FIRST_WINDOW, false).forces(&last.controls).map_err(failed)?;
    Ok(InitialStates { time: time + FIRST_WINDOW, state, guess, settled: [once, twice], first, last })
}
