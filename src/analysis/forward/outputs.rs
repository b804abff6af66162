//! What a forward simulation reports at chosen times: each driven muscle's activation, fiber
//! length and tendon force (a rigid tendon's from the path's lengthening speed), and the
//! generalized forces the muscles produce together,
//! Σ F_t r (N·m or N; r the moment arm about the coordinate, positive when tension drives it
//! up) — and how these compare with inverse dynamics.

use std::path::{Path, PathBuf};

use super::{DrivenMuscle, ForwardError, PrescribedMotion, Trajectory};
use crate::analysis::inverse_dynamics::label;
use crate::analysis::storage;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MuscleGeometry, PathEvaluation};

/// Per report time (rows) the muscles' states and forces and their generalized forces.
#[derive(Debug, Clone)]
pub struct ForwardOutputs {
    pub times: Vec<f64>,
    pub muscles: Vec<String>,
    /// Per row, per muscle.
    pub activations: Vec<Vec<f64>>,
    /// Per row, per muscle, m.
    pub fiber_lengths: Vec<Vec<f64>>,
    /// Per row, per muscle, N.
    pub tendon_forces: Vec<Vec<f64>>,
    /// Per muscle: F_max (N) when its state is the normalized tendon force (compliant
    /// DeGroote muscles), else `None` (its state is the fiber length).
    pub normalized_tendon_force_scales: Vec<Option<f64>>,
    /// `<coordinate>_moment` or `_force` for each coordinate a driven muscle's tension loads
    /// (`GeometryPath::loaded`; no coupler's dependent), model order.
    pub labels: Vec<String>,
    /// Per row, per label, N·m or N.
    pub generalized_forces: Vec<Vec<f64>>,
}

/// How the muscles' generalized force on one coordinate compares with inverse dynamics.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateComparison {
    pub label: String,
    /// RMS of muscles − inverse dynamics, N·m or N.
    pub rms_difference: f64,
    /// RMS of the inverse-dynamics force itself.
    pub rms_inverse_dynamics: f64,
    /// The largest |muscles − inverse dynamics| and its time (s).
    pub max_difference: f64,
    pub time_of_max: f64,
}

impl ForwardOutputs {
    /// The outputs at `times` (s, inside the trajectory's range).
    pub fn new(geometry: &MuscleGeometry, muscles: &[DrivenMuscle], motion: &PrescribedMotion, trajectory: &Trajectory, times: &[f64]) -> ForwardOutputs {
        let multibody = &geometry.multibody;
        let mut reported: Vec<usize> = muscles.iter().flat_map(|m| geometry.paths[m.path].loaded.iter().copied()).filter(|&c| !multibody.is_dependent(c)).collect();
        reported.sort_unstable();
        reported.dedup();
        let paths: Vec<usize> = muscles.iter().map(|m| m.path).collect();
        let mut evaluation = PathEvaluation::loading(geometry, &paths);
        let (mut q, mut speeds) = (vec![0.0; multibody.coordinates.len()], vec![0.0; multibody.coordinates.len()]);
        let mut outputs = ForwardOutputs {
            times: times.to_vec(),
            muscles: muscles.iter().map(|m| m.name.clone()).collect(),
            activations: Vec::new(),
            fiber_lengths: Vec::new(),
            tendon_forces: Vec::new(),
            normalized_tendon_force_scales: muscles.iter().map(|m| m.tendon_force_state().map(|d| d.max_isometric_force())).collect(),
            labels: reported.iter().map(|&c| label(multibody, c)).collect(),
            generalized_forces: Vec::new(),
        };
        for &time in times {
            motion.pose(time, &mut q);
            motion.speeds(time, &q, &mut speeds);
            evaluation.evaluate_moving(geometry, &q, Some(&speeds));
            let (activations, mut fiber_lengths) = trajectory.states(time);
            let mut forces = vec![0.0; muscles.len()];
            for (k, m) in muscles.iter().enumerate() {
                let length = evaluation.length(k);
                if let Some(d) = m.tendon_force_state() {
                    let normalized_force = fiber_lengths[k];
                    (fiber_lengths[k], forces[k]) = (d.fiber_length_at(length, normalized_force), d.max_isometric_force() * normalized_force);
                    continue;
                }
                let rigid = m.muscle.rigid_tendon_state(activations[k], length, evaluation.lengthening_speed(k));
                match rigid {
                    Some((fiber_length, force)) => (fiber_lengths[k], forces[k]) = (fiber_length, force),
                    None => forces[k] = m.muscle.tendon_force(fiber_lengths[k], length),
                }
            }
            let mut generalized = vec![0.0; multibody.coordinates.len()];
            for (k, force) in forces.iter().enumerate() {
                for (&c, r) in evaluation.coordinates(geometry, k).iter().zip(evaluation.moment_arms(k)) {
                    generalized[c] += force * r;
                }
            }
            outputs.activations.push(activations);
            outputs.fiber_lengths.push(fiber_lengths);
            outputs.tendon_forces.push(forces);
            outputs.generalized_forces.push(reported.iter().map(|&c| generalized[c]).collect());
        }
        outputs
    }

    /// OpenSim's states table: `/forceset/<muscle>/activation`, then `/forceset/<muscle>/fiber_length`
    /// (m) or, for a compliant DeGroote muscle, `/forceset/<muscle>/normalized_tendon_force`.
    pub fn states_table(&self, name: &str) -> Result<StorageTable, TableError> {
        let scales = &self.normalized_tendon_force_scales;
        let second = |m: &String, scale: &Option<f64>| format!("/forceset/{m}/{}", if scale.is_some() { "normalized_tendon_force" } else { "fiber_length" });
        let labels = self.muscles.iter().map(|m| format!("/forceset/{m}/activation")).chain(self.muscles.iter().zip(scales).map(|(m, s)| second(m, s)));
        let rows = (0..self.times.len()).map(|i| {
            let states = scales.iter().enumerate().map(|(k, scale)| scale.map_or(self.fiber_lengths[i][k], |f_max| self.tendon_forces[i][k] / f_max));
            self.activations[i].iter().copied().chain(states).collect()
        });
        self.table(name, labels, rows)
    }

    /// Tendon force (N) per muscle.
    pub fn tendon_force_table(&self, name: &str) -> Result<StorageTable, TableError> {
        self.table(name, self.muscles.iter().cloned(), self.tendon_forces.iter().cloned())
    }

    /// The muscles' generalized forces, columns named as inverse dynamics names them.
    pub fn generalized_force_table(&self, name: &str) -> Result<StorageTable, TableError> {
        self.table(name, self.labels.iter().cloned(), self.generalized_forces.iter().cloned())
    }

    fn table(&self, name: &str, labels: impl Iterator<Item = String>, rows: impl Iterator<Item = Vec<f64>>) -> Result<StorageTable, TableError> {
        let labels = std::iter::once("time".to_string()).chain(labels).collect();
        let values = self.times.iter().zip(rows).flat_map(|(&t, row)| std::iter::once(t).chain(row)).collect();
        storage(name, labels, values)
    }
}

/// The rows of an inverse-dynamics table (`table`, read from `file`) inside `range` (s).
pub fn inverse_dynamics_times(table: &StorageTable, range: [f64; 2]) -> Vec<f64> {
    table.times().into_iter().filter(|t| (range[0]..=range[1]).contains(t)).collect()
}

/// Compares `outputs` — computed at [`inverse_dynamics_times`] of `table` — with the columns
/// of `table` (read from `file`) that carry the same labels.
pub fn compare_with_inverse_dynamics(outputs: &ForwardOutputs, table: &StorageTable, file: &Path) -> Result<Vec<CoordinateComparison>, ForwardError> {
    // Each output row with the table's row at its time (both from `inverse_dynamics_times`).
    let rows: Vec<&[f64]> = outputs.times.iter().filter_map(|&t| table.rows().find(|row| row[0] == t)).collect();
    let compared: Vec<(usize, usize)> = outputs.labels.iter().enumerate().filter_map(|(j, l)| table.column_index(l).map(|c| (j, c))).collect();
    if compared.is_empty() || rows.is_empty() || rows.len() != outputs.times.len() {
        return Err(ForwardError::NothingToCompare { file: PathBuf::from(file), labels: outputs.labels.clone() });
    }
    Ok(compared
        .iter()
        .map(|&(j, c)| {
            let differences: Vec<(f64, f64)> = rows.iter().zip(&outputs.generalized_forces).map(|(row, ours)| (ours[j] - row[c], row[0])).collect();
            let rms = |values: &mut dyn Iterator<Item = f64>| (values.map(|v| v * v).sum::<f64>() / rows.len() as f64).sqrt();
            let (max_difference, time_of_max) = differences.iter().map(|&(d, t)| (d.abs(), t)).fold((0.0, rows[0][0]), |m, d| if d.0 > m.0 { d } else { m });
            CoordinateComparison {
                label: outputs.labels[j].clone(),
                rms_difference: rms(&mut differences.iter().map(|d| d.0)),
                rms_inverse_dynamics: rms(&mut rows.iter().map(|row| row[c])),
                max_difference,
                time_of_max,
            }
        })
        .collect())
}
