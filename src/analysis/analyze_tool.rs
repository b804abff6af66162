//! OpenSim's AnalyzeTool on a coordinates file: the states it hands its analyses (the
//! coordinates filtered and splined as for static optimisation, each pose assembled, with the
//! speeds; the muscles at their default or equilibrium states, [`super::muscle_states`]; the
//! accelerations they give, [`super::analyze_dynamics`]) and the tables its
//! `MuscleAnalysis`, `Kinematics`, `BodyKinematics`, `PointKinematics`, `ForceReporter`,
//! `Actuation` and `StatesReporter` write, by file name.

use std::path::{Path, PathBuf};

use super::analyze_dynamics::analyze_dynamics;
use super::analyze_states::{AnalyzeStates, GivenMuscleStates, StatesError};
use super::body_kinematics::{body_tables, coordinate_tables, point_tables, KinematicsError};
use super::muscle_analysis::MuscleAnalysis;
use super::muscle_state_tables::muscle_state_tables;
use super::muscle_states::muscle_states;
use super::external_loads::ExternalLoads;
use super::joint_reaction::{reaction_reports, reaction_row, reaction_table, JointReactionError};
use super::reporters::{actuation_tables, force_reporter_table, states_reporter_table, AppliedAt, ReporterError};
use super::static_optimization::generators;
use super::signal::{frames_in_range, NoFramesInRange};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MotionState, Motion, Multibody, MuscleGeometry};
use crate::model::{ActuatorSpec, ModelSpec};
use crate::setup::{AnalyzeSetup, ControlSet, ReporterSetup};
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
    /// The tables OpenSim also writes that osim-tune does not form here, with why.
    pub not_written: Vec<String>,
    /// What OpenSim warns about while forming the muscles' states (each once).
    pub warnings: Vec<String>,
}

/// The model an AnalyzeTool setup analyses: the model (`geometry` its paths), the actuators of
/// its `force_set_files` (`added`, replacing the model's forces when `replace`) and its external
/// loads.
#[derive(Debug, Clone, Copy)]
pub struct AnalyzeModel<'a> {
    pub spec: &'a ModelSpec,
    pub geometry: &'a MuscleGeometry,
    pub added: &'a [ActuatorSpec],
    pub replace: bool,
    pub external: Option<&'a ExternalLoads>,
    /// The control sets of the setup's `ControlSetController`s, whose controls add up.
    pub controls: &'a [ControlSet],
}

/// The tables of `setup`'s analyses (see the module documentation) on `table` (read from
/// `file`) with `model`; `tool_name` prefixes the file names.
pub fn analyze_tool_tables(model: &AnalyzeModel, table: &StorageTable, file: &Path, setup: &AnalyzeSetup, tool_name: &str) -> Result<AnalyzeToolTables, AnalyzeToolError> {
    if !setup.has_analyze_tables() {
        return Err(AnalyzeToolError::NothingToRun { file: setup.file.clone() });
    }
    let &AnalyzeModel { spec, geometry, external, controls, .. } = model;
    let multibody = &geometry.multibody;
    // The forces the model applies, or why they cannot be applied here.
    let generators = match controls_ignored(spec, setup, true) {
        Some(reason) => Err(reason),
        None => generators(spec, geometry, model.added, model.replace).map_err(|e| e.to_string()),
    };
    let cutoff = Some(setup.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0);
    // Filtered and splined once (or read from a states file); each analysis takes its rows and
    // assembles them.
    let all_states = if setup.states_file.is_some() {
        let muscles: Vec<String> = spec.muscles().map(|m| m.name.clone()).collect();
        AnalyzeStates::from_states(multibody, table, file, &muscles)?
    } else {
        AnalyzeStates::new(multibody, table, file, cutoff)?
    };
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
    let muscles = |states: &AnalyzeToolMotion| muscle_states(spec, geometry, states, controls, setup.solve_for_equilibrium_for_auxiliary_states);
    if let (Some(analysis), true) = (&setup.muscle_analysis, model.replace) {
        tables.not_written.push(format!("{}: replace_force_set replaces the model's muscles by the force-set files' actuators, so OpenSim's MuscleAnalysis has no muscles", analysis.name));
    } else if let Some(analysis) = &setup.muscle_analysis {
        let states = states(analysis.step_interval)?;
        let selected = MuscleAnalysis::run(geometry, &states.motion)?.setup_tables(multibody, analysis)?;
        let arms: Vec<&StorageTable> = selected.tables.iter().filter(|t| t.name().starts_with("MomentArm_")).collect();
        let formed = match (controls_ignored(spec, setup, false), muscles(&states)) {
            (Some(reason), _) => Err(reason),
            (None, Err(e)) => Err(e.to_string()),
            (None, Ok(muscles)) => {
                tables.warnings.extend(muscles.warnings.iter().cloned());
                Ok(muscle_state_tables(&muscles, &states.motion.times, &selected.muscles, &arms)?)
            }
        };
        let state_tables = formed.unwrap_or_else(|reason| {
            tables.not_written.push(format!("the MuscleAnalysis' fiber, tendon, force, power and moment tables: {reason}"));
            Vec::new()
        });
        for table in selected.tables.into_iter().chain(state_tables) {
            let suffix = table.name().to_string();
            add(&mut tables, &analysis.name, &suffix, table, &states);
        }
        (tables.unknown_muscles, tables.unknown_coordinates) = (selected.unknown_muscles, selected.unknown_coordinates);
    }
    // The dynamics of a row set, or why they are not formed (noted once per analysis).
    let dynamics = |states: &AnalyzeToolMotion, tables: &mut AnalyzeToolTables, what: &str| {
        let formed = generators.clone().and_then(|generators| {
            let muscles = muscles(states).map_err(|e| e.to_string())?;
            tables.warnings.extend(muscles.warnings.iter().cloned());
            let at = AppliedAt { multibody, generators: &generators, external, controls, muscles: &muscles, motion: &states.motion, speeds: &states.speeds };
            analyze_dynamics(geometry, &at)
        });
        formed.map_err(|reason| tables.not_written.push(format!("{what}: {reason}"))).ok()
    };
    let accelerations = |states: &AnalyzeToolMotion, tables: &mut AnalyzeToolTables, what: &str| dynamics(states, tables, what).map(|rows| rows.into_iter().map(|r| r.udot).collect::<Vec<_>>());
    if let Some(analysis) = &setup.kinematics {
        let states = states(analysis.step_interval)?;
        let udot = accelerations(&states, &mut tables, "Kinematics' accelerations (_dudt)");
        let formed = coordinate_tables(multibody, &states, analysis, udot.as_deref()).map_err(in_setup)?;
        for (suffix, table) in ["q", "u", "dudt"].into_iter().zip(formed) {
            add(&mut tables, &analysis.name, suffix, table, &states);
        }
    }
    if let Some(analysis) = &setup.body_kinematics {
        let states = states(analysis.step_interval)?;
        let udot = accelerations(&states, &mut tables, "BodyKinematics' accelerations (_acc_…)");
        let bodies: Vec<usize> = spec.bodies.iter().filter_map(|b| multibody.bodies.iter().position(|m| m.name == b.name)).collect();
        let formed = body_tables(multibody, &bodies, &states, analysis, udot.as_deref()).map_err(in_setup)?;
        let frame = if analysis.express_in_local_frame { "bodyLocal" } else { "global" };
        for (suffix, table) in ["pos_global".to_string(), format!("vel_{frame}"), format!("acc_{frame}")].into_iter().zip(formed) {
            add(&mut tables, &analysis.name, &suffix, table, &states);
        }
    }
    for analysis in &setup.point_kinematics {
        let states = states(analysis.step_interval)?;
        let udot = accelerations(&states, &mut tables, &format!("PointKinematics {}'s accelerations (_acc)", analysis.point_name));
        let formed = point_tables(multibody, &states, analysis, udot.as_deref()).map_err(in_setup)?;
        for (suffix, table) in ["pos", "vel", "acc"].into_iter().zip(formed) {
            add(&mut tables, &analysis.name, &format!("{}_{suffix}", analysis.point_name), table, &states);
        }
    }
    if let Some(analysis) = setup.joint_reaction.as_ref().filter(|a| a.forces_file.is_none()) {
        let states = states(analysis.step_interval)?;
        let reports = reaction_reports(spec, multibody, &analysis.joint_names, &analysis.apply_on_bodies, &analysis.express_in_frame, &setup.file).map_err(Box::new)?;
        if let Some(rows) = dynamics(&states, &mut tables, "the JointReaction's loads") {
            let mut kinematics = multibody.kinematics();
            let mut values = Vec::new();
            for (row, dynamics) in rows.iter().enumerate() {
                let (q, u) = (states.motion.pose(row), &states.speeds[row]);
                multibody.realize(q, &mut kinematics);
                values.push(states.motion.times[row]);
                values.extend(reaction_row(multibody, &kinematics, &MotionState { q, u, udot: &dynamics.udot }, &dynamics.loads, &reports));
            }
            add(&mut tables, &analysis.name, "ReactionLoads", reaction_table(multibody, &reports, values)?, &states);
        }
    }
    let reporters = [(&setup.force_reporter, "ForceReporter"), (&setup.actuation, "Actuation"), (&setup.states_reporter, "StatesReporter")];
    for (analysis, class) in reporters.into_iter().filter_map(|(a, class)| a.as_ref().map(|a| (a, class))) {
        let states = states(analysis.step_interval)?;
        let formed = muscles(&states).map_err(|e| ReporterError::NotFormed(e.to_string())).and_then(|muscles| {
            tables.warnings.extend(muscles.warnings.iter().cloned());
            if class == "StatesReporter" {
                return Ok(vec![("states", states_reporter_table(spec, multibody, &muscles, &states.motion, &states.speeds)?)]);
            }
            let generators = generators.clone().map_err(ReporterError::NotFormed)?;
            let at = AppliedAt { multibody, generators: &generators, external, controls, muscles: &muscles, motion: &states.motion, speeds: &states.speeds };
            reporter_tables(spec, analysis, class, &at)
        });
        match formed {
            Ok(formed) => formed.into_iter().for_each(|(suffix, t)| add(&mut tables, &analysis.name, suffix, t, &states)),
            Err(ReporterError::Table(e)) => return Err(e.into()),
            Err(reason) => tables.not_written.push(format!("{class}'s tables: {reason}")),
        }
    }
    tables.warnings.sort();
    tables.warnings.dedup();
    Ok(tables)
}

/// The tables of reporter `class` (`ForceReporter` or `Actuation`) with their file name suffixes.
fn reporter_tables(spec: &ModelSpec, analysis: &ReporterSetup, class: &str, at: &AppliedAt) -> Result<Vec<(&'static str, StorageTable)>, ReporterError> {
    if class == "Actuation" {
        let [force, speed, power] = actuation_tables(at)?;
        return Ok(vec![("force", force), ("speed", speed), ("power", power)]);
    }
    if analysis.include_constraint_forces && !spec.constraints.is_empty() {
        return Err(ReporterError::NotFormed("include_constraint_forces: the constraints' forces need the model's dynamics".into()));
    }
    Ok(vec![("forces", force_reporter_table(at)?)])
}

/// Why a force table would not be OpenSim's: a controller of the setup that osim-tune does not
/// apply (any but a `ControlSetController` with its file) drives a muscle without activation
/// dynamics or, with `actuators`, a non-muscle actuator.
fn controls_ignored(spec: &ModelSpec, setup: &AnalyzeSetup, actuators: bool) -> Option<String> {
    let unapplied: Vec<&str> = setup.controllers.iter().filter(|c| c.controls_file.is_none()).map(|c| c.description.as_str()).collect();
    if unapplied.is_empty() {
        return None;
    }
    let driven = (actuators && !spec.actuators.is_empty()) || spec.forces.iter().any(|f| f.muscle.as_ref().is_some_and(|m| m.ignore_activation_dynamics));
    driven.then(|| format!("the ControllerSet's {} drives forces of the model, and osim-tune applies only ControlSetControllers", unapplied.join(", ")))
}

/// Why an AnalyzeTool setup's tables cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeToolError {
    #[error("{}: the AnalysisSet has no MuscleAnalysis, Kinematics, BodyKinematics, PointKinematics, ForceReporter, Actuation or StatesReporter that is on", file.display())]
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
fn analyze_tool_motion(multibody: &Multibody, states: &AnalyzeStates, file: &Path, time_range: [f64; 2], step_interval: usize) -> Result<AnalyzeToolMotion, AnalyzeToolError> {
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
