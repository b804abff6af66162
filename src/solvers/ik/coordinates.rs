//! The unknowns of a frame: which coordinates are free, which are held and which follow a
//! coupler, mapping the free values x to a full pose q and carrying ∂q/∂x.
//!
//! OpenSim's rules (`AssemblySolver::setupGoals`, Simbody's `Assembler`):
//! - a locked coordinate stays at the value it was locked at, its `default_value`;
//! - a clamped coordinate is bounded by its range; an unclamped one is not bounded at all;
//! - with an infinite constraint weight (what OpenSim 4.6's `InverseKinematicsTool` always
//!   uses, see [`ConstraintWeight`]) a `CoordinateCouplerConstraint` holds exactly:
//!   q_dependent = scale · f(q_independent), so the dependent coordinate is no unknown;
//! - with a finite weight every constraint error becomes a weighted goal instead (the coupler's
//!   and the lock of each locked coordinate that has no coordinate task).

use crate::mechanics::{Coupler, Multibody};
use crate::solvers::least_squares::Bounds;
use crate::solvers::IkError;

/// How strictly the model's kinematic constraints (couplers, coordinate locks) hold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ConstraintWeight {
    /// Exactly (Simbody treats them as assembly errors). OpenSim 4.6's `InverseKinematicsTool`
    /// always solves this way: the `InverseKinematicsSolver` constructor it calls assigns
    /// `SimTK::Infinity` to the weight before passing it on, whatever `constraint_weight` says.
    Infinite,
    /// As goals: w · e²/2 added to the objective per constraint error e (Simbody's
    /// `BuiltInConstraints` goal), e = scale·f(q_independent) − q_dependent for a coupler and
    /// q − default_value for a lock.
    Finite(f64),
}

/// What a coordinate is during a solve.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Role {
    /// Unknown number k.
    Free(usize),
    /// Held at this value.
    Held(f64),
    /// Follows coupler k exactly.
    Dependent(usize),
}

/// Free values ↔ pose, bounds and the constraint goals of a finite weight.
#[derive(Debug, Clone)]
pub(super) struct CoordinateMap {
    roles: Vec<Role>,
    /// The coordinate of each unknown.
    free: Vec<usize>,
    /// Couplers whose dependents are computed, independents first.
    dependents: Vec<usize>,
    pub bounds: Bounds,
    /// Goals of a finite constraint weight: √w and what they hold.
    pub soft_couplers: Vec<usize>,
    pub soft_locks: Vec<usize>,
    pub root_weight: f64,
}

/// ∂q_c/∂x as (unknown, coefficient) lists, per coordinate, at one pose.
#[derive(Debug, Clone, Default)]
pub(super) struct PoseDerivatives {
    lists: Vec<Vec<(usize, f64)>>,
}

impl PoseDerivatives {
    /// ∂q_c/∂x as (unknown, coefficient) pairs.
    pub fn of(&self, c: usize) -> &[(usize, f64)] {
        &self.lists[c]
    }
}

impl CoordinateMap {
    /// `tasked[c]`: whether coordinate c has a coordinate task (a locked coordinate with a task
    /// is locked in the assembler even when constraints are goals).
    pub fn new(multibody: &Multibody, weight: ConstraintWeight, tasked: &[bool]) -> Result<CoordinateMap, IkError> {
        let coordinates = &multibody.coordinates;
        let unsupported = |component: &str, what: &str| IkError::Unsupported { model: multibody.file.clone(), component: component.into(), what: what.into() };
        if let Some(c) = coordinates.iter().find(|c| c.prescribed) {
            return Err(unsupported(&c.name, "a prescribed coordinate"));
        }
        let root_weight = match weight {
            ConstraintWeight::Infinite => f64::INFINITY,
            ConstraintWeight::Finite(w) if w.is_finite() && w >= 0.0 => w.sqrt(),
            ConstraintWeight::Finite(w) => return Err(IkError::InvalidWeight { name: "constraint weight".into(), weight: w }),
        };
        let exact = root_weight.is_infinite();
        let mut roles = vec![Role::Free(0); coordinates.len()];
        let mut soft_locks = Vec::new();
        for (c, spec) in coordinates.iter().enumerate() {
            if spec.locked && (exact || tasked[c]) {
                roles[c] = Role::Held(spec.default_value);
            } else if spec.locked && root_weight > 0.0 {
                soft_locks.push(c);
            }
        }
        let mut soft_couplers = Vec::new();
        if exact {
            for (k, coupler) in multibody.couplers.iter().enumerate() {
                let dependent = &coordinates[coupler.dependent];
                if dependent.locked {
                    return Err(unsupported(&coupler.name, "a coupler whose dependent coordinate is locked"));
                }
                if dependent.clamped {
                    return Err(unsupported(&coupler.name, "a coupler whose dependent coordinate is clamped (a bound through the coupling function)"));
                }
                if matches!(roles[coupler.dependent], Role::Dependent(_)) {
                    return Err(unsupported(&dependent.name, "a coordinate that is the dependent of two couplers"));
                }
                roles[coupler.dependent] = Role::Dependent(k);
            }
        } else if root_weight > 0.0 {
            soft_couplers = (0..multibody.couplers.len()).collect();
        }
        let dependents = evaluation_order(&multibody.couplers, &roles).ok_or_else(|| unsupported("couplers", "a cycle of couplers"))?;
        let mut free = Vec::new();
        let (mut lower, mut upper) = (Vec::new(), Vec::new());
        for (c, role) in roles.iter_mut().enumerate() {
            if let Role::Free(k) = role {
                *k = free.len();
                free.push(c);
                let spec = &coordinates[c];
                lower.push(if spec.clamped { spec.range[0] } else { f64::NEG_INFINITY });
                upper.push(if spec.clamped { spec.range[1] } else { f64::INFINITY });
            }
        }
        Ok(CoordinateMap { roles, free, dependents, bounds: Bounds { lower, upper }, soft_couplers, soft_locks, root_weight })
    }

    pub fn variable_count(&self) -> usize {
        self.free.len()
    }

    /// Whether coordinate c is held (locked, or a dependent of a held coordinate).
    pub fn is_held(&self, c: usize) -> bool {
        matches!(self.roles[c], Role::Held(_))
    }

    /// The free values of pose `q`.
    pub fn free_values(&self, q: &[f64], x: &mut [f64]) {
        for (value, &c) in x.iter_mut().zip(&self.free) {
            *value = q[c];
        }
    }

    /// The pose of free values `x`: held values, then the dependents.
    pub fn pose(&self, multibody: &Multibody, x: &[f64], q: &mut [f64]) {
        for (c, role) in self.roles.iter().enumerate() {
            match role {
                Role::Free(k) => q[c] = x[*k],
                Role::Held(value) => q[c] = *value,
                Role::Dependent(_) => {}
            }
        }
        for &k in &self.dependents {
            let coupler = &multibody.couplers[k];
            q[coupler.dependent] = coupler.dependent_value(q);
        }
    }

    /// Speeds and accelerations of every coordinate at pose `q` (from [`CoordinateMap::pose`])
    /// for rates `x_dot` and `x_ddot` of the free values: held coordinates rest, a dependent
    /// follows its coupler (u_d = f′ u_i, u̇_d = f″ u_i² + f′ u̇_i).
    pub fn rates(&self, multibody: &Multibody, q: &[f64], x_dot: &[f64], x_ddot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (mut u, mut udot) = (vec![0.0; self.roles.len()], vec![0.0; self.roles.len()]);
        for (c, role) in self.roles.iter().enumerate() {
            if let Role::Free(k) = role {
                (u[c], udot[c]) = (x_dot[*k], x_ddot[*k]);
            }
        }
        for &k in &self.dependents {
            let coupler = &multibody.couplers[k];
            let (slope, curvature, speed) = (coupler.slope(q), coupler.curvature(q), u[coupler.independent]);
            u[coupler.dependent] = slope * speed;
            udot[coupler.dependent] = curvature * speed * speed + slope * udot[coupler.independent];
        }
        (u, udot)
    }

    /// ∂q/∂x at pose `q` (from [`CoordinateMap::pose`]).
    pub fn derivatives(&self, multibody: &Multibody, q: &[f64], derivatives: &mut PoseDerivatives) {
        derivatives.lists.resize_with(self.roles.len(), Vec::new);
        for (c, role) in self.roles.iter().enumerate() {
            let list = &mut derivatives.lists[c];
            list.clear();
            if let Role::Free(k) = role {
                list.push((*k, 1.0));
            }
        }
        for &k in &self.dependents {
            let coupler = &multibody.couplers[k];
            let slope = coupler.slope(q);
            let mut terms = std::mem::take(&mut derivatives.lists[coupler.dependent]);
            terms.extend(derivatives.lists[coupler.independent].iter().map(|&(x, d)| (x, slope * d)));
            derivatives.lists[coupler.dependent] = terms;
        }
    }
}

/// Couplers with a dependent role, ordered so that each one's independent coordinate is known
/// before it is used; `None` for a cycle.
fn evaluation_order(couplers: &[Coupler], roles: &[Role]) -> Option<Vec<usize>> {
    let pending: Vec<usize> = (0..couplers.len()).filter(|&k| roles[couplers[k].dependent] == Role::Dependent(k)).collect();
    let mut known: Vec<bool> = roles.iter().map(|r| !matches!(r, Role::Dependent(_))).collect();
    let mut order = Vec::with_capacity(pending.len());
    while order.len() < pending.len() {
        let before = order.len();
        for &k in &pending {
            let coupler = &couplers[k];
            if !known[coupler.dependent] && known[coupler.independent] {
                known[coupler.dependent] = true;
                order.push(k);
            }
        }
        if order.len() == before {
            return None;
        }
    }
    Some(order)
}
