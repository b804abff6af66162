//! Forward dynamics: the accelerations the applied forces give the model, as Simbody's
//! `realizeAcceleration` finds them — M(q)·u̇ + h(q, u) = τ, with the coordinate locks
//! (u̇ = 0) and `CoordinateCouplerConstraint`s (q̈_d = f′·q̈_i + f″·q̇_i², with the state's q̇_i)
//! holding exactly and their forces doing no work along the motions they allow.
//!
//! Both M and h come from inverse dynamics: column k of M is the generalized force of a unit
//! u̇_k at rest without gravity, h the generalized force of zero u̇ with gravity and the applied
//! body loads. The constraints leave u̇ = P·v + p₀ over the free speeds v, and
//! Pᵀ(M·(P·v + p₀) + h − τ) = 0 is solved by Cholesky.

use nalgebra::{DMatrix, DVector};

use super::inverse_dynamics::{BodyLoad, MotionState};
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::spatial::Vec3;

/// Why no accelerations were found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ForwardDynamicsError {
    #[error("the mass matrix over the free coordinates is not positive definite (a body without mass or inertia?)")]
    Singular,
    #[error("coordinate {0:?} is prescribed; prescribed motion is not supported")]
    Prescribed(String),
    #[error("the model's constraints {} are enforced; only CoordinateCouplerConstraints are applied", .0.join(", "))]
    Constraints(Vec<String>),
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
        let n = self.coordinates.len();
        assert!(tau.len() == n, "one mobility force per coordinate");
        if let Some(c) = self.coordinates.iter().find(|c| c.prescribed && !c.locked) {
            return Err(ForwardDynamicsError::Prescribed(c.name.clone()));
        }
        let refused = self.constraints_dynamics_refuses();
        if !refused.is_empty() {
            return Err(ForwardDynamicsError::Constraints(refused));
        }
        let bias = DVector::from_vec(self.inverse_dynamics_at(kinematics, &MotionState { q, u, udot: &vec![0.0; n] }, loads));
        let (projection, offset) = self.constraint_projection(q, u);
        let mass = self.mass_matrix(kinematics, q);
        let reduced = projection.transpose() * &mass * &projection;
        let rhs = projection.transpose() * (DVector::from_column_slice(tau) - bias - &mass * &offset);
        let free = reduced.cholesky().ok_or(ForwardDynamicsError::Singular)?.solve(&rhs);
        Ok((projection * free + offset).as_slice().to_vec())
    }

    /// u̇ = P·v + p₀: one column of P per free coordinate (neither locked nor a coupler's
    /// dependent) carrying its dependents by their slopes; p₀ the dependents' f″·q̇_i².
    fn constraint_projection(&self, q: &[f64], u: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
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
}
