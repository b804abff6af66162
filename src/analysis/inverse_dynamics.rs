//! OpenSim's `InverseDynamicsTool` along a motion: coordinates padded and low-pass filtered (when
//! asked), differentiated by degree-5 GCV splines (or with their speeds and accelerations given,
//! e.g. the Kalman smoother's), and the generalized forces that give those accelerations with
//! gravity and the external loads, in Simbody's mobility order; and, for the
//! joints asked (`joints_to_report_body_forces`), the body force and torque equivalent to each
//! joint's generalized forces ([`Multibody::equivalent_body_force`]).

use std::path::Path;

use super::external_loads::ExternalLoads;
use super::sampled_motion::{SampledMotion, SampledMotionError};
use super::splined_motion::{SplinedMotion, SplinedMotionError};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MotionState, Multibody};
use crate::model::MotionType;

/// Why inverse dynamics cannot run.
#[derive(Debug, thiserror::Error)]
pub enum InverseDynamicsError {
    #[error(transparent)]
    Motion(#[from] SplinedMotionError),
    #[error(transparent)]
    Sampled(#[from] SampledMotionError),
    #[error(transparent)]
    Table(#[from] TableError),
}

/// How the tool differentiates the coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InverseDynamicsSettings {
    /// s; clipped to the coordinates' times.
    pub time_range: [f64; 2],
    /// Low-pass cutoff for the coordinates, Hz (`None`: no filtering).
    pub lowpass_cutoff: Option<f64>,
}

impl InverseDynamicsSettings {
    /// The coordinates of `table` (read from `file`) as the tool differentiates them, at its
    /// frames within the time range.
    pub fn motion(&self, multibody: &Multibody, table: &StorageTable, file: &Path) -> Result<SampledMotion, SplinedMotionError> {
        SplinedMotion::new(multibody, table, file, self.lowpass_cutoff)?.sample(multibody, self.time_range)
    }
}

/// The generalized forces along the motion and what the coordinates file lacked.
#[derive(Debug, Clone)]
pub struct InverseDynamicsResult {
    /// `<coordinate>_moment` (N·m) or `<coordinate>_force` (N) per coordinate, Simbody's order.
    pub forces: StorageTable,
    /// `<joint>_<child frame>_F{X,Y,Z}` (N) and `_M{X,Y,Z}` (N·m), in ground, per joint asked;
    /// `None` when none was.
    pub body_forces: Option<StorageTable>,
    /// Coordinates held at their default value (not in the file).
    pub defaulted: Vec<String>,
    /// Columns that are no coordinate of the model.
    pub ignored_columns: Vec<String>,
}

/// Runs inverse dynamics at the frames of `motion` with `loads`, and reports the equivalent body
/// forces of `body_force_joints` ([`Multibody::joints`] indices).
pub fn inverse_dynamics(multibody: &Multibody, motion: &SampledMotion, loads: Option<&ExternalLoads>, body_force_joints: &[usize]) -> Result<InverseDynamicsResult, InverseDynamicsError> {
    let order = tree_order(multibody);
    let mut values = Vec::with_capacity(motion.times.len() * (order.len() + 1));
    let mut kinematics = multibody.kinematics();
    let mut body_forces = Vec::new();
    for (&time, state) in motion.times.iter().zip(&motion.states) {
        multibody.realize(&state.q, &mut kinematics);
        let applied = loads.map(|l| l.at(time, &kinematics)).unwrap_or_default();
        let forces = multibody.inverse_dynamics_at(&kinematics, &MotionState { q: &state.q, u: &state.u, udot: &state.udot }, &applied);
        values.push(time);
        values.extend(order.iter().map(|&c| forces[c]));
        body_forces.push(time);
        for &joint in body_force_joints {
            let (force, torque) = multibody.equivalent_body_force(&kinematics, joint, &forces);
            body_forces.extend(force.iter().chain(torque.iter()));
        }
    }
    let labels = std::iter::once("time".to_string()).chain(order.iter().map(|&c| label(multibody, c))).collect();
    let forces = StorageTable::new("Inverse Dynamics Generalized Forces", labels, values)?.with_in_degrees(false);
    let body_forces = if body_force_joints.is_empty() { None } else { Some(body_force_table(multibody, body_force_joints, body_forces)?) };
    Ok(InverseDynamicsResult { forces, body_forces, defaulted: motion.defaulted.clone(), ignored_columns: motion.ignored_columns.clone() })
}

/// OpenSim's body-forces table: per joint `<joint>_<child frame>_FX … _MZ`.
fn body_force_table(multibody: &Multibody, joints: &[usize], values: Vec<f64>) -> Result<StorageTable, TableError> {
    let mut labels = vec!["time".to_string()];
    for &j in joints {
        let joint = &multibody.joints[j];
        labels.extend(["FX", "FY", "FZ", "MX", "MY", "MZ"].map(|s| format!("{}_{}_{s}", joint.name, joint.child_frame)));
    }
    Ok(StorageTable::new("Inverse Dynamics Body Forces at Specified Joints", labels, values)?.with_in_degrees(false))
}

/// Coordinates in Simbody's mobility order: joints by their depth below ground, then in the
/// model's order (`Model::getCoordinatesInMultibodyTreeOrder`).
fn tree_order(multibody: &Multibody) -> Vec<usize> {
    let depth = |c: usize| {
        let mut joint = multibody.coordinate_joint(c);
        let mut depth = 0;
        while let Some(parent) = multibody.bodies[multibody.joints[joint].parent].joint {
            joint = parent;
            depth += 1;
        }
        depth
    };
    let mut order: Vec<usize> = (0..multibody.coordinates.len()).collect();
    order.sort_by_key(|&c| (depth(c), c));
    order
}

/// OpenSim's column name: `_moment` for a rotational coordinate, else `_force`.
pub(super) fn label(multibody: &Multibody, c: usize) -> String {
    let coordinate = &multibody.coordinates[c];
    let suffix = if coordinate.motion_type == MotionType::Rotational { "moment" } else { "force" };
    format!("{}_{suffix}", coordinate.name)
}
