//! The states OpenSim's `AnalyzeTool` forms from a coordinates file, and the accelerations its
//! `StaticOptimization` tracks: coordinates padded and low-pass filtered (when asked), a
//! coordinate the file lacks held at 0 (`SimbodyEngine::formCompleteStorages`), speeds u the
//! derivatives of degree-5 GCV splines through the coordinates at the rows, and accelerations u̇
//! the derivatives of degree-5 GCV splines through those speeds (`GCVSplineSet(5, states)`).
//!
//! Each row is then assembled: a coupler's dependent coordinate is put where its constraint says,
//! its speed left as it is (OpenSim assembles positions only) — 0 when the file lacks it. A dependent coordinate whose motion
//! type is `Coupled` (e.g. leg6dof9musc's patella) is not converted from degrees by OpenSim's
//! degree rule, so in a file in degrees its speed is in degrees per second — as OpenSim has it,
//! whose velocity-dependent forces then follow from that speed.

use std::path::{Path, PathBuf};

use super::signal::{rows_in_range, Series, SignalError};
use crate::io::table::StorageTable;
use crate::mechanics::{Motion, MotionError, Multibody};

/// Why the states cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum StatesError {
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error("{}: {source}", file.display())]
    Signal { file: PathBuf, source: SignalError },
}

/// Coordinates (rad or m), speeds and accelerations per row, [`Multibody::coordinates`] order.
#[derive(Debug, Clone)]
pub struct AnalyzeStates {
    /// s, the filtered (padded, resampled) grid when filtered.
    pub times: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub u: Vec<Vec<f64>>,
    pub udot: Vec<Vec<f64>>,
    /// Coordinates the file lacks and no coupler sets (held at 0, as OpenSim does).
    pub missing: Vec<String>,
    /// Columns that are no coordinate of the model.
    pub ignored_columns: Vec<String>,
}

impl AnalyzeStates {
    /// Forms the states from `table` (read from `file`), low-pass filtered at `cutoff` Hz.
    pub fn new(multibody: &Multibody, table: &StorageTable, file: &Path, cutoff: Option<f64>) -> Result<AnalyzeStates, StatesError> {
        let signal = |source| StatesError::Signal { file: file.into(), source };
        let motion = Motion::from_table(table, file, multibody, true)?;
        let absent: Vec<usize> = (0..multibody.coordinates.len()).filter(|&c| motion.defaulted.contains(&multibody.coordinates[c].name)).collect();
        let missing: Vec<usize> = absent.iter().copied().filter(|&c| !multibody.is_dependent(c)).collect();
        let columns = (0..multibody.coordinates.len())
            .map(|c| (0..motion.len()).map(|i| if absent.contains(&c) { 0.0 } else { motion.pose(i)[c] }).collect())
            .collect();
        let q = Series::new(motion.times.clone(), columns, 6).and_then(|s| s.filtered(cutoff)).map_err(signal)?;
        let u = derivatives(&q).map_err(signal)?;
        let udot = derivatives(&u).map_err(signal)?;
        let mut q_rows = rows(&q);
        for row in &mut q_rows {
            multibody.follow_couplers(row, &[]);
        }
        Ok(AnalyzeStates {
            q: q_rows,
            u: rows(&u),
            udot: rows(&udot),
            times: q.times,
            missing: missing.iter().map(|&c| multibody.coordinates[c].name.clone()).collect(),
            ignored_columns: motion.ignored_columns,
        })
    }

    /// The poses of `rows` (e.g. [`AnalyzeStates::analysed_rows`]) as a [`Motion`]; its
    /// defaulted coordinates are those held at 0.
    pub fn motion(&self, rows: &[usize]) -> Motion {
        let poses: Vec<Vec<f64>> = rows.iter().map(|&i| self.q[i].clone()).collect();
        Motion::from_poses(rows.iter().map(|&i| self.times[i]).collect(), &poses, self.missing.clone(), self.ignored_columns.clone())
    }

    /// The rows an analysis records in `time_range` (s; see `rows_in_range`): the first, the
    /// last and those whose index is a multiple of `step_interval` (`Analysis::proceed`);
    /// `None` when the range misses the times.
    pub fn analysed_rows(&self, time_range: [f64; 2], step_interval: usize) -> Option<Vec<usize>> {
        let range = rows_in_range(&self.times, time_range)?;
        let (first, last) = (*range.start(), *range.end());
        Some(range.filter(|&i| i == first || i == last || i % step_interval == 0).collect())
    }
}

/// The derivative at each row of the degree-5 GCV spline through each signal.
fn derivatives(series: &Series) -> Result<Series, SignalError> {
    let columns = series.splines()?.iter().map(|s| series.times.iter().map(|&t| s.derivative(t)).collect()).collect();
    Ok(Series { times: series.times.clone(), columns })
}

/// Per row, every signal's value.
fn rows(series: &Series) -> Vec<Vec<f64>> {
    (0..series.times.len()).map(|i| series.columns.iter().map(|c| c[i]).collect()).collect()
}
