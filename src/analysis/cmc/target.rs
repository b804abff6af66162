//! CMC's optimisation targets: the generators' forces f at the predicted state, within their
//! force range. The forward dynamics are linear in f (q̈ = q̈₀ + S f), so each is a convex QP
//! (clarabel, solved to the optimum where OpenSim's IPOPT stops at its tolerance):
//! - `Fast` (`ActuatorForceTargetFast`, CMC's default): min Σⱼ (fⱼ/F₁,ⱼ)² with every task's
//!   acceleration met exactly, F₁ a muscle's active fiber force at activation 1 with a rigid
//!   tendon at the predicted path (`calcInextensibleTendonActiveFiberForce`), an actuator's
//!   optimal force;
//! - `Slow` (`ActuatorForceTarget`, RRA's): min Σᵢ wᵢ·(q̈ᵢ − q̈ᵢ*)² + s·Σⱼ (fⱼ/Fⱼ)², F a muscle's
//!   maximum isometric force, an actuator's optimal force, s the stress term's weight.
//!
//! The muscle state tasks' terms ([`super::state_tasks`]) join them: the fast target's linear
//! term and constant, the slow target's constant.

use nalgebra::{DMatrix, DVector};

use super::state_tasks::StateTerms;
use super::tracking::Controller;
use crate::analysis::simulation::{Plant, SimulatedState};
use crate::mechanics::{AppliedForces, PathScratch};
use crate::solvers::qp::{DenseQp, QpSettings};

/// Which of CMC's optimisation targets chooses the forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Fast,
    Slow,
}

/// The forces (N or N·m) `controller`'s target chooses at the `predicted` state at `time` (s) for
/// the tasks' `desired` accelerations and the state tasks' `terms`, within `bounds` ([lower,
/// upper]; an excluded generator's force is its lower bound), and the target's value there
/// (OpenSim's "performance", over the controlled generators).
pub fn optimal_forces(controller: &Controller, predicted: &SimulatedState, time: f64, (desired, terms): (&[f64], &StateTerms), stress_weight: f64, [lower, upper]: [&[f64]; 2]) -> Result<(Vec<f64>, f64), String> {
    let plant = controller.plant;
    let coordinates: Vec<usize> = controller.tasks.iter().map(|t| t.coordinate).collect();
    let (base, sensitivity) = acceleration_map(plant, predicted, time, &coordinates)?;
    // The variables: the controlled generators' forces; an excluded one's (its force range is a
    // point) joins the accelerations without forces.
    let free: Vec<usize> = (0..plant.generators.len()).filter(|&j| !controller.excluded[j]).collect();
    let offset: Vec<f64> = (0..coordinates.len())
        .map(|i| base[i] - desired[i] + (0..plant.generators.len()).filter(|&j| controller.excluded[j]).map(|j| sensitivity[(i, j)] * lower[j]).sum::<f64>())
        .collect();
    let n = free.len();
    // In the variables x = f/c (c the force scales) the stress term is Σx² for both targets.
    let scales: Vec<f64> = match controller.target {
        Target::Fast => fast_scales(plant, predicted, &free),
        Target::Slow => free.iter().map(|&j| plant.generators[j].unit_force(false, 0.0, 0.0).abs()).collect(),
    };
    let scaled = DMatrix::from_fn(coordinates.len(), n, |i, k| sensitivity[(i, free[k])] * scales[k]);
    let (lower_x, upper_x): (Vec<f64>, Vec<f64>) = free.iter().zip(&scales).map(|(&j, c)| (lower[j] / c, upper[j] / c)).unzip();
    let solved = match controller.target {
        Target::Fast => {
            let hessian = DMatrix::from_diagonal_element(n, n, 2.0);
            let weighted: Vec<usize> = (0..coordinates.len()).filter(|&i| controller.tasks[i].task.weight != 0.0).collect();
            let rows = DMatrix::from_fn(weighted.len(), n, |r, k| scaled[(weighted[r], k)]);
            let rhs: Vec<f64> = weighted.iter().map(|&i| -offset[i]).collect();
            let linear: Vec<f64> = free.iter().zip(&scales).map(|(&j, c)| terms.linear[j] * c).collect();
            let qp = DenseQp::new(&hessian, &linear).and_then(|qp| qp.with_equalities(&rows, &rhs)).and_then(|qp| qp.with_bounds(&lower_x, &upper_x)).map_err(|e| e.to_string())?;
            qp.solve(&QpSettings::default())
        }
        Target::Slow => {
            let weights = DMatrix::from_diagonal(&DVector::from_iterator(coordinates.len(), controller.tasks.iter().map(|t| t.task.weight)));
            let hessian = 2.0 * (scaled.transpose() * &weights * &scaled + DMatrix::from_diagonal_element(n, n, stress_weight));
            let linear: Vec<f64> = (2.0 * scaled.transpose() * &weights * DVector::from_vec(offset.clone())).iter().copied().collect();
            let qp = DenseQp::new(&hessian, &linear).and_then(|qp| qp.with_bounds(&lower_x, &upper_x)).map_err(|e| e.to_string())?;
            qp.solve(&QpSettings::default())
        }
    };
    if !solved.status.is_solved() {
        return Err(format!(
            "no actuator forces within their ranges reach the desired accelerations ({:?}): are all coordinates actuated, tasks free of locked coordinates, reserve actuators unconstrained?",
            solved.status
        ));
    }
    let x = &solved.x;
    let stress: f64 = x.iter().map(|x| x * x).sum();
    let performance = match controller.target {
        Target::Fast => stress + terms.weighted,
        Target::Slow => stress_weight * stress + (0..coordinates.len()).map(|i| controller.tasks[i].task.weight * (offset[i] + (0..n).map(|k| scaled[(i, k)] * x[k]).sum::<f64>()).powi(2)).sum::<f64>() + terms.unweighted,
    };
    let mut forces = lower.to_vec();
    for ((&j, x), c) in free.iter().zip(x).zip(&scales) {
        forces[j] = x * c;
    }
    Ok((forces, performance))
}

/// The fast target's force scale of each generator of `free`: a muscle's rigid-tendon active
/// fiber force at activation 1 on its predicted path (its magnitude, at least SimTK's `TinyReal`
/// as OpenSim floors it), an actuator's optimal force.
fn fast_scales(plant: &Plant, state: &SimulatedState, free: &[usize]) -> Vec<f64> {
    let multibody = &plant.geometry.multibody;
    let mut kinematics = multibody.kinematics();
    multibody.realize(&state.q, &mut kinematics);
    let mut scratch = PathScratch::default();
    free.iter()
        .map(|&j| &plant.generators[j])
        .map(|g| match g.muscle_path() {
            Some((path, _)) => {
                let path = &plant.geometry.paths[path];
                let (length, speed) = path.length_and_speed(multibody, &kinematics, &state.q, &mut scratch, &path.loaded, &state.u);
                let force = g.unit_force(true, length, speed);
                if force.abs() < TINY { TINY } else { force.abs() }
            }
            None => g.unit_force(false, 0.0, 0.0).abs(),
        })
        .collect()
}

/// SimTK's `TinyReal` (ε^1.25 of double precision, about 2e-20).
const TINY: f64 = 2.168404344971009e-20;

/// The `coordinates`' accelerations at `state` with no generator force, and their change per
/// unit force of each generator (rows: coordinates; columns: generators).
fn acceleration_map(plant: &Plant, state: &SimulatedState, time: f64, coordinates: &[usize]) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let multibody = &plant.geometry.multibody;
    let mut kinematics = multibody.kinematics();
    multibody.realize(&state.q, &mut kinematics);
    let loads = plant.external.map(|e| e.at(time, &kinematics)).unwrap_or_default();
    let zero = vec![0.0; state.q.len()];
    let dynamics = multibody.prepare_dynamics(&kinematics, &state.q, &state.u).map_err(|e| format!("forward dynamics: {e}"))?;
    let at = |applied: &AppliedForces| dynamics.solve(&applied.loads, &applied.mobility).map(|(udot, _)| udot).map_err(|e| format!("forward dynamics: {e}"));
    let base = at(&AppliedForces { loads: loads.clone(), mobility: zero.clone() })?;
    let mut sensitivity = DMatrix::zeros(coordinates.len(), plant.generators.len());
    let mut scratch = PathScratch::default();
    for (j, generator) in plant.generators.iter().enumerate() {
        let mut applied = AppliedForces { loads: loads.clone(), mobility: zero.clone() };
        generator.apply(plant.geometry, &kinematics, &state.q, &mut scratch, 1.0, &mut applied);
        let moved = at(&applied)?;
        for (i, &c) in coordinates.iter().enumerate() {
            sensitivity[(i, j)] = moved[c] - base[c];
        }
    }
    Ok((coordinates.iter().map(|&c| base[c]).collect(), sensitivity))
}
