//! OpenSim's AnalyzeTool on a coordinates file: the states it hands its analyses (the
//! coordinates filtered and splined as for static optimisation, each pose assembled, with the
//! speeds; the muscles at their default or equilibrium states, [`super::muscle_states`]; the
//! accelerations they give, [`super::analyze_dynamics`]) and the tables its
//! `MuscleAnalysis`, `Kinematics`, `BodyKinematics`, `PointKinematics`, `ForceReporter`,
//! `Actuation`, `StatesReporter`, `ProbeReporter` and `InducedAccelerations` write, by file name.

use std::path::{Path, PathBuf};

use super::analyze_runs::ToolRun;
use super::controllers::Controllers;
use super::analyze_states::{AnalyzeStates, GivenMuscleStates, StatesError};
use super::body_kinematics::KinematicsError;
use super::external_loads::ExternalLoads;
use super::induced_accelerations::InducedAccelerationsError;
use super::joint_reaction::JointReactionError;
use super::signal::NoFramesInRange;
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{Motion, Multibody, MuscleGeometry};
use crate::model::{ActuatorSpec, ModelSpec};
use crate::setup::AnalyzeSetup;
use crate::solvers::{assemble, IkError};

/// The tables an AnalyzeTool setup's analyses write, with what the run leaves to note.
#[derive(Debug, Clone, Default)]
pub struct AnalyzeToolTables {
    /// Each table with its file name, `<tool>_<analysis>_<table>.sto`.
    pub files: Vec<(String, StorageTable)>,
    /// The rows analysed: count, first and last time (s), of the last analysis run.
    pub rows: (usize, f64, f64),
    /// Coordinates the input lacks, held as OpenSim holds them (at 0; from a states file at their
    /// default values).
    pub missing_coordinates: Vec<String>,
    /// Names the MuscleAnalysis lists that the model lacks (dropped, as OpenSim drops them).
    pub unknown_muscles: Vec<String>,
    pub unknown_coordinates: Vec<String>,
    /// The tables OpenSim also writes that osim-tune does not form here, with why.
    pub not_written: Vec<String>,
    /// What OpenSim warns about while forming the muscles' states (each once).
    pub warnings: Vec<String>,
    /// Where an analysis follows OpenSim rather than what its setup may mean.
    pub notes: Vec<String>,
}

/// The model an AnalyzeTool setup analyses: the model (`geometry` its paths), the actuators of
/// its `force_set_files` (`added`, replacing the model's forces when `replace`), its external
/// loads and controllers.
#[derive(Debug, Clone, Copy)]
pub struct AnalyzeModel<'a> {
    pub spec: &'a ModelSpec,
    pub geometry: &'a MuscleGeometry,
    pub added: &'a [ActuatorSpec],
    pub replace: bool,
    pub external: Option<&'a ExternalLoads>,
    /// The model's and the setup's controllers.
    pub controls: &'a Controllers,
}

/// The tables of `setup`'s analyses (see the module documentation) on `table` (read from
/// `file`) with `model`; `tool_name` prefixes the file names.
pub fn analyze_tool_tables(model: &AnalyzeModel, table: &StorageTable, file: &Path, setup: &AnalyzeSetup, tool_name: &str) -> Result<AnalyzeToolTables, AnalyzeToolError> {
    if !setup.has_analyze_tables() {
        return Err(AnalyzeToolError::NothingToRun { file: setup.file.clone() });
    }
    let run = ToolRun::new(model, table, file, setup, tool_name)?;
    let mut tables = AnalyzeToolTables::default();
    if let Some(analysis) = &setup.muscle_analysis {
        run.muscle_analysis(analysis, &mut tables)?;
    }
    if let Some(analysis) = &setup.kinematics {
        run.kinematics(analysis, &mut tables)?;
    }
    if let Some(analysis) = &setup.body_kinematics {
        run.body_kinematics(analysis, &mut tables)?;
    }
    for analysis in &setup.point_kinematics {
        run.point_kinematics(analysis, &mut tables)?;
    }
    if let Some(analysis) = setup.joint_reaction.as_ref().filter(|a| a.forces_file.is_none()) {
        run.joint_reaction(analysis, &mut tables)?;
    }
    if let Some(analysis) = &setup.induced_accelerations {
        run.induced_accelerations(analysis, &mut tables)?;
    }
    let reporters = [(&setup.force_reporter, "ForceReporter"), (&setup.actuation, "Actuation"), (&setup.states_reporter, "StatesReporter"), (&setup.probe_reporter, "ProbeReporter")];
    for (analysis, class) in reporters.into_iter().filter_map(|(a, class)| a.as_ref().map(|a| (a, class))) {
        run.reporter(analysis, class, &mut tables)?;
    }
    tables.warnings = run.warnings();
    Ok(tables)
}

impl AnalyzeToolTables {
    /// Adds `table` as `<tool>_<analysis>_<suffix>.sto`, formed at the rows of `states`.
    pub(super) fn add(&mut self, tool: &str, analysis: &str, suffix: &str, table: StorageTable, states: &AnalyzeToolMotion) {
        self.files.push((format!("{tool}_{analysis}_{suffix}.sto"), table));
        let times = &states.motion.times;
        self.rows = (times.len(), times.first().copied().unwrap_or(f64::NAN), times.last().copied().unwrap_or(f64::NAN));
        self.missing_coordinates.clone_from(&states.motion.defaulted);
    }
}

/// Why an AnalyzeTool setup's tables cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeToolError {
    #[error("{}: the AnalysisSet has no MuscleAnalysis, Kinematics, BodyKinematics, PointKinematics, ForceReporter, Actuation, StatesReporter, ProbeReporter, InducedAccelerations or JointReaction without a forces file that is on", file.display())]
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
    #[error(transparent)]
    Reaction(#[from] Box<JointReactionError>),
    #[error(transparent)]
    InducedAccelerations(#[from] InducedAccelerationsError),
}

/// The states OpenSim's `AnalyzeTool` hands an analysis: the poses (each assembled) and the
/// coordinates' speeds (rad/s or m/s, [`Multibody::coordinates`] order) at its rows.
#[derive(Debug, Clone)]
pub struct AnalyzeToolMotion {
    pub motion: Motion,
    pub speeds: Vec<Vec<f64>>,
    /// The muscles' states a states file gives, at these rows.
    pub muscle_states: Vec<GivenMuscleStates>,
}

/// The states OpenSim's `AnalyzeTool` hands an analysis of `step_interval`: of `states` (the
/// coordinates file's, read from `file`, filtered and splined as for static optimisation; a
/// coordinate the file lacks held at 0), the rows of `time_range` (s) the analysis records, each
/// pose assembled.
pub(super) fn analyze_tool_motion(multibody: &Multibody, states: &AnalyzeStates, file: &Path, time_range: [f64; 2], step_interval: usize) -> Result<AnalyzeToolMotion, AnalyzeToolError> {
    let rows = states.analysed_rows(time_range, step_interval).unwrap_or_default();
    let mut motion = states.motion(&rows);
    let mut row = 0;
    motion.assemble_poses(|q| {
        row += 1;
        assemble(multibody, q).map_err(|source| AnalyzeToolError::Assembly { file: file.into(), time: states.times[rows[row - 1]], source: Box::new(source) })
    })?;
    let at_rows = |column: &Option<Vec<f64>>| column.as_ref().map(|c| rows.iter().map(|&i| c[i]).collect());
    let muscle_states = states.muscle_states.iter().map(|(m, columns)| (m.clone(), columns.each_ref().map(at_rows))).collect();
    Ok(AnalyzeToolMotion { motion, speeds: rows.iter().map(|&i| states.u[i].clone()).collect(), muscle_states })
}
