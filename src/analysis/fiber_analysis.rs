//! The fiber side of OpenSim's `MuscleAnalysis` at static equilibrium: for each time of a
//! motion and each muscle's activation, the fiber–tendon balance at the path length of that
//! pose, and the moments r·F_t it produces about each spanned coordinate.

use super::activation::Activations;
use super::{path_labels, storage, Spans};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::muscle::{EquilibriumStatus, FiberEquilibrium, HillMuscle, MuscleError};
use crate::mechanics::{Motion, MuscleGeometry, PathEvaluation};
use crate::model::ModelSpec;

/// The tables of a fiber analysis, each with `time` first and one column per muscle.
#[derive(Debug, Clone)]
pub struct FiberAnalysis {
    /// FiberLength, NormFiberLength, PennationAngle (rad), TendonLength, TendonForce,
    /// ActiveFiberForce, PassiveFiberForce — in this order.
    pub tables: Vec<StorageTable>,
    /// `Moment_<coordinate>`: r·F_t per muscle (N·m, or N for a translational coordinate) and
    /// their `total`.
    pub moments: Vec<(String, StorageTable)>,
    /// Muscles held at their minimum fiber length without fiber force
    /// (`ClampedAtMinimumFiberLength`) in some rows, with the number of rows.
    pub clamped: Vec<(String, usize)>,
}

/// Why the analysis stopped.
#[derive(Debug, thiserror::Error)]
pub enum FiberAnalysisError {
    #[error("at time {time} s: {source}")]
    Muscle { time: f64, source: MuscleError },
    #[error(transparent)]
    Table(#[from] TableError),
}

/// A reported quantity of a muscle state.
type Quantity = fn(&FiberEquilibrium) -> f64;

const QUANTITIES: [(&str, Quantity); 7] = [
    ("FiberLength", |e| e.fiber_length),
    ("NormFiberLength", |e| e.normalized_fiber_length),
    ("PennationAngle", |e| e.pennation_angle),
    ("TendonLength", |e| e.tendon_length),
    ("TendonForce", |e| e.tendon_force),
    ("ActiveFiberForce", |e| e.active_fiber_force),
    ("PassiveFiberForce", |e| e.passive_fiber_force),
];

/// A Hill muscle and the index of its path in `MuscleGeometry::paths`.
pub type IndexedMuscle = (usize, HillMuscle);

/// The Hill muscles among a model's paths as (path index, muscle), and the names of paths whose
/// class has no muscle mechanics here (path actuators, ligaments, other muscle classes).
pub fn hill_muscles(
    spec: &ModelSpec,
    geometry: &MuscleGeometry,
) -> Result<(Vec<IndexedMuscle>, Vec<String>), MuscleError> {
    let (mut muscles, mut skipped) = (Vec::new(), Vec::new());
    for (index, path) in geometry.paths.iter().enumerate() {
        match spec
            .forces
            .iter()
            .find(|f| f.name == path.name)
            .map(HillMuscle::from_force)
        {
            Some(Ok(muscle)) => muscles.push((index, muscle)),
            Some(Err(MuscleError::Unsupported { .. })) | None => skipped.push(path.name.clone()),
            Some(Err(other)) => return Err(other),
        }
    }
    Ok((muscles, skipped))
}

impl FiberAnalysis {
    /// Runs the analysis for `muscles` = (path index, muscle); activation k belongs to
    /// `muscles[k]`.
    pub fn run(
        geometry: &MuscleGeometry,
        muscles: &[(usize, HillMuscle)],
        motion: &Motion,
        activations: &Activations,
    ) -> Result<FiberAnalysis, FiberAnalysisError> {
        let paths: Vec<usize> = muscles.iter().map(|(p, _)| *p).collect();
        let mut evaluation = PathEvaluation::new(geometry, &paths);
        let Spans { coordinates: spanned, slots } = Spans::new(geometry, &paths);
        let n = muscles.len();
        let mut columns = vec![Vec::with_capacity(motion.len() * (n + 1)); QUANTITIES.len()];
        let mut moments = vec![Vec::with_capacity(motion.len() * (n + 2)); spanned.len()];
        let mut clamped = vec![0usize; n];
        let mut states = Vec::with_capacity(n);
        for (row, &time) in motion.times.iter().enumerate() {
            evaluation.evaluate(geometry, motion.pose(row));
            states.clear();
            for (k, (_, muscle)) in muscles.iter().enumerate() {
                let state = muscle
                    .equilibrium(activations.at(k, time), evaluation.length(k))
                    .map_err(|source| FiberAnalysisError::Muscle { time, source })?;
                clamped[k] += usize::from(state.status == EquilibriumStatus::ClampedAtMinimumFiberLength);
                states.push(state);
            }
            for (table, (_, quantity)) in columns.iter_mut().zip(QUANTITIES) {
                table.push(time);
                table.extend(states.iter().map(quantity));
            }
            for (table, slots) in moments.iter_mut().zip(&slots) {
                table.push(time);
                let first = table.len();
                table.extend(slots.iter().enumerate().map(|(k, slot)| {
                    slot.map_or(0.0, |i| evaluation.moment_arms(k)[i] * states[k].tendon_force)
                }));
                let total = table[first..].iter().sum();
                table.push(total);
            }
        }
        let labels = path_labels(geometry, &paths);
        let tables = QUANTITIES
            .iter()
            .zip(columns)
            .map(|((name, _), values)| storage(name, labels.clone(), values))
            .collect::<Result<_, _>>()?;
        let mut moment_labels = labels;
        moment_labels.push("total".into());
        let moments = spanned
            .iter()
            .zip(moments)
            .map(|(&c, values)| {
                let name = geometry.multibody.coordinates[c].name.clone();
                Ok((
                    name.clone(),
                    storage(&format!("Moment_{name}"), moment_labels.clone(), values)?,
                ))
            })
            .collect::<Result<_, TableError>>()?;
        let clamped = paths
            .iter()
            .zip(clamped)
            .filter(|(_, count)| *count > 0)
            .map(|(&p, count)| (geometry.paths[p].name.clone(), count))
            .collect();
        Ok(FiberAnalysis { tables, moments, clamped })
    }
}
