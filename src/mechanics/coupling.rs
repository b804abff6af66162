//! `CoordinateCouplerConstraint`s: q_dependent = scale · f(q_independent), and the coupling
//! vectors OpenSim's `MomentArmSolver` uses to sum generalized forces over coupled coordinates.

use std::path::Path;

use super::error::MechanicsError;
use super::function::Function;
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
