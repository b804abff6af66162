//! The states OpenSim's `AnalyzeTool` forms from a coordinates file, and the accelerations its
//! `StaticOptimization` tracks: coordinates padded and low-pass filtered (when asked), a
//! coordinate the file lacks held at 0 (`SimbodyEngine::formCompleteStorages`), speeds u the
//! derivatives of degree-5 GCV splines through the coordinates at the rows, and accelerations u̇
//! the derivatives of degree-5 GCV splines through those speeds (`GCVSplineSet(5, states)`).
//!
//! A states file (`states_file`) gives every state variable per row instead, used as it is: each
//! column found as OpenSim's `formStateStorage` finds it (`findStateLabelIndex`: the state's
//! path, a shorter tail of it, or OpenSim 3's name — `<coordinate>`, `<coordinate>_u`,
//! `<muscle>.activation`), a state the file lacks at its default.
//!
//! Each row is then assembled: a coupler's dependent coordinate is put where its constraint says
//! (and, for the rows analysed, links between bodies closed: [`AnalyzeStates::assembled_rows`]),
//! its speed left as it is (OpenSim assembles positions only) — 0 when the file lacks it. A dependent coordinate whose motion
//! type is `Coupled` (e.g. leg6dof9musc's patella) is not converted from degrees by OpenSim's
//! degree rule, so in a file in degrees its speed is in degrees per second — as OpenSim has it,
//! whose velocity-dependent forces then follow from that speed.

use std::path::{Path, PathBuf};

use super::signal::{rows_in_range, Series, SignalError};
use crate::io::table::StorageTable;
use crate::mechanics::{Motion, MotionError, Multibody};
use crate::model::ModelSpec;
use crate::solvers::{assemble, IkError};

/// Why the states cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum StatesError {
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error("{}: {source}", file.display())]
    Signal { file: PathBuf, source: SignalError },
    #[error("{}: a states file holds coordinates in radians and meters (inDegrees=no), as OpenSim requires", file.display())]
    StatesInDegrees { file: PathBuf },
    #[error("{}: the pose at {time} s cannot be assembled: {source}", file.display())]
    Assembly { file: PathBuf, time: f64, source: Box<IkError> },
}

/// A muscle's state variables as a states file gives them per row: activation and the second
/// state (fiber length in m, or normalized tendon force), each `None` when the file lacks it.
pub type GivenMuscleStates = (String, [Option<Vec<f64>>; 2]);

/// What an analysis runs along: a coordinates file's table (filtered, its speeds and
/// accelerations splined) or a states file's (its coordinates and speeds as they are, the
/// accelerations splined from the speeds) with each muscle's name and second state's name
/// ([`muscle_state_names`]).
#[derive(Debug, Clone, Copy)]
pub enum MotionInput<'a> {
    Coordinates(&'a StorageTable),
    States { table: &'a StorageTable, muscles: &'a [(String, &'static str)] },
}

/// Each muscle of `spec` with the name of its second state (`fiber_length` or
/// `normalized_tendon_force`), as a states file names them.
pub fn muscle_state_names(spec: &ModelSpec) -> Vec<(String, &'static str)> {
    spec.muscles().filter_map(|m| m.muscle.as_ref().map(|s| (m.name.clone(), s.default_state().1.label()))).collect()
}

/// Coordinates (rad or m), speeds and accelerations per row, [`Multibody::coordinates`] order.
#[derive(Debug, Clone)]
pub struct AnalyzeStates {
    /// s, the filtered (padded, resampled) grid when filtered.
    pub times: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub u: Vec<Vec<f64>>,
    pub udot: Vec<Vec<f64>>,
    /// Coordinates the file lacks and no coupler sets (held at 0 — from a states file at their
    /// default values — as OpenSim does).
    pub missing: Vec<String>,
    /// Columns that are no coordinate (no state variable, for a states file) of the model.
    pub ignored_columns: Vec<String>,
    /// The muscles' states a states file gives (empty from a coordinates file).
    pub muscle_states: Vec<GivenMuscleStates>,
}

impl AnalyzeStates {
    /// The states of `input` (read from `file`; a coordinates file low-pass filtered at `cutoff`
    /// Hz, which a states file is not, as in OpenSim).
    pub fn read(multibody: &Multibody, input: MotionInput, file: &Path, cutoff: Option<f64>) -> Result<AnalyzeStates, StatesError> {
        match input {
            MotionInput::Coordinates(table) => AnalyzeStates::new(multibody, table, file, cutoff),
            MotionInput::States { table, muscles } => AnalyzeStates::from_states(multibody, table, file, muscles),
        }
    }

    /// Forms the states from `table` (read from `file`), low-pass filtered at `cutoff` Hz.
    pub fn new(multibody: &Multibody, table: &StorageTable, file: &Path, cutoff: Option<f64>) -> Result<AnalyzeStates, StatesError> {
        Self::processed(multibody, table, file, |q| q.filtered(cutoff))
    }

    /// Forms the states from `table` (read from `file`), its coordinates (rad or m, one column per
    /// model coordinate) passed through `process` (padding, filtering) before they are splined.
    pub fn processed(multibody: &Multibody, table: &StorageTable, file: &Path, process: impl FnOnce(Series) -> Result<Series, SignalError>) -> Result<AnalyzeStates, StatesError> {
        let signal = |source| StatesError::Signal { file: file.into(), source };
        let motion = Motion::from_table(table, file, multibody, true)?;
        let absent: Vec<usize> = (0..multibody.coordinates.len()).filter(|&c| motion.defaulted.contains(&multibody.coordinates[c].name)).collect();
        let missing: Vec<usize> = absent.iter().copied().filter(|&c| !multibody.is_dependent(c)).collect();
        let columns = (0..multibody.coordinates.len())
            .map(|c| (0..motion.len()).map(|i| if absent.contains(&c) { 0.0 } else { motion.pose(i)[c] }).collect())
            .collect();
        let q = Series::new(motion.times.clone(), columns, 6).and_then(process).map_err(signal)?;
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
            muscle_states: Vec::new(),
        })
    }

    /// The states of a states file `table` (read from `file`, times increasing; a repeated time's
    /// later row replacing the earlier, as OpenSim's `Storage`) for `multibody`
    /// and the muscles `muscles` (name, second state's name: `fiber_length` or
    /// `normalized_tendon_force`): no filtering; a coordinate the file lacks at its default
    /// value, a speed at 0, each a muscle state at the muscle's default; u̇ the derivatives of
    /// degree-5 GCV splines through the speeds (NaN with fewer than 6 rows).
    pub fn from_states(multibody: &Multibody, table: &StorageTable, file: &Path, muscles: &[(String, &str)]) -> Result<AnalyzeStates, StatesError> {
        let table = &table.with_repeated_times_replaced();
        if table.in_degrees() == Some(true) {
            return Err(StatesError::StatesInDegrees { file: file.into() });
        }
        let labels = &table.labels()[1..];
        let mut used = vec![false; labels.len()];
        let mut column = |path: String| {
            let index = state_label_index(labels, &path)?;
            used[index] = true;
            table.column(&labels[index])
        };
        let coordinates = &multibody.coordinates;
        let (mut q_columns, mut u_columns, mut missing) = (Vec::new(), Vec::new(), Vec::new());
        for (c, coordinate) in coordinates.iter().enumerate() {
            let path = format!("/jointset/{}/{}", multibody.joints[multibody.coordinate_joint(c)].name, coordinate.name);
            let value = column(format!("{path}/value"));
            if value.is_none() && !multibody.is_dependent(c) {
                missing.push(coordinate.name.clone());
            }
            q_columns.push(value.unwrap_or_else(|| vec![coordinate.default_value; table.n_rows()]));
            u_columns.push(column(format!("{path}/speed")).unwrap_or_else(|| vec![0.0; table.n_rows()]));
        }
        let muscle_states = muscles.iter().map(|(m, second)| (m.clone(), ["activation", second].map(|v| column(format!("/forceset/{m}/{v}"))))).collect();
        let rows_of = |columns: &[Vec<f64>]| (0..table.n_rows()).map(|i| columns.iter().map(|c| c[i]).collect::<Vec<f64>>()).collect::<Vec<_>>();
        let mut q = rows_of(&q_columns);
        for row in &mut q {
            multibody.follow_couplers(row, &[]);
        }
        let signal = |source| StatesError::Signal { file: file.into(), source };
        let speeds = Series::new(table.times(), u_columns, 1).map_err(signal)?;
        // As StaticOptimization's splines through the states: GCV splines need 6 rows.
        let udot = if table.n_rows() >= 6 { rows(&derivatives(&speeds).map_err(signal)?) } else { vec![vec![f64::NAN; coordinates.len()]; table.n_rows()] };
        Ok(AnalyzeStates {
            times: table.times(),
            u: rows(&speeds),
            udot,
            q,
            missing,
            ignored_columns: labels.iter().zip(&used).filter(|(_, used)| !**used).map(|(l, _)| l.clone()).collect(),
            muscle_states,
        })
    }

    /// The poses of `rows` (e.g. [`AnalyzeStates::analysed_rows`]) as a [`Motion`]; its
    /// defaulted coordinates are those the file lacks.
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

    /// [`AnalyzeStates::analysed_rows`] with, where the model has links between bodies, each
    /// of those poses assembled as the AnalyzeTool assembles it before its analyses record
    /// (`Model::assemble`): the pose nearest the row's that closes every link ([`assemble`]);
    /// the speeds and accelerations stay the splines'. (Couplers were followed when the states
    /// were formed; a model without links is left as it is.) `Ok(None)` when the range misses
    /// the times.
    pub fn assembled_rows(&mut self, multibody: &Multibody, time_range: [f64; 2], step_interval: usize, file: &Path) -> Result<Option<Vec<usize>>, StatesError> {
        let Some(rows) = self.analysed_rows(time_range, step_interval) else { return Ok(None) };
        if !multibody.links.is_empty() {
            for &i in &rows {
                self.q[i] = assemble(multibody, &self.q[i]).map_err(|source| StatesError::Assembly { file: file.into(), time: self.times[i], source: Box::new(source) })?;
            }
        }
        Ok(Some(rows))
    }
}

/// The column of `labels` (time excluded) OpenSim takes for the state variable `path`
/// (`TableUtilities::findStateLabelIndex`): the path itself, else its shorter tails, else its last
/// element, else OpenSim 3's name — a coordinate's `value` its name, its `speed` `<name>_u`,
/// another state `<component>.<state>`.
fn state_label_index(labels: &[String], path: &str) -> Option<usize> {
    let find = |name: &str| labels.iter().position(|l| l == name);
    let mut tail = path;
    while let Some(slash) = tail.find('/') {
        if let Some(index) = find(tail) {
            return Some(index);
        }
        tail = &tail[slash + 1..];
    }
    if let Some(index) = find(tail) {
        return Some(index);
    }
    let (prefix, last) = path.rsplit_once('/')?;
    let owner = prefix.rsplit('/').next().unwrap_or(prefix);
    match last {
        "value" => find(owner),
        "speed" => find(&format!("{owner}_u")),
        _ => find(&format!("{owner}.{last}")),
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

#[cfg(test)]
mod tests {
    use super::state_label_index;

    /// OpenSim's `findStateLabelIndex` cases: the full path, a 4.0-beta tail, OpenSim 3's names.
    #[test]
    fn state_columns_are_found_as_opensim_finds_them() {
        let labels: Vec<String> = ["r_shoulder/r_shoulder_elev/value", "r_elbow_flex", "r_elbow_flex_u", "TRIlong.activation", "/forceset/BRA/fiber_length"].map(String::from).to_vec();
        let find = |path: &str| state_label_index(&labels, path);
        assert_eq!(find("/jointset/r_shoulder/r_shoulder_elev/value"), Some(0));
        assert_eq!(find("/jointset/r_elbow/r_elbow_flex/value"), Some(1));
        assert_eq!(find("/jointset/r_elbow/r_elbow_flex/speed"), Some(2));
        assert_eq!(find("/forceset/TRIlong/activation"), Some(3));
        assert_eq!(find("/forceset/BRA/fiber_length"), Some(4));
        assert_eq!((find("/jointset/r_shoulder/r_shoulder_elev/speed"), find("/forceset/BRA/activation")), (None, None));
    }
}
