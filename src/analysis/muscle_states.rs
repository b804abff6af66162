//! The muscle states OpenSim's AnalyzeTool hands its analyses: those a states file gives, and
//! what a coordinates file (or a states file) lacks filled with the model's defaults
//! (`formStateStorage`): each muscle at its `default_activation` — a muscle without activation
//! dynamics at its control (a `ControlSetController`'s, else 0) — and its fiber at `default_fiber_length`, or, with
//! `solve_for_equilibrium_for_auxiliary_states`, where `equilibrateMuscles` puts it (Thelen's
//! speed-sharing `initMuscleState`, Millard's static equilibrium); each on the path of the
//! analysed pose moving at the pose's speeds.

use crate::mechanics::muscle::{HillMuscle, MuscleError, MuscleState};
use super::analyze_tool::AnalyzeToolMotion;
use super::reporters::control;
use crate::setup::ControlSet;
use crate::mechanics::{MuscleGeometry, PathEvaluation};
use crate::model::{ModelSpec, MuscleSpec};

/// One muscle's state variables as OpenSim holds them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateVariables {
    /// `activation`, `None` for a muscle without activation dynamics (no such state).
    pub activation: Option<f64>,
    /// `fiber_length`, m, `None` for a rigid tendon (no such state).
    pub fiber_length: Option<f64>,
}

/// The model's muscles at each analysed pose.
#[derive(Debug, Clone)]
pub struct MuscleStates {
    /// (index into [`MuscleGeometry::paths`], name) of every muscle, ForceSet order.
    pub muscles: Vec<(usize, String)>,
    /// `variables[row][k]`: muscle k's state variables at the row.
    pub variables: Vec<Vec<StateVariables>>,
    /// `states[row][k]`: what OpenSim reports for muscle k, `None` where OpenSim cannot
    /// evaluate it (it writes NaN).
    pub states: Vec<Vec<Option<MuscleState>>>,
    /// What OpenSim warns about: muscles it cannot equilibrate (left at their defaults) or
    /// evaluate, with the time.
    pub warnings: Vec<String>,
}

/// Why the muscles' states cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum MuscleStatesError {
    #[error("muscle '{muscle}' ({class}) has no fiber-length state here, so its states are not formed")]
    NotFormed { muscle: String, class: String },
    #[error(transparent)]
    Muscle(#[from] MuscleError),
}

/// One muscle as the AnalyzeTool holds it.
struct HeldMuscle<'a> {
    muscle: HillMuscle,
    spec: &'a MuscleSpec,
    /// (activation, fiber length in m) of the model's initial state, the fiber length raised to
    /// the minimum as the initial state holds it.
    defaults: (f64, f64),
    /// Activation and fiber length per row, as a states file gives them.
    given: [Option<Vec<f64>>; 2],
}

impl HeldMuscle<'_> {
    /// Its state variables at `row`: the given ones, else the defaults.
    fn variables(&self, row: usize) -> StateVariables {
        let [activation, fiber_length] = self.given.each_ref().map(|c| c.as_ref().map(|c| c[row]));
        state_variables(self.spec, (activation.unwrap_or(self.defaults.0), fiber_length.unwrap_or(self.defaults.1)))
    }
}

/// The states of every muscle of `spec` (`geometry` its paths) at each pose of `states` with its
/// speeds — those its states file gives, the others at their defaults — equilibrated when
/// `equilibrate`.
pub fn muscle_states(spec: &ModelSpec, geometry: &MuscleGeometry, states: &AnalyzeToolMotion, controls: &[ControlSet], equilibrate: bool) -> Result<MuscleStates, MuscleStatesError> {
    let (motion, speeds) = (&states.motion, &states.speeds);
    let (mut muscles, mut held) = (Vec::new(), Vec::new());
    for force in spec.muscles() {
        let not_formed = || MuscleStatesError::NotFormed { muscle: force.name.clone(), class: force.class.clone() };
        let muscle_spec = force.muscle.as_ref().ok_or_else(not_formed)?;
        let defaults = muscle_spec.default_fiber_state().ok_or_else(not_formed)?;
        let path = geometry.path_index(&force.name).ok_or_else(not_formed)?;
        let muscle = HillMuscle::from_force(force)?;
        let given = states.muscle_states.iter().find(|(m, _)| *m == force.name).map(|(_, columns)| columns.clone()).unwrap_or_default();
        let defaults = (defaults.0, defaults.1.max(muscle.minimum_fiber_length()));
        held.push(HeldMuscle { muscle, spec: muscle_spec, defaults, given });
        muscles.push((path, force.name.clone()));
    }
    let indices: Vec<usize> = muscles.iter().map(|(p, _)| *p).collect();
    let mut evaluation = PathEvaluation::new(geometry, &indices);
    let mut result = MuscleStates { muscles, variables: Vec::new(), states: Vec::new(), warnings: Vec::new() };
    for (row, &time) in motion.times.iter().enumerate() {
        evaluation.evaluate_moving(geometry, motion.pose(row), Some(&speeds[row]));
        let (mut variables, mut reports) = (Vec::new(), Vec::new());
        for (k, held) in held.iter().enumerate() {
            let (length, speed) = (evaluation.length(k), evaluation.lengthening_speed(k));
            let mut warn = |what: &str, e: MuscleError| result.warnings.push(format!("at {time} s: {what}: {e}"));
            let start = held.variables(row);
            // A muscle without activation dynamics is activated by its control.
            let activation = start.activation.unwrap_or_else(|| control(controls, &result.muscles[k].1, time));
            let variable = match start.fiber_length {
                Some(_) if equilibrate => match equilibrated_fiber_length(&held.muscle, activation, length, speed) {
                    Ok(fiber_length) => StateVariables { fiber_length: Some(fiber_length), ..start },
                    Err(e) => {
                        warn("not equilibrated, left as it was", e);
                        start
                    }
                },
                _ => start,
            };
            let report = held.muscle.state(activation, variable.fiber_length.unwrap_or(0.0), length, speed);
            reports.push(report.map_err(|e| warn("not evaluated (NaN)", e)).ok());
            variables.push(variable);
        }
        result.variables.push(variables);
        result.states.push(reports);
    }
    Ok(result)
}

/// The fiber length (m) OpenSim's `equilibrateMuscles` leaves at `activation` on a path of length
/// `length` (m) lengthening at `speed` (m/s): Millard's static Newton iteration to its own
/// tolerance (so its reported numbers match), Thelen's `initMuscleState`.
fn equilibrated_fiber_length(muscle: &HillMuscle, activation: f64, length: f64, speed: f64) -> Result<f64, MuscleError> {
    match muscle {
        HillMuscle::Millard(m) => Ok(m.opensim_equilibrium(activation, length)?.fiber_length),
        _ => muscle.initial_fiber_length(activation, length, speed),
    }
}

/// The state variables a muscle starts from, (activation, fiber length) `defaults`: no
/// activation state without activation dynamics (its control, 0, drives it), no fiber-length
/// state beside a rigid tendon.
fn state_variables(spec: &MuscleSpec, defaults: (f64, f64)) -> StateVariables {
    StateVariables {
        activation: Some(defaults.0).filter(|_| !spec.ignore_activation_dynamics),
        fiber_length: Some(defaults.1).filter(|_| !spec.ignore_tendon_compliance),
    }
}
