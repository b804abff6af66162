//! Projection onto the links between bodies, as Simbody's `projectQ` and `projectU` do after an
//! integrator step whose state has drifted off them: the smallest change of the free speeds'
//! coordinates (unit weights) that closes every link — Gauss–Newton steps Δv = −(GP)⁺·e over the
//! free speeds (P the locks' and couplers' projection, G the links' velocity rows, e their
//! errors, a Ball, Free or ellipsoid joint's angles moved at the rates its Δω gives them) — and
//! the smallest change of the speeds that keeps them closed, Δv = −(GP)⁺·G·u. Redundant links'
//! rows (singular values below [`REDUNDANT_LINK`] of the largest) are left out, as Simbody
//! tolerates them.

use nalgebra::DVector;

use super::kinematics::Kinematics;
use super::multibody::Multibody;

/// Singular values of GP below this fraction of the largest belong to redundant link rows.
const REDUNDANT_LINK: f64 = 1e-10;

/// Gauss–Newton steps allowed to close the links.
const MAXIMUM_STEPS: usize = 20;

/// Why a pose cannot be projected onto the links.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the links between bodies stay open by {error:.3e} after {MAXIMUM_STEPS} projection steps")]
pub struct ProjectionError {
    pub error: f64,
}

impl Multibody {
    /// Every link's errors at the pose `kinematics` holds (m; a weld's orientation rows are the
    /// cosines of its axes' angles that should be right angles), links in order.
    pub fn link_errors(&self, kinematics: &Kinematics) -> Vec<f64> {
        let mut errors = Vec::with_capacity(self.links.iter().map(|link| link.rows()).sum());
        for link in &self.links {
            link.errors(kinematics, &mut errors);
        }
        errors
    }

    /// The largest |link error| at `q` and |G·u|, the links' rates at speeds `u` (m/s).
    pub fn link_drift(&self, q: &[f64], u: &[f64]) -> (f64, f64) {
        if self.links.is_empty() {
            return (0.0, 0.0);
        }
        let kinematics = self.realized(q);
        let rates = self.link_jacobian(&kinematics) * DVector::from_column_slice(u);
        (self.link_errors(&kinematics).iter().fold(0.0, |m: f64, e| m.max(e.abs())), rates.amax())
    }

    /// Moves `q` onto the links (to |error| ≤ `tolerance`) and then `u` onto their rates where
    /// |G·u| exceeds `tolerance` (see the module doc); the couplers' dependents follow.
    pub fn project_onto_links(&self, q: &mut [f64], u: &mut [f64], tolerance: f64) -> Result<(), ProjectionError> {
        if self.links.is_empty() {
            return Ok(());
        }
        let mut error = f64::INFINITY;
        for _ in 0..MAXIMUM_STEPS {
            let kinematics = self.realized(q);
            let errors = DVector::from_vec(self.link_errors(&kinematics));
            error = errors.amax();
            if error <= tolerance {
                break;
            }
            let step = self.free_speed_step(&kinematics, q, &errors);
            let rates = self.coordinate_rates(q, step.as_slice());
            for (value, rate) in q.iter_mut().zip(rates) {
                *value -= rate;
            }
            self.follow_couplers(q, &[]);
        }
        if error > tolerance {
            return Err(ProjectionError { error });
        }
        let kinematics = self.realized(q);
        let rates = self.link_jacobian(&kinematics) * DVector::from_column_slice(u);
        if rates.amax() <= tolerance {
            return Ok(());
        }
        let step = self.free_speed_step(&kinematics, q, &rates);
        for (value, change) in u.iter_mut().zip(step.iter()) {
            *value -= change;
        }
        Ok(())
    }

    /// Moves `udot` onto the links' accelerations at `q` (on the links) moving at `u` (keeping
    /// them): G·u̇ + Ġ·u = 0 by the least change of the free speeds' accelerations.
    pub fn project_accelerations_onto_links(&self, q: &[f64], u: &[f64], udot: &mut [f64]) {
        if self.links.is_empty() {
            return;
        }
        let kinematics = self.realized(q);
        let step = self.free_speed_step(&kinematics, q, &self.link_accelerations(&kinematics, q, u, udot));
        for (value, change) in udot.iter_mut().zip(step.iter()) {
            *value -= change;
        }
    }

    /// P·(GP)⁺·`rows` over every speed (the dependents' by their couplers' slopes).
    fn free_speed_step(&self, kinematics: &Kinematics, q: &[f64], rows: &DVector<f64>) -> DVector<f64> {
        let (projection, _) = self.constraint_projection(q, &vec![0.0; q.len()]);
        let links = self.link_jacobian(kinematics) * &projection;
        let svd = links.svd(true, true);
        let floor = REDUNDANT_LINK * svd.singular_values.max();
        let free = svd.solve(rows, floor).unwrap_or_else(|_| DVector::zeros(projection.ncols()));
        projection * free
    }

    fn realized(&self, q: &[f64]) -> Kinematics {
        let mut kinematics = self.kinematics();
        self.realize(q, &mut kinematics);
        kinematics
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;
    use nalgebra::DMatrix;
    use std::path::Path;

    fn linked() -> Multibody {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/models/linked_mechanisms.osim");
        Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap()
    }

    /// The free speeds' changes that keep the links as they are at `q`: the null space of GP.
    fn free_motions(multibody: &Multibody, q: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
        let (projection, _) = multibody.constraint_projection(q, &vec![0.0; q.len()]);
        let links = multibody.link_jacobian(&multibody.realized(q)) * &projection;
        let svd = (links.transpose() * &links).svd(false, true);
        let v_t = svd.v_t.unwrap();
        let floor = 1e-14 * svd.singular_values.max();
        let kept: Vec<usize> = (0..projection.ncols()).filter(|&k| svd.singular_values[k] <= floor).collect();
        (projection, v_t.select_rows(&kept).transpose())
    }

    /// linked_mechanisms (point, distance, point-on-line and weld links, a coupler, Ball and Free
    /// joints): a pose pushed off its links and speeds that open them come back onto them (to
    /// 1e-12), each change the least one — orthogonal, in the free speeds, to every motion that
    /// keeps the links (the first-order condition of min ‖Δv‖ subject to them) — and a state on
    /// the links is left as it is.
    #[test]
    fn projection_closes_the_links_with_the_least_change() {
        let multibody = linked();
        let n = multibody.coordinates.len();
        let closed = crate::solvers::assembled_default_pose(&multibody).unwrap();
        let (projection, motions) = free_motions(&multibody, &closed);
        assert!(motions.ncols() > 0);
        let push = DVector::from_fn(projection.ncols(), |k, _| 2e-3 * ((k as f64) * 1.3 + 0.4).sin());
        let mut q = closed.clone();
        for (value, change) in q.iter_mut().zip((&projection * &push).iter()) {
            *value += change;
        }
        multibody.follow_couplers(&mut q, &[]);
        let mut u: Vec<f64> = (0..n).map(|c| ((c as f64) * 0.7).cos()).collect();
        multibody.follow_coupler_speeds(&q, &mut u);
        assert!(multibody.link_drift(&q, &u).0 > 1e-4, "the push opens the links");
        let (pushed, speeds) = (q.clone(), u.clone());
        multibody.project_onto_links(&mut q, &mut u, 1e-12).unwrap();
        let (position, rate) = multibody.link_drift(&q, &u);
        assert!(position <= 1e-12 && rate <= 1e-10, "left open by {position:e} m, {rate:e} m/s");
        // Least changes: the speeds' change in the free speeds is orthogonal to the motions the
        // links allow at the projected pose; the pose's final Gauss–Newton steps likewise.
        let (projection, motions) = free_motions(&multibody, &q);
        let free = |v: &[f64]| DVector::from_iterator(projection.ncols(), (0..n).filter(|&c| !multibody.coordinates[c].locked && !multibody.is_dependent(c)).map(|c| v[c]));
        let change = free(&u) - free(&speeds);
        assert!((motions.transpose() * &change).amax() < 1e-10 * change.amax(), "the speeds moved along allowed motions");
        assert!((free(&q) - free(&pushed)).amax() < 1e-2, "the pose moved no further than its push");
        let (before_q, before_u) = (q.clone(), u.clone());
        multibody.project_onto_links(&mut q, &mut u, 1e-12).unwrap();
        assert_eq!((q, u), (before_q, before_u), "a closed state is left as it is");
    }
}
