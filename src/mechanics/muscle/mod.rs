//! Hill-type muscle mechanics equal to OpenSim 4.6's: the curves of `Millard2012EquilibriumMuscle`,
//! `Thelen2003Muscle` and `DeGrooteFregly2016Muscle`, fixed-width pennation, and the static
//! (zero fiber velocity) equilibrium between fiber and tendon for an activation and path length.

mod activation_dynamics;
mod degroote;
mod equilibrium;
mod error;
mod millard;
mod pennation;
mod root;
mod state;
mod thelen;

pub use activation_dynamics::{ActivationDynamics, FirstOrderActivation};
pub use degroote::{DeGrooteCurves, DeGrooteFregly2016Muscle};
pub use equilibrium::{EquilibriumStatus, FiberEquilibrium};
pub use error::MuscleError;
pub use millard::{
    force_velocity_inverse, Millard2012Muscle, MillardCurves,
    SmoothSegmentedFunction,
};
pub use pennation::FixedWidthPennation;
pub use state::MuscleState;
pub use root::{bracketed_newton, bracketed_newton_from, BracketEnd, Root, RootFailure};
pub use thelen::{Thelen2003Muscle, ThelenCurves};

use crate::model::{ForceSpec, MuscleModelSpec, MuscleSpec};

/// A muscle of one of the supported classes.
#[derive(Debug, Clone)]
pub enum HillMuscle {
    Millard(Box<Millard2012Muscle>),
    Thelen(Thelen2003Muscle),
    DeGroote(DeGrooteFregly2016Muscle),
}

impl HillMuscle {
    /// Builds the muscle of a force element; an error for classes without mechanics here.
    pub fn from_force(force: &ForceSpec) -> Result<HillMuscle, MuscleError> {
        let spec = force
            .muscle
            .as_ref()
            .ok_or_else(|| MuscleError::Unsupported {
                muscle: force.name.clone(),
                class: force.class.clone(),
            })?;
        HillMuscle::new(&force.name, spec)
    }

    pub fn new(name: &str, spec: &MuscleSpec) -> Result<HillMuscle, MuscleError> {
        Ok(match &spec.model {
            MuscleModelSpec::Millard2012(m) => {
                HillMuscle::Millard(Box::new(Millard2012Muscle::new(name, spec, m)?))
            }
            MuscleModelSpec::Thelen2003(t) => {
                HillMuscle::Thelen(Thelen2003Muscle::new(name, spec, t)?)
            }
            MuscleModelSpec::DeGrooteFregly2016(d) => {
                HillMuscle::DeGroote(DeGrooteFregly2016Muscle::new(name, spec, d)?)
            }
        })
    }

    /// Static equilibrium (fiber velocity 0) at activation `activation` ∈ [0, 1] and path length
    /// `mt_length` (m).
    pub fn equilibrium(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<FiberEquilibrium, MuscleError> {
        match self {
            HillMuscle::Millard(m) => m.equilibrium(activation, mt_length),
            HillMuscle::Thelen(m) => m.equilibrium(activation, mt_length),
            HillMuscle::DeGroote(m) => m.equilibrium(activation, mt_length),
        }
    }

    /// The fiber length (m) OpenSim's `equilibrateMuscles` starts a forward simulation from, at
    /// `activation` ∈ [0, 1] on a path of length `mt_length` (m) lengthening at
    /// `lengthening_speed` (m/s): the static equilibrium for Millard (which ignores the speed),
    /// `initMuscleState`'s speed-sharing iteration for Thelen, and for a compliant DeGroote
    /// muscle the bisection for its normalized tendon force at that speed.
    pub fn initial_fiber_length(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> Result<f64, MuscleError> {
        match self {
            HillMuscle::Thelen(m) => {
                check_inputs(m.name(), activation, mt_length)?;
                m.initial_fiber_length(activation, mt_length, lengthening_speed)
            }
            HillMuscle::DeGroote(m) if !m.ignore_tendon_compliance => {
                let force = m.initial_normalized_tendon_force(activation, mt_length, lengthening_speed)?;
                Ok(m.fiber_length_at(mt_length, force))
            }
            _ => Ok(self.equilibrium(activation, mt_length)?.fiber_length),
        }
    }

    /// Static force balance F_m cos α − F_t (N, zero fiber velocity) at fiber length
    /// `fiber_length` (m) for the classes that solve for the fiber length (Millard, Thelen);
    /// `None` for DeGroote, which solves for the tendon force.
    pub fn static_force_residual(
        &self,
        activation: f64,
        fiber_length: f64,
        mt_length: f64,
    ) -> Option<f64> {
        match self {
            HillMuscle::Millard(m) => Some(
                m.force_balance(m.clamp_activation(activation), fiber_length, mt_length)
                    .0,
            ),
            HillMuscle::Thelen(m) => {
                Some(m.static_force_residual(activation, fiber_length, mt_length))
            }
            HillMuscle::DeGroote(_) => None,
        }
    }

    /// OpenSim's `calcInextensibleTendonActiveFiberForce`: the active fiber force along the tendon (N)
    /// at `activation` with the tendon at its slack length, for a path of length `mt_length` (m)
    /// lengthening at `lengthening_speed` (m/s). StaticOptimization (use_muscle_physiology) takes
    /// it as the muscle's force at activation 1. Each class keeps OpenSim's quirks: Millard
    /// evaluates the pennation at the normalised fiber length, Thelen inverts its force–velocity
    /// relation iteratively (NaN where OpenSim throws), DeGroote returns the force along the
    /// fiber and does not clamp the activation; Millard and Thelen give 0 at the minimum fiber
    /// length.
    pub fn inextensible_tendon_active_fiber_force(
        &self,
        activation: f64,
        mt_length: f64,
        lengthening_speed: f64,
    ) -> f64 {
        let (a, length, speed) = (activation, mt_length, lengthening_speed);
        match self {
            HillMuscle::Millard(m) => m.inextensible_tendon_active_fiber_force(a, length, speed),
            HillMuscle::Thelen(m) => m.inextensible_tendon_active_fiber_force(a, length, speed),
            HillMuscle::DeGroote(m) => m.inextensible_tendon_active_fiber_force(a, length, speed),
        }
    }

    /// The activation the dynamics and forces see at least (Millard, Thelen); 0 for DeGroote.
    pub fn minimum_activation(&self) -> f64 {
        match self {
            HillMuscle::Millard(m) => m.minimum_activation,
            HillMuscle::Thelen(m) => m.clamp_activation(0.0),
            HillMuscle::DeGroote(_) => 0.0,
        }
    }

    /// F_t = F_max f_T(L_t / L_ts) (N) with the fiber at `fiber_length` (m, raised to the
    /// minimum fiber length for Millard and Thelen) on a path of length `mt_length` (m),
    /// L_t = L_mt − L_m cos α.
    pub fn tendon_force(&self, fiber_length: f64, mt_length: f64) -> f64 {
        match self {
            HillMuscle::Millard(m) => m.tendon_force(fiber_length, mt_length),
            HillMuscle::Thelen(m) => m.tendon_force(fiber_length, mt_length),
            HillMuscle::DeGroote(m) => m.tendon_force(fiber_length, mt_length),
        }
    }

    /// The shortest fiber the muscle allows, m (Millard, Thelen: `getMinimumFiberLength`); 0 for
    /// DeGroote, which has no fiber-length state.
    pub fn minimum_fiber_length(&self) -> f64 {
        match self {
            HillMuscle::Millard(m) => m.minimum_fiber_length,
            HillMuscle::Thelen(m) => m.minimum_fiber_length(),
            HillMuscle::DeGroote(_) => 0.0,
        }
    }

    /// Whether the fiber follows the path beside a rigid tendon (`ignore_tendon_compliance`).
    pub fn has_rigid_tendon(&self) -> bool {
        match self {
            HillMuscle::Millard(m) => m.ignore_tendon_compliance,
            HillMuscle::Thelen(_) => false,
            HillMuscle::DeGroote(m) => m.ignore_tendon_compliance,
        }
    }

    /// (L_m in m, F_t in N) of a rigid-tendon Millard or DeGroote muscle at `activation` on a
    /// path of length `mt_length` (m) lengthening at `lengthening_speed` (m/s); `None` for other
    /// muscles.
    pub fn rigid_tendon_state(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> Option<(f64, f64)> {
        match self {
            HillMuscle::Millard(m) if m.ignore_tendon_compliance => {
                Some((m.rigid_tendon_fiber_length(mt_length), m.rigid_tendon_force(activation, mt_length, lengthening_speed)))
            }
            HillMuscle::DeGroote(m) if m.ignore_tendon_compliance => Some(m.rigid_tendon_state(activation, mt_length, lengthening_speed)),
            _ => None,
        }
    }

    /// The muscle at activation `activation` ∈ [0, 1] with its second state `state` — the fiber
    /// length (m, Millard and Thelen) or the normalized tendon force (DeGroote); ignored by a
    /// rigid tendon — on a path of length `mt_length` (m) lengthening at `lengthening_speed`
    /// (m/s), as OpenSim reports it.
    pub fn state(&self, activation: f64, state: f64, mt_length: f64, lengthening_speed: f64) -> Result<MuscleState, MuscleError> {
        match self {
            HillMuscle::Millard(m) => m.state(activation, state, mt_length, lengthening_speed),
            HillMuscle::Thelen(m) => m.state(activation, state, mt_length, lengthening_speed),
            HillMuscle::DeGroote(m) => m.state(activation, state, mt_length, lengthening_speed),
        }
    }

    /// dL_m/dt (m/s) at activation `activation`, fiber length `fiber_length` (m) and path
    /// length `mt_length` (m), the path at rest: the state derivative OpenSim's forward
    /// simulation uses (Millard, Thelen and implicit-mode DeGroote balance fiber and tendon
    /// forces; explicit-mode DeGroote, as OpenSim, leaves fiber damping out). Lengthening
    /// positive.
    pub fn fiber_velocity(
        &self,
        activation: f64,
        fiber_length: f64,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        match self {
            HillMuscle::Millard(m) => m.fiber_velocity(activation, fiber_length, mt_length),
            HillMuscle::Thelen(m) => m.fiber_velocity(activation, fiber_length, mt_length),
            HillMuscle::DeGroote(m) => m.fiber_velocity(activation, fiber_length, mt_length),
        }
    }
}

/// Checks activation ∈ [0, 1] and a positive, finite path length.
pub(crate) fn check_inputs(
    muscle: &str,
    activation: f64,
    mt_length: f64,
) -> Result<(), MuscleError> {
    if !(0.0..=1.0).contains(&activation) {
        return Err(MuscleError::invalid_input(
            muscle,
            "activation",
            activation,
            "a number in [0, 1]",
        ));
    }
    if !(mt_length > 0.0 && mt_length.is_finite()) {
        return Err(MuscleError::invalid_input(
            muscle,
            "muscle-tendon length",
            mt_length,
            "a positive length in m",
        ));
    }
    Ok(())
}

/// Fiber velocity is a state derivative only with a compliant tendon: a rigid-tendon muscle
/// (`ignore_tendon_compliance`) has no fiber-length state, its fiber follows the path.
pub(crate) fn check_compliant_tendon(muscle: &str, ignore_tendon_compliance: bool) -> Result<(), MuscleError> {
    if ignore_tendon_compliance {
        let expected = "a compliant tendon (a rigid-tendon muscle has no fiber-length state; its fiber follows the path)";
        return Err(MuscleError::invalid_input(muscle, "ignore_tendon_compliance", 1.0, expected));
    }
    Ok(())
}
