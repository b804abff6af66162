//! The muscle states OpenSim's AnalyzeTool hands its analyses: those a states file gives, and
//! what a coordinates file (or a states file) lacks filled with the model's defaults
//! (`formStateStorage`): each muscle at its `default_activation` — a muscle without activation
//! dynamics at its control (its controllers', else 0) — and its second state at its
//! default (`default_fiber_length` raised to the minimum, DeGroote's
//! `default_normalized_tendon_force`) or, with `solve_for_equilibrium_for_auxiliary_states`,
//! where `equilibrateMuscles` puts it (Thelen's speed-sharing `initMuscleState`, Millard's static
//! equilibrium, DeGroote's bisection for the tendon force); each on the path of the analysed pose
//! moving at the pose's speeds.

use super::analyze_tool::AnalyzeToolMotion;
use super::controllers::Controllers;
use crate::mechanics::muscle::{HillMuscle, MuscleError, MuscleState};
use crate::mechanics::{MuscleGeometry, PathEvaluation};
use crate::model::{ModelSpec, MuscleSpec, SecondState};

/// One muscle's state variables as OpenSim holds them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateVariables {
    /// `activation`, `None` for a muscle without activation dynamics (no such state).
    pub activation: Option<f64>,
    /// The second state (`fiber_length` in m, or `normalized_tendon_force`), `None` beside a
    /// rigid tendon (no such state).
    pub second: Option<f64>,
}

/// The model's muscles at each analysed pose.
#[derive(Debug, Clone)]
pub struct MuscleStates {
    /// (index into [`MuscleGeometry::paths`], name) of every muscle, ForceSet order.
    pub muscles: Vec<(usize, String)>,
    /// Each muscle's second state.
    pub second_states: Vec<SecondState>,
    /// `variables[row][k]`: muscle k's state variables at the row.
    pub variables: Vec<Vec<StateVariables>>,
    /// `states[row][k]`: what OpenSim reports for muscle k, `None` where OpenSim cannot
    /// evaluate it (it writes NaN).
    pub states: Vec<Vec<Option<MuscleState>>>,
    /// What OpenSim warns about: muscles it cannot equilibrate (left as they were) or evaluate,
    /// with the time — once per muscle and kind, with the number of rows and their times.
    pub warnings: Vec<String>,
}

/// Why the muscles' states cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum MuscleStatesError {
    #[error("muscle '{muscle}' ({class}) has no muscle mechanics here, so the muscles' states are not formed")]
    NotFormed { muscle: String, class: String },
    #[error(transparent)]
    Muscle(#[from] MuscleError),
}

/// One muscle as the AnalyzeTool holds it.
struct HeldMuscle<'a> {
    muscle: HillMuscle,
    spec: &'a MuscleSpec,
    second: SecondState,
    /// (activation, second state) of the model's initial state (a fiber length raised to the
    /// minimum, as the initial state holds it).
    defaults: (f64, f64),
    /// Activation and the second state per row, as a states file gives them.
    given: [Option<Vec<f64>>; 2],
}

impl HeldMuscle<'_> {
    /// Its state variables at `row`: the given ones, else the defaults; none where the muscle
    /// has no such state (no activation dynamics, a rigid tendon).
    fn variables(&self, row: usize) -> StateVariables {
        let [activation, second] = self.given.each_ref().map(|c| c.as_ref().map(|c| c[row]));
        StateVariables {
            activation: Some(activation.unwrap_or(self.defaults.0)).filter(|_| !self.spec.ignore_activation_dynamics),
            second: Some(second.unwrap_or(self.defaults.1)).filter(|_| !self.spec.ignore_tendon_compliance),
        }
    }
}

/// A muscle's default state as OpenSim forms it: (`default_activation`, the second state's
/// kind, its default — `default_fiber_length` raised to the minimum fiber length, DeGroote's
/// `default_normalized_tendon_force`).
pub(super) fn default_state(spec: &MuscleSpec, muscle: &HillMuscle) -> (f64, SecondState, f64) {
    let (activation, second, value) = spec.default_state();
    let value = if second == SecondState::FiberLength { value.max(muscle.minimum_fiber_length()) } else { value };
    (activation, second, value)
}

/// The second state OpenSim's `equilibrateMuscles` leaves `muscle` in at `activation` on a path
/// of length `length` (m) lengthening at `speed` (m/s): Millard's static Newton iteration to its
/// own tolerance (so its reported numbers match), Thelen's `initMuscleState`, DeGroote's
/// normalized tendon force.
pub(super) fn equilibrated(muscle: &HillMuscle, activation: f64, length: f64, speed: f64) -> Result<f64, MuscleError> {
    match muscle {
        HillMuscle::Millard(m) => Ok(m.opensim_equilibrium(activation, length)?.fiber_length),
        HillMuscle::DeGroote(m) => m.initial_normalized_tendon_force(activation, length, speed),
        muscle => muscle.initial_fiber_length(activation, length, speed),
    }
}

/// The states of every muscle of `spec` (`geometry` its paths) at each pose of `states` with its
/// speeds — those its states file gives, the others at their defaults — equilibrated when
/// `equilibrate`; `controls` activate the muscles without activation dynamics.
pub fn muscle_states(spec: &ModelSpec, geometry: &MuscleGeometry, states: &AnalyzeToolMotion, controls: &Controllers, equilibrate: bool) -> Result<MuscleStates, MuscleStatesError> {
    let (mut muscles, mut held) = (Vec::new(), Vec::new());
    for force in spec.muscles() {
        let not_formed = || MuscleStatesError::NotFormed { muscle: force.name.clone(), class: force.class.clone() };
        let muscle_spec = force.muscle.as_ref().ok_or_else(not_formed)?;
        let path = geometry.path_index(&force.name).ok_or_else(not_formed)?;
        let muscle = HillMuscle::from_force(force)?;
        let (activation, second, value) = default_state(muscle_spec, &muscle);
        let given = states.muscle_states.iter().find(|(m, _)| *m == force.name).map(|(_, columns)| columns.clone()).unwrap_or_default();
        held.push(HeldMuscle { muscle, spec: muscle_spec, second, defaults: (activation, value), given });
        muscles.push((path, force.name.clone()));
    }
    let indices: Vec<usize> = muscles.iter().map(|(p, _)| *p).collect();
    let mut evaluation = PathEvaluation::new(geometry, &indices);
    let second_states = held.iter().map(|h| h.second).collect();
    let mut result = MuscleStates { muscles, second_states, variables: Vec::new(), states: Vec::new(), warnings: Vec::new() };
    let mut failures = Failures::default();
    for (row, &time) in states.motion.times.iter().enumerate() {
        evaluation.evaluate_moving(geometry, states.motion.pose(row), Some(&states.speeds[row]));
        let (mut variables, mut reports) = (Vec::new(), Vec::new());
        for (k, held) in held.iter().enumerate() {
            let (length, speed) = (evaluation.length(k), evaluation.lengthening_speed(k));
            let mut warn = |what: &'static str, e: MuscleError| failures.add(k, what, time, e);
            let start = held.variables(row);
            // A muscle without activation dynamics is activated by its control. OpenSim's
            // `getActivation` clamps the state (a forward simulation can carry it past its
            // bounds) for the equilibrium and the evaluation alike; the muscle then holds it at
            // its minimum activation.
            let activation = start.activation.unwrap_or_else(|| controls.control(&result.muscles[k].1, time)).clamp(0.0, 1.0);
            let variable = match start.second {
                Some(_) if equilibrate => match equilibrated(&held.muscle, activation, length, speed) {
                    Ok(second) => StateVariables { second: Some(second), ..start },
                    Err(e) => {
                        warn("not equilibrated, left as it was", e);
                        start
                    }
                },
                _ => start,
            };
            let report = held.muscle.state(activation, variable.second.unwrap_or(0.0), length, speed);
            reports.push(report.map_err(|e| warn("not evaluated (NaN)", e)).ok());
            variables.push(variable);
        }
        result.variables.push(variables);
        result.states.push(reports);
    }
    result.warnings = failures.warnings();
    Ok(result)
}

/// The failures of one muscle and kind over the rows: how many, the first and last time (s),
/// the first one's error.
struct Failure {
    muscle: usize,
    what: &'static str,
    count: usize,
    times: [f64; 2],
    first: MuscleError,
}

/// Failures collected over the rows, so that a muscle that fails at every row is reported once.
#[derive(Default)]
struct Failures(Vec<Failure>);

impl Failures {
    fn add(&mut self, muscle: usize, what: &'static str, time: f64, error: MuscleError) {
        match self.0.iter_mut().find(|f| f.muscle == muscle && f.what == what) {
            Some(failure) => {
                failure.count += 1;
                failure.times[1] = time;
            }
            None => self.0.push(Failure { muscle, what, count: 1, times: [time, time], first: error }),
        }
    }

    /// One line per muscle and kind, in the order they first failed.
    fn warnings(&self) -> Vec<String> {
        self.0
            .iter()
            .map(|f| match f.count {
                1 => format!("at {} s: {}: {}", f.times[0], f.what, f.first),
                n => format!("at {n} rows from {} to {} s: {}: {} (at the first; the others alike)", f.times[0], f.times[1], f.what, f.first),
            })
            .collect()
    }
}
