//! The state of a `DeGrooteFregly2016Muscle` with a compliant tendon in explicit mode, its
//! normalized tendon force f̃_T: its rate, and where OpenSim's `equilibrateMuscles` starts it.
//!
//! Rate (`computeStateVariableDerivatives`): the fiber at f̃_T (L_t = L_ts f_T⁻¹(f̃_T),
//! L_m cos α = L_mt − L_t) moves at ṽ = f_V⁻¹((f̃_T / cos α − f_PE) / (a f_L)) (damping left
//! out, as OpenSim does), and the tendon takes the rest of the path's lengthening speed v_mt:
//! df̃_T/dt = f_T′(L̃_t) (v_mt − L̇_m / cos α) / L_ts. With OpenSim's path speed — over wrap
//! objects not the exact dL_mt/dt — this differs from integrating the fiber length.
//!
//! Start (`computeInitialFiberEquilibrium`): the normalized tendon force f̃_T that zeroes the
//! implicit residual (`calcEquilibriumResidual`) at the path's lengthening speed v_mt with a
//! tendon-force derivative of 0 — the tendon not stretching, the fiber takes the whole speed:
//! L̇_m cos α-wise v_mt, L̇_m = v_mt cos α, ṽ = L̇_m / (v_max L_opt), and
//! r(f̃_T) = f̃_T − (a f_L f_V(ṽ) + f_PE + β ṽ) cos α — found as OpenSim finds it, by bisection
//! (`solveBisection`) on [0, 5] until the bracket is 1e-10 wide (at most 100 halvings), the
//! last midpoint returned.

use super::curves::DeGrooteCurves;
use super::muscle::LengthInfo;
use super::DeGrooteFregly2016Muscle;
use crate::mechanics::muscle::{check_compliant_tendon, check_inputs, MuscleError};

/// `solveBisection`'s bracket width and iteration limit in `computeInitialFiberEquilibrium`.
const BRACKET: f64 = 1e-10;
const MAX_HALVINGS: usize = 100;

impl DeGrooteFregly2016Muscle {
    /// f̃_T of OpenSim's initial equilibrium at activation `activation` ∈ [0, 1], path length
    /// `mt_length` (m) and lengthening speed `lengthening_speed` (m/s); `Infeasible` where
    /// OpenSim throws (r has the same sign at 0 and 5).
    pub fn initial_normalized_tendon_force(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> Result<f64, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        check_compliant_tendon(&self.name, self.ignore_tendon_compliance)?;
        let residual = |force: f64| self.moving_residual(activation, mt_length, lengthening_speed, force);
        let (mut left, mut right) = (0.0, DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE);
        let ends = residual(left) * residual(right);
        if ends >= 0.0 || ends.is_nan() {
            let reason = format!("the equilibrium residual has the same sign at normalized tendon forces {left} and {right} (lengthening speed {lengthening_speed} m/s)");
            return Err(MuscleError::Infeasible { muscle: self.name.clone(), activation, mt_length, reason });
        }
        let (mut midpoint, mut residual_left) = (left, residual(left));
        let mut halvings = 0;
        while halvings < MAX_HALVINGS && right - left > BRACKET {
            midpoint = 0.5 * (left + right);
            if residual(midpoint) * residual_left < 0.0 {
                right = midpoint;
            } else {
                left = midpoint;
                residual_left = residual(left);
            }
            halvings += 1;
        }
        Ok(midpoint)
    }

    /// df̃_T/dt (1/s) at activation `activation`, normalized tendon force
    /// `normalized_tendon_force`, path length `mt_length` (m) and lengthening speed
    /// `lengthening_speed` (m/s); not finite where no fiber velocity balances the tendon.
    pub fn normalized_tendon_force_rate(&self, activation: f64, normalized_tendon_force: f64, mt_length: f64, lengthening_speed: f64) -> f64 {
        let length = self.length_info(mt_length, normalized_tendon_force);
        let curves = &self.curves;
        let fiber_force = normalized_tendon_force / length.cos_pennation_angle;
        let force_velocity = (fiber_force - curves.calc_passive_force_multiplier(length.normalized_fiber_length))
            / (activation * curves.calc_active_force_length_multiplier(length.normalized_fiber_length));
        let fiber_velocity = DeGrooteCurves::calc_force_velocity_inverse_curve(force_velocity) * (self.max_contraction_velocity * self.optimal_fiber_length);
        let tendon_velocity = lengthening_speed - fiber_velocity / length.cos_pennation_angle;
        tendon_velocity / self.tendon_slack_length * curves.calc_tendon_force_multiplier_derivative(length.normalized_tendon_length)
    }

    /// The fiber length (m) at normalized tendon force `normalized_tendon_force` on a path of
    /// length `mt_length` (m).
    pub fn fiber_length_at(&self, mt_length: f64, normalized_tendon_force: f64) -> f64 {
        self.length_info(mt_length, normalized_tendon_force).fiber_length
    }

    /// F_t = F_max f_T(L_t / L_ts) (N) with the fiber at `fiber_length` (m, ≥ the fiber width) on
    /// a path of length `mt_length` (m), L_t = L_mt − √(L_m² − w²).
    pub fn tendon_force(&self, fiber_length: f64, mt_length: f64) -> f64 {
        let along_tendon = (fiber_length * fiber_length - self.fiber_width * self.fiber_width).sqrt();
        self.max_isometric_force * self.curves.calc_tendon_force_multiplier((mt_length - along_tendon) / self.tendon_slack_length)
    }

    /// (L_m in m, F_t in N) of a rigid-tendon muscle at activation `activation` on a path of
    /// length `mt_length` (m) lengthening at `lengthening_speed` (m/s): the fiber takes the whole
    /// speed and pulls along the tendon with a f_L f_V + f_PE + β ṽ (OpenSim's
    /// `calcMuscleDynamicsInfo` with `ignore_tendon_compliance`).
    pub fn rigid_tendon_state(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> (f64, f64) {
        let length = self.length_info(mt_length, f64::NAN);
        (length.fiber_length, self.fiber_force_along_tendon(activation, &length, lengthening_speed))
    }

    /// OpenSim's `calcEquilibriumResidual(L_mt, v_mt, a, f̃_T, 0)`, its operations in its order.
    fn moving_residual(&self, activation: f64, mt_length: f64, lengthening_speed: f64, normalized_tendon_force: f64) -> f64 {
        let length = self.length_info(mt_length, normalized_tendon_force);
        normalized_tendon_force - self.fiber_force_along_tendon(activation, &length, lengthening_speed) / self.max_isometric_force
    }

    /// The fiber force along the tendon (N) when the tendon does not stretch, so that the fiber
    /// takes the path's whole lengthening speed (`calcFiberVelocityInfo`'s implicit branch with a
    /// zero tendon-force derivative, then `calcMuscleDynamicsInfo`), its operations in OpenSim's
    /// order.
    fn fiber_force_along_tendon(&self, activation: f64, length: &LengthInfo, lengthening_speed: f64) -> f64 {
        let fiber_velocity = lengthening_speed * length.cos_pennation_angle;
        let normalized_velocity = fiber_velocity / (self.max_contraction_velocity * self.optimal_fiber_length);
        let curves = &self.curves;
        let force_velocity = DeGrooteCurves::calc_force_velocity_multiplier(normalized_velocity);
        let f_max = self.max_isometric_force;
        let active = f_max * (activation * curves.calc_active_force_length_multiplier(length.normalized_fiber_length) * force_velocity);
        let passive = f_max * curves.calc_passive_force_multiplier(length.normalized_fiber_length);
        let damping = f_max * self.fiber_damping * normalized_velocity;
        (active + passive + damping) * length.cos_pennation_angle
    }
}

#[cfg(test)]
mod tests {
    /// At rest the bisection lands within its bracket of the static equilibrium; moving, the
    /// residual vanishes at the found force to the bracket's precision, a shortening fiber
    /// pulling less (force–velocity); and the fiber length of the found force maps back to it.
    #[test]
    fn the_bisection_finds_the_equilibrium_opensim_finds() {
        let m = super::super::test_muscle(0.2, 0.01);
        let (a, length) = (0.6, 0.33);
        let at_rest = m.initial_normalized_tendon_force(a, length, 0.0).unwrap();
        let static_force = m.equilibrium(a, length).unwrap().tendon_force / 1000.0;
        assert!((at_rest - static_force).abs() < 1e-10, "{at_rest} vs {static_force}");
        let shortening = m.initial_normalized_tendon_force(a, length, -0.2).unwrap();
        assert!(shortening < at_rest, "a shortening fiber pulls less (force–velocity): {shortening} vs {at_rest}");
        assert!(m.moving_residual(a, length, -0.2, shortening).abs() < 1e-8);
        let fiber = m.fiber_length_at(length, shortening);
        assert!((m.tendon_force(fiber, length) / 1000.0 - shortening).abs() < 1e-12);
    }

    /// Without damping the rate is the change of f_T((L_mt − L_m cos α)/L_ts) when the fiber moves
    /// at its explicit velocity and the path at its speed (first principles, by central
    /// differences along that motion).
    #[test]
    fn the_rate_follows_fiber_and_path() {
        let m = super::super::test_muscle(0.2, 0.0);
        let (a, length, speed, force) = (0.5, 0.34, 0.3, 0.4);
        let fiber = m.fiber_length_at(length, force);
        let fiber_velocity = m.fiber_velocity(a, fiber, length).unwrap();
        let h = 1e-6;
        let at = |t: f64| m.tendon_force(fiber + fiber_velocity * t, length + speed * t) / 1000.0;
        let numeric = (at(h) - at(-h)) / (2.0 * h);
        let rate = m.normalized_tendon_force_rate(a, force, length, speed);
        assert!((rate - numeric).abs() < 1e-6 * rate.abs().max(1.0), "{rate} vs {numeric}");
    }
}
