//! Scaled models compared with OpenSim's, component by component and property by property.

use crate::io::osim::OsimDocument;
use crate::io::table::MarkerTable;
use crate::mechanics::{Multibody, Vec3};
use crate::review::{diff_flat, flatten, flatten_for_comparison, Change, Difference, Tolerance};
use crate::setup::IkTaskSet;

/// The agreement the Scale step must reach: 1e-7 relative, or 1e-9 (m, kg, …) for values near 0.
pub const SCALED_MODEL_TOLERANCE: Tolerance = Tolerance { relative: 1e-7, absolute: 1e-9 };

/// Every difference between OpenSim's scaled model and ours beyond `tolerance`, ours read as
/// OpenSim 4.6 writes it (a 4.0 generic model names a muscle's path `geometrypath`; 4.6 `path`).
/// A frame's default `frame_geometry`, which OpenSim writes for every frame once it has built
/// the model and a model converted from 3.x does not hold, is no difference.
pub fn compare_scaled_models(opensim: &OsimDocument, ours: &OsimDocument, tolerance: Tolerance) -> Vec<Difference> {
    let (ours, _) = flatten_for_comparison(ours, opensim.version.number);
    let mut differences = diff_flat(&flatten(opensim), &ours, tolerance);
    differences.retain(|d| !(d.path.ends_with("/frame_geometry") && matches!(&d.change, Change::Removed { class } if class == "FrameGeometry")));
    differences
}

/// MarkerPlacer's objective Σ w_i‖x_i(q) − x̂_i‖² (m²) over the applied marker tasks of `tasks`,
/// with x̂ the first frame of `static_pose` (m), written out independently of the IK solver so
/// that its result can be checked against OpenSim's pose. `None` when a task's marker is
/// missing from the model or the pose.
pub fn marker_objective(multibody: &Multibody, tasks: &IkTaskSet, static_pose: &MarkerTable, q: &[f64]) -> Option<f64> {
    let mut kinematics = multibody.kinematics();
    multibody.realize(q, &mut kinematics);
    let mut objective = 0.0;
    for task in tasks.marker_tasks.iter().filter(|t| t.apply) {
        let marker = multibody.markers.iter().position(|m| m.name == task.name)?;
        let observed = Vec3::from(static_pose.position(0, static_pose.marker_index(&task.name)?)?);
        objective += task.weight * (kinematics.marker_location(multibody, marker) - observed).norm_squared();
    }
    Some(objective)
}
