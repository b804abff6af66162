//! MuscleAnalysis: muscle-tendon lengths, moment arms and marker locations along a motion, as
//! OpenSim's `MuscleAnalysis` and `MarkerLocations` report them.

use super::{path_labels, storage, Spans};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Motion, MuscleGeometry, PathEvaluation};

/// The tables of one analysis; every table has a `time` column first.
#[derive(Debug, Clone)]
pub struct MuscleAnalysis {
    /// `Length`: one column per muscle (m).
    pub lengths: StorageTable,
    /// `MomentArm_<coordinate>` for each coordinate some muscle spans: one column per muscle
    /// (m, or m/m for a translational coordinate; 0 for muscles that do not span it).
    pub moment_arms: Vec<(String, StorageTable)>,
    /// `MarkerLocations`: `<marker>_tx/_ty/_tz` in ground (m).
    pub marker_locations: StorageTable,
    /// Muscles whose values ignore their wrap objects (some not wrapped over yet), with the objects.
    pub ignored_wraps: Vec<(String, Vec<String>)>,
}

impl MuscleAnalysis {
    pub fn run(geometry: &MuscleGeometry, motion: &Motion) -> Result<MuscleAnalysis, TableError> {
        let multibody = &geometry.multibody;
        let muscles: Vec<usize> = (0..geometry.paths.len()).collect();
        let mut evaluation = PathEvaluation::new(geometry, &muscles);
        let Spans { coordinates: spanned, slots } = Spans::new(geometry, &muscles);
        let n_muscles = muscles.len();
        let mut lengths = Vec::with_capacity(motion.len() * (n_muscles + 1));
        let mut moment_arms = vec![Vec::with_capacity(motion.len() * (n_muscles + 1)); spanned.len()];
        let mut markers = Vec::with_capacity(motion.len() * (3 * multibody.markers.len() + 1));
        for (row, &time) in motion.times.iter().enumerate() {
            evaluation.evaluate(geometry, motion.pose(row));
            lengths.push(time);
            lengths.extend((0..n_muscles).map(|k| evaluation.length(k)));
            for (table, slots) in moment_arms.iter_mut().zip(&slots) {
                table.push(time);
                table.extend(slots.iter().enumerate().map(|(k, slot)| slot.map_or(0.0, |i| evaluation.moment_arms(k)[i])));
            }
            markers.push(time);
            for marker in 0..multibody.markers.len() {
                markers.extend(evaluation.kinematics().marker_location(multibody, marker).iter());
            }
        }
        let muscle_labels = path_labels(geometry, &muscles);
        let marker_labels = std::iter::once("time".to_string())
            .chain(multibody.markers.iter().flat_map(|m| ["tx", "ty", "tz"].map(|axis| format!("{}_{axis}", m.name))))
            .collect();
        let moment_arms = spanned
            .iter()
            .zip(moment_arms)
            .map(|(&c, values)| {
                let name = multibody.coordinates[c].name.clone();
                Ok((name.clone(), storage(&format!("MomentArm_{name}"), muscle_labels.clone(), values)?))
            })
            .collect::<Result<_, TableError>>()?;
        Ok(MuscleAnalysis {
            lengths: storage("Length", muscle_labels, lengths)?,
            moment_arms,
            marker_locations: storage("MarkerLocations", marker_labels, markers)?,
            ignored_wraps: geometry.paths.iter().filter(|p| !p.ignored_wraps.is_empty()).map(|p| (p.name.clone(), p.ignored_wraps.clone())).collect(),
        })
    }
}
