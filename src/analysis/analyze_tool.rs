//! OpenSim's AnalyzeTool on a coordinates file: the states it hands its analyses (the
//! coordinates filtered and splined as for static optimisation, each pose assembled, with the
//! speeds) and the tables its `MuscleAnalysis`, `Kinematics`, `BodyKinematics` and
//! `PointKinematics` write, by file name.

use std::path::{Path, PathBuf};

use super::analyze_states::{AnalyzeStates, StatesError};
use super::body_kinematics::{body_tables, coordinate_tables, point_tables, KinematicsError};
use super::muscle_analysis::MuscleAnalysis;
use super::signal::{frames_in_range, NoFramesInRange};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Motion, Multibody, MuscleGeometry};
use crate::model::ModelSpec;
use crate::setup::AnalyzeSetup;
use crate::solvers::{assemble, IkError};

/// The tables an AnalyzeTool setup's analyses write, with what the run leaves to note.
#[derive(Debug, Clone, Default)]
pub struct AnalyzeToolTables {
    /// Each table with its file name, `<tool>_<analysis>_<table>.sto`.
    pub files: Vec<(String, StorageTable)>,
    /// The rows analysed: count, first and last time (s), of the last analysis run.
    pub rows: (usize, f64, f64),
    /// Coordinates the coordinates file lacks, held at 0 as OpenSim holds them.
    pub held_at_zero: Vec<String>,
    /// Names the MuscleAnalysis lists that the model lacks (dropped, as OpenSim drops them).
    pub unknown_muscles: Vec<String>,
    pub unknown_coordinates: Vec<String>,
    /// The tables OpenSim also writes that depend on states a coordinates file does not give.
    pub not_written: Vec<String>,
}

/// Why the analyses' accelerations are not formed.
const FORWARD_DYNAMICS: &str = "the model's forward dynamics at muscle states and controls a coordinates file does not give";

/// The tables of `setup`'s MuscleAnalysis, Kinematics, BodyKinematics and PointKinematics on
/// `table` (read from `file`) with the model `spec` (`geometry` its paths); `tool_name` prefixes
/// the file names.
pub fn analyze_tool_tables(spec: &ModelSpec, geometry: &MuscleGeometry, table: &StorageTable, file: &Path, setup: &AnalyzeSetup, tool_name: &str) -> Result<AnalyzeToolTables, AnalyzeToolError> {
    if setup.muscle_analysis.is_none() && setup.kinematics.is_none() && setup.body_kinematics.is_none() && setup.point_kinematics.is_empty() {
        return Err(AnalyzeToolError::NothingToRun { file: setup.file.clone() });
    }
    let multibody = &geometry.multibody;
    let cutoff = Some(setup.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0);
    // Filtered and splined once; each analysis takes its rows and assembles them.
    let all_states = AnalyzeStates::new(multibody, table, file, cutoff)?;
    let time_range = [setup.initial_time, setup.final_time];
    frames_in_range(file, &all_states.times, time_range)?;
    let states = |step_interval| analyze_tool_motion(multibody, &all_states, file, time_range, step_interval);
    let in_setup = |source| AnalyzeToolError::Kinematics { file: setup.file.clone(), source };
    let mut tables = AnalyzeToolTables::default();
    let add = |tables: &mut AnalyzeToolTables, analysis: &str, suffix: &str, table: StorageTable, states: &AnalyzeToolMotion| {
        tables.files.push((format!("{tool_name}_{analysis}_{suffix}.sto"), table));
        let times = &states.motion.times;
        tables.rows = (times.len(), times.first().copied().unwrap_or(f64::NAN), times.last().copied().unwrap_or(f64::NAN));
        tables.held_at_zero.clone_from(&states.motion.defaulted);
    };
    if let Some(analysis) = &setup.muscle_analysis {
        let states = states(analysis.step_interval)?;
        let selected = MuscleAnalysis::run(geometry, &states.motion)?.setup_tables(multibody, analysis)?;
        for table in selected.tables {
            let suffix = table.name().to_string();
            add(&mut tables, &analysis.name, &suffix, table, &states);
        }
        (tables.unknown_muscles, tables.unknown_coordinates) = (selected.unknown_muscles, selected.unknown_coordinates);
        tables.not_written.push("the MuscleAnalysis' fiber, tendon, force and power tables, which need the muscles' states".into());
    }
    if let Some(analysis) = &setup.kinematics {
        let states = states(analysis.step_interval)?;
        let [q, u] = coordinate_tables(multibody, &states, analysis).map_err(in_setup)?;
        add(&mut tables, &analysis.name, "q", q, &states);
        add(&mut tables, &analysis.name, "u", u, &states);
        tables.not_written.push(format!("Kinematics' accelerations (_dudt), {FORWARD_DYNAMICS}"));
    }
    if let Some(analysis) = &setup.body_kinematics {
        let states = states(analysis.step_interval)?;
        let bodies: Vec<usize> = spec.bodies.iter().filter_map(|b| multibody.bodies.iter().position(|m| m.name == b.name)).collect();
        let [positions, velocities] = body_tables(multibody, &bodies, &states, analysis).map_err(in_setup)?;
        add(&mut tables, &analysis.name, "pos_global", positions, &states);
        add(&mut tables, &analysis.name, if analysis.express_in_local_frame { "vel_bodyLocal" } else { "vel_global" }, velocities, &states);
        tables.not_written.push(format!("BodyKinematics' accelerations (_acc_…), {FORWARD_DYNAMICS}"));
    }
    for analysis in &setup.point_kinematics {
        let states = states(analysis.step_interval)?;
        let [positions, velocities] = point_tables(multibody, &states, analysis).map_err(in_setup)?;
        add(&mut tables, &analysis.name, &format!("{}_pos", analysis.point_name), positions, &states);
        add(&mut tables, &analysis.name, &format!("{}_vel", analysis.point_name), velocities, &states);
    }
    if !setup.point_kinematics.is_empty() {
        tables.not_written.push(format!("PointKinematics' accelerations (_acc), {FORWARD_DYNAMICS}"));
    }
    Ok(tables)
}

/// Why an AnalyzeTool setup's tables cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeToolError {
    #[error("{}: the AnalysisSet has no MuscleAnalysis, Kinematics, BodyKinematics or PointKinematics that is on", file.display())]
    NothingToRun { file: PathBuf },
    #[error(transparent)]
    States(#[from] StatesError),
    #[error(transparent)]
    NoFrames(#[from] NoFramesInRange),
    #[error("{}: the pose at {time} s cannot be assembled: {source}", file.display())]
    Assembly { file: PathBuf, time: f64, source: Box<IkError> },
    #[error("{}: {source}", file.display())]
    Kinematics { file: PathBuf, source: KinematicsError },
    #[error(transparent)]
    Table(#[from] TableError),
}

/// The states OpenSim's `AnalyzeTool` hands an analysis: the poses (each assembled) and the
/// coordinates' speeds (rad/s or m/s, [`Multibody::coordinates`] order) at its rows.
#[derive(Debug, Clone)]
pub struct AnalyzeToolMotion {
    pub motion: Motion,
    pub speeds: Vec<Vec<f64>>,
}

/// The states OpenSim's `AnalyzeTool` hands an analysis of `step_interval`: of `states` (the
/// coordinates file's, read from `file`, filtered and splined as for static optimisation; a
/// coordinate the file lacks held at 0), the rows of `time_range` (s) the analysis records, each
/// pose assembled.
fn analyze_tool_motion(multibody: &Multibody, states: &AnalyzeStates, file: &Path, time_range: [f64; 2], step_interval: usize) -> Result<AnalyzeToolMotion, AnalyzeToolError> {
    let rows = states.analysed_rows(time_range, step_interval).unwrap_or_default();
    let mut motion = states.motion(&rows);
    let mut row = 0;
    motion.assemble_poses(|q| {
        row += 1;
        assemble(multibody, q).map_err(|source| AnalyzeToolError::Assembly { file: file.into(), time: states.times[rows[row - 1]], source: Box::new(source) })
    })?;
    Ok(AnalyzeToolMotion { motion, speeds: rows.iter().map(|&i| states.u[i].clone()).collect() })
}
