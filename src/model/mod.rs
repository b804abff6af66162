//! Typed view of an OpenSim model document: bodies, frames, joints, coordinates, functions,
//! markers, forces with their paths, actuators, controllers, constraints and wrap objects, read from either
//! the 4.x or the 3.x layout into one form. Elements keep their `ElementId` where later edits
//! need it.

mod actuator;
mod body;
mod constraint;
mod controller;
mod conversion;
mod coordinate;
mod error;
mod force;
mod frame;
mod function;
mod joint;
mod marker;
mod muscle;
mod orientation;
mod path_point;
mod probe;
mod reader;
mod spec;
mod station_frame;
mod upgrade;
mod wrap_object;

pub use actuator::{read_force_set, ActuatorKind, ActuatorSpec};
pub use body::BodySpec;
pub use constraint::{ConstraintSpec, CouplerSpec, LinkSpec};
pub use controller::{ControllerSpec, PrescribedControllerSpec};
pub use coordinate::{CoordinateSpec, CoordinateUnit, MotionType};
pub use error::{BadProperty, ModelError};
pub use force::{ForceSpec, PathWrapSpec};
pub use frame::{opensim_path, FrameChain, FrameIndex, Offset};
pub use function::FunctionSpec;
pub use joint::{JointSpec, JointSurface, TransformAxisSpec};
pub use marker::MarkerSpec;
pub use orientation::{body_fixed_xyz, body_fixed_xyz_angles};
pub use muscle::{
    ActiveForceLengthCurveSpec, DeGrooteSpec, FiberForceLengthCurveSpec, ForceVelocityCurveSpec, MillardSpec,
    MuscleModelSpec, MuscleSpec, SecondState, TendonForceLengthCurveSpec, ThelenSpec, MUSCLE_CLASSES,
};
pub use reader::{ComponentReader, PropertySources};
pub use path_point::{MovingComponent, PathPointKind, PathPointSpec};
pub use probe::{ActuatorQuantity, BhargavaRates, MetabolicModel, MetabolicMuscleSpec, MetabolicsProbeSpec, ProbeKind, ProbeSpec, UmbergerRates};
pub use spec::{ModelSpec, GROUND};
pub use upgrade::{upgrade, UPGRADED_VERSION};
pub use wrap_object::{WrapObjectSpec, WrapShape};
