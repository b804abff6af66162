//! The prescribed kinematics of a forward simulation: every coordinate of a motion file as the
//! degree-5 interpolating GCV spline through its samples (after OpenSim's padding and low-pass
//! filter when a cutoff is given), a coordinate the file lacks at its default value, a coupler's
//! dependent coordinate where its constraint puts it.

use std::path::Path;

use crate::analysis::signal::Series;
use crate::analysis::StatesError;
use crate::io::table::StorageTable;
use crate::mechanics::{Coupler, Function, Motion, Multibody};

/// q(t) for every coordinate (rad or m, CoordinateSet order).
#[derive(Debug, Clone)]
pub struct PrescribedMotion {
    /// The file's rows (s), unfiltered.
    pub times: Vec<f64>,
    splines: Vec<Function>,
    couplers: Vec<Coupler>,
    /// Columns that are no coordinate of the model.
    pub ignored_columns: Vec<String>,
    /// Coordinates the file lacks (at their default value, or following their coupler).
    pub defaulted: Vec<String>,
}

impl PrescribedMotion {
    /// The motion of `table` (read from `file`), low-pass filtered at `cutoff` Hz when given.
    pub fn new(multibody: &Multibody, table: &StorageTable, file: &Path, cutoff: Option<f64>) -> Result<PrescribedMotion, StatesError> {
        let signal = |source| StatesError::Signal { file: file.into(), source };
        let motion = Motion::from_table(table, file, multibody, true)?;
        let columns = (0..multibody.coordinates.len()).map(|c| (0..motion.len()).map(|i| motion.pose(i)[c]).collect()).collect();
        let series = Series::new(motion.times.clone(), columns, 6).and_then(|s| s.filtered(cutoff)).map_err(signal)?;
        let splines = series.splines().map_err(signal)?;
        Ok(PrescribedMotion { times: motion.times, splines, couplers: multibody.couplers.clone(), ignored_columns: motion.ignored_columns, defaulted: motion.defaulted })
    }

    /// The pose at `time` (s) into `q`.
    pub fn pose(&self, time: f64, q: &mut [f64]) {
        for (value, spline) in q.iter_mut().zip(&self.splines) {
            *value = spline.value(time);
        }
        for coupler in &self.couplers {
            q[coupler.dependent] = coupler.dependent_value(q);
        }
    }

    /// dq/dt at `time` (s), whose pose is `q`, into `speeds` (rad/s or m/s): the splines'
    /// derivatives; a coupler's dependent coordinate gets its constraint's f′(q_i) q̇_i.
    pub fn speeds(&self, time: f64, q: &[f64], speeds: &mut [f64]) {
        for (speed, spline) in speeds.iter_mut().zip(&self.splines) {
            *speed = spline.derivative(time);
        }
        for coupler in &self.couplers {
            speeds[coupler.dependent] = coupler.slope(q) * speeds[coupler.independent];
        }
    }

    /// [first, last] time of the file, s.
    pub fn range(&self) -> [f64; 2] {
        [self.times[0], self.times[self.times.len() - 1]]
    }
}
