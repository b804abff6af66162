//! OpenSim's `Joint::calcEquivalentSpatialForce`, what the InverseDynamicsTool reports for
//! `joints_to_report_body_forces`: a force F and torque M on the joint's child, at its child
//! frame origin, whose power along the joint's mobilities is the joint's generalized forces f
//! (Hᵥᵀ F + H_ωᵀ M = f, H the joint's partial velocities). OpenSim picks one by pseudoinverses
//! (SimTK's `FactorQTZ`, rank to max(n, 3)·ε^⅞ of the largest): F = pinv(Hᵥᵀ) f and
//! M = pinv(H_ωᵀ) f each alone; if both can act, the one with the larger |Hᵀx|/|x| keeps its
//! solution and the other takes what is left of f. Expressed in ground.

use nalgebra::{DMatrix, DVector};

use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::spatial::Vec3;

/// SimTK's `SignificantReal`, ε^⅞.
fn significant() -> f64 {
    f64::EPSILON.powf(0.875)
}

/// The minimum-norm least-squares x of Aᵀ x = f, A's columns the 3-vectors `columns`; zero when
/// A has rank 0.
fn pseudo_solve(columns: &[Vec3], f: &DVector<f64>) -> Vec3 {
    let transposed = DMatrix::from_fn(columns.len(), 3, |i, j| columns[i][j]);
    let svd = transposed.svd(true, true);
    let largest = svd.singular_values.max();
    if largest == 0.0 {
        return Vec3::zeros();
    }
    let tolerance = columns.len().max(3) as f64 * significant() * largest;
    let solution = svd.solve(f, tolerance).unwrap_or_else(|_| DVector::zeros(3));
    Vec3::new(solution[0], solution[1], solution[2])
}

/// Aᵀ x.
fn project(columns: &[Vec3], x: &Vec3) -> DVector<f64> {
    DVector::from_iterator(columns.len(), columns.iter().map(|c| c.dot(x)))
}

impl Multibody {
    /// (force N, torque N·m) in ground, on the child of `joint` at its child frame origin,
    /// equivalent to the generalized forces `forces` (one per coordinate, [`Multibody::coordinates`]
    /// order) of its coordinates, at the pose `kinematics` holds.
    pub fn equivalent_body_force(&self, kinematics: &Kinematics, joint: usize, forces: &[f64]) -> (Vec3, Vec3) {
        let coordinates = &self.joints[joint].coordinates;
        if coordinates.is_empty() {
            return (Vec3::zeros(), Vec3::zeros());
        }
        let linear: Vec<Vec3> = coordinates.iter().map(|&c| kinematics.axes[c].linear).collect();
        let angular: Vec<Vec3> = coordinates.iter().map(|&c| kinematics.axes[c].angular).collect();
        let f = DVector::from_iterator(coordinates.len(), coordinates.iter().map(|&c| forces[c]));
        let mut force = pseudo_solve(&linear, &f);
        let mut torque = pseudo_solve(&angular, &f);
        let (by_force, by_torque) = (project(&linear, &force), project(&angular, &torque));
        if by_force.norm() > significant() && by_torque.norm() > significant() {
            if by_torque.norm() / torque.norm() > by_force.norm() / force.norm() {
                force = pseudo_solve(&linear, &(&f - by_torque));
            } else {
                torque = pseudo_solve(&angular, &(&f - by_force));
            }
        }
        (force, torque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;
    use std::path::Path;

    /// First principles on gait2392: the equivalent load does the joint's generalized forces'
    /// work along every mobility of the joint (Hᵥᵀ F + H_ωᵀ M = f), for a pin-like joint (the
    /// ankle), a ball-like one (the hip) and the free pelvis.
    #[test]
    fn the_equivalent_load_does_the_generalized_forces_work() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/gait2392_thelen2003muscle.osim");
        let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap();
        let mut q = multibody.default_pose();
        q.iter_mut().enumerate().for_each(|(c, v)| *v += 0.2 * (c as f64 * 0.9).sin());
        let mut kinematics = multibody.kinematics();
        multibody.realize(&q, &mut kinematics);
        let forces: Vec<f64> = (0..q.len()).map(|c| 10.0 * (c as f64 * 1.7).cos()).collect();
        for name in ["ankle_r", "hip_r", "ground_pelvis", "knee_r"] {
            let joint = multibody.joints.iter().position(|j| j.name == name).unwrap();
            let (force, torque) = multibody.equivalent_body_force(&kinematics, joint, &forces);
            for &c in &multibody.joints[joint].coordinates {
                let axis = kinematics.axes[c];
                let work = axis.linear.dot(&force) + axis.angular.dot(&torque);
                assert!((work - forces[c]).abs() < 1e-9, "{name} {}: {work} vs {}", multibody.coordinates[c].name, forces[c]);
            }
        }
    }
}
