//! `Millard2012EquilibriumMuscle`: quintic-Bézier curves (`bezier`, `smooth_function`,
//! `curves`) and the muscle (`muscle`: parameters as OpenSim finalises them, static
//! equilibrium, OpenSim's own equilibrium iteration, fiber velocity; `inextensible`: the active
//! fiber force with a rigid tendon as static optimisation takes it; `rigid_tendon`: a rigid-tendon
//! muscle in motion).

mod bezier;
mod curves;
mod inextensible;
mod muscle;
mod opensim_equilibrium;
mod rigid_tendon;
mod smooth_function;
mod velocity;

pub use curves::force_velocity_inverse;
pub use muscle::{Millard2012Muscle, MillardCurves};
pub use smooth_function::SmoothSegmentedFunction;
