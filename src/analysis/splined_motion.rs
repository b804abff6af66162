//! A motion as OpenSim's `InverseDynamicsTool` differentiates it: the coordinates in the file
//! padded and low-pass filtered (when asked), then degree-5 GCV splines give q, q̇ and q̈ at any
//! time; the coordinates the file lacks rest at their default values.

use std::path::{Path, PathBuf};

use super::sampled_motion::{CoordinateState, SampledMotion};
use super::signal::{frames_in_range, NoFramesInRange, Series, SignalError};
use crate::io::table::StorageTable;
use crate::mechanics::{Function, Motion, MotionError, Multibody};

/// Why a motion cannot be splined.
#[derive(Debug, thiserror::Error)]
pub enum SplinedMotionError {
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error("{}: {source}", file.display())]
    Signal { file: PathBuf, source: SignalError },
    #[error(transparent)]
    NoFrames(#[from] NoFramesInRange),
}

/// The coordinates of a motion file as splines of time.
pub struct SplinedMotion {
    file: PathBuf,
    /// The rows' times (after filtering, the same as the file's).
    pub times: Vec<f64>,
    /// The coordinates the file has ([`Multibody::coordinates`] indices) and their splines.
    measured: Vec<usize>,
    splines: Vec<Function>,
    /// Coordinates held at their default value (not in the file).
    pub defaulted: Vec<String>,
    /// Columns that are no coordinate of the model.
    pub ignored_columns: Vec<String>,
}

impl SplinedMotion {
    /// Splines the coordinates of `table` (read from `file`), low-pass filtered at `cutoff` Hz
    /// when given.
    pub fn new(multibody: &Multibody, table: &StorageTable, file: &Path, cutoff: Option<f64>) -> Result<SplinedMotion, SplinedMotionError> {
        let motion = Motion::from_table(table, file, multibody, true)?;
        let signal = |source| SplinedMotionError::Signal { file: file.into(), source };
        let measured: Vec<usize> = (0..multibody.coordinates.len()).filter(|&c| !motion.defaulted.contains(&multibody.coordinates[c].name)).collect();
        let columns = measured.iter().map(|&c| (0..motion.len()).map(|i| motion.pose(i)[c]).collect()).collect();
        let series = Series::new(motion.times.clone(), columns, 6).and_then(|s| s.filtered(cutoff)).map_err(signal)?;
        let splines = series.splines().map_err(signal)?;
        Ok(SplinedMotion { file: file.into(), times: series.times, measured, splines, defaulted: motion.defaulted, ignored_columns: motion.ignored_columns })
    }

    /// The motion's file.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The frames within `range` (s) with the splines' states.
    pub fn sample(&self, multibody: &Multibody, range: [f64; 2]) -> Result<SampledMotion, SplinedMotionError> {
        let times = self.times[frames_in_range(&self.file, &self.times, range)?].to_vec();
        let states = times.iter().map(|&time| self.state_at(multibody, time)).collect();
        Ok(SampledMotion { file: self.file.clone(), times, states, defaulted: self.defaulted.clone(), ignored_columns: self.ignored_columns.clone() })
    }

    /// The splines' value and derivatives at `time` for the coordinates in the file, the
    /// default value at rest for the others.
    pub fn state_at(&self, multibody: &Multibody, time: f64) -> CoordinateState {
        let n = multibody.coordinates.len();
        let mut state = CoordinateState { q: multibody.default_pose(), u: vec![0.0; n], udot: vec![0.0; n] };
        for (&c, spline) in self.measured.iter().zip(&self.splines) {
            (state.q[c], state.u[c], state.udot[c]) = (spline.value(time), spline.derivative(time), spline.second_derivative(time));
        }
        state
    }
}
