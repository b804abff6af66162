//! Forward dynamics: the accelerations the applied forces give the model, as Simbody's
//! `realizeAcceleration` finds them — M(q)·u̇ + h(q, u) = τ, with the coordinate locks
//! (u̇ = 0) and `CoordinateCouplerConstraint`s (q̈_d = f′·q̈_i + f″·q̇_i², with the state's q̇_i)
//! holding exactly and their forces doing no work along the motions they allow.
//!
//! Both M and h come from inverse dynamics: column k of M is the generalized force of a unit
//! u̇_k at rest without gravity, h the generalized force of zero u̇ with gravity and the applied
//! body loads. The locks and couplers leave u̇ = P·v + p₀ over the free speeds v, and
//! Pᵀ(M·(P·v + p₀) + h − τ) = 0 is solved by Cholesky. Links between bodies (point, distance,
//! point-on-line and weld constraints) hold at the acceleration level, G·u̇ + Ġ·u = 0 with G the
//! links' velocity rows ([`Multibody::link_jacobian`]), their forces Gᵀλ doing no work: the
//! Schur complement S = (GP)·A⁻¹·(GP)ᵀ of A = PᵀMP gives λ (least squares where links are
//! redundant, as Simbody tolerates). Ġ·u is G's rate along q̇ by a central difference.

use nalgebra::{DMatrix, DVector};

use super::inverse_dynamics::{BodyLoad, MotionState};
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::spatial::Vec3;

/// Singular values of the links' Schur complement below this fraction of its norm are
/// redundant links' (their multipliers left at the least-squares solution).
const LINK_RANK_TOLERANCE: f64 = 1e-12;

/// The time step (s, per unit of the fastest coordinate rate) of Ġ·u's central difference:
/// truncation ~h² and rounding ~ε/h both near 1e-10 of G·u's scale.
const LINK_RATE_STEP: f64 = 1e-6;

/// Why no accelerations were found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ForwardDynamicsError {
    #[error("the mass matrix over the free coordinates is not positive definite (a body without mass or inertia?)")]
    Singular,
    #[error("coordinate {0:?} is prescribed; prescribed motion is not supported")]
    Prescribed(String),
    #[error("the model's constraints {} are enforced; only CoordinateCouplerConstraints and links between bodies are applied", .0.join(", "))]
    Constraints(Vec<String>),
}

/// One state's forward dynamics, factored: the mass matrix over the free speeds and, with links,
/// the decomposed Schur complement ([`Multibody::prepare_dynamics`]).
pub struct PreparedDynamics<'a> {
    multibody: &'a Multibody,
    kinematics: &'a Kinematics,
    q: &'a [f64],
    u: &'a [f64],
    projection: DMatrix<f64>,
    offset: DVector<f64>,
    mass: DMatrix<f64>,
    reduced: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    links: Option<LinkSolve>,
}

/// The links' rows over the free speeds, their acceleration target, A⁻¹(GP)ᵀ and S's SVD.
struct LinkSolve {
    links: DMatrix<f64>,
    target: DVector<f64>,
    spread: DMatrix<f64>,
    schur: nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>,
    rank_floor: f64,
}

impl PreparedDynamics<'_> {
    /// u̇ under the body `loads` and mobility forces `tau` (one per coordinate), and the links'
    /// multipliers λ (none without links).
    ///
    /// # Panics
    /// If `tau` does not hold one value per coordinate.
    pub fn solve(&self, loads: &[BodyLoad], tau: &[f64]) -> Result<(Vec<f64>, Option<DVector<f64>>), ForwardDynamicsError> {
        let n = self.multibody.coordinates.len();
        assert!(tau.len() == n, "one mobility force per coordinate");
        let bias = DVector::from_vec(self.multibody.inverse_dynamics_at(self.kinematics, &MotionState { q: self.q, u: self.u, udot: &vec![0.0; n] }, loads));
        let rhs = self.projection.transpose() * (DVector::from_column_slice(tau) - bias - &self.mass * &self.offset);
        let mut free = self.reduced.solve(&rhs);
        let mut link_multipliers = None;
        if let Some(links) = &self.links {
            let multipliers = links.schur.solve(&(&links.links * &free - &links.target), links.rank_floor).map_err(|_| ForwardDynamicsError::Singular)?;
            free -= &links.spread * &multipliers;
            link_multipliers = Some(multipliers);
        }
        Ok(((&self.projection * free + &self.offset).as_slice().to_vec(), link_multipliers))
    }
}

impl Multibody {
    /// M(q) (kg·m², kg·m or kg), [`Multibody::coordinates`] order, at the pose `kinematics`
    /// holds ([`Multibody::realize`] at `q`).
    pub fn mass_matrix(&self, kinematics: &Kinematics, q: &[f64]) -> DMatrix<f64> {
        let n = self.coordinates.len();
        let (zero, mut unit) = (vec![0.0; n], vec![0.0; n]);
        let mut matrix = DMatrix::zeros(n, n);
        for k in 0..n {
            unit[k] = 1.0;
            let motions = self.body_motions(&MotionState { q, u: &zero, udot: &unit });
            let wrenches = self.body_wrenches(&motions, &[], &Vec3::zeros());
            matrix.set_column(k, &DVector::from_vec(self.generalized_forces_of(kinematics, &wrenches)));
            unit[k] = 0.0;
        }
        matrix
    }

    /// u̇ at coordinates `q` (realized in `kinematics`) and speeds `u` under gravity, the body
    /// `loads` and the mobility forces `tau` (N·m or N per coordinate), with locks and couplers
    /// enforced.
    ///
    /// # Panics
    /// If a slice does not hold one value per coordinate.
    pub fn accelerations(&self, kinematics: &Kinematics, q: &[f64], u: &[f64], loads: &[BodyLoad], tau: &[f64]) -> Result<Vec<f64>, ForwardDynamicsError> {
        Ok(self.solve_accelerations(kinematics, q, u, loads, tau)?.0)
    }

    /// [`Multibody::accelerations`] with the links' constraint forces as body loads (each link
    /// row's −λ along its rate terms: −Gᵀλ in generalized forces), which a joint reaction
    /// counts among the loads its subtree gets.
    pub fn constrained_accelerations(&self, kinematics: &Kinematics, q: &[f64], u: &[f64], loads: &[BodyLoad], tau: &[f64]) -> Result<(Vec<f64>, Vec<BodyLoad>), ForwardDynamicsError> {
        let (udot, multipliers) = self.solve_accelerations(kinematics, q, u, loads, tau)?;
        Ok((udot, multipliers.map(|m| self.link_loads(kinematics, &m)).unwrap_or_default()))
    }

    /// [`Multibody::accelerations`] with the links' multipliers λ, one per row of
    /// [`Multibody::link_jacobian`] (Simbody's sign: the links apply −Gᵀλ; none without links).
    pub fn accelerations_with_multipliers(&self, kinematics: &Kinematics, q: &[f64], u: &[f64], loads: &[BodyLoad], tau: &[f64]) -> Result<(Vec<f64>, DVector<f64>), ForwardDynamicsError> {
        let (udot, multipliers) = self.solve_accelerations(kinematics, q, u, loads, tau)?;
        Ok((udot, multipliers.unwrap_or_else(|| DVector::zeros(0))))
    }

    /// u̇ and, with links, their multipliers λ.
    fn solve_accelerations(&self, kinematics: &Kinematics, q: &[f64], u: &[f64], loads: &[BodyLoad], tau: &[f64]) -> Result<(Vec<f64>, Option<DVector<f64>>), ForwardDynamicsError> {
        self.prepare_dynamics(kinematics, q, u)?.solve(loads, tau)
    }

    /// The forward dynamics of the state (`q`, `u`; `kinematics` realized at `q`) factored once,
    /// for the accelerations of many sets of applied forces ([`PreparedDynamics::solve`]).
    pub fn prepare_dynamics<'a>(&'a self, kinematics: &'a Kinematics, q: &'a [f64], u: &'a [f64]) -> Result<PreparedDynamics<'a>, ForwardDynamicsError> {
        if let Some(c) = self.coordinates.iter().find(|c| c.prescribed && !c.locked) {
            return Err(ForwardDynamicsError::Prescribed(c.name.clone()));
        }
        if !self.unheld_constraints.is_empty() {
            return Err(ForwardDynamicsError::Constraints(self.unheld_constraints.clone()));
        }
        let (projection, offset) = self.constraint_projection(q, u);
        let mass = self.mass_matrix(kinematics, q);
        let reduced = (projection.transpose() * &mass * &projection).cholesky().ok_or(ForwardDynamicsError::Singular)?;
        let links = (!self.links.is_empty()).then(|| {
            let g = self.link_jacobian(kinematics);
            let links = &g * &projection;
            let target = -(self.link_jacobian_rate(q, u) + &g * &offset);
            let spread = reduced.solve(&links.transpose());
            let schur = &links * &spread;
            let rank_floor = LINK_RANK_TOLERANCE * schur.norm();
            LinkSolve { links, target, spread, schur: schur.svd(true, true), rank_floor }
        });
        Ok(PreparedDynamics { multibody: self, kinematics, q, u, projection, offset, mass, reduced, links })
    }

    /// The links' accelerations G·u̇ + Ġ·u (m/s², or rad/s² for a weld's orientation rows; 0
    /// where a motion keeps them closed) at the pose `kinematics` holds (realized at `q`).
    pub fn link_accelerations(&self, kinematics: &Kinematics, q: &[f64], u: &[f64], udot: &[f64]) -> DVector<f64> {
        self.link_accelerations_along(&self.link_jacobian(kinematics), q, u, udot)
    }

    /// [`Multibody::link_accelerations`] with the links' velocity rows `jacobian` at `q` given.
    pub fn link_accelerations_along(&self, jacobian: &DMatrix<f64>, q: &[f64], u: &[f64], udot: &[f64]) -> DVector<f64> {
        jacobian * DVector::from_column_slice(udot) + self.link_jacobian_rate(q, u)
    }

    /// Ġ·u of the links at `q` moving at `u`: (G(q + hq̇) − G(q − hq̇))·u / 2h, q̇ the
    /// coordinates' rates.
    fn link_jacobian_rate(&self, q: &[f64], u: &[f64]) -> DVector<f64> {
        let qdot = self.coordinate_rates(q, u);
        let scale = qdot.iter().fold(1.0f64, |m, r| m.max(r.abs()));
        let h = LINK_RATE_STEP / scale;
        let mut kinematics = self.kinematics();
        let speeds = DVector::from_column_slice(u);
        let mut at = |sign: f64| {
            let moved: Vec<f64> = q.iter().zip(&qdot).map(|(q, r)| q + sign * h * r).collect();
            self.realize(&moved, &mut kinematics);
            self.link_jacobian(&kinematics) * &speeds
        };
        (at(1.0) - at(-1.0)) / (2.0 * h)
    }

    /// u̇ = P·v + p₀: one column of P per free coordinate (neither locked nor a coupler's
    /// dependent) carrying its dependents by their slopes; p₀ the dependents' f″·q̇_i².
    pub(super) fn constraint_projection(&self, q: &[f64], u: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
        let n = self.coordinates.len();
        let free: Vec<usize> = (0..n).filter(|&c| !self.coordinates[c].locked && !self.is_dependent(c)).collect();
        let mut projection = DMatrix::zeros(n, free.len());
        let mut offset = DVector::zeros(n);
        for (column, &c) in free.iter().enumerate() {
            projection[(c, column)] = 1.0;
        }
        for coupler in self.couplers.iter().filter(|k| !self.coordinates[k.dependent].locked) {
            if let Some(column) = free.iter().position(|&c| c == coupler.independent) {
                projection[(coupler.dependent, column)] = coupler.slope(q);
            }
            offset[coupler.dependent] = coupler.curvature(q) * u[coupler.independent].powi(2);
        }
        (projection, offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;
    use approx::assert_relative_eq;
    use std::path::Path;

    fn multibody(file: &str) -> Multibody {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap()
    }

    /// A state with every coordinate moved off its default and moving.
    fn state(multibody: &Multibody) -> (Vec<f64>, Vec<f64>) {
        let n = multibody.coordinates.len();
        let mut q = multibody.default_pose();
        for (c, value) in q.iter_mut().enumerate() {
            *value += 0.1 * ((c as f64) * 0.7).sin();
        }
        multibody.follow_couplers(&mut q, &[]);
        let u = (0..n).map(|c| 0.5 * ((c as f64) * 1.3).cos()).collect();
        (q, u)
    }

    /// Forward dynamics undoes inverse dynamics: the forces that inverse dynamics says give u̇
    /// give back u̇ (an unconstrained tree).
    #[test]
    fn accelerations_invert_inverse_dynamics() {
        let multibody = multibody("models/gait2392_thelen2003muscle.osim");
        let (q, u) = state(&multibody);
        let n = multibody.coordinates.len();
        let udot: Vec<f64> = (0..n).map(|c| if multibody.coordinates[c].locked { 0.0 } else { ((c as f64) * 0.9).sin() }).collect();
        let tau = multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]);
        let found = multibody.accelerations(&realized(&multibody, &q), &q, &u, &[], &tau).unwrap();
        for (a, b) in found.iter().zip(&udot) {
            assert_relative_eq!(a, b, epsilon = 1e-9);
        }
    }

    fn realized(multibody: &Multibody, q: &[f64]) -> Kinematics {
        let mut kinematics = multibody.kinematics();
        multibody.realize(q, &mut kinematics);
        kinematics
    }

    /// The mass matrix is symmetric and gives the kinetic energy ½uᵀMu that the bodies' own
    /// velocities give (first principles).
    #[test]
    fn mass_matrix_is_symmetric_and_gives_kinetic_energy() {
        let multibody = multibody("models/gait2392_thelen2003muscle.osim");
        let (q, u) = state(&multibody);
        let mass = multibody.mass_matrix(&realized(&multibody, &q), &q);
        assert_relative_eq!(mass, mass.transpose(), epsilon = 1e-12);
        let zero = vec![0.0; u.len()];
        let motions = multibody.body_motions(&MotionState { q: &q, u: &u, udot: &zero });
        let energy: f64 = motions
            .iter()
            .zip(&multibody.bodies)
            .map(|(m, b)| {
                let v = m.point_velocity(&b.mass_center);
                let omega = m.angular_velocity();
                let inertia = m.transform.rotation * b.inertia * m.transform.rotation.transpose();
                0.5 * b.mass * v.norm_squared() + 0.5 * omega.dot(&(inertia * omega))
            })
            .sum();
        let u = DVector::from_vec(u);
        assert_relative_eq!(0.5 * u.dot(&(&mass * &u)), energy, max_relative = 1e-12);
    }

    /// With a coupler, the dependent accelerates as its constraint says, and the constraint
    /// force does no work: the forces inverse dynamics gives for a motion that keeps the
    /// constraint, summed along the coupling vectors, return that motion.
    #[test]
    fn couplers_and_locks_hold() {
        let multibody = multibody("fixtures/models/leg6dof9musc.osim");
        assert!(!multibody.couplers.is_empty());
        let (q, u) = state(&multibody);
        let n = multibody.coordinates.len();
        let mut udot: Vec<f64> = (0..n).map(|c| if multibody.coordinates[c].locked { 0.0 } else { ((c as f64) * 0.9).sin() }).collect();
        for k in &multibody.couplers {
            udot[k.dependent] = k.slope(&q) * udot[k.independent] + k.curvature(&q) * u[k.independent].powi(2);
        }
        let demand = multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]);
        let mut tau = demand.clone();
        for k in &multibody.couplers {
            tau[k.independent] += k.slope(&q) * demand[k.dependent];
            tau[k.dependent] = 0.0;
        }
        let found = multibody.accelerations(&realized(&multibody, &q), &q, &u, &[], &tau).unwrap();
        for (a, b) in found.iter().zip(&udot) {
            assert_relative_eq!(a, b, epsilon = 1e-9);
        }
    }

    /// With links closing loops (linked_mechanisms: point, distance, point-on-line and weld
    /// constraints, a coupler, a Ball and two Free joints), at a pose where they hold and speeds
    /// they allow, the accelerations keep the links' rates at zero (d/dt of G·u by a central
    /// difference along the motion) and the constraint forces do no work: what inverse
    /// dynamics asks for that motion (gravity only) is orthogonal to every motion the
    /// constraints allow — d'Alembert's principle, which with the first fixes u̇ — and the
    /// links' loads (their constraint forces) balance it along the unlocked, uncoupled speeds.
    #[test]
    fn links_hold_and_do_no_work() {
        let multibody = multibody("fixtures/models/linked_mechanisms.osim");
        let n = multibody.coordinates.len();
        let q = crate::solvers::assembled_default_pose(&multibody).unwrap();
        let kinematics = realized(&multibody, &q);
        let allowed = allowed_motions(&multibody, &kinematics, &q);
        assert!(allowed.ncols() > 0 && allowed.ncols() + 10 < n, "{} of {n} speeds free", allowed.ncols());
        let wiggle = DVector::from_fn(n, |c, _| 0.8 * ((c as f64) * 1.7 + 0.3).sin());
        let u: Vec<f64> = (&allowed * (allowed.transpose() * wiggle)).as_slice().to_vec();
        let udot = multibody.accelerations(&kinematics, &q, &u, &[], &vec![0.0; n]).unwrap();
        let h = 1e-6;
        let rate_at = |sign: f64| {
            let qdot = multibody.coordinate_rates(&q, &u);
            let moved: Vec<f64> = q.iter().zip(&qdot).map(|(q, r)| q + sign * h * r).collect();
            let speeds = DVector::from_iterator(n, u.iter().zip(&udot).map(|(u, a)| u + sign * h * a));
            multibody.link_jacobian(&realized(&multibody, &moved)) * speeds
        };
        let link_acceleration = (rate_at(1.0) - rate_at(-1.0)) / (2.0 * h);
        assert!(link_acceleration.amax() < 1e-6, "the links' rates change at {:e}", link_acceleration.amax());
        let demand = DVector::from_vec(multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]));
        let work = allowed.transpose() * &demand;
        assert!(work.amax() < 1e-9 * demand.amax().max(1.0), "constraint forces do work {:e} (demand {:e})", work.amax(), demand.amax());
        // The links' loads supply what the motion demands beyond gravity: with them, inverse
        // dynamics asks nothing along the speeds the locks and couplers leave free.
        let (_, loads) = multibody.constrained_accelerations(&kinematics, &q, &u, &[], &vec![0.0; n]).unwrap();
        let residual = DVector::from_vec(multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &loads));
        let (projection, _) = multibody.constraint_projection(&q, &u);
        let unbalanced = projection.transpose() * residual;
        assert!(unbalanced.amax() < 1e-8 * demand.amax().max(1.0), "the links' loads leave {:e} unbalanced (demand {:e})", unbalanced.amax(), demand.amax());
    }

    /// An orthonormal basis of the speeds the locks, couplers and links allow at `q`.
    fn allowed_motions(multibody: &Multibody, kinematics: &Kinematics, q: &[f64]) -> DMatrix<f64> {
        let n = multibody.coordinates.len();
        let links = multibody.link_jacobian(kinematics);
        let mut rows: Vec<DVector<f64>> = links.row_iter().map(|r| r.transpose()).collect();
        for k in &multibody.couplers {
            let mut row = DVector::zeros(n);
            row[k.dependent] = 1.0;
            row[k.independent] = -k.slope(q);
            rows.push(row);
        }
        rows.extend((0..n).filter(|&c| multibody.coordinates[c].locked).map(|c| DVector::from_fn(n, |i, _| if i == c { 1.0 } else { 0.0 })));
        let g = DMatrix::from_columns(&rows).transpose();
        // The null space of G is that of GᵀG (n × n): its right singular vectors of value ~0.
        let svd = (g.transpose() * &g).svd(false, true);
        let v_t = svd.v_t.unwrap();
        let floor = 1e-14 * svd.singular_values.max();
        let free: Vec<DVector<f64>> = (0..n).filter(|&k| svd.singular_values[k] <= floor).map(|k| v_t.row(k).transpose()).collect();
        DMatrix::from_columns(&free)
    }
}
