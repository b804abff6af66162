//! Agreement with OpenSim: comparisons of our mechanics against golden tables that OpenSim 4.6
//! produced, used by the conformance tests and `cargo xtask validate`.

mod analyze_tool;
mod assembly;
mod dynamometer;
pub mod functional;
mod forward;
mod forward_tool;
mod geometry;
mod golden;
pub mod ik;
mod inverse_dynamics;
mod joint_reaction;
pub mod kalman_ik;
pub mod knee_axis;
mod muscle;
mod muscle_degroote;
mod model_goldens;
mod muscle_thelen;
mod scale;
mod tool_case;
mod upgrade;
mod walk_dynamics;
mod cmc;
mod rra;

pub use upgrade::conversion_mismatches;
pub use cmc::{cmc_tolerances, compare_cmc_case, run_cmc_case, CmcComparison, CmcTolerances, TrackedBounds, CMC_CASES, cmc_inputs, POSITION_ERROR_MARGIN};
pub use rra::{compare_rra_case, rra_tolerances, run_rra_case, RraComparison, RRA_CASES, RRA_INPUTS, RRA_MASS_CENTER_TOLERANCE, RRA_REPORT_TOLERANCE};
pub use analyze_tool::{case_tolerance, compare_analyze_tool_setup, row_errors, row_tolerance, table_error, AnalyzeToolComparison, ANALYZE_TOOL_CASES, ANALYZE_TOOL_INPUTS, OFF_BOUND_TOLERANCE, VALUE_TOLERANCE};
pub use assembly::{compare_assembly, AssemblyComparison, ILL_DEFINED_SPEED};
pub use dynamometer::{dynamometer_golden_run, DynamometerCase, DynamometerComparison, DYNAMOMETER_CASES};
pub use forward_tool::{compare_forward_tool, ForwardToolComparison, FORWARD_TOOL_CASES, FORWARD_TOOL_VALIDATE_CASES};
pub use forward::{compare_forward, ForwardCase, ForwardComparison, FORWARD_CASES};
pub use geometry::{compare_geometry, GeometryComparison, Worst};
pub use golden::{GoldenError, GoldenPoses, GoldenTable};
pub use inverse_dynamics::compare_inverse_dynamics;
pub use model_goldens::{compare_model_golden, ModelGoldenError, PoseComparison};
pub use joint_reaction::{JointReactionCase, JointReactionComparison, JOINT_REACTION_CASES};
pub use muscle::{
    compare_equilibrium, compare_millard_curves, default_force_velocity_inverse, CurveComparison, EquilibriumComparison,
    EquilibriumSolution, EquilibriumValidationError, FIBER_LENGTH_TOLERANCE, STATIC_FIBER_LENGTH_TOLERANCE,
};
pub use muscle_degroote::{
    compare_degroote_curves, compare_degroote_equilibrium, compare_degroote_fiber_velocity, DeGrooteCurveComparison, DeGrooteEquilibriumComparison,
    DEGROOTE_LENGTH_TOLERANCE,
};
pub use muscle_thelen::{compare_thelen_curves, compare_thelen_fiber_velocity, ThelenCurveComparison};
pub use walk_dynamics::{compare_static_optimization, static_optimization_cases, StaticOptimizationCase, Subject01Walk, WalkStaticOptimization};
pub use scale::{compare_scaled_models, marker_objective, SCALED_MODEL_TOLERANCE};
