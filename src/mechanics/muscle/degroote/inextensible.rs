//! The rigid-tendon active fiber force of a `DeGrooteFregly2016Muscle`
//! (`calcInextensibleTendonActiveFiberForce`), whatever the muscle's own tendon compliance.

use super::curves::DeGrooteCurves;
use super::DeGrooteFregly2016Muscle;

impl DeGrooteFregly2016Muscle {
    /// OpenSim's `calcInextensibleTendonActiveFiberForce` (N): the tendon at L_ts, the fiber
    /// L_m = √((L_mt − L_ts)² + w²) lengthening at v_m = `lengthening_speed` · cos α (m/s,
    /// lengthening positive), F_max (a f_L(L_m / L_opt) f_V(v_m / (v_max L_opt))) at
    /// `activation` as given (no clamp) and path length `mt_length` (m).
    ///
    /// As OpenSim's, the force is the fiber's, not its projection on the tendon (no cos α), and
    /// nothing stops a short path: with L_mt < L_ts, cos α < 0 reverses the fiber velocity.
    /// Only a fiber of zero length (w = 0 and L_mt = L_ts) differs: OpenSim's 0/0 makes it NaN,
    /// here cos α = 0 (see `length_info`).
    pub fn inextensible_tendon_active_fiber_force(
        &self,
        activation: f64,
        mt_length: f64,
        lengthening_speed: f64,
    ) -> f64 {
        let length = self.length_info_at_tendon_length(mt_length, 1.0);
        let fiber_velocity = lengthening_speed * length.cos_pennation_angle;
        let normalized_fiber_velocity =
            fiber_velocity / (self.max_contraction_velocity * self.optimal_fiber_length);
        let active_force_length = self
            .curves
            .calc_active_force_length_multiplier(length.normalized_fiber_length);
        let force_velocity =
            DeGrooteCurves::calc_force_velocity_multiplier(normalized_fiber_velocity);
        self.max_isometric_force * (activation * active_force_length * force_velocity)
    }
}
