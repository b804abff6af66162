//! Model features OpenSim computes in its own way against the JSON goldens of
//! `oracle/gen_{ellipsoid_joints,station_frames,legacy_conversion}.py`: joints that glide on
//! an ellipsoid, station-defined frames and a 3.x model as OpenSim 4 converts it. Each golden
//! holds poses with the markers in ground and a muscle's length, and where it says so the
//! moment arms about every coordinate and the inverse-dynamics generalized forces.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::geometry::Worst;
use crate::io::osim::OsimDocument;
use crate::mechanics::{body_fixed_xyz, MotionState, MuscleGeometry, PathEvaluation};
use crate::model::{ComponentReader, ModelSpec};

/// A golden that cannot be read or a model that cannot be compiled.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", file.display())]
pub struct ModelGoldenError {
    pub file: PathBuf,
    pub problem: String,
}

/// The worst differences over a golden's poses (absolute; m, m, m, N·m or N, and for the
/// station frames rotation entries and origins).
#[derive(Debug, Clone, Default)]
pub struct PoseComparison {
    pub markers: Worst,
    pub lengths: Worst,
    pub moment_arms: Worst,
    pub generalized_forces: Worst,
    /// Station-defined frames' transforms in their bodies: rotation entries and origins (m).
    pub frames: Worst,
}

/// The model at `model` and the golden at `golden` (both under `root/fixtures`), compared.
pub fn compare_model_golden(root: &Path, model: &str, golden: &str) -> Result<PoseComparison, ModelGoldenError> {
    let (model, golden) = (root.join("fixtures").join(model), root.join("fixtures").join(golden));
    let failed = |file: &Path, problem: String| ModelGoldenError { file: file.into(), problem };
    let text = std::fs::read_to_string(&golden).map_err(|e| failed(&golden, e.to_string()))?;
    let golden_json: Value = serde_json::from_str(&text).map_err(|e| failed(&golden, e.to_string()))?;
    let document = OsimDocument::read(&model).map_err(|e| failed(&model, e.to_string()))?;
    let spec = ModelSpec::read(&document).map_err(|e| failed(&model, e.to_string()))?;
    let geometry = MuscleGeometry::new(&spec).map_err(|e| failed(&model, e.to_string()))?;
    let names: Vec<&str> = geometry.multibody.coordinates.iter().map(|c| c.name.as_str()).collect();
    if let Some(expected) = golden_json["coordinates"].as_array() {
        if expected.iter().map(|n| n.as_str().unwrap_or_default()).ne(names.iter().copied()) {
            return Err(failed(&golden, format!("coordinates {expected:?}; the model's are {names:?}")));
        }
    }
    let mut comparison = PoseComparison::default();
    compare_frames(&document, &golden_json, &mut comparison).map_err(|e| failed(&model, e.to_string()))?;
    let poses = golden_json["poses"].as_array().ok_or_else(|| failed(&golden, "no \"poses\"".into()))?;
    for pose in poses {
        compare_pose(&geometry, pose, &mut comparison);
    }
    Ok(comparison)
}

/// The numbers of a JSON array (NaN for an entry that is not one; none for a non-array).
pub(super) fn numbers(value: &Value) -> Vec<f64> {
    value.as_array().map(|a| a.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect()).unwrap_or_default()
}

/// Markers (`markers_in_ground`), the muscle's `length` and, where the golden has them,
/// `moment_arms` and `generalized_forces` (for speeds `u` and accelerations `udot`) at one pose.
fn compare_pose(geometry: &MuscleGeometry, pose: &Value, comparison: &mut PoseComparison) {
    let multibody = &geometry.multibody;
    let q = numbers(&pose["q"]);
    let mut evaluation = PathEvaluation::loading(geometry, &[0]);
    evaluation.evaluate(geometry, &q);
    for (m, marker) in multibody.markers.iter().enumerate() {
        let expected = numbers(&pose["markers_in_ground"][&marker.name]);
        let ours = evaluation.kinematics().marker_location(multibody, m);
        for (axis, value) in expected.iter().enumerate() {
            comparison.markers.update((ours[axis] - value).abs(), || format!("{q:?} / {}", marker.name));
        }
    }
    let length = pose["length"].as_f64().unwrap_or(f64::NAN);
    comparison.lengths.update((evaluation.length(0) - length).abs(), || format!("{q:?}"));
    if pose["moment_arms"].is_object() {
        let mut arms = vec![0.0; multibody.coordinates.len()];
        for (&c, &arm) in evaluation.coordinates(geometry, 0).iter().zip(evaluation.moment_arms(0)) {
            arms[c] = arm;
        }
        for (c, coordinate) in multibody.coordinates.iter().enumerate() {
            let expected = pose["moment_arms"][&coordinate.name].as_f64().unwrap_or(f64::NAN);
            comparison.moment_arms.update((arms[c] - expected).abs(), || format!("{q:?} / {}", coordinate.name));
        }
    }
    if pose["generalized_forces"].is_array() {
        let (u, udot) = (numbers(&pose["u"]), numbers(&pose["udot"]));
        let forces = multibody.inverse_dynamics(&MotionState { q: &q, u: &u, udot: &udot }, &[]);
        for ((ours, expected), coordinate) in forces.iter().zip(numbers(&pose["generalized_forces"])).zip(&multibody.coordinates) {
            comparison.generalized_forces.update((ours - expected).abs(), || format!("{q:?} / {}", coordinate.name));
        }
    }
}

/// The station-defined frames' transforms in their bodies (`frames_in_body`, keyed by the
/// frame's component path below the model), as the model reader resolves them.
fn compare_frames(document: &OsimDocument, golden: &Value, comparison: &mut PoseComparison) -> Result<(), crate::model::ModelError> {
    let Some(frames) = golden["frames_in_body"].as_object() else { return Ok(()) };
    let index = ModelSpec::frame_index(document)?;
    let model = ComponentReader::new(document, document.object);
    for (name, frame) in frames {
        let chain = index.resolve(model, &format!("/{name}"), "frame")?;
        let Some(offset) = chain.offsets.first() else { continue };
        let rotation = body_fixed_xyz(offset.orientation);
        for (i, row) in frame["rotation"].as_array().into_iter().flatten().enumerate() {
            for (j, value) in numbers(row).into_iter().enumerate() {
                comparison.frames.update((rotation[(i, j)] - value).abs(), || format!("{name} R[{i}][{j}]"));
            }
        }
        for (ours, value) in offset.translation.iter().zip(numbers(&frame["origin"])) {
            comparison.frames.update((ours - value).abs(), || format!("{name} origin"));
        }
    }
    Ok(())
}
