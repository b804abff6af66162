//! One AnalyzeTool run, analysis by analysis: the states formed once from the input file, each
//! step interval's rows taken from them — with the muscles' states and the model's dynamics —
//! formed once however many analyses record them, and what cannot be formed named rather than
//! guessed.

use std::cell::{OnceCell, RefCell};
use std::path::Path;
use std::rc::Rc;

use super::analyze_dynamics::{analyze_dynamics, RowDynamics};
use super::analyze_states::{muscle_state_names, AnalyzeStates, MotionInput};
use super::analyze_tool::{analyze_tool_motion, AnalyzeModel, AnalyzeToolError, AnalyzeToolMotion, AnalyzeToolTables};
use super::body_kinematics::{body_tables, coordinate_tables, point_tables, KinematicsError};
use super::induced_accelerations::induced_acceleration_tables;
use super::joint_reaction::{reaction_reports, reaction_row, reaction_table};
use super::muscle_analysis::MuscleAnalysis;
use super::probes::probe_table;
use super::muscle_state_tables::muscle_state_tables;
use super::muscle_states::{muscle_states, MuscleStates};
use super::reporters::{actuation_tables, force_reporter_table, states_reporter_table, AppliedAt, ReporterError};
use super::signal::frames_in_range;
use super::static_optimization::{force_generators, Generator};
use crate::io::table::StorageTable;
use crate::mechanics::MotionState;
use crate::model::ModelSpec;
use crate::setup::{AnalyzeSetup, BodyKinematicsSetup, InducedAccelerationsSetup, JointReactionSetup, KinematicsSetup, MuscleAnalysisSetup, PointKinematicsSetup, ReporterSetup};

/// The rows of one step interval and what they form, each formed at most once.
struct RowSet {
    states: AnalyzeToolMotion,
    /// The muscles' states, or why they are not formed.
    muscles: OnceCell<Result<MuscleStates, String>>,
    /// The forward dynamics at those states, or why they are not formed.
    dynamics: OnceCell<Result<Vec<RowDynamics>, String>>,
}

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
    /// The row sets formed so far, by step interval.
    row_sets: RefCell<Vec<(usize, Rc<RowSet>)>>,
}

impl<'a> ToolRun<'a> {
    pub(super) fn new(model: &'a AnalyzeModel<'a>, table: &StorageTable, file: &'a Path, setup: &'a AnalyzeSetup, tool_name: &'a str) -> Result<ToolRun<'a>, AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = model;
        let multibody = &geometry.multibody;
        let muscles = muscle_state_names(spec);
        let input = if setup.states_file.is_some() { MotionInput::States { table, muscles: &muscles } } else { MotionInput::Coordinates(table) };
        let states = AnalyzeStates::read(multibody, input, file, Some(setup.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0))?;
        frames_in_range(file, &states.times, [setup.initial_time, setup.final_time])?;
        let generators = match controls_ignored(model, true) {
            Some(reason) => Err(reason),
            None => force_generators(spec, geometry, model.added, model.replace).map_err(|e| e.to_string()),
        };
        Ok(ToolRun { model, setup, file, tool_name, states, generators, row_sets: RefCell::new(Vec::new()) })
    }

    /// The assembled rows an analysis of `step_interval` records (formed once per interval).
    fn rows(&self, step_interval: usize) -> Result<Rc<RowSet>, AnalyzeToolError> {
        if let Some((_, rows)) = self.row_sets.borrow().iter().find(|(step, _)| *step == step_interval) {
            return Ok(Rc::clone(rows));
        }
        let time_range = [self.setup.initial_time, self.setup.final_time];
        let states = analyze_tool_motion(&self.model.geometry.multibody, &self.states, self.file, time_range, step_interval)?;
        let rows = Rc::new(RowSet { states, muscles: OnceCell::new(), dynamics: OnceCell::new() });
        self.row_sets.borrow_mut().push((step_interval, Rc::clone(&rows)));
        Ok(rows)
    }

    /// The muscles' states at `rows`, or why they are not formed.
    fn muscles<'r>(&self, rows: &'r RowSet) -> Result<&'r MuscleStates, String> {
        let formed = rows.muscles.get_or_init(|| {
            let &AnalyzeModel { spec, geometry, controls, .. } = self.model;
            muscle_states(spec, geometry, &rows.states, controls, self.setup.solve_for_equilibrium_for_auxiliary_states).map_err(|e| e.to_string())
        });
        formed.as_ref().map_err(Clone::clone)
    }

    /// The forces applied at `rows` with the muscles at `muscles`, or why they are not formed.
    fn applied<'r>(&'r self, rows: &'r RowSet, muscles: &'r MuscleStates) -> Result<AppliedAt<'r>, String> {
        let generators = self.generators.as_ref().map_err(Clone::clone)?;
        let &AnalyzeModel { geometry, external, controls, .. } = self.model;
        Ok(AppliedAt::new(&geometry.multibody, generators, external, controls, muscles, &rows.states))
    }

    /// The forward dynamics of `rows`, or why they are not formed.
    fn dynamics<'r>(&self, rows: &'r RowSet) -> Result<&'r [RowDynamics], String> {
        let formed = rows.dynamics.get_or_init(|| {
            let muscles = self.muscles(rows)?;
            analyze_dynamics(self.model.geometry, &self.applied(rows, muscles)?)
        });
        formed.as_deref().map_err(Clone::clone)
    }

    /// u̇ of each row of `rows`, or `None` with the reason noted as `what` not written.
    fn accelerations(&self, rows: &RowSet, tables: &mut AnalyzeToolTables, what: &str) -> Option<Vec<Vec<f64>>> {
        let formed = self.dynamics(rows).map(|rows| rows.iter().map(|r| r.udot.clone()).collect());
        formed.map_err(|reason| tables.not_written.push(format!("{what}: {reason}"))).ok()
    }

    /// What OpenSim warns about while forming the muscles' states of every row set, each once.
    pub(super) fn warnings(&self) -> Vec<String> {
        let row_sets = self.row_sets.borrow();
        let mut warnings: Vec<String> = row_sets.iter().filter_map(|(_, rows)| rows.muscles.get()?.as_ref().ok()).flat_map(|m| m.warnings.iter().cloned()).collect();
        warnings.sort();
        warnings.dedup();
        warnings
    }

    /// `add` of `tables` under this tool's name.
    fn add(&self, tables: &mut AnalyzeToolTables, analysis: &str, suffix: &str, table: StorageTable, states: &AnalyzeToolMotion) {
        tables.add(self.tool_name, analysis, suffix, table, states);
    }

    /// An error of a kinematics analysis, naming the setup.
    fn in_setup(&self, source: KinematicsError) -> AnalyzeToolError {
        AnalyzeToolError::Kinematics { file: self.setup.file.clone(), source }
    }

    /// The MuscleAnalysis: path tables, then the muscles' state tables (or why not).
    pub(super) fn muscle_analysis(&self, analysis: &MuscleAnalysisSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { geometry, replace, .. } = self.model;
        if replace {
            tables.not_written.push(format!("{}: replace_force_set replaces the model's muscles by the force-set files' actuators, so OpenSim's MuscleAnalysis has no muscles", analysis.name));
            return Ok(());
        }
        let rows = self.rows(analysis.step_interval)?;
        let states = &rows.states;
        let selected = MuscleAnalysis::run(geometry, &states.motion)?.setup_tables(&geometry.multibody, analysis)?;
        let arms: Vec<&StorageTable> = selected.tables.iter().filter(|t| t.name().starts_with("MomentArm_")).collect();
        let state_tables = match controls_ignored(self.model, false).map_or_else(|| self.muscles(&rows), Err) {
            Ok(muscles) => muscle_state_tables(muscles, &states.motion.times, &selected.muscles, &arms)?,
            Err(reason) => {
                tables.not_written.push(format!("the MuscleAnalysis' fiber, tendon, force, power and moment tables: {reason}"));
                Vec::new()
            }
        };
        for table in selected.tables.into_iter().chain(state_tables) {
            let suffix = table.name().to_string();
            self.add(tables, &analysis.name, &suffix, table, states);
        }
        (tables.unknown_muscles, tables.unknown_coordinates) = (selected.unknown_muscles, selected.unknown_coordinates);
        Ok(())
    }

    /// Kinematics: q, u and u̇.
    pub(super) fn kinematics(&self, analysis: &KinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let rows = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&rows, tables, "Kinematics' accelerations (_dudt)");
        let formed = coordinate_tables(&self.model.geometry.multibody, &rows.states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        for (suffix, table) in ["q", "u", "dudt"].into_iter().zip(formed) {
            self.add(tables, &analysis.name, suffix, table, &rows.states);
        }
        Ok(())
    }

    /// BodyKinematics: positions, velocities and accelerations.
    pub(super) fn body_kinematics(&self, analysis: &BodyKinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let multibody = &self.model.geometry.multibody;
        let rows = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&rows, tables, "BodyKinematics' accelerations (_acc_…)");
        let formed = body_tables(multibody, &self.body_set(), &rows.states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        let frame = if analysis.express_in_local_frame { "bodyLocal" } else { "global" };
        for (suffix, table) in ["pos_global".to_string(), format!("vel_{frame}"), format!("acc_{frame}")].into_iter().zip(formed) {
            self.add(tables, &analysis.name, &suffix, table, &rows.states);
        }
        Ok(())
    }

    /// The model's BodySet as [`crate::mechanics::Multibody::bodies`] indices, in its order.
    fn body_set(&self) -> Vec<usize> {
        let multibody = &self.model.geometry.multibody;
        self.model.spec.bodies.iter().filter_map(|b| multibody.bodies.iter().position(|m| m.name == b.name)).collect()
    }

    /// InducedAccelerations: each contributor's accelerations (and the reactions they induce).
    pub(super) fn induced_accelerations(&self, analysis: &InducedAccelerationsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let rows = self.rows(analysis.step_interval)?;
        let at = match self.muscles(&rows).and_then(|muscles| self.applied(&rows, muscles)) {
            Ok(at) => at,
            Err(reason) => {
                tables.not_written.push(format!("the InducedAccelerations' tables: {reason}"));
                return Ok(());
            }
        };
        let formed = induced_acceleration_tables(self.model.geometry, &at, analysis, &self.body_set(), &self.setup.file)?;
        for (suffix, table) in formed.tables {
            self.add(tables, &analysis.name, &suffix, table, &rows.states);
        }
        tables.notes.extend(formed.notes);
        let idle: Vec<&str> = self.model.spec.forces.iter().filter(|f| !f.applies_force && (f.is_muscle() || self.model.spec.actuators.iter().any(|a| a.name == f.name))).map(|f| f.name.as_str()).collect();
        if !idle.is_empty() {
            tables.notes.push(format!("InducedAccelerations: the actuators {} apply no force and are no contributors here (OpenSim lists them and switches them on)", idle.join(", ")));
        }
        Ok(())
    }

    /// A PointKinematics: the point's position, velocity and acceleration.
    pub(super) fn point_kinematics(&self, analysis: &PointKinematicsSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let rows = self.rows(analysis.step_interval)?;
        let udot = self.accelerations(&rows, tables, &format!("PointKinematics {}'s accelerations (_acc)", analysis.point_name));
        let formed = point_tables(&self.model.geometry.multibody, &rows.states, analysis, udot.as_deref()).map_err(|e| self.in_setup(e))?;
        for (suffix, table) in ["pos", "vel", "acc"].into_iter().zip(formed) {
            self.add(tables, &analysis.name, &format!("{}_{suffix}", analysis.point_name), table, &rows.states);
        }
        Ok(())
    }

    /// A JointReaction without a forces file: the loads under the model's own forces.
    pub(super) fn joint_reaction(&self, analysis: &JointReactionSetup, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = self.model;
        let multibody = &geometry.multibody;
        let rows = self.rows(analysis.step_interval)?;
        let states = &rows.states;
        let reports = reaction_reports(spec, multibody, &analysis.joint_names, &analysis.apply_on_bodies, &analysis.express_in_frame, &self.setup.file).map_err(Box::new)?;
        let dynamics = match self.dynamics(&rows) {
            Ok(dynamics) => dynamics,
            Err(reason) => {
                tables.not_written.push(format!("the JointReaction's loads: {reason}"));
                return Ok(());
            }
        };
        let mut kinematics = multibody.kinematics();
        let mut values = Vec::new();
        for (row, dynamics) in dynamics.iter().enumerate() {
            let (q, u) = (states.motion.pose(row), &states.speeds[row]);
            multibody.realize(q, &mut kinematics);
            values.push(states.motion.times[row]);
            values.extend(reaction_row(multibody, &kinematics, &MotionState { q, u, udot: &dynamics.udot }, &dynamics.loads, &reports));
        }
        self.add(tables, &analysis.name, "ReactionLoads", reaction_table(multibody, &reports, values)?, states);
        Ok(())
    }

    /// A reporter (`ForceReporter`, `Actuation`, `StatesReporter` or `ProbeReporter`).
    pub(super) fn reporter(&self, analysis: &ReporterSetup, class: &str, tables: &mut AnalyzeToolTables) -> Result<(), AnalyzeToolError> {
        let &AnalyzeModel { spec, geometry, .. } = self.model;
        let rows = self.rows(analysis.step_interval)?;
        let states = &rows.states;
        let formed = self.muscles(&rows).map_err(ReporterError::NotFormed).and_then(|muscles| match class {
            "StatesReporter" => Ok(vec![("states", states_reporter_table(spec, &geometry.multibody, muscles, &states.motion, &states.speeds)?)]),
            "ProbeReporter" => Ok(vec![("probes", probe_table(spec, &self.applied(&rows, muscles).map_err(ReporterError::NotFormed)?, &mut tables.notes)?)]),
            _ => force_tables(spec, analysis, class, &self.applied(&rows, muscles).map_err(ReporterError::NotFormed)?),
        });
        match formed {
            Ok(formed) => formed.into_iter().for_each(|(suffix, t)| self.add(tables, &analysis.name, suffix, t, states)),
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

/// Why a force table would not be OpenSim's: a controller osim-tune does not apply could drive a
/// muscle without activation dynamics or, with `actuators`, a non-muscle actuator.
fn controls_ignored(model: &AnalyzeModel, actuators: bool) -> Option<String> {
    let unapplied = &model.controls.unapplied;
    if unapplied.is_empty() {
        return None;
    }
    let spec = model.spec;
    let driven = (actuators && (!spec.actuators.is_empty() || !model.added.is_empty())) || spec.forces.iter().any(|f| f.muscle.as_ref().is_some_and(|m| m.ignore_activation_dynamics));
    driven.then(|| format!("controllers osim-tune does not apply ({}) may drive forces of the model", unapplied.join(", ")))
}
