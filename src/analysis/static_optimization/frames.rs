//! One frame's static-optimisation problem: the generalized forces Σ aⱼ·Fⱼ·Rⱼ the controls a must
//! produce — one row per unlocked coordinate — and the inverse-dynamics forces they must equal.

use nalgebra::DMatrix;

use super::generators::Generator;
use crate::analysis::external_loads::ExternalLoads;
use crate::mechanics::{Kinematics, MotionState, MuscleGeometry, PathEvaluation};

/// A frame's rows: `matrix` a = `rhs`, with each generator's force at control 1.
pub struct FrameProblem {
    /// Rows: unlocked coordinates; columns: generators. N·m or N per unit control.
    pub matrix: DMatrix<f64>,
    /// Inverse dynamics at the tracked accelerations, N·m or N.
    pub rhs: Vec<f64>,
    /// Fⱼ: a muscle's force at activation 1 (N), an actuator's optimal force.
    pub unit_forces: Vec<f64>,
}

/// What every frame's problem shares, and its buffers.
pub struct Frames<'a> {
    geometry: &'a MuscleGeometry,
    generators: &'a [Generator],
    loads: Option<&'a ExternalLoads>,
    /// OpenSim's `use_muscle_physiology`.
    physiology: bool,
    paths: PathEvaluation,
    /// Coordinates whose accelerations are tracked (not locked).
    rows: Vec<usize>,
    column: Vec<f64>,
}

impl<'a> Frames<'a> {
    pub fn new(geometry: &'a MuscleGeometry, generators: &'a [Generator], loads: Option<&'a ExternalLoads>, physiology: bool) -> Frames<'a> {
        let muscles: Vec<usize> = generators.iter().filter_map(Generator::path).collect();
        let rows = geometry.multibody.coordinates.iter().enumerate().filter(|(_, c)| !c.locked).map(|(i, _)| i).collect();
        let (paths, column) = (PathEvaluation::new(geometry, &muscles), vec![0.0; geometry.multibody.coordinates.len()]);
        Frames { geometry, generators, loads, physiology, paths, rows, column }
    }

    /// Every generator's [min_control, max_control].
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.generators.iter().map(|g| (g.bounds[0], g.bounds[1])).unzip()
    }

    /// The body poses of the last frame.
    pub fn kinematics(&self) -> &Kinematics {
        self.paths.kinematics()
    }

    /// The problem at `state` and `time` (s, for the external loads).
    pub fn problem(&mut self, state: &MotionState, time: f64) -> FrameProblem {
        let (geometry, generators, physiology) = (self.geometry, self.generators, self.physiology);
        self.paths.evaluate(geometry, state.q);
        let applied = self.loads.map(|l| l.at(time, self.paths.kinematics())).unwrap_or_default();
        let demand = geometry.multibody.inverse_dynamics(state, &applied);
        let mut matrix = DMatrix::zeros(self.rows.len(), generators.len());
        let mut unit_forces = Vec::with_capacity(generators.len());
        for (j, generator) in generators.iter().enumerate() {
            generator.generalized_forces(geometry, &self.paths, &mut self.column);
            let unit = match generator.muscle_path() {
                Some((path, k)) => {
                    let moment_arms = geometry.paths[path].spanned.iter().zip(self.paths.moment_arms(k));
                    let lengthening_speed = -moment_arms.map(|(&c, r)| r * state.u[c]).sum::<f64>();
                    generator.unit_force(physiology, self.paths.length(k), lengthening_speed)
                }
                None => generator.unit_force(physiology, 0.0, 0.0),
            };
            for (r, &c) in self.rows.iter().enumerate() {
                matrix[(r, j)] = unit * self.column[c];
            }
            unit_forces.push(unit);
        }
        FrameProblem { matrix, rhs: self.rows.iter().map(|&c| demand[c]).collect(), unit_forces }
    }
}
