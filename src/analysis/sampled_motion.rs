//! A motion as q, u and u̇ of every coordinate at its frames: sampled from splines
//! ([`SplinedMotion::sample`](super::SplinedMotion::sample)), or given with its speeds and
//! accelerations frame by frame — e.g. by the Kalman smoother (`ik --kalman HZ --kalman-rates
//! R.sto`), whose rates are consistent with its poses and need no splines or filter.

use std::path::{Path, PathBuf};

use super::signal::{frames_in_range, NoFramesInRange};
use crate::io::table::StorageTable;
use crate::mechanics::{Motion, MotionError, Multibody};
use crate::model::MotionType;

/// Rate and coordinate times further apart than this (s) are different frames.
const SAME_TIME: f64 = 1e-6;

/// Why a motion with its rates cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum SampledMotionError {
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error("{}: {problem}", file.display())]
    Rates { file: PathBuf, problem: String },
    #[error(transparent)]
    NoFrames(#[from] NoFramesInRange),
}

/// q, u and u̇ of every coordinate at one time ([`Multibody::coordinates`] order; rad or m, per s,
/// per s²).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateState {
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    pub udot: Vec<f64>,
}

/// A motion's frames: their times (s) and states.
#[derive(Debug, Clone)]
pub struct SampledMotion {
    pub file: PathBuf,
    pub times: Vec<f64>,
    pub states: Vec<CoordinateState>,
    /// Coordinates held at their default value, at rest (not in the file).
    pub defaulted: Vec<String>,
    /// Columns that are no coordinate of the model.
    pub ignored_columns: Vec<String>,
}

impl SampledMotion {
    /// The coordinates of `table` (read from `file`) with the speeds and accelerations of
    /// `rates` (read from `rates_file`): per coordinate in the coordinates file the columns
    /// `<coordinate>_speed` and `<coordinate>_acceleration`, in degrees when its header says so,
    /// one row per frame at the same times.
    pub fn with_rates(multibody: &Multibody, table: &StorageTable, file: &Path, rates: &StorageTable, rates_file: &Path) -> Result<SampledMotion, SampledMotionError> {
        let motion = Motion::from_table(table, file, multibody, true)?;
        let problem = |problem: String| SampledMotionError::Rates { file: rates_file.into(), problem };
        let rate_times = rates.times();
        if rate_times.len() != motion.len() {
            return Err(problem(format!("has {} rows; the coordinates ({}) have {}: expected one row of rates per frame", rate_times.len(), file.display(), motion.len())));
        }
        if let Some(row) = (0..motion.len()).find(|&i| (rate_times[i] - motion.times[i]).abs() > SAME_TIME) {
            return Err(problem(format!("row {} is at {} s, the coordinates' frame at {} s: expected the same times", row + 1, rate_times[row], motion.times[row])));
        }
        let n = multibody.coordinates.len();
        let mut states: Vec<CoordinateState> = (0..motion.len()).map(|i| CoordinateState { q: motion.pose(i).to_vec(), u: vec![0.0; n], udot: vec![0.0; n] }).collect();
        for (c, coordinate) in multibody.coordinates.iter().enumerate().filter(|(_, c)| !motion.defaulted.contains(&c.name)) {
            let scale = if rates.in_degrees() == Some(true) && coordinate.motion_type == MotionType::Rotational { 1f64.to_radians() } else { 1.0 };
            let column = |suffix: &str| {
                let label = format!("{}_{suffix}", coordinate.name);
                let values = rates.column(&label).ok_or_else(|| problem(format!("has no column {label:?} (the coordinate {:?} is in {})", coordinate.name, file.display())))?;
                match values.iter().position(|v| !v.is_finite()) {
                    Some(row) => Err(problem(format!("column {label:?}, row {}: not a number", row + 1))),
                    None => Ok(values.into_iter().map(|v| v * scale).collect::<Vec<f64>>()),
                }
            };
            let (speeds, accelerations) = (column("speed")?, column("acceleration")?);
            for (state, (u, udot)) in states.iter_mut().zip(speeds.into_iter().zip(accelerations)) {
                (state.u[c], state.udot[c]) = (u, udot);
            }
        }
        Ok(SampledMotion { file: file.into(), times: motion.times.clone(), states, defaulted: motion.defaulted, ignored_columns: motion.ignored_columns })
    }

    /// The frames within `range` (s; each end goes to the frame at or before it), or why there
    /// are none.
    pub fn within(mut self, range: [f64; 2]) -> Result<SampledMotion, SampledMotionError> {
        let rows = frames_in_range(&self.file, &self.times, range)?;
        self.states = self.states.drain(rows.clone()).collect();
        self.times = self.times[rows].to_vec();
        Ok(self)
    }
}
