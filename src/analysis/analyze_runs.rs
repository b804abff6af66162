//! One AnalyzeTool run, analysis by analysis: the states formed once from the input file, each
//! analysis's rows taken from them, the muscles' states and the model's dynamics formed for the
//! analyses that need them, and what cannot be formed named rather than guessed.

use std::path::Path;

use super::analyze_dynamics::{analyze_dynamics, RowDynamics};
use super::analyze_states::AnalyzeStates;
use super::analyze_tool::{analyze_tool_motion, AnalyzeModel, AnalyzeToolError, AnalyzeToolMotion, AnalyzeToolTables};
use super::body_kinematics::{body_tables, coordinate_tables, point_tables, KinematicsError};
use super::joint_reaction::{reaction_reports, reaction_row, reaction_table};
use super::muscle_analysis::MuscleAnalysis;
use super::muscle_state_tables::muscle_state_tables;
use super::muscle_states::{muscle_states, MuscleStates, MuscleStatesError};
use super::reporters::{actuation_tables, force_reporter_table, states_reporter_table, AppliedAt, ReporterError};
use super::signal::frames_in_range;
use super::static_optimization::{generators, Generator};
use crate::io::table::StorageTable;
use crate::mechanics::MotionState;
use crate::model::ModelSpec;
use crate::setup::{AnalyzeSetup, BodyKinematicsSetup, JointReactionSetup, KinematicsSetup, MuscleAnalysisSetup, PointKinematicsSetup, ReporterSetup};

/// An AnalyzeTool setup running on its model and input.
pub(super) struct ToolRun<'a> {
    model: &'a AnalyzeModel<'a>,
    setup: &'a AnalyzeSetup,
    file: &'a Path,
    tool_name: &'a str,
    /// Every row of the input, filtered and splined once (or read from a states file).
    states: AnalyzeStates,
    /// The forces the model applies, or why they cannot be applied here.
    generators: Result<Vec<Generator>, String>,
}

impl<'a> ToolRun<'a> {
    pub(super) fn new(model: &'a AnalyzeModel<'a>, table: &StorageTable, file: &'a Path, setup: &'a AnalyzeSetup, tool_name: &'a str) -> Result<ToolRun<'a>, AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = model;
        let multibody = &geometry.multibody;
        let states = if setup.states_file.is_some() {
            let muscles: Vec<(String, &str)> = spec.muscles().filter_map(|m| m.muscle.as_ref().map(|s| (m.name.clone(), s.default_state().1.label()))).collect();
            AnalyzeStates::from_states(multibody, table, file, &muscles)?
        } else {
            let cutoff = Some(setup.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0);
            AnalyzeStates::new(multibody, table, file, cutoff)?
        };
        frames_in_range(file, &states.times, [setup.initial_time, setup.final_time])?;
        let generators = match controls_ignored(spec, setup, true) {
            Some(reason) => Err(reason),
            None => generators(spec, geometry, model.added, model.replace).map_err(|e| e.to_string()),
        };
        Ok(ToolRun { model, setup, file, tool_name, states, generators })
    }

    /// The assembled states an analysis of `step_interval` records.
    fn rows(&self, step_interval: usize) -> Result<AnalyzeToolMotion, AnalyzeToolError> {
        let time_range = [self.setup.initial_time, self.setup.final_time];
        analyze_tool_motion(&self.model.geometry.multibody, &self.states, self.file, time_range, step_interval)
    }

    /// The muscles' states at `states`.
    fn muscles(&self, states: &AnalyzeToolMotion) -> Result<MuscleStates, MuscleStatesError> {
        muscle_states(self.model.spec, self.model.geometry, states, self.model.controls, self.setup.solve_for_equilibrium_for_auxiliary_states)
    }

    /// `add` of `tables` under this tool's name.
    fn add(&self, tables: &mut AnalyzeToolTables, analysis: &str, suffix: &str, table: StorageTable, states: &AnalyzeToolMotion) {
        tables.add(self.tool_name, analysis, suffix, table, states);
    }

    /// The forces at `states` and `muscles`, or why they are not formed.
    fn with_forces<T>(&self, states: &AnalyzeToolMotion, muscles: &MuscleStates, then: impl FnOnce(&AppliedAt) -> Result<T, ReporterError>) -> Result<T, ReporterError> {
        let generators = self.generators.as_ref().map_err(|reason| ReporterError::NotFormed(reason.clone()))?;
        let multibody = &self.model.geometry.multibody;
        then(&AppliedAt { multibody, generators, external: self.model.external, controls: self.model.controls, muscles, motion: &states.motion, speeds: &states.speeds })
    }

    /// The dynamics of `states`, or `None` with the reason noted as `what` not written.
    fn dynamics(&self, states: &AnalyzeToolMotion, tables: &mut AnalyzeToolTables, what: &str) -> Option<Vec<RowDynamics>> {
        let formed = self.muscles(states).map_err(|e| ReporterError::NotFormed(e.to_string())).and_then(|muscles| {
            tables.warnings.extend(muscles.warnings.iter().cloned());
            self.with_forces(states, &muscles, |at| analyze_dynamics(self.model.geometry, at).map_err(ReporterError::NotFormed))
        });
        formed.map_err(|reason| tables.not_written.push(format!("{what}: {reason}"))).ok()
    }

    /// u̇ of each row of `states`, as [`ToolRun::dynamics`].
    fn accelerations(&self, states: &AnalyzeToolMotion, tables: &mut AnalyzeToolTables, what: &str) -> Option<Vec<Vec<f64>>> {
        self.dynamics(states, tables, what).map(|rows| rows.into_iter().map(|r| r.udot).collect())
    }

    /// An error of a kinematics analysis, naming the setup.
    fn in_setup(&self, source: KinematicsError) -> AnalyzeToolError {
        AnalyzeToolError::Kinematics { file: self.setup.file.clone(), source }
    }

    /// The MuscleAnalysis: path tables, then the muscles' state tables (or why not).
    pub(super) fn muscle_analysis(&self, analysis: &MuscleAnalysisSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, replace, .. } = self.model;
        if replace {
            tables.not_written.push(format!("{}: replace_force_set replaces the model's muscles by the force-set files' actuators, so OpenSim's MuscleAnalysis has no muscles", analysis.name));
            return Ok(());
        }
        let states = self.rows(analysis.step_interval)?;
        let selected = MuscleAnalysis::run(geometry, &states.motion)?.setup_tables(&geometry.multibody, analysis)?;
        let arms: Vec<&StorageTable> = selected.tables.iter().filter(|t| t.name().starts_with("MomentArm_")).collect();
        let formed = match (controls_ignored(spec, self.setup, false), self.muscles(&states)) {
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
            self.add(tables, &analysis.name, &suffix, table, &states);
        }
        (tables.unknown_muscles, tables.unknown_coordinates) = (selected.unknown_muscles, selected.unknown_coordinates);
        Ok(())
    }

    /// Kinematics: q, u and u̇.
    pub(super) fn kinematics(&self, analysis: &KinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let states = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&states, tables, "Kinematics' accelerations (_dudt)");
        let formed = coordinate_tables(&self.model.geometry.multibody, &states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        for (suffix, table) in ["q", "u", "dudt"].into_iter().zip(formed) {
            self.add(tables, &analysis.name, suffix, table, &states);
        }
        Ok(())
    }

    /// BodyKinematics: positions, velocities and accelerations.
    pub(super) fn body_kinematics(&self, analysis: &BodyKinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let multibody = &self.model.geometry.multibody;
        let states = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&states, tables, "BodyKinematics' accelerations (_acc_…)");
        let bodies: Vec<usize> = self.model.spec.bodies.iter().filter_map(|b| multibody.bodies.iter().position(|m| m.name == b.name)).collect();
        let formed = body_tables(multibody, &bodies, &states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        let frame = if analysis.express_in_local_frame { "bodyLocal" } else { "global" };
        for (suffix, table) in ["pos_global".to_string(), format!("vel_{frame}"), format!("acc_{frame}")].into_iter().zip(formed) {
            self.add(tables, &analysis.name, &suffix, table, &states);
        }
        Ok(())
    }

    /// A PointKinematics: the point's position, velocity and acceleration.
    pub(super) fn point_kinematics(&self, analysis: &PointKinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let states = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&states, tables, &format!("PointKinematics {}'s accelerations (_acc)", analysis.point_name));
        let formed = point_tables(&self.model.geometry.multibody, &states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        for (suffix, table) in ["pos", "vel", "acc"].into_iter().zip(formed) {
            self.add(tables, &analysis.name, &format!("{}_{suffix}", analysis.point_name), table, &states);
        }
        Ok(())
    }

    /// A JointReaction without a forces file: the loads under the model's own forces.
    pub(super) fn joint_reaction(&self, analysis: &JointReactionSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = self.model;
        let multibody = &geometry.multibody;
        let states = self.rows(analysis.step_interval)?;
        let reports = reaction_reports(spec, multibody, &analysis.joint_names, &analysis.apply_on_bodies, &analysis.express_in_frame, &self.setup.file).map_err(Box::new)?;
        let Some(rows) = self.dynamics(&states, tables, "the JointReaction's loads") else { return Ok(()) };
        let mut kinematics = multibody.kinematics();
        let mut values = Vec::new();
        for (row, dynamics) in rows.iter().enumerate() {
            let (q, u) = (states.motion.pose(row), &states.speeds[row]);
            multibody.realize(q, &mut kinematics);
            values.push(states.motion.times[row]);
            values.extend(reaction_row(multibody, &kinematics, &MotionState { q, u, udot: &dynamics.udot }, &dynamics.loads, &reports));
        }
        self.add(tables, &analysis.name, "ReactionLoads", reaction_table(multibody, &reports, values)?, &states);
        Ok(())
    }

    /// A reporter (`ForceReporter`, `Actuation` or `StatesReporter`).
    pub(super) fn reporter(&self, analysis: &ReporterSetup, class: &str, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = self.model;
        let states = self.rows(analysis.step_interval)?;
        let formed = self.muscles(&states).map_err(|e| ReporterError::NotFormed(e.to_string())).and_then(|muscles| {
            tables.warnings.extend(muscles.warnings.iter().cloned());
            if class == "StatesReporter" {
                return Ok(vec![("states", states_reporter_table(spec, &geometry.multibody, &muscles, &states.motion, &states.speeds)?)]);
            }
            self.with_forces(&states, &muscles, |at| force_tables(spec, analysis, class, at))
        });
        match formed {
            Ok(formed) => formed.into_iter().for_each(|(suffix, t)| self.add(tables, &analysis.name, suffix, t, &states)),
            Err(ReporterError::Table(e)) => return Err(e.into()),
            Err(reason) => tables.not_written.push(format!("{class}'s tables: {reason}")),
        }
        Ok(())
    }
}

/// The tables of reporter `class` (`ForceReporter` or `Actuation`) with their file name suffixes.
fn force_tables(spec: &ModelSpec, analysis: &ReporterSetup, class: &str, at: &AppliedAt) -> Result<Vec<(&'static str, StorageTable)>, ReporterError> {
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
