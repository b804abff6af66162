//! How a joint swap changes the muscles that cross the joint: path length and moment arm about
//! the joint's coordinate across its range, every other coordinate at its default.

use serde::Serialize;

use crate::mechanics::{MechanicsError, MuscleGeometry, PathEvaluation};
use crate::model::CoordinateSpec;

/// Coordinate values sampled across the range (ends included).
pub const SAMPLES: usize = 101;

/// One muscle's changes (after − before) across the coordinate's range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathChange {
    pub muscle: String,
    /// Largest |ΔL_mt| (m) and the coordinate value (rad) where it occurs.
    pub max_length_change: f64,
    pub max_length_change_at: f64,
    /// Largest |Δr| (m) of the moment arm about the coordinate and where it occurs.
    pub max_moment_arm_change: f64,
    pub max_moment_arm_change_at: f64,
    /// RMS of Δr over the samples, m.
    pub rms_moment_arm_change: f64,
}

/// The changes of every path of `before` that spans `coordinate`, compared with the same path in
/// `after` (the same model with one joint replaced).
pub fn path_changes(before: &MuscleGeometry, after: &MuscleGeometry, coordinate: &CoordinateSpec) -> Result<Vec<PathChange>, MechanicsError> {
    let missing = |what: &str| MechanicsError::Invalid { file: after.multibody.file.clone(), component: what.to_string(), problem: "missing after the swap".into() };
    let index_before = before.multibody.coordinate_index(&coordinate.name).ok_or_else(|| missing(&coordinate.name))?;
    let index_after = after.multibody.coordinate_index(&coordinate.name).ok_or_else(|| missing(&coordinate.name))?;
    let crossing: Vec<usize> = (0..before.paths.len()).filter(|&m| before.paths[m].spanned.contains(&index_before)).collect();
    let counterparts = crossing.iter().map(|&m| after.path_index(&before.paths[m].name).ok_or_else(|| missing(&before.paths[m].name))).collect::<Result<Vec<_>, _>>()?;
    let old = sweep(before, &crossing, index_before, coordinate);
    let new = sweep(after, &counterparts, index_after, coordinate);
    let angles = sample_angles(coordinate);
    Ok(crossing.iter().enumerate().map(|(k, &m)| change(&before.paths[m].name, &angles, &old[k], &new[k])).collect())
}

/// The sampled coordinate values, rad.
fn sample_angles(coordinate: &CoordinateSpec) -> Vec<f64> {
    let [low, high] = coordinate.range;
    (0..SAMPLES).map(|i| low + (high - low) * i as f64 / (SAMPLES - 1) as f64).collect()
}

/// (length, moment arm about the coordinate) per sample, per chosen muscle.
fn sweep(geometry: &MuscleGeometry, muscles: &[usize], coordinate: usize, spec: &CoordinateSpec) -> Vec<Vec<(f64, f64)>> {
    let mut evaluation = PathEvaluation::new(geometry, muscles);
    let mut q = geometry.multibody.default_pose();
    let mut values = vec![Vec::with_capacity(SAMPLES); muscles.len()];
    for angle in sample_angles(spec) {
        q[coordinate] = angle;
        evaluation.evaluate(geometry, &q);
        for (k, &m) in muscles.iter().enumerate() {
            let slot = geometry.paths[m].spanned.iter().position(|&c| c == coordinate);
            let moment_arm = slot.map_or(0.0, |s| evaluation.moment_arms(k)[s]);
            values[k].push((evaluation.length(k), moment_arm));
        }
    }
    values
}

fn change(muscle: &str, angles: &[f64], old: &[(f64, f64)], new: &[(f64, f64)]) -> PathChange {
    let worst = |part: fn(&(f64, f64)) -> f64| {
        let deltas = old.iter().zip(new).map(|(a, b)| (part(b) - part(a)).abs());
        deltas.enumerate().fold((0.0, angles[0]), |best, (i, d)| if d > best.0 { (d, angles[i]) } else { best })
    };
    let (max_length_change, max_length_change_at) = worst(|v| v.0);
    let (max_moment_arm_change, max_moment_arm_change_at) = worst(|v| v.1);
    let squares: f64 = old.iter().zip(new).map(|(a, b)| (b.1 - a.1).powi(2)).sum();
    PathChange {
        muscle: muscle.to_string(),
        max_length_change,
        max_length_change_at,
        max_moment_arm_change,
        max_moment_arm_change_at,
        rms_moment_arm_change: (squares / old.len() as f64).sqrt(),
    }
}
