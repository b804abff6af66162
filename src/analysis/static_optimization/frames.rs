//! One frame's static-optimisation problem: the generalized forces Σ aⱼ·Fⱼ·Rⱼ the controls a must
//! produce — one row per unconstrained coordinate — and the inverse-dynamics forces they must
//! equal.
//!
//! A `CoordinateCouplerConstraint` q_d = f(q_i) makes q_d constrained: OpenSim tracks only the
//! unconstrained coordinates' accelerations, and the dependent one follows the constraint,
//! q̈_d = f′·q̈_i + f″·q̇_i². The constraint force acts along (−f′, 1), so eliminating it leaves
//! one row per independent coordinate along its coupling vector (1, f′): muscle moment arms are
//! already taken along it (`MomentArmSolver`), actuator and inverse-dynamics forces are summed
//! along it here.

use nalgebra::DMatrix;

use super::generators::Generator;
use crate::analysis::external_loads::ExternalLoads;
use crate::mechanics::{for_each_coupling, Kinematics, MotionState, Multibody, MuscleGeometry, PathEvaluation};

/// A frame's rows: `matrix` a = `rhs`, with each generator's force at control 1.
pub struct FrameProblem {
    /// Rows: unlocked coordinates; columns: generators. N·m or N per unit control.
    pub matrix: DMatrix<f64>,
    /// Inverse dynamics at the tracked accelerations, N·m or N.
    pub rhs: Vec<f64>,
    /// Fⱼ: a muscle's force at activation 1 (N), an actuator's optimal force.
    pub unit_forces: Vec<f64>,
    /// `matrix` per unit force instead of per unit control: N·m or N per N or N·m.
    pub arms: DMatrix<f64>,
    /// A muscle's path length (m); 0 for an actuator.
    pub lengths: Vec<f64>,
}

/// What every frame's problem shares, and its buffers.
pub struct Frames<'a> {
    geometry: &'a MuscleGeometry,
    generators: &'a [Generator],
    loads: Option<&'a ExternalLoads>,
    /// OpenSim's `use_muscle_physiology`.
    physiology: bool,
    paths: PathEvaluation,
    /// Coordinates whose accelerations are tracked (not locked, not a coupler's dependent).
    rows: Vec<usize>,
    column: Vec<f64>,
}

impl<'a> Frames<'a> {
    pub fn new(geometry: &'a MuscleGeometry, generators: &'a [Generator], loads: Option<&'a ExternalLoads>, physiology: bool) -> Frames<'a> {
        let muscles: Vec<usize> = generators.iter().filter_map(|g| g.muscle_path().map(|(path, _)| path)).collect();
        let multibody = &geometry.multibody;
        let rows = multibody.coordinates.iter().enumerate().filter(|&(i, c)| !c.locked && !multibody.is_dependent(i)).map(|(i, _)| i).collect();
        let (paths, column) = (PathEvaluation::loading(geometry, &muscles), vec![0.0; geometry.multibody.coordinates.len()]);
        Frames { geometry, generators, loads, physiology, paths, rows, column }
    }

    /// Every generator's [min_control, max_control].
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.generators.iter().map(|g| (g.bounds[0], g.bounds[1])).unzip()
    }

    /// The coordinates whose rows each frame has, in row order.
    pub fn tracked(&self) -> &[usize] {
        &self.rows
    }

    /// The body poses of the last frame.
    pub fn kinematics(&self) -> &Kinematics {
        self.paths.kinematics()
    }

    /// The problem at `state` and `time` (s, for the external loads).
    pub fn problem(&mut self, state: &MotionState, time: f64) -> FrameProblem {
        let (geometry, generators, physiology) = (self.geometry, self.generators, self.physiology);
        let multibody = &geometry.multibody;
        self.paths.evaluate_moving(geometry, state.q, Some(state.u));
        let applied = self.loads.map(|l| l.at(time, self.paths.kinematics())).unwrap_or_default();
        let udot = constrained_accelerations(multibody, state);
        let demand = multibody.inverse_dynamics_at(self.paths.kinematics(), &MotionState { udot: &udot, ..*state }, &applied);
        let along = |forces: &[f64], c: usize| {
            let mut sum = 0.0;
            for_each_coupling(&multibody.couplers, state.q, c, |d, weight| sum += weight * forces[d]);
            sum
        };
        let mut arms = DMatrix::zeros(self.rows.len(), generators.len());
        let (mut unit_forces, mut lengths) = (Vec::with_capacity(generators.len()), Vec::with_capacity(generators.len()));
        for (j, generator) in generators.iter().enumerate() {
            generator.generalized_forces(geometry, &self.paths, &mut self.column);
            let muscle = generator.muscle_path();
            let (unit, length) = match muscle {
                Some((_, k)) => (generator.unit_force(physiology, self.paths.length(k), self.paths.lengthening_speed(k)), self.paths.length(k)),
                None => (generator.unit_force(physiology, 0.0, 0.0), 0.0),
            };
            for (r, &c) in self.rows.iter().enumerate() {
                arms[(r, j)] = if muscle.is_some() { self.column[c] } else { along(&self.column, c) };
            }
            unit_forces.push(unit);
            lengths.push(length);
        }
        let mut matrix = arms.clone();
        for (mut column, unit) in matrix.column_iter_mut().zip(&unit_forces) {
            column *= *unit;
        }
        FrameProblem { matrix, rhs: self.rows.iter().map(|&c| along(&demand, c)).collect(), unit_forces, arms, lengths }
    }
}

/// `state.udot` with each coupler's dependent acceleration replaced by the constraint's,
/// f′·u̇_i + f″·u_i² (OpenSim tracks the independent one only).
fn constrained_accelerations(multibody: &Multibody, state: &MotionState) -> Vec<f64> {
    let mut udot = state.udot.to_vec();
    for coupler in &multibody.couplers {
        let speed = state.u[coupler.independent];
        udot[coupler.dependent] = coupler.slope(state.q) * state.udot[coupler.independent] + coupler.curvature(state.q) * speed * speed;
    }
    udot
}
