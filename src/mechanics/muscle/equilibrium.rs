//! The state of a muscle in equilibrium and the quantities OpenSim's Muscle API reports for it.

use serde::Serialize;

/// A muscle at equilibrium for one activation and path length (SI units; forces in N, tension
/// positive). Field names follow OpenSim's `Muscle::get<Name>` getters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FiberEquilibrium {
    pub activation: f64,
    /// L_mt, m.
    pub mt_length: f64,
    /// L_m, m.
    pub fiber_length: f64,
    /// L_m / L_opt.
    pub normalized_fiber_length: f64,
    /// α, rad.
    pub pennation_angle: f64,
    pub cos_pennation_angle: f64,
    /// L_m cos α, m.
    pub fiber_length_along_tendon: f64,
    /// L_t = L_mt − L_m cos α, m.
    pub tendon_length: f64,
    /// (L_t − L_ts) / L_ts.
    pub tendon_strain: f64,
    pub tendon_force: f64,
    /// a · f_L · f_V · F_max.
    pub active_fiber_force: f64,
    /// Passive elastic (plus damping, for damped models) fiber force.
    pub passive_fiber_force: f64,
    pub fiber_force: f64,
    pub fiber_force_along_tendon: f64,
    pub active_force_length_multiplier: f64,
    pub passive_force_multiplier: f64,
    pub force_velocity_multiplier: f64,
    /// dL_m/dt / (v_max · L_opt); 0 in static equilibrium.
    pub normalized_fiber_velocity: f64,
    pub status: EquilibriumStatus,
}

/// How the equilibrium was reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum EquilibriumStatus {
    /// Fiber and tendon forces balance within the solver tolerance.
    Converged,
    /// No fiber length balances the tendon, and the fiber is held at its minimum length with no
    /// fiber force, as OpenSim clamps it: the path is so short that the tendon is slack (all
    /// forces 0), or the fiber at its shortest still pulls harder than the tendon can — then
    /// the tendon may keep a small force f_T·F_max (OpenSim's Thelen reports it so).
    ClampedAtMinimumFiberLength,
}
