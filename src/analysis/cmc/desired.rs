//! The desired kinematics RRA tracks, formed as `RRATool` forms them: the coordinates padded by
//! 60 rows (`Storage::pad`), low-pass filtered by OpenSim's order-50 FIR filter when a cutoff is
//! given, completed as `formCompleteStorages` completes them (a coordinate the file lacks at 0),
//! then degree-5 GCV splines through q, through their derivatives u and through those's
//! derivatives u̇ — functions of time for the tracking tasks, rows for the inverse dynamics whose
//! average residuals move the mass center.

use std::path::Path;

use crate::analysis::analyze_states::{AnalyzeStates, StatesError};
use crate::analysis::signal::spline;
use crate::io::table::StorageTable;
use crate::mechanics::{Function, Multibody};

/// Rows `Storage::pad` adds before and after the desired kinematics.
const PAD: usize = 60;
/// Order of `Storage::lowpassFIR` in RRA.
const FIR_ORDER: usize = 50;

/// The desired kinematics as rows and as splines of time.
pub struct DesiredKinematics {
    /// Rows (padded) with q, u and u̇ ([`Multibody::coordinates`] order).
    pub states: AnalyzeStates,
    /// Per coordinate: q (rad or m), u and u̇ as functions of time (s).
    q: Vec<Function>,
    u: Vec<Function>,
    udot: Vec<Function>,
}

impl DesiredKinematics {
    /// The desired kinematics of `table` (read from `file`), filtered at `cutoff` Hz when given.
    pub fn new(multibody: &Multibody, table: &StorageTable, file: &Path, cutoff: Option<f64>) -> Result<DesiredKinematics, StatesError> {
        let states = AnalyzeStates::processed(multibody, table, file, |q| match cutoff {
            Some(cutoff) => q.pad(PAD).lowpass_fir(FIR_ORDER, cutoff),
            None => Ok(q.pad(PAD)),
        })?;
        let signal = |source| StatesError::Signal { file: file.into(), source };
        let splines = |rows: &[Vec<f64>]| (0..multibody.coordinates.len()).map(|c| spline(5, &states.times, &rows.iter().map(|row| row[c]).collect::<Vec<f64>>())).collect::<Result<Vec<Function>, _>>().map_err(signal);
        let (q, u, udot) = (splines(&states.q)?, splines(&states.u)?, splines(&states.udot)?);
        Ok(DesiredKinematics { states, q, u, udot })
    }

    /// Coordinate c's desired value and speed at `time` (s).
    pub fn value_and_speed(&self, c: usize, time: f64) -> (f64, f64) {
        (self.q[c].value(time), self.u[c].value(time))
    }

    /// Coordinate c's desired acceleration at `time` (s).
    pub fn acceleration(&self, c: usize, time: f64) -> f64 {
        self.udot[c].value(time)
    }

    /// Every coordinate's desired value and speed (the speeds' spline) at `time` (s).
    pub fn pose(&self, time: f64) -> (Vec<f64>, Vec<f64>) {
        (self.q.iter().map(|f| f.value(time)).collect(), self.u.iter().map(|f| f.value(time)).collect())
    }

    /// Every coordinate's desired value and its spline's derivative at `time` (s) — the
    /// trajectories CMC's actuator subsystem follows, which has no speeds' splines.
    pub fn path(&self, time: f64) -> (Vec<f64>, Vec<f64>) {
        (self.q.iter().map(|f| f.value(time)).collect(), self.q.iter().map(|f| f.derivative(time)).collect())
    }
}
