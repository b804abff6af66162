//! OpenSim 4.6's `DeGrooteFregly2016Muscle`, the muscle of OpenSim Moco models: its closed-form
//! curves (`curves.rs`), architecture, parameter checks and constant-width pennation
//! (`muscle.rs`), the static equilibrium solved for the normalized tendon force as OpenSim does
//! (`equilibrium.rs`), the fiber velocity of explicit and implicit tendon dynamics
//! (`fiber_velocity.rs`), the active fiber force with a rigid tendon (`inextensible.rs`) and
//! the normalized tendon force as a forward-simulation state, its rate and its start as OpenSim's
//! `equilibrateMuscles` finds it (`tendon_force_state.rs`), and the muscle at any state
//! (`state.rs`).

mod curves;
mod equilibrium;
mod fiber_velocity;
mod inextensible;
mod state;
mod tendon_force_state;
mod muscle;

pub use curves::DeGrooteCurves;
pub use muscle::DeGrooteFregly2016Muscle;

/// A compliant-tendon muscle (F_max 1000 N, L_opt 0.1 m, L_ts 0.25 m, v_max 10 L_opt/s) for the
/// unit tests.
#[cfg(test)]
fn test_muscle(pennation_angle_at_optimal: f64, fiber_damping: f64) -> DeGrooteFregly2016Muscle {
    use crate::model::{DeGrooteSpec, MuscleModelSpec, MuscleSpec};
    let class = DeGrooteSpec {
        active_force_width_scale: 1.3,
        fiber_damping,
        ignore_passive_fiber_force: false,
        passive_fiber_strain_at_one_norm_force: 0.6,
        tendon_strain_at_one_norm_force: 0.049,
        default_activation: 0.5,
        default_normalized_tendon_force: 0.5,
        tendon_compliance_dynamics_mode: "explicit".into(),
        activation_time_constant: 0.015,
        deactivation_time_constant: 0.060,
        activation_dynamics_smoothing: 0.1,
    };
    let spec = MuscleSpec {
        max_isometric_force: 1000.0,
        optimal_fiber_length: 0.1,
        tendon_slack_length: 0.25,
        pennation_angle_at_optimal,
        max_contraction_velocity: 10.0,
        ignore_tendon_compliance: false,
        ignore_activation_dynamics: false,
        model: MuscleModelSpec::DeGrooteFregly2016(class.clone()),
    };
    DeGrooteFregly2016Muscle::new("test", &spec, &class).unwrap()
}
