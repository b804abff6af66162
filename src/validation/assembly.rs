//! The default pose OpenSim's `initSystem` assembles, against the goldens of
//! `oracle/gen_constraint_assembly.py` and `oracle/gen_shoulder_moment_arms.py`: per model,
//! the assembled coordinates and every marker in ground there; where the golden has `poses`,
//! each muscle's length and its moment arms about every coordinate through the constraints.

use std::path::Path;

use serde_json::Value;

use super::geometry::Worst;
use super::model_goldens::{numbers, ModelGoldenError};
use crate::io::osim::OsimDocument;
use crate::mechanics::{projected_coupling, MuscleGeometry, PathEvaluation};
use crate::model::ModelSpec;
use crate::solvers::assemble;

/// The worst differences of our assembled default pose from OpenSim's, and of lengths and
/// moment arms at the golden's poses.
#[derive(Debug, Clone, Default)]
pub struct AssemblyComparison {
    /// rad or m.
    pub coordinates: Worst,
    /// m.
    pub markers: Worst,
    /// m.
    pub lengths: Worst,
    /// m (m/m about translations).
    pub moment_arms: Worst,
    /// Moment arms not compared: about a coordinate the constraints (nearly) fix, whose lit
    /// speed projects below [`ILL_DEFINED_SPEED`], where OpenSim's value is round-off.
    pub ill_defined: usize,
}

/// A coordinate whose unit speed keeps less than this after projection onto the velocity
/// constraints is (nearly) fixed by them: moment arms about it divide by that remainder.
pub const ILL_DEFINED_SPEED: f64 = 1e-3;

/// `fixtures/models/<model>` assembled from its default values, against its entry in
/// `fixtures/golden/<golden>` (`constraint_assembly.json`, `shoulder_moment_arms.json`).
pub fn compare_assembly(root: &Path, model: &str, golden: &str) -> Result<AssemblyComparison, ModelGoldenError> {
    let (path, golden_path) = (root.join("fixtures/models").join(model), root.join("fixtures/golden").join(golden));
    let failed = |file: &Path, problem: String| ModelGoldenError { file: file.into(), problem };
    let text = std::fs::read_to_string(&golden_path).map_err(|e| failed(&golden_path, e.to_string()))?;
    let goldens: Value = serde_json::from_str(&text).map_err(|e| failed(&golden_path, e.to_string()))?;
    let golden = &goldens[model];
    let document = OsimDocument::read(&path).map_err(|e| failed(&path, e.to_string()))?;
    let geometry = ModelSpec::read(&document).map_err(|e| e.to_string()).and_then(|spec| MuscleGeometry::new(&spec).map_err(|e| e.to_string())).map_err(|e| failed(&path, e))?;
    let multibody = &geometry.multibody;
    let names: Vec<&str> = multibody.coordinates.iter().map(|c| c.name.as_str()).collect();
    let expected: Vec<&str> = golden["coordinates"].as_array().map(|a| a.iter().filter_map(Value::as_str).collect()).unwrap_or_default();
    if expected != names {
        return Err(failed(&golden_path, format!("{model}: coordinates {expected:?}; the model's are {names:?}")));
    }
    let defaults: Vec<f64> = multibody.coordinates.iter().map(|c| c.default_value).collect();
    let q = assemble(multibody, &defaults).map_err(|e| failed(&path, e.to_string()))?;
    let mut comparison = AssemblyComparison::default();
    for ((name, ours), theirs) in names.iter().zip(&q).zip(numbers(&golden["assembled"])) {
        comparison.coordinates.update((ours - theirs).abs(), || name.to_string());
    }
    let mut kinematics = multibody.kinematics();
    multibody.realize(&q, &mut kinematics);
    for (m, marker) in multibody.markers.iter().enumerate() {
        let ours = kinematics.marker_location(multibody, m);
        let theirs = numbers(&golden["markers_in_ground"][&marker.name]);
        for axis in 0..3 {
            let error = theirs.get(axis).map_or(f64::NAN, |value| (ours[axis] - value).abs());
            comparison.markers.update(error, || marker.name.clone());
        }
    }
    for pose in golden["poses"].as_array().into_iter().flatten() {
        compare_pose(&geometry, pose, &mut comparison);
    }
    Ok(comparison)
}

/// Each muscle's length and moment arms about every coordinate at the pose's `q`.
fn compare_pose(geometry: &MuscleGeometry, pose: &Value, comparison: &mut AssemblyComparison) {
    let multibody = &geometry.multibody;
    let q = numbers(&pose["q"]);
    let muscles: Vec<usize> = (0..geometry.paths.len()).collect();
    let mut evaluation = PathEvaluation::loading(geometry, &muscles);
    evaluation.evaluate(geometry, &q);
    let fixed: Vec<bool> = (0..q.len()).map(|c| projected_coupling(multibody, evaluation.kinematics(), &q, c).lit_speed.abs() < ILL_DEFINED_SPEED).collect();
    for (k, path) in geometry.paths.iter().enumerate() {
        let length = pose["lengths"][&path.name].as_f64().unwrap_or(f64::NAN);
        comparison.lengths.update((evaluation.length(k) - length).abs(), || path.name.clone());
        let mut arms = vec![0.0; q.len()];
        for (&c, &arm) in evaluation.coordinates(geometry, k).iter().zip(evaluation.moment_arms(k)) {
            arms[c] = arm;
        }
        for (c, coordinate) in multibody.coordinates.iter().enumerate() {
            if fixed[c] {
                comparison.ill_defined += 1;
                continue;
            }
            let expected = pose["moment_arms"][&path.name][&coordinate.name].as_f64().unwrap_or(f64::NAN);
            comparison.moment_arms.update((arms[c] - expected).abs(), || format!("{} about {} at {q:?}", path.name, coordinate.name));
        }
    }
}
