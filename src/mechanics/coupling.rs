//! `CoordinateCouplerConstraint`s: q_dependent = scale · f(q_independent), and the coupling
//! vectors OpenSim's `MomentArmSolver` uses to sum generalized forces over coupled coordinates:
//! along the couplers, or, in a model with links, by projecting the lit speed onto every
//! velocity constraint.

use std::path::Path;

use nalgebra::{DMatrix, DVector};

use super::error::MechanicsError;
use super::function::Function;
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use crate::model::{CoordinateSpec, ModelSpec};

/// One enforced coupler, by coordinate index.
#[derive(Debug, Clone)]
pub struct Coupler {
    pub name: String,
    pub independent: usize,
    pub dependent: usize,
    pub function: Function,
    pub scale: f64,
}

impl Coupler {
    /// Every enforced coupler of `model`; `coordinates` in CoordinateSet order.
    pub fn compile_all(model: &ModelSpec, coordinates: &[CoordinateSpec], file: &Path) -> Result<Vec<Coupler>, MechanicsError> {
        let mut couplers = Vec::new();
        for constraint in model.constraints.iter().filter(|c| c.enforced) {
            let Some(coupler) = &constraint.coupler else { continue };
            let invalid = |problem: String| MechanicsError::Invalid { file: file.into(), component: constraint.name.clone(), problem };
            let index = |name: &str| coordinates.iter().position(|c| c.name == name).ok_or_else(|| invalid(format!("coordinate {name:?} does not exist in the model")));
            let [independent] = coupler.independent_coordinates.as_slice() else {
                return Err(MechanicsError::Unsupported {
                    file: file.into(),
                    component: constraint.name.clone(),
                    what: format!("a coupler of {} independent coordinates", coupler.independent_coordinates.len()),
                });
            };
            couplers.push(Coupler {
                name: constraint.name.clone(),
                independent: index(independent)?,
                dependent: index(&coupler.dependent_coordinate)?,
                function: Function::new(&coupler.function),
                scale: coupler.scale_factor,
            });
        }
        Ok(couplers)
    }

    /// dq_dependent / dq_independent at coordinate values `q`.
    pub fn slope(&self, q: &[f64]) -> f64 {
        self.scale * self.function.derivative(q[self.independent])
    }

    /// d²q_dependent / dq_independent² at coordinate values `q`.
    pub fn curvature(&self, q: &[f64]) -> f64 {
        self.scale * self.function.second_derivative(q[self.independent])
    }

    /// q_dependent for the independent value in `q`.
    pub fn dependent_value(&self, q: &[f64]) -> f64 {
        self.scale * self.function.value(q[self.independent])
    }
}

/// Calls `term(coordinate, weight)` for each entry of the coupling vector of `coordinate`: the
/// coordinate's speed is lit and the coupled speeds follow the constraints, normalised by the
/// lit coordinate's resulting speed (OpenSim's `MomentArmSolver::computeCouplingVector`).
pub fn for_each_coupling(couplers: &[Coupler], q: &[f64], coordinate: usize, mut term: impl FnMut(usize, f64)) {
    let (root, scale) = match couplers.iter().find(|k| k.dependent == coordinate) {
        Some(k) => (k.independent, 1.0 / k.slope(q)),
        None => (coordinate, 1.0),
    };
    term(root, scale);
    for k in couplers.iter().filter(|k| k.independent == root) {
        term(k.dependent, scale * k.slope(q));
    }
}

/// The coordinates coupled to `coordinate` (its independent coordinate and that one's other
/// dependents, or its dependents), without `coordinate` itself.
pub fn partners(couplers: &[Coupler], coordinate: usize) -> Vec<usize> {
    let root = couplers.iter().find(|k| k.dependent == coordinate).map_or(coordinate, |k| k.independent);
    let mut group: Vec<usize> = std::iter::once(root).chain(couplers.iter().filter(|k| k.independent == root).map(|k| k.dependent)).collect();
    group.retain(|&c| c != coordinate);
    group
}

/// `coordinates` with every coordinate a constraint ties to them: couplers' partners and, for
/// each link one of them moves an end body of, every coordinate that moves either end body —
/// repeated until nothing is added. Sorted, without repeats.
pub fn tied_coordinates(multibody: &Multibody, coordinates: &[usize]) -> Vec<usize> {
    let movers: Vec<Vec<usize>> = multibody
        .links
        .iter()
        .map(|link| (0..multibody.coordinates.len()).filter(|&c| link.ends.iter().any(|end| multibody.is_moved_by(end.body, multibody.coordinate_joint(c)))).collect())
        .collect();
    let mut tied = coordinates.to_vec();
    tied.sort_unstable();
    tied.dedup();
    loop {
        let before = tied.len();
        let partners: Vec<usize> = tied.iter().flat_map(|&c| partners(&multibody.couplers, c)).collect();
        tied.extend(partners);
        let reached: Vec<usize> = movers.iter().filter(|group| group.iter().any(|c| tied.contains(c))).flatten().copied().collect();
        tied.extend(reached);
        tied.sort_unstable();
        tied.dedup();
        if tied.len() == before {
            return tied;
        }
    }
}

/// A coupling vector found by projection ([`projected_coupling`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectedCoupling {
    /// (coordinate, weight) for the nonzero entries; empty when the coordinate cannot move on
    /// its own.
    pub weights: Vec<(usize, f64)>,
    /// The lit coordinate's speed after the projection (of the unit speed it was given): near 0
    /// when the constraints nearly fix it, where its moment arms are ill-defined.
    pub lit_speed: f64,
}

/// Below this projected speed (of a unit lit speed) a coordinate counts as fixed by the
/// constraints.
const FIXED_SPEED: f64 = 1e-9;
/// Singular values of the velocity-constraint matrix below this fraction of the largest are
/// taken as zero (redundant constraints).
const RANK_TOLERANCE: f64 = 1e-10;

/// OpenSim's `MomentArmSolver::computeCouplingVector` with constraints between bodies: the
/// coordinate's speed is lit (unit), every other speed 0, and Simbody's `projectU` takes the
/// nearest speeds (unit weights) that satisfy all velocity constraints — couplers,
/// [`BodyLink`](super::BodyLink)s, locked coordinates other than this one — at the realized pose;
/// the result divided by the lit coordinate's remaining speed.
///
/// OpenSim unlocks the lit coordinate in its path's solver's own copy of the state and never
/// locks it again, so its later moment arms about other coordinates treat that coordinate as
/// free: its values depend on which coordinates were asked about before. We answer as a fresh
/// solver does (every other lock held): e.g. PushUpToesOnGroundWithMuscles' EDCR about
/// wrist_flexion_l is 0.00684 m fresh, −0.0128 m once wrist_flexion_r has been asked about.
pub fn projected_coupling(multibody: &Multibody, kinematics: &Kinematics, q: &[f64], coordinate: usize) -> ProjectedCoupling {
    let g = velocity_constraints(multibody, kinematics, q, coordinate);
    let mut u = DVector::zeros(multibody.coordinates.len());
    u[coordinate] = 1.0;
    if g.nrows() > 0 {
        let svd = g.svd(false, true);
        let largest = svd.singular_values.max();
        if let Some(v_t) = svd.v_t.as_ref() {
            for (k, &sigma) in svd.singular_values.iter().enumerate() {
                if sigma > RANK_TOLERANCE * largest {
                    let row = v_t.row(k);
                    u -= row.transpose() * row[coordinate];
                }
            }
        }
    }
    let lit_speed = u[coordinate];
    let weights = if lit_speed.abs() < FIXED_SPEED {
        Vec::new()
    } else {
        u.iter().enumerate().filter(|(_, w)| **w != 0.0).map(|(c, w)| (c, w / lit_speed)).collect()
    };
    ProjectedCoupling { weights, lit_speed }
}

/// The velocity constraints G·u = 0 at the realized pose: one row per coupler (u_dependent −
/// f′·u_independent), per locked coordinate other than `lit`, per link error.
fn velocity_constraints(multibody: &Multibody, kinematics: &Kinematics, q: &[f64], lit: usize) -> DMatrix<f64> {
    let n = multibody.coordinates.len();
    let locked: Vec<usize> = (0..n).filter(|&c| c != lit && multibody.coordinates[c].locked).collect();
    let link_rows: usize = multibody.links.iter().map(|link| link.rows()).sum();
    let mut g = DMatrix::zeros(multibody.couplers.len() + locked.len() + link_rows, n);
    for (row, coupler) in multibody.couplers.iter().enumerate() {
        g[(row, coupler.dependent)] += 1.0;
        g[(row, coupler.independent)] -= coupler.slope(q);
    }
    let mut row = multibody.couplers.len();
    for c in locked {
        g[(row, c)] = 1.0;
        row += 1;
    }
    let links = multibody.link_jacobian(kinematics);
    g.rows_mut(row, links.nrows()).copy_from(&links);
    g
}
