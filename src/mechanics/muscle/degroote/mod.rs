//! OpenSim 4.6's `DeGrooteFregly2016Muscle`, the muscle of OpenSim Moco models: its closed-form
//! curves (`curves.rs`), architecture, parameter checks and constant-width pennation
//! (`muscle.rs`), the static equilibrium solved for the normalized tendon force as OpenSim does
//! (`equilibrium.rs`), the fiber velocity of explicit and implicit tendon dynamics
//! (`fiber_velocity.rs`) and the active fiber force with a rigid tendon (`inextensible.rs`).

mod curves;
mod equilibrium;
mod fiber_velocity;
mod inextensible;
mod muscle;

pub use curves::DeGrooteCurves;
pub use muscle::DeGrooteFregly2016Muscle;
