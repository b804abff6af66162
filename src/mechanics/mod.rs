//! Mechanics compiled from the model view: functions, kinematics, muscle paths.

mod actuator;
mod coupling;
mod error;
pub mod function;
mod geometry;
mod inverse_dynamics;
mod kinematics;
mod mobilizer;
mod mobilizer_rates;
mod motion;
mod motion_rates;
mod multibody;
pub mod muscle;
mod path;
mod spatial;
mod wrap_cylinder;
mod wrap_ellipsoid;
mod wrap_math;
mod wrap_sphere;
mod wrap_surface;
mod wrap_torus;

pub use actuator::Actuator;
pub use coupling::{for_each_coupling, Coupler};
pub use error::MechanicsError;
pub use function::Function;
pub use geometry::{MuscleGeometry, PathEvaluation};
pub use inverse_dynamics::{BodyLoad, MotionState};
pub use kinematics::{CoordinateAxis, Kinematics};
pub use mobilizer::{Mobilizer, PartialVelocity, TransformAxis};
pub use motion::{Motion, MotionError};
pub use motion_rates::TransformRates;
pub use multibody::{Body, Joint, Marker, Multibody, GROUND_INDEX};
pub use path::{GeometryPath, PathScratch};
pub use spatial::{body_fixed_xyz, body_fixed_xyz_angles, rotation_about, Mat3, Transform, Vec3};
