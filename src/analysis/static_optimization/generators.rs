//! What static optimisation distributes the generalized forces over, and what a joint reaction
//! analysis applies: the model's muscles and scalar actuators (ForceSet order, then the
//! actuators of added force-set files), each with its control bounds, its generalized forces per
//! unit control in a state and the loads a force of it applies.

use crate::mechanics::muscle::{HillMuscle, MuscleError, MuscleState};
use crate::mechanics::{Actuator, AppliedForces, Kinematics, MechanicsError, MuscleGeometry, PathEvaluation, PathScratch, TransformRates};
use crate::model::{ActuatorSpec, ModelSpec, MuscleModelSpec};

use super::StaticOptimizationError;

/// A muscle (force a·F₁ along its path, F₁ its force at activation 1) or a scalar actuator
/// (force a·optimal_force).
#[derive(Debug, Clone)]
pub struct Generator {
    pub name: String,
    /// [min_control, max_control].
    pub bounds: [f64; 2],
    kind: Kind,
}

#[derive(Debug, Clone)]
enum Kind {
    /// `path` indexes `MuscleGeometry::paths`, `slot` the muscles of the `PathEvaluation` built
    /// from the muscles' paths in generator order.
    Muscle { muscle: Box<HillMuscle>, path: usize, slot: usize, max_isometric_force: f64, time_constants: [f64; 2] },
    Actuator { actuator: Actuator, optimal_force: f64 },
}

/// The generators of `spec` (unless `replace`, which keeps only `added`) and of `added` for the
/// inverse problems (static optimisation, joint reactions), which hold couplers and links between
/// bodies: a model with other enforced constraints is refused. `force_generators` skips that
/// check (the forward dynamics refuses them itself).
pub fn generators(spec: &ModelSpec, geometry: &MuscleGeometry, added: &[ActuatorSpec], replace: bool) -> Result<Vec<Generator>, StaticOptimizationError> {
    let constraints = &geometry.multibody.unheld_constraints;
    if !constraints.is_empty() {
        return Err(StaticOptimizationError::Model(format!(
            "{}: the constraints {} are enforced; osim-tune's inverse problems hold only CoordinateCouplerConstraints and point, distance, point-on-line and weld constraints (disable the others, or remove them)",
            spec.file.display(),
            constraints.join(", ")
        )));
    }
    force_generators(spec, geometry, added, replace)
}

/// The generators of `spec` (unless `replace`) and of `added`, whatever the constraints (the
/// forward dynamics refuses those it does not hold); forces that apply no force are left out, and any other force
/// is refused (we cannot apply it).
pub fn force_generators(spec: &ModelSpec, geometry: &MuscleGeometry, added: &[ActuatorSpec], replace: bool) -> Result<Vec<Generator>, StaticOptimizationError> {
    let mut generators = Vec::new();
    for force in spec.forces.iter().filter(|f| !replace && f.applies_force) {
        if force.is_muscle() {
            let muscle = HillMuscle::from_force(force).map_err(|e| StaticOptimizationError::Model(e.to_string()))?;
            let muscle_spec = force.muscle.as_ref().ok_or_else(|| StaticOptimizationError::Model(format!("{}: no muscle properties", force.name)))?;
            let path = geometry.path_index(&force.name).ok_or_else(|| StaticOptimizationError::Model(format!("muscle {} has no path", force.name)))?;
            let minimum = match &muscle_spec.model {
                MuscleModelSpec::Millard2012(m) => m.minimum_activation,
                MuscleModelSpec::Thelen2003(t) => t.minimum_activation,
                MuscleModelSpec::DeGrooteFregly2016(_) => 0.0,
            };
            let time_constants = muscle_spec.time_constants();
            let bounds = [force.controls[0].unwrap_or(minimum), force.controls[1].unwrap_or(1.0)];
            let slot = generators.iter().filter(|g: &&Generator| g.muscle_path().is_some()).count();
            let kind = Kind::Muscle { muscle: Box::new(muscle), path, slot, max_isometric_force: muscle_spec.max_isometric_force, time_constants };
            generators.push(Generator { name: force.name.clone(), bounds, kind });
        } else if let Some(actuator) = spec.actuators.iter().find(|a| a.name == force.name) {
            generators.push(actuator_generator(actuator, geometry)?);
        } else {
            return Err(StaticOptimizationError::Model(format!(
                "{}: force {} ({}) is neither a muscle nor a Coordinate-, Point- or TorqueActuator; osim-tune cannot apply it (static optimisation, joint reactions)",
                spec.file.display(),
                force.name,
                force.class
            )));
        }
    }
    for actuator in added.iter().filter(|a| a.applies_force) {
        generators.push(actuator_generator(actuator, geometry)?);
    }
    Ok(generators)
}

fn actuator_generator(spec: &ActuatorSpec, geometry: &MuscleGeometry) -> Result<Generator, StaticOptimizationError> {
    let actuator = Actuator::new(spec, &geometry.multibody).map_err(|e: MechanicsError| StaticOptimizationError::Model(e.to_string()))?;
    Ok(Generator { name: spec.name.clone(), bounds: [spec.min_control, spec.max_control], kind: Kind::Actuator { actuator, optimal_force: spec.optimal_force } })
}

impl Generator {
    /// The force at control 1 (N or N·m): a muscle's active fiber force along the tendon with a
    /// rigid tendon at activation 1 (`physiology`, OpenSim's `use_muscle_physiology`) or F_max, at
    /// its path's `length` (m) and `lengthening_speed` (m/s); an actuator's optimal force.
    pub fn unit_force(&self, physiology: bool, length: f64, lengthening_speed: f64) -> f64 {
        match &self.kind {
            Kind::Muscle { muscle, max_isometric_force, .. } => {
                if physiology {
                    muscle.inextensible_tendon_active_fiber_force(1.0, length, lengthening_speed)
                } else {
                    *max_isometric_force
                }
            }
            Kind::Actuator { optimal_force, .. } => *optimal_force,
        }
    }

    /// The force (N or N·m) at control `control`: a muscle's tendon force with its fiber in
    /// static equilibrium (zero fiber velocity, passive force included) on a path of length
    /// `length` (m); an actuator's control × optimal force.
    pub fn equilibrium_force(&self, control: f64, length: f64) -> Result<f64, MuscleError> {
        match &self.kind {
            Kind::Muscle { muscle, .. } => Ok(muscle.equilibrium(control, length)?.tendon_force),
            Kind::Actuator { optimal_force, .. } => Ok(control * optimal_force),
        }
    }

    /// A muscle's tendon force (N) at its state `state` with its path at rest, as OpenSim's
    /// induced accelerations apply it: a rigid tendon's fiber then at rest too, a compliant
    /// tendon's force unchanged (it depends on the lengths only); an actuator's 0.
    pub fn force_at_rest(&self, state: &MuscleState) -> f64 {
        let Kind::Muscle { muscle, .. } = &self.kind else { return 0.0 };
        let report = &state.report;
        muscle.rigid_tendon_state(report.activation, report.mt_length, 0.0).map_or(report.tendon_force, |(_, force)| force)
    }

    /// A muscle's activation and deactivation time constants τ_a, τ_d (s).
    pub fn time_constants(&self) -> Option<[f64; 2]> {
        match &self.kind {
            Kind::Muscle { time_constants, .. } => Some(*time_constants),
            Kind::Actuator { .. } => None,
        }
    }

    /// A muscle's path and its slot among the evaluated paths.
    pub fn muscle_path(&self) -> Option<(usize, usize)> {
        match &self.kind {
            Kind::Muscle { path, slot, .. } => Some((*path, *slot)),
            Kind::Actuator { .. } => None,
        }
    }

    /// A scalar actuator's speed (m/s or rad/s, [`Actuator::speed`]) with the bodies moving as
    /// `motions` at speeds `u`; `None` for a muscle (its path's lengthening speed).
    pub fn actuator_speed(&self, motions: &[TransformRates], u: &[f64]) -> Option<f64> {
        let Kind::Actuator { actuator, .. } = &self.kind else { return None };
        Some(actuator.speed(motions, u))
    }

    /// What a force `force` (N or N·m) of the generator applies at coordinates `q`, whose body
    /// poses `kinematics` holds: a muscle's tension along its path
    /// ([`GeometryPath::tension_loads`](crate::mechanics::GeometryPath::tension_loads)), an
    /// actuator's actuation ([`Actuator::apply`]).
    pub fn apply(&self, geometry: &MuscleGeometry, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch, force: f64, applied: &mut AppliedForces) {
        match &self.kind {
            Kind::Muscle { path, .. } => geometry.paths[*path].tension_loads(kinematics, q, scratch, force, applied),
            Kind::Actuator { actuator, .. } => actuator.apply(kinematics, force, applied),
        }
    }

    /// Generalized forces per unit force (N·m or N per N or N·m) on every coordinate at the pose
    /// `paths` was evaluated at (whose body poses are `paths.kinematics()`).
    pub fn generalized_forces(&self, geometry: &MuscleGeometry, paths: &PathEvaluation, out: &mut [f64]) {
        out.fill(0.0);
        match &self.kind {
            Kind::Muscle { slot, .. } => {
                for (&c, r) in paths.coordinates(geometry, *slot).iter().zip(paths.moment_arms(*slot)) {
                    out[c] = *r;
                }
            }
            Kind::Actuator { actuator, .. } => actuator.generalized_forces(&geometry.multibody, paths.kinematics(), out),
        }
    }
}
