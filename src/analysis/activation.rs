//! Where muscle activations (or excitations) come from in an analysis: one value for every
//! muscle, or a `.sto` with a column per muscle (e.g. a static optimisation `activation.sto`),
//! linearly interpolated in time and held at its end values.

use std::path::{Path, PathBuf};

use crate::io::table::StorageTable;

/// Activations of the analysed muscles over time.
#[derive(Debug, Clone)]
pub enum Activations {
    /// The same activation for every muscle and time, in [0, 1].
    Uniform(f64),
    /// Per-muscle columns of a table: `columns[k]` is muscle k's column.
    Table {
        times: Vec<f64>,
        rows: Vec<Vec<f64>>,
        columns: Vec<usize>,
    },
}

/// Why an activation table cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ActivationError {
    #[error("{}: no {quantity} column for muscles {}", file.display(), muscles.join(", "))]
    MissingMuscles { file: PathBuf, quantity: &'static str, muscles: Vec<String> },
    #[error("{}: has no rows", file.display())]
    Empty { file: PathBuf },
    #[error("{}: time {time} s: {quantity} of {muscle} is {value}; expected a number in [0, 1]", file.display())]
    OutOfRange {
        file: PathBuf,
        quantity: &'static str,
        time: f64,
        muscle: String,
        value: f64,
    },
    #[error("{}: time column is not increasing at row {row}", file.display())]
    TimeNotIncreasing { file: PathBuf, row: usize },
}

impl Activations {
    /// The columns of `table` (read from `file`) named after `muscles`; other columns
    /// (reserve actuators, …) are not used. `quantity` names the values in errors
    /// ("activation", "excitation").
    pub fn from_table(
        table: &StorageTable,
        file: &Path,
        muscles: &[String],
        quantity: &'static str,
    ) -> Result<Activations, ActivationError> {
        let missing: Vec<String> = muscles
            .iter()
            .filter(|m| table.column_index(m).is_none())
            .cloned()
            .collect();
        if !missing.is_empty() {
            return Err(ActivationError::MissingMuscles {
                file: file.into(),
                quantity,
                muscles: missing,
            });
        }
        let columns: Vec<usize> = muscles
            .iter()
            .filter_map(|m| table.column_index(m))
            .collect();
        let times = table.times();
        if times.is_empty() {
            return Err(ActivationError::Empty { file: file.into() });
        }
        if let Some(row) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(ActivationError::TimeNotIncreasing {
                file: file.into(),
                row: row + 2,
            });
        }
        let rows: Vec<Vec<f64>> = table.rows().map(<[f64]>::to_vec).collect();
        for (row, &time) in rows.iter().zip(&times) {
            for (muscle, &c) in muscles.iter().zip(&columns) {
                if !(0.0..=1.0).contains(&row[c]) {
                    return Err(ActivationError::OutOfRange {
                        file: file.into(),
                        quantity,
                        time,
                        muscle: muscle.clone(),
                        value: row[c],
                    });
                }
            }
        }
        Ok(Activations::Table {
            times,
            rows,
            columns,
        })
    }

    /// Activation of muscle `k` at `time` (s).
    pub fn at(&self, k: usize, time: f64) -> f64 {
        match self {
            Activations::Uniform(a) => *a,
            Activations::Table {
                times,
                rows,
                columns,
            } => {
                let c = columns[k];
                let after = times.partition_point(|&t| t <= time);
                if after == 0 {
                    return rows[0][c];
                }
                if after == times.len() {
                    return rows[after - 1][c];
                }
                let (t0, t1) = (times[after - 1], times[after]);
                let w = (time - t0) / (t1 - t0);
                rows[after - 1][c] * (1.0 - w) + rows[after][c] * w
            }
        }
    }
}
