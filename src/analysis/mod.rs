//! Analyses along a motion, in the spirit of OpenSim's analyses (`MuscleAnalysis`, …).

mod activation;
mod analyze_dynamics;
mod analyze_runs;
mod analyze_states;
mod analyze_tool;
mod body_kinematics;
mod cmc;
mod controllers;
mod dynamometer;
mod emg_comparison;
mod external_loads;
mod forward;
mod fiber_analysis;
mod induced_accelerations;
mod inverse_dynamics;
mod joint_reaction;
mod metabolics;
mod muscle_analysis;
mod muscle_state_tables;
mod muscle_states;
mod physiological_inverse;
mod probes;
mod reporters;
mod residual_reduction;
mod signal;
mod simulation;
mod sampled_motion;
mod splined_motion;
mod static_optimization;

pub use activation::{ActivationError, Activations};
pub use body_kinematics::KinematicsError;
pub use cmc::{run_cmc, CmcError, CmcOutputs, InitialStates as CmcInitialStates, WindowSolution};
pub use controllers::Controllers;
pub use dynamometer::{agreement, dynamometer_analysis, isometric_contraction, plateau, Agreement, IsometricContraction, Agreements, Axis, DynamometerSummary, HerzogEstimate, Spread, PERPENDICULAR_TOLERANCE, DynamometerError, DynamometerFrame, DynamometerModel, DynamometerResult, DynamometerSettings, MeasuredMoment, Perturbations, SensitivityRow};
pub use emg_comparison::{correlate_with_emg, EmgComparisonError, EmgCorrelation};
pub use external_loads::{ExternalLoads, ExternalLoadsError};
pub use forward::{
    compare_with_inverse_dynamics, driven_muscles, inverse_dynamics_times, simulate, CoordinateComparison, DrivenMuscle, ForwardError, ForwardOutputs, ForwardSettings, InitialStates, PrescribedMotion,
    Trajectory,
};
pub use fiber_analysis::{hill_muscles, FiberAnalysis, FiberAnalysisError};
pub use induced_accelerations::InducedAccelerationsError;
pub use inverse_dynamics::{inverse_dynamics, InverseDynamicsError, InverseDynamicsResult, InverseDynamicsSettings};
pub use joint_reaction::{joint_reactions, reaction_reports, ActuatorForces, JointReactionError, JointReactionResult, JointReactionSettings, ReactionProblem, ReactionReport, ReactionSide};
pub use analyze_tool::{analyze_tool_tables, AnalyzeModel, AnalyzeToolError, AnalyzeToolTables};
pub use muscle_analysis::{MuscleAnalysis, SetupTables};
pub use physiological_inverse::{physiological_inverse, Contraction, Criterion, PhysiologicalInverseResult, PhysiologicalInverseSettings, MAX_LINEARISATIONS, SETTLED_STEP, SETTLED_VIOLATION};
pub use residual_reduction::{run_rra, Adjusted, MassAdjustment, ResidualReductionError, Residuals, RraOutputs, RESIDUALS};
pub use signal::{spline, Series, SignalError};
pub use simulation::{controls_table, initial_state, ForwardModel, simulate_plant, state_labels, state_values, states_table, InitialSource, Plant, SimulatedState, Simulation, SimulationError};
pub use sampled_motion::{CoordinateState, SampledMotion, SampledMotionError};
pub use splined_motion::{SplinedMotion, SplinedMotionError};
pub use static_optimization::{generators, static_optimization, FrameFailure, Generator, ReferenceControls, ReferenceFrame, StaticOptimizationError, StaticOptimizationResult, StaticOptimizationSettings};
pub use analyze_states::{muscle_state_names, MotionInput, StatesError};

use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{MuscleGeometry, Multibody};
use crate::model::ModelSpec;

/// The coordinates some of the chosen paths span, in model order, and where each sits in each
/// path's `spanned` list: `slots[t][k]` for coordinate t and chosen path k.
struct Spans {
    coordinates: Vec<usize>,
    slots: Vec<Vec<Option<usize>>>,
}

impl Spans {
    fn new(geometry: &MuscleGeometry, paths: &[usize]) -> Spans {
        let mut coordinates: Vec<usize> = paths.iter().flat_map(|&p| geometry.paths[p].spanned.iter().copied()).collect();
        coordinates.sort_unstable();
        coordinates.dedup();
        let slots = coordinates
            .iter()
            .map(|&c| paths.iter().map(|&p| geometry.paths[p].spanned.iter().position(|&s| s == c)).collect())
            .collect();
        Spans { coordinates, slots }
    }
}

/// `time` and then one label per chosen path.
fn path_labels(geometry: &MuscleGeometry, paths: &[usize]) -> Vec<String> {
    std::iter::once("time".to_string()).chain(paths.iter().map(|&p| geometry.paths[p].name.clone())).collect()
}

/// The joints ([`crate::mechanics::Multibody::joints`] indices) a tool's joint list names: every
/// joint in the model's order for an empty list or one whose entry is `ALL` (any case, OpenSim's
/// keyword, which ends the list), else the named ones in order; an unknown name is an error.
pub fn named_joints(spec: &ModelSpec, multibody: &Multibody, names: &[String]) -> Result<Vec<usize>, String> {
    let index = |name: &str| multibody.joints.iter().position(|j| j.name == name).ok_or_else(|| format!("joint {name:?} does not exist in the model"));
    let mut joints = Vec::new();
    for name in names {
        if name.eq_ignore_ascii_case("all") {
            return spec.joints.iter().map(|j| index(&j.name)).collect();
        }
        joints.push(index(name)?);
    }
    if names.is_empty() {
        return spec.joints.iter().map(|j| index(&j.name)).collect();
    }
    Ok(joints)
}

/// A radian-valued storage table.
fn storage(name: &str, labels: Vec<String>, values: Vec<f64>) -> Result<StorageTable, TableError> {
    Ok(StorageTable::new(name, labels, values)?.with_in_degrees(false))
}
