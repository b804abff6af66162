//! One frame's static-optimisation problem: the generalized forces Σ aⱼ·Fⱼ·Rⱼ the controls a must
//! produce — one row per unconstrained coordinate — and the inverse-dynamics forces they must
//! equal.
//!
//! A `CoordinateCouplerConstraint` q_d = f(q_i) makes q_d constrained: OpenSim tracks only the
//! unconstrained coordinates' accelerations, and the dependent one follows the constraint,
//! q̈_d = f′·q̈_i + f″·q̇_i². The constraint force acts along (−f′, 1), so eliminating it leaves
//! one row per independent coordinate along its coupling vector (1, f′): muscles' generalized
//! forces are already taken along it ([`PathEvaluation::applying`]), actuator and
//! inverse-dynamics forces are summed along it here.
//!
//! Links between bodies (point, distance, point-on-line and weld constraints) constrain no
//! coordinate: OpenSim tracks every coordinate's acceleration, which its forward dynamics finds
//! with the links' forces −Gᵀλ among the generalized forces. Each frame carries those forces per
//! unit multiplier along the rows (`link_forces`); [`FrameProblem::along_allowed_motions`]
//! eliminates them by keeping the rows' components along the motions the links allow (the null
//! space of the links' velocity rows): when the tracked motion keeps its loops closed, forces
//! meeting those rows give exactly the tracked accelerations, the multipliers λ taking up the rest.

use nalgebra::DMatrix;

use super::generators::Generator;
use crate::analysis::external_loads::ExternalLoads;
use crate::mechanics::{for_each_coupling, Kinematics, MotionState, Multibody, MuscleGeometry, PathEvaluation};

/// Singular values of the links' forces below this fraction of the largest are redundant links'
/// (e.g. a point constraint's row normal to a planar loop).
const LINK_RANK_TOLERANCE: f64 = 1e-10;

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
    /// Rows: as `matrix`; columns: the links' velocity rows ([`Multibody::link_jacobian`]). The
    /// generalized forces of a unit multiplier (−Gᵀ along each row), N·m or N per N or N·m.
    pub link_forces: DMatrix<f64>,
    /// The largest |G·u̇ + Ġ·u| of the tracked motion (m/s² or rad/s²; 0 without links): how far
    /// its accelerations break the links. Forces meeting the rows give the nearest accelerations
    /// that keep them (OpenSim's static optimisation cannot meet its constraints there).
    pub link_acceleration_error: f64,
    /// After [`FrameProblem::along_allowed_motions`] on a model with links: the orthonormal basis
    /// N (columns over the tracked coordinates) the rows now run along; a row vector e maps back
    /// onto the tracked coordinates as N·e. `None` while the rows are the coordinates'.
    pub motions: Option<DMatrix<f64>>,
}

impl FrameProblem {
    /// The problem with the links' forces eliminated: `matrix`, `rhs` and `arms` replaced by
    /// their components along an orthonormal basis of the motions the links allow (one row per
    /// degree of freedom the links leave; the same problem when the model has no links).
    pub fn along_allowed_motions(self) -> FrameProblem {
        if self.link_forces.ncols() == 0 {
            return self;
        }
        let basis = allowed_motions(&self.link_forces);
        let project = |m: &DMatrix<f64>| basis.transpose() * m;
        let rhs = project(&DMatrix::from_column_slice(self.rhs.len(), 1, &self.rhs));
        FrameProblem {
            matrix: project(&self.matrix),
            rhs: rhs.as_slice().to_vec(),
            arms: project(&self.arms),
            link_forces: DMatrix::zeros(basis.ncols(), 0),
            motions: Some(basis),
            ..self
        }
    }
}

/// An orthonormal basis (columns) of the vectors orthogonal to every column of `link_forces`:
/// the projector I − UUᵀ off their range (U the left singular vectors above
/// [`LINK_RANK_TOLERANCE`]), whose eigenvectors of eigenvalue 1 span it.
fn allowed_motions(link_forces: &DMatrix<f64>) -> DMatrix<f64> {
    let n = link_forces.nrows();
    let svd = link_forces.clone().svd(true, false);
    let floor = LINK_RANK_TOLERANCE * svd.singular_values.max();
    let mut projector = DMatrix::identity(n, n);
    if let Some(u) = &svd.u {
        for (k, _) in svd.singular_values.iter().enumerate().filter(|&(_, s)| *s > floor) {
            projector -= u.column(k) * u.column(k).transpose();
        }
    }
    let eigen = projector.symmetric_eigen();
    let kept: Vec<usize> = (0..n).filter(|&k| eigen.eigenvalues[k] > 0.5).collect();
    eigen.eigenvectors.select_columns(&kept)
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
        let (paths, column) = (PathEvaluation::applying(geometry, &muscles), vec![0.0; geometry.multibody.coordinates.len()]);
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
        let link_rows = multibody.link_jacobian(self.paths.kinematics());
        let link_velocities = link_rows.transpose();
        let link_forces = DMatrix::from_fn(self.rows.len(), link_velocities.ncols(), |r, l| -along(link_velocities.column(l).as_slice(), self.rows[r]));
        let link_acceleration_error = if multibody.links.is_empty() { 0.0 } else { multibody.link_accelerations_along(&link_rows, state.q, state.u, &udot).amax() };
        FrameProblem { matrix, rhs: self.rows.iter().map(|&c| along(&demand, c)).collect(), unit_forces, arms, lengths, link_forces, link_acceleration_error, motions: None }
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

#[cfg(test)]
mod tests {
    use super::allowed_motions;
    use nalgebra::DMatrix;

    /// The basis is orthonormal, orthogonal to every link's forces and as large as the links
    /// leave: a repeated column and a zero one (redundant rows) take no dimension away.
    #[test]
    fn allowed_motions_span_the_complement_of_the_links_forces() {
        let first = [0.3, -1.2, 0.5, 2.0, 0.1];
        let second = [1.0, 0.0, -0.4, 0.2, 0.7];
        let columns: Vec<f64> = [first, second, first.map(|v| -2.0 * v), [0.0; 5]].concat();
        let forces = DMatrix::from_column_slice(5, 4, &columns);
        let basis = allowed_motions(&forces);
        assert_eq!(basis.ncols(), 3, "five coordinates less two independent links");
        assert!((basis.transpose() * &basis - DMatrix::identity(3, 3)).amax() < 1e-14);
        assert!((basis.transpose() * &forces).amax() < 1e-14);
    }
}
