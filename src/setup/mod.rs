//! Typed views of OpenSim tool setup files — `<ScaleTool>`, `<InverseKinematicsTool>`,
//! `<InverseDynamicsTool>`, `<AnalyzeTool>`, `<ForwardTool>`, `<RRATool>` (with its `CMC_TaskSet`) and the `<ExternalLoads>` they
//! name — in the 2.x/3.x and 4.x dialects, read through `io::osim::OsimDocument` with OpenSim's defaults
//! for absent properties. Objects given by reference (`<IKTaskSet file="…"/>`) are read from
//! their files; file names resolve against the setup file's directory, as OpenSim resolves them;
//! empty and `Unassigned` names are `None`.

mod analyze;
mod controls;
mod error;
mod external_loads;
mod forward;
mod ik;
mod ik_tasks;
mod induced_accelerations;
mod inverse_dynamics;
mod marker_placer;
mod measurement;
mod model_scaler;
mod object;
mod path;
mod property;
mod cmc;
mod rra;
mod scale;
mod time_range;

pub use analyze::{AnalyzeSetup, BodyKinematicsSetup, JointReactionSetup, KinematicsSetup, MuscleAnalysisSetup, PointKinematicsSetup, ReporterSetup, StaticOptimizationSetup};
pub use controls::{ControlBounds, ControlLinear, ControlSet};
pub use error::SetupError;
pub use object::read_document;
pub use external_loads::{ExternalForceSpec, ExternalLoadsSetup};
pub use forward::{ForwardSetup, IntegratorSettings};
pub use ik::IkSetup;
pub use inverse_dynamics::IdSetup;
pub use induced_accelerations::{ContactConstraintSetup, ContactSetup, InducedAccelerationsSetup};
pub use ik_tasks::{CoordinateTarget, CoordinateTask, IkTaskSet, MarkerTask};
pub use marker_placer::MarkerPlacer;
pub use measurement::{BodyScale, Measurement};
pub use model_scaler::{ManualScale, ModelScaler, ScalingStep};
pub use path::{required_input, SetupPath};
pub use cmc::{CmcSetup, CmcTaskSet, JointTask, StateTask, TrackingSetup};
pub use rra::RraSetup;
pub use scale::{GenericModelMaker, ScaleSetup};
pub use time_range::TimeRange;
