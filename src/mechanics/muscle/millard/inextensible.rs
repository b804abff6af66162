//! The rigid-tendon active fiber force of a Millard 2012 muscle
//! (`calcInextensibleTendonActiveFiberForce`, `calcActiveFiberForceAlongTendon`), whatever the
//! muscle's own tendon compliance.

use super::Millard2012Muscle;

impl Millard2012Muscle {
    /// OpenSim's `calcInextensibleTendonActiveFiberForce` (N) at activation `activation`, path
    /// length `mt_length` (m) and path lengthening speed `lengthening_speed` (m/s): the tendon at
    /// L_ts, the pennation model's fiber L_m = √(h² + (L_mt − L_ts)²) (its minimum when the
    /// path is shorter), lengthening at `lengthening_speed` · cos α(L_m) (m/s), into
    /// [`Self::active_fiber_force_along_tendon`]. 0 when that velocity is NaN, as OpenSim skips it.
    pub fn inextensible_tendon_active_fiber_force(
        &self,
        activation: f64,
        mt_length: f64,
        lengthening_speed: f64,
    ) -> f64 {
        let fiber_length = self.pennation.fiber_length(mt_length, self.tendon_slack_length);
        let cos_alpha = self.pennation.pennation_angle(fiber_length).cos();
        let fiber_velocity = lengthening_speed * cos_alpha;
        if fiber_velocity.is_nan() {
            return 0.0;
        }
        self.active_fiber_force_along_tendon(activation, fiber_length, fiber_velocity)
    }

    /// OpenSim's `calcActiveFiberForceAlongTendon` (N): F_max (a f_L(l̃) f_V(ṽ)) cos α̃ at
    /// activation `activation` clamped to [minimum_activation, 1], fiber length `fiber_length`
    /// (m; l̃ = L_m / L_opt) and fiber velocity `fiber_velocity` (m/s, lengthening positive;
    /// ṽ = v_m / (L_opt v_max)); 0 at or below the minimum fiber length.
    ///
    /// OpenSim's quirk, kept: α̃ is the pennation model's angle at the *normalised* length l̃
    /// taken as a length in m — sin α̃ = h / l̃ with h = L_opt sin α_opt in m, α_max when
    /// l̃ is at or below the pennation model's minimum length (m) — not the fiber's α(L_m).
    pub fn active_fiber_force_along_tendon(
        &self,
        activation: f64,
        fiber_length: f64,
        fiber_velocity: f64,
    ) -> f64 {
        if fiber_length <= self.minimum_fiber_length {
            return 0.0;
        }
        let a = self.clamp_activation(activation);
        let norm_length = fiber_length / self.optimal_fiber_length;
        let norm_velocity =
            fiber_velocity / (self.optimal_fiber_length * self.max_contraction_velocity);
        let active_force_length = self.curves.active_force_length.value(norm_length);
        let force_velocity = self.curves.force_velocity.value(norm_velocity);
        let cos_alpha = self.pennation.pennation_angle(norm_length).cos();
        self.max_isometric_force * (a * active_force_length * force_velocity) * cos_alpha
    }
}
