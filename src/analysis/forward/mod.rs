//! Muscle-driven forward simulation along prescribed kinematics — the thesis' EMG-driven
//! simulation (ch. 7) and what OpenSim integrates for a model whose coordinates are all
//! prescribed and whose muscles a `PrescribedController` excites.
//!
//! Each driven muscle has two states: its activation a, which follows its class's activation
//! dynamics from the excitation u(t) ([`ActivationDynamics`]), and its fiber length L_m, which
//! moves at the velocity that balances fiber and tendon (`HillMuscle::fiber_velocity`) — unless
//! its tendon is rigid: then the fiber follows the path and its force depends on the path's
//! speed. A compliant DeGroote–Fregly muscle's second state is, as in OpenSim, its normalized
//! tendon force f̃_T, whose rate takes the path's lengthening speed (OpenSim's, which over wrap
//! objects is not the exact dL/dt, so integrating L_m instead would drift from OpenSim). The path
//! length comes from the pose q(t) ([`PrescribedMotion`]). The states are integrated by a
//! Dormand–Prince 5(4) method with error control (crate `ode_solvers`), relative and absolute
//! tolerance `accuracy` per state, and read at the report times from its dense output. The
//! muscles' generalized forces Σ F_t r (N·m or N) can then be compared with inverse dynamics.

mod outputs;
mod prescribed_motion;
mod system;

pub use outputs::{compare_with_inverse_dynamics, inverse_dynamics_times, CoordinateComparison, ForwardOutputs};
pub use prescribed_motion::PrescribedMotion;

use std::cell::RefCell;
use std::path::PathBuf;

use ode_solvers::continuous_output_model::ContinuousOutputModel;
use ode_solvers::{DVector, Dopri5};

use super::Activations;
use crate::mechanics::muscle::{ActivationDynamics, DeGrooteFregly2016Muscle, HillMuscle, MuscleError};
use crate::mechanics::{MuscleGeometry, PathEvaluation};
use crate::model::ModelSpec;
use system::MuscleDynamics;

/// Steps the integrator may take before it gives up.
const MAX_STEPS: u32 = 2_000_000;

/// Why a forward simulation cannot be run or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum ForwardError {
    #[error("{}: muscle {muscle}: {reason}", file.display())]
    Muscle { file: PathBuf, muscle: String, reason: String },
    #[error("no muscle of {} has an excitation column in {}", model.display(), excitations.display())]
    NoDrivenMuscle { model: PathBuf, excitations: PathBuf },
    #[error("{}: excitations cover {}–{} s, which does not contain the simulated {}–{} s", file.display(), covered[0], covered[1], simulated[0], simulated[1])]
    ExcitationsTooShort { file: PathBuf, covered: [f64; 2], simulated: [f64; 2] },
    #[error("the time range {}–{} s is empty or not inside the motion's {}–{} s", asked[0], asked[1], motion[0], motion[1])]
    TimeRange { asked: [f64; 2], motion: [f64; 2] },
    #[error("muscle {muscle}: the initial equilibrium at {time} s failed: {source}")]
    InitialEquilibrium { muscle: String, time: f64, source: MuscleError },
    #[error("at {time} s: {source}")]
    MuscleState { time: f64, source: MuscleError },
    #[error("{}: no column matches the muscles' generalized forces ({}) at the simulated times", file.display(), labels.join(", "))]
    NothingToCompare { file: PathBuf, labels: Vec<String> },
    #[error("the integration stopped at {time} s: {reason}")]
    Integration { time: f64, reason: String },
}

/// A muscle the simulation drives.
#[derive(Debug, Clone)]
pub struct DrivenMuscle {
    pub name: String,
    pub muscle: HillMuscle,
    /// The activation dynamics; `None` when the activation is the excitation itself (OpenSim's
    /// `ignore_activation_dynamics`).
    pub activation: Option<ActivationDynamics>,
    /// Index into [`MuscleGeometry::paths`].
    pub path: usize,
}

impl DrivenMuscle {
    /// The muscle whose second state is its normalized tendon force (a compliant DeGroote
    /// muscle), else `None` (the state is the fiber length).
    pub fn tendon_force_state(&self) -> Option<&DeGrooteFregly2016Muscle> {
        match &self.muscle {
            HillMuscle::DeGroote(m) if !m.ignore_tendon_compliance => Some(m),
            _ => None,
        }
    }
}

/// The muscles of `spec` named in `names` (those that apply force and have a path; a rigid
/// tendon's fiber length follows the path and is no state), each with
/// its activation dynamics — none when it ignores them or when `activations_given` (the
/// driving table then holds activations); an error for a class or tendon we cannot simulate.
pub fn driven_muscles(spec: &ModelSpec, geometry: &MuscleGeometry, names: &[String], activations_given: bool) -> Result<Vec<DrivenMuscle>, ForwardError> {
    let refuse = |muscle: &str, reason: &str| ForwardError::Muscle { file: spec.file.clone(), muscle: muscle.into(), reason: reason.into() };
    let mut driven = Vec::new();
    for force in spec.muscles().filter(|f| f.applies_force && names.contains(&f.name)) {
        let muscle = HillMuscle::from_force(force).map_err(|e| refuse(&force.name, &e.to_string()))?;
        let properties = force.muscle.as_ref().ok_or_else(|| refuse(&force.name, "no muscle properties"))?;
        if let crate::model::MuscleModelSpec::DeGrooteFregly2016(class) = &properties.model {
            if !properties.ignore_tendon_compliance && class.tendon_compliance_dynamics_mode != "explicit" {
                return Err(refuse(&force.name, "tendon_compliance_dynamics_mode implicit: its tendon-force derivative is a control of a direct collocation problem, not a forward simulation state; use explicit"));
            }
        }
        let dynamics = ActivationDynamics::of(properties, muscle.minimum_activation());
        let activation = Some(dynamics).filter(|_| !(activations_given || properties.ignore_activation_dynamics));
        let path = geometry.path_index(&force.name).ok_or_else(|| refuse(&force.name, "no geometry path"))?;
        driven.push(DrivenMuscle { name: force.name.clone(), muscle, activation, path });
    }
    Ok(driven)
}

/// Whether coordinate `c`'s speed is a component of its joint's angular velocity, not its rate
/// (`BallJoint`, `FreeJoint`, the ellipsoid glides).
fn angular_velocity_speeds(geometry: &MuscleGeometry, c: usize) -> bool {
    let multibody = &geometry.multibody;
    let joint = &multibody.joints[multibody.coordinate_joint(c)];
    joint.coordinates.iter().position(|&k| k == c).is_some_and(|k| k < joint.mobilizer.angular_velocity_speeds())
}

/// Where the states start.
#[derive(Debug, Clone)]
pub enum InitialStates {
    /// a = u(t₀) (clamped to [a_min, 1]) and the fiber length OpenSim's `equilibrateMuscles`
    /// gives it at t₀ (`HillMuscle::initial_fiber_length`; a DeGroote muscle's normalized tendon
    /// force by its bisection).
    Equilibrium,
    /// [a, L_m (m)] per driven muscle (a DeGroote muscle's f̃_T follows from L_m).
    Given(Vec<[f64; 2]>),
}

/// What to simulate.
#[derive(Debug, Clone)]
pub struct ForwardSettings {
    /// [start, end] in s, inside the motion.
    pub range: [f64; 2],
    /// Relative and absolute error tolerance per state and step.
    pub accuracy: f64,
    pub initial: InitialStates,
}

/// The integrated states: [a…, s…] at any time of the range, s the fiber length L_m (m) or a
/// DeGroote muscle's f̃_T (a muscle without activation dynamics keeps its initial a there; its
/// activation is its excitation).
pub struct Trajectory {
    pub range: [f64; 2],
    pub muscles: usize,
    output: ContinuousOutputModel<f64, DVector<f64>>,
    /// The driving table, and which muscles take their activation straight from it.
    excitations: Activations,
    without_dynamics: Vec<bool>,
    /// Integrator statistics: accepted and rejected steps, right-hand-side evaluations.
    pub accepted_steps: u32,
    pub rejected_steps: u32,
    pub evaluations: u32,
}

impl Trajectory {
    /// The activations and second states (L_m in m, or f̃_T) of the muscles at `time` (s),
    /// inside the range.
    pub fn states(&self, time: f64) -> (Vec<f64>, Vec<f64>) {
        // The output model covers [0, its last step's end], which rounding may leave a hair off
        // end − start; `simulate` made at least one step.
        let (first, last) = self.output.bounds();
        let y = self.output.evaluate((time - self.range[0]).clamp(first, last)).expect("the output model covers its bounds");
        let activations = (0..self.muscles).map(|k| if self.without_dynamics[k] { self.excitations.at(k, time) } else { y[k] }).collect();
        (activations, y.rows(self.muscles, self.muscles).iter().copied().collect())
    }
}

/// Integrates the driven muscles' states over `settings.range` along `motion`, excited by
/// `excitations` (one column per driven muscle, in order).
pub fn simulate(
    geometry: &MuscleGeometry,
    muscles: &[DrivenMuscle],
    motion: &PrescribedMotion,
    excitations: &Activations,
    settings: &ForwardSettings,
) -> Result<Trajectory, ForwardError> {
    let [start, end] = settings.range;
    if start.partial_cmp(&end) != Some(std::cmp::Ordering::Less) {
        return Err(ForwardError::TimeRange { asked: settings.range, motion: motion.range() });
    }
    if let Some(muscle) = muscles.iter().find(|m| m.muscle.has_rigid_tendon() && geometry.paths[m.path].loaded.iter().any(|&c| angular_velocity_speeds(geometry, c))) {
        let reason = "a rigid tendon across a BallJoint, FreeJoint or ellipsoid joint: its path speed would need the joint's angular velocity, which the motion does not give";
        return Err(ForwardError::Muscle { file: geometry.multibody.file.clone(), muscle: muscle.name.clone(), reason: reason.into() });
    }
    let initial = initial_states(geometry, muscles, motion, excitations, settings)?;
    let failure = RefCell::new(None);
    let dynamics = MuscleDynamics::new(geometry, muscles, motion, excitations, start, &failure);
    let mut solver = Dopri5::from_param(
        dynamics,
        0.0,
        end - start,
        end - start,
        DVector::from_vec(initial),
        settings.accuracy,
        settings.accuracy,
        0.9,
        0.04,
        0.2,
        10.0,
        end - start,
        0.0,
        MAX_STEPS,
        u32::MAX,
        ode_solvers::OutputType::Continuous,
    );
    let mut output = ContinuousOutputModel::default();
    let outcome = solver.integrate_with_continuous_output_model(&mut output);
    drop(solver);
    let stats = match (outcome, failure.into_inner()) {
        (Ok(stats), _) => stats,
        (Err(_), Some((time, source))) => return Err(ForwardError::MuscleState { time: start + time, source }),
        (Err(error), None) => return Err(ForwardError::Integration { time: start + integration_time(&error), reason: error.to_string() }),
    };
    let without_dynamics = muscles.iter().map(|m| m.activation.is_none()).collect();
    Ok(Trajectory { range: settings.range, muscles: muscles.len(), output, excitations: excitations.clone(), without_dynamics, accepted_steps: stats.accepted_steps, rejected_steps: stats.rejected_steps, evaluations: stats.num_eval })
}

fn integration_time(error: &ode_solvers::dop_shared::IntegrationError) -> f64 {
    use ode_solvers::dop_shared::IntegrationError::*;
    match error {
        MaxNumStepReached { x, .. } | StepSizeUnderflow { x } | StiffnessDetected { x } => *x,
    }
}

/// [a…, s…] at the start.
fn initial_states(geometry: &MuscleGeometry, muscles: &[DrivenMuscle], motion: &PrescribedMotion, excitations: &Activations, settings: &ForwardSettings) -> Result<Vec<f64>, ForwardError> {
    let start = settings.range[0];
    let coordinates = geometry.multibody.coordinates.len();
    let (mut q, mut speeds) = (vec![0.0; coordinates], vec![0.0; coordinates]);
    motion.pose(start, &mut q);
    motion.speeds(start, &q, &mut speeds);
    let mut paths = PathEvaluation::loading(geometry, &muscles.iter().map(|m| m.path).collect::<Vec<_>>());
    paths.evaluate_moving(geometry, &q, Some(&speeds));
    let pairs: Vec<[f64; 2]> = muscles
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let (length, speed) = (paths.length(k), paths.lengthening_speed(k));
            match (&settings.initial, m.tendon_force_state()) {
                (InitialStates::Given(states), None) => Ok(states[k]),
                (InitialStates::Given(states), Some(d)) => Ok([states[k][0], d.tendon_force(states[k][1], length) / d.max_isometric_force()]),
                (InitialStates::Equilibrium, state) => {
                    let a = excitations.at(k, start).clamp(m.muscle.minimum_activation(), 1.0);
                    let second = match state {
                        Some(d) => d.initial_normalized_tendon_force(a, length, speed),
                        None => m.muscle.initial_fiber_length(a, length, speed),
                    };
                    Ok([a, second.map_err(|source| ForwardError::InitialEquilibrium { muscle: m.name.clone(), time: start, source })?])
                }
            }
        })
        .collect::<Result<_, ForwardError>>()?;
    Ok(pairs.iter().map(|p| p[0]).chain(pairs.iter().map(|p| p[1])).collect())
}
