//! OpenSim 4.6's `Thelen2003Muscle`: the Thelen (2003) curves with OpenSim's exact tendon-toe
//! constants and linear force–velocity extrapolation (`curves.rs`, `force_velocity.rs`), fixed-width
//! pennation, the static fiber–tendon equilibrium and the fiber-length state derivative
//! (`muscle.rs`), the active fiber force with a rigid tendon (`inextensible.rs`), and OpenSim's
//! initial fiber length for a moving path (`initial_state.rs`).

mod curves;
mod force_velocity;
mod inextensible;
mod initial_state;
mod muscle;

pub use curves::ThelenCurves;
pub use muscle::Thelen2003Muscle;
