//! MuscleAnalysis: muscle-tendon lengths, moment arms and marker locations along a motion, as
//! OpenSim's `MuscleAnalysis` and `MarkerLocations` report them, and the tables a
//! `MuscleAnalysis` setup asks for.

use super::{path_labels, storage, Spans};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Motion, Multibody, MuscleGeometry, PathEvaluation};
use crate::setup::MuscleAnalysisSetup;

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

/// What a `MuscleAnalysis` setup asks of the path geometry, as OpenSim writes it.
#[derive(Debug, Clone)]
pub struct SetupTables {
    /// `Length`, then `MomentArm_<coordinate>` per coordinate of the list when moments are
    /// computed — zeros about a coordinate no muscle spans — each with the listed muscles'
    /// columns in the list's order.
    pub tables: Vec<StorageTable>,
    /// The listed muscles of the model, in the tables' column order.
    pub muscles: Vec<String>,
    /// Listed names that are no muscle or no coordinate of the model (OpenSim drops them).
    pub unknown_muscles: Vec<String>,
    pub unknown_coordinates: Vec<String>,
}

impl MuscleAnalysis {
    /// The tables `setup` asks for: `muscle_list` exactly `all` is every muscle; a
    /// `moment_arm_coordinate_list` whose first word is `all` (any case) every coordinate, in
    /// the model's order (OpenSim's `MuscleAnalysis::allocateStorageObjects`).
    pub fn setup_tables(&self, multibody: &Multibody, setup: &MuscleAnalysisSetup) -> Result<SetupTables, TableError> {
        let every_muscle = setup.muscle_list.len() == 1 && setup.muscle_list[0] == "all";
        let muscle_columns = self.lengths.labels()[1..].to_vec();
        let muscles: Vec<String> = if every_muscle { muscle_columns.clone() } else { setup.muscle_list.clone() };
        let (muscles, unknown_muscles): (Vec<String>, Vec<String>) = muscles.into_iter().partition(|m| muscle_columns.contains(m));
        let every_coordinate = setup.moment_arm_coordinate_list.first().is_some_and(|c| c.eq_ignore_ascii_case("all"));
        let coordinates: Vec<String> = if every_coordinate { multibody.coordinates.iter().map(|c| c.name.clone()).collect() } else { setup.moment_arm_coordinate_list.clone() };
        let (coordinates, unknown_coordinates): (Vec<String>, Vec<String>) = coordinates.into_iter().partition(|c| multibody.coordinates.iter().any(|m| &m.name == c));
        let mut tables = vec![columns_of(&self.lengths, "Length", &muscles)?];
        if setup.compute_moments {
            for coordinate in &coordinates {
                let name = format!("MomentArm_{coordinate}");
                let table = match self.moment_arms.iter().find(|(c, _)| c == coordinate) {
                    Some((_, table)) => columns_of(table, &name, &muscles)?,
                    None => zeros(&self.lengths.times(), &name, &muscles)?,
                };
                tables.push(table);
            }
        }
        Ok(SetupTables { tables, muscles, unknown_muscles, unknown_coordinates })
    }
}

/// `table`'s time and `columns`, named `name`.
fn columns_of(table: &StorageTable, name: &str, columns: &[String]) -> Result<StorageTable, TableError> {
    let indices: Vec<usize> = columns.iter().filter_map(|c| table.column_index(c)).collect();
    let values = table.rows().flat_map(|row| std::iter::once(row[0]).chain(indices.iter().map(|&i| row[i])).collect::<Vec<_>>()).collect();
    let labels = std::iter::once("time".to_string()).chain(columns.iter().cloned()).collect();
    storage(name, labels, values)
}

/// A table of zeros at `times`, a column per muscle of `muscles`, named `name`.
fn zeros(times: &[f64], name: &str, muscles: &[String]) -> Result<StorageTable, TableError> {
    let values = times.iter().flat_map(|&t| std::iter::once(t).chain(std::iter::repeat_n(0.0, muscles.len()))).collect();
    storage(name, std::iter::once("time".to_string()).chain(muscles.iter().cloned()).collect(), values)
}
