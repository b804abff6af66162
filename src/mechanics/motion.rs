//! Coordinate trajectories from a motion table (`.mot`/`.sto`), mapped onto a model's
//! coordinates with OpenSim's unit rules.

use std::path::{Path, PathBuf};

use super::multibody::Multibody;
use crate::io::table::StorageTable;
use crate::model::MotionType;

#[derive(Debug, thiserror::Error)]
pub enum MotionError {
    #[error("{}: column {column:?} is not a coordinate of the model {} ({others} more columns are no coordinate either)", file.display(), model.display())]
    UnknownCoordinate { file: PathBuf, model: PathBuf, column: String, others: usize },
    #[error("{}: coordinate {coordinate:?} has more than one column", file.display())]
    RepeatedCoordinate { file: PathBuf, coordinate: String },
    #[error("{}: the table has no rows", file.display())]
    Empty { file: PathBuf },
}

/// Poses over time: one value per model coordinate (rad or m) per row.
#[derive(Debug, Clone)]
pub struct Motion {
    pub times: Vec<f64>,
    /// Row-major, `coordinates.len()` values per row.
    poses: Vec<f64>,
    width: usize,
    /// Columns not used: speeds, and (when asked to skip them) columns that are no coordinate.
    pub ignored_columns: Vec<String>,
    /// Coordinates the table does not give; they stay at their default value, or follow their
    /// coupler when they are its dependent coordinate.
    pub defaulted: Vec<String>,
    /// Whether rotational columns were converted from degrees.
    pub in_degrees: bool,
}

impl Motion {
    /// Maps `table` (read from `file`) onto `multibody`'s coordinates. Columns are coordinate
    /// names or paths ending in `<coordinate>/value`; `…/speed` columns are ignored; any other
    /// column is an error unless `skip_unknown` (then it is listed in `ignored_columns`). Rotational coordinates are converted
    /// from degrees when the table is in degrees as OpenSim reads its unit (`inDegrees`, a SIMM
    /// header's angle line, a `.mot` without `version`; see [`StorageTable::parse`]), radians
    /// when it does not say. Coupled coordinates are never
    /// converted (OpenSim converts only rotational ones). A coupler's dependent coordinate that
    /// the table lacks is set from its independent one. A row at the time of the row before it
    /// replaces that row, as OpenSim's `Storage` reads it.
    pub fn from_table(table: &StorageTable, file: &Path, multibody: &Multibody, skip_unknown: bool) -> Result<Motion, MotionError> {
        let table = &table.with_repeated_times_replaced();
        if table.n_rows() == 0 {
            return Err(MotionError::Empty { file: file.into() });
        }
        let in_degrees = table.in_degrees().unwrap_or(false);
        let mut sources: Vec<Option<usize>> = vec![None; multibody.coordinates.len()];
        let mut ignored_columns = Vec::new();
        let mut unknown = Vec::new();
        for (column, label) in table.labels().iter().enumerate().skip(1) {
            match column_coordinate(label, multibody) {
                ColumnKind::Coordinate(c) if sources[c].is_some() => {
                    return Err(MotionError::RepeatedCoordinate { file: file.into(), coordinate: multibody.coordinates[c].name.clone() })
                }
                ColumnKind::Coordinate(c) => sources[c] = Some(column),
                ColumnKind::Speed => ignored_columns.push(label.clone()),
                ColumnKind::Unknown if skip_unknown => ignored_columns.push(label.clone()),
                ColumnKind::Unknown => unknown.push(label.clone()),
            }
        }
        if let Some(column) = unknown.first() {
            return Err(MotionError::UnknownCoordinate { file: file.into(), model: multibody.file.clone(), column: column.clone(), others: unknown.len() - 1 });
        }
        let width = multibody.coordinates.len();
        let defaults = multibody.default_pose();
        let given: Vec<usize> = (0..width).filter(|&c| sources[c].is_some()).collect();
        let mut poses = Vec::with_capacity(width * table.n_rows());
        for row in table.rows() {
            let start = poses.len();
            for (c, source) in sources.iter().enumerate() {
                let value = source.map_or(defaults[c], |column| row[column]);
                let rotational = multibody.coordinates[c].motion_type == MotionType::Rotational;
                poses.push(if in_degrees && rotational && source.is_some() { value.to_radians() } else { value });
            }
            multibody.follow_couplers(&mut poses[start..], &given);
        }
        let defaulted = sources.iter().zip(&multibody.coordinates).filter(|(s, _)| s.is_none()).map(|(_, c)| c.name.clone()).collect();
        Ok(Motion { times: table.times(), poses, width, ignored_columns, defaulted, in_degrees })
    }

    /// A motion of `poses` (each every coordinate's value, rad or m, [`Multibody::coordinates`]
    /// order) at `times`, with the coordinates and columns its source did not give or use.
    pub fn from_poses(times: Vec<f64>, poses: &[Vec<f64>], defaulted: Vec<String>, ignored_columns: Vec<String>) -> Motion {
        let width = poses.first().map_or(0, Vec::len);
        Motion { times, poses: poses.concat(), width, ignored_columns, defaulted, in_degrees: false }
    }

    /// Replaces each pose by `assemble(pose)` (OpenSim's `AnalyzeTool` assembles every state:
    /// couplers' dependents follow, other constraints close).
    pub fn assemble_poses<E>(&mut self, mut assemble: impl FnMut(&[f64]) -> Result<Vec<f64>, E>) -> Result<(), E> {
        for pose in self.poses.chunks_mut(self.width) {
            let assembled = assemble(pose)?;
            pose.copy_from_slice(&assembled);
        }
        Ok(())
    }

    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Coordinate values of row `index` (rad or m).
    pub fn pose(&self, index: usize) -> &[f64] {
        &self.poses[index * self.width..(index + 1) * self.width]
    }
}

enum ColumnKind {
    Coordinate(usize),
    Speed,
    Unknown,
}

/// What a column label names: a coordinate (`knee_angle_r`, `/jointset/knee_r/knee_angle_r/value`),
/// a speed (`…/speed`), or nothing the model has.
fn column_coordinate(label: &str, multibody: &Multibody) -> ColumnKind {
    let segments: Vec<&str> = label.trim_start_matches('/').split('/').collect();
    let coordinate = match segments.as_slice() {
        [name] | [.., name, "value"] => *name,
        [.., _, "speed"] => return ColumnKind::Speed,
        _ => return ColumnKind::Unknown,
    };
    multibody.coordinate_index(coordinate).map_or(ColumnKind::Unknown, ColumnKind::Coordinate)
}
