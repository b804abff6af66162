//! The default pose OpenSim's `initSystem` assembles, against the goldens of
//! `oracle/gen_constraint_assembly.py` (`fixtures/golden/constraint_assembly.json`): per model,
//! the assembled coordinates and every marker in ground there.

use std::path::Path;

use serde_json::Value;

use super::geometry::Worst;
use super::model_goldens::{numbers, ModelGoldenError};
use crate::io::osim::OsimDocument;
use crate::mechanics::Multibody;
use crate::model::ModelSpec;
use crate::solvers::assemble;

/// The worst differences of our assembled default pose from OpenSim's.
#[derive(Debug, Clone, Default)]
pub struct AssemblyComparison {
    /// rad or m.
    pub coordinates: Worst,
    /// m.
    pub markers: Worst,
}

/// `fixtures/models/<model>` assembled from its default values, against its entry in the golden.
pub fn compare_assembly(root: &Path, model: &str) -> Result<AssemblyComparison, ModelGoldenError> {
    let (path, golden_path) = (root.join("fixtures/models").join(model), root.join("fixtures/golden/constraint_assembly.json"));
    let failed = |file: &Path, problem: String| ModelGoldenError { file: file.into(), problem };
    let text = std::fs::read_to_string(&golden_path).map_err(|e| failed(&golden_path, e.to_string()))?;
    let goldens: Value = serde_json::from_str(&text).map_err(|e| failed(&golden_path, e.to_string()))?;
    let golden = &goldens[model];
    let document = OsimDocument::read(&path).map_err(|e| failed(&path, e.to_string()))?;
    let multibody = ModelSpec::read(&document).map_err(|e| e.to_string()).and_then(|spec| Multibody::new(&spec).map_err(|e| e.to_string())).map_err(|e| failed(&path, e))?;
    let names: Vec<&str> = multibody.coordinates.iter().map(|c| c.name.as_str()).collect();
    let expected: Vec<&str> = golden["coordinates"].as_array().map(|a| a.iter().filter_map(Value::as_str).collect()).unwrap_or_default();
    if expected != names {
        return Err(failed(&golden_path, format!("{model}: coordinates {expected:?}; the model's are {names:?}")));
    }
    let defaults: Vec<f64> = multibody.coordinates.iter().map(|c| c.default_value).collect();
    let q = assemble(&multibody, &defaults).map_err(|e| failed(&path, e.to_string()))?;
    let mut comparison = AssemblyComparison::default();
    for ((name, ours), theirs) in names.iter().zip(&q).zip(numbers(&golden["assembled"])) {
        comparison.coordinates.update((ours - theirs).abs(), || name.to_string());
    }
    let mut kinematics = multibody.kinematics();
    multibody.realize(&q, &mut kinematics);
    for (m, marker) in multibody.markers.iter().enumerate() {
        let ours = kinematics.marker_location(&multibody, m);
        let theirs = numbers(&golden["markers_in_ground"][&marker.name]);
        for axis in 0..3 {
            let error = theirs.get(axis).map_or(f64::NAN, |value| (ours[axis] - value).abs());
            comparison.markers.update(error, || marker.name.clone());
        }
    }
    Ok(comparison)
}
