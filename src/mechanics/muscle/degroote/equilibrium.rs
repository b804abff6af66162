//! The static (zero-velocity) equilibrium of a `DeGrooteFregly2016Muscle`.
//!
//! OpenSim's `computeInitialFiberEquilibrium` solves, for the normalized tendon force f̃_T, the
//! implicit residual (`calcEquilibriumResidual` with path and tendon-force speeds 0)
//!
//! r(f̃_T) = f̃_T − (a f_L(l̃_m) f_V(0) + f_PE(l̃_m)) cos α,
//!
//! where the fiber follows from the tendon: L_t = L_ts l̃_T(f̃_T), L_m cos α = L_mt − L_t,
//! L_m = √((L_m cos α)² + w²). Damping contributes nothing at zero velocity. OpenSim bisects
//! f̃_T on [0, 5] to a bracket of 1e-10 and throws when r has the same sign at both ends. Here the
//! same residual is solved by safeguarded Newton to |r| ≤ 1e-14 on the same bracket, cut at
//! f̃_T = f_T(L_mt / L_ts), where the tendon fills the whole path (L_m cos α = 0): OpenSim's answer
//! is within 1e-10 of this root. Beyond that cut the fiber would point backwards; it is taken
//! to transmit no force along the tendon there (r = f̃_T; OpenSim would use the negative cos α),
//! which keeps r continuous at the cut for a pennate muscle and positive past it for any muscle.
//! A rigid tendon (`ignore_tendon_compliance`) needs no solve: L_t = L_ts.
//!
//! Edge behaviour, all as errors (`Infeasible`), never NaN:
//! - L_mt ≤ L_ts: the fiber would point backwards (cos α ≤ 0). OpenSim throws here for a compliant
//!   tendon unless the fiber pushes, and reports the backwards fiber for a rigid one; both refused.
//! - r(0) > 0, the path is too short: even with a slack tendon the fiber does not pull (it pushes
//!   below l̃_m = 0.2 when a f_L < −f_PE). OpenSim throws.
//! - r(5) < 0, the path is too long: the fiber pulls harder than 5 F_max. OpenSim throws.
//! - An unpennated fiber whose force at zero length exceeds the tendon's at the cut: r jumps
//!   from negative to positive where the fiber length reaches 0, no fiber length balances the
//!   tendon (OpenSim returns a fiber of length ≈ 0 pointing either way).
//!
//! A root exactly at an end (e.g. a = 0 with `ignore_passive_fiber_force`: r(f̃_T) = f̃_T) is
//! returned, where OpenSim's sign test `r(0) r(5) ≥ 0` throws.

use super::curves::DeGrooteCurves;
use super::muscle::LengthInfo;
use super::DeGrooteFregly2016Muscle;
use crate::mechanics::muscle::{
    bracketed_newton, check_inputs, EquilibriumStatus, FiberEquilibrium, MuscleError, RootFailure,
};

/// The solver stops when |r| ≤ this (normalized force: 1e-14 F_max) …
const RESIDUAL_TOLERANCE: f64 = 1e-14;
/// … or when the bracket on f̃_T is this narrow (a few ulps of the largest bracket end, 5) …
const BRACKET_TOLERANCE: f64 = 4.0 * f64::EPSILON * DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE;
/// … where the point is a root only if |r| ≤ this (the floating-point floor of r is ~1e-15; a
/// jump of r is far larger).
const JUMP_TOLERANCE: f64 = 1e-12;
const MAX_ITERATIONS: usize = 100;

impl DeGrooteFregly2016Muscle {
    /// Static equilibrium (fiber velocity 0) at activation `activation` ∈ [0, 1] and path length
    /// `mt_length` (m). See the module documentation for the cases without equilibrium.
    pub fn equilibrium(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<FiberEquilibrium, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        if mt_length <= self.tendon_slack_length {
            let reason = format!(
                "the path is no longer than tendon_slack_length {} m: the fiber would point backwards",
                self.tendon_slack_length
            );
            return Err(self.infeasible(activation, mt_length, reason));
        }
        if self.ignore_tendon_compliance {
            let length = self.length_info(mt_length, f64::NAN);
            return Ok(self.static_state(activation, mt_length, &length, None));
        }
        let normalized_tendon_force = self.solve_normalized_tendon_force(activation, mt_length)?;
        let length = self.length_info(mt_length, normalized_tendon_force);
        Ok(self.static_state(
            activation,
            mt_length,
            &length,
            Some(normalized_tendon_force),
        ))
    }

    /// OpenSim's `calcEquilibriumResidual` at path speed 0 and tendon-force derivative 0:
    /// f̃_T − f̃_M cos α (normalized force; positive when the tendon pulls harder than the fiber)
    /// at activation `activation`, path length `mt_length` (m) and normalized tendon force
    /// `normalized_tendon_force` (the tendon length of a rigid tendon stays L_ts). A fiber
    /// pointing backwards (L_m cos α ≤ 0) transmits nothing: r = f̃_T.
    pub fn calc_equilibrium_residual(
        &self,
        activation: f64,
        mt_length: f64,
        normalized_tendon_force: f64,
    ) -> f64 {
        self.residual(activation, mt_length, normalized_tendon_force)
            .0
    }

    /// (r, dr/df̃_T) for the Newton solve. With f̃_M^AT = f̃_M cos α and ' = d/dL_m:
    /// dr/df̃_T = 1 − d f̃_M^AT/d(L_m cos α) · d(L_m cos α)/df̃_T, where
    /// d(L_m cos α)/df̃_T = −L_ts / (df_T/dl̃_T) and
    /// d f̃_M^AT/d(L_m cos α) = f̃_M' cos² α + f̃_M sin² α / L_m.
    fn residual(
        &self,
        activation: f64,
        mt_length: f64,
        normalized_tendon_force: f64,
    ) -> (f64, f64) {
        let length = self.length_info(mt_length, normalized_tendon_force);
        if length.fiber_length_along_tendon <= 0.0 {
            return (normalized_tendon_force, 1.0);
        }
        let (fiber_force, fiber_stiffness) =
            self.static_normalized_fiber_force(activation, &length);
        let (cos, sin) = (length.cos_pennation_angle, length.sin_pennation_angle);
        let residual = normalized_tendon_force - fiber_force * cos;
        if self.ignore_tendon_compliance {
            return (residual, 1.0);
        }
        let along_tendon_stiffness =
            fiber_stiffness * cos * cos + fiber_force * sin * sin / length.fiber_length;
        let tendon_stiffness = self
            .curves
            .calc_tendon_force_multiplier_derivative(length.normalized_tendon_length);
        (
            residual,
            1.0 + along_tendon_stiffness * self.tendon_slack_length / tendon_stiffness,
        )
    }

    /// The static fiber force f̃_M = a f_L f_V(0) + f_PE (normalized) and its derivative with
    /// respect to the fiber length (1/m).
    fn static_normalized_fiber_force(&self, activation: f64, length: &LengthInfo) -> (f64, f64) {
        let curves = &self.curves;
        let l = length.normalized_fiber_length;
        let force_velocity = DeGrooteCurves::calc_force_velocity_multiplier(0.0);
        let force = activation * curves.calc_active_force_length_multiplier(l) * force_velocity
            + curves.calc_passive_force_multiplier(l);
        let derivative =
            activation * curves.calc_active_force_length_multiplier_derivative(l) * force_velocity
                + curves.calc_passive_force_multiplier_derivative(l);
        (force, derivative / self.optimal_fiber_length)
    }

    /// The upper end of the bracket on f̃_T: 5, or the tendon force at which the tendon fills
    /// the path (L_m cos α ≤ 0 there, moved up by ulps where rounding left it positive).
    fn upper_normalized_tendon_force(&self, mt_length: f64) -> f64 {
        let mut path_filling = self
            .curves
            .calc_tendon_force_multiplier(mt_length / self.tendon_slack_length);
        while path_filling < DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE
            && self
                .length_info(mt_length, path_filling)
                .fiber_length_along_tendon
                > 0.0
        {
            path_filling = path_filling.next_up();
        }
        path_filling.min(DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE)
    }

    /// f̃_T at equilibrium on [0, `upper_normalized_tendon_force`].
    fn solve_normalized_tendon_force(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        let upper = self.upper_normalized_tendon_force(mt_length);
        let residual = |force: f64| self.residual(activation, mt_length, force);
        match bracketed_newton(
            residual,
            DeGrooteCurves::MIN_NORMALIZED_TENDON_FORCE,
            upper,
            BRACKET_TOLERANCE,
            RESIDUAL_TOLERANCE,
            MAX_ITERATIONS,
        ) {
            Ok(root) if root.residual.abs() <= JUMP_TOLERANCE => Ok(root.x),
            Ok(root) => {
                let reason = format!(
                    "no fiber length balances the tendon: the force balance jumps by {:e} F_max where \
                     the unpennated fiber reaches zero length",
                    root.residual.abs()
                );
                Err(self.infeasible(activation, mt_length, reason))
            }
            Err(RootFailure::NoSignChange(at_slack, _)) if at_slack > 0.0 => {
                let reason = format!(
                    "the path is too short: with the tendon slack the fiber does not pull \
                     (fiber force along the tendon {:e} F_max)",
                    -at_slack
                );
                Err(self.infeasible(activation, mt_length, reason))
            }
            Err(RootFailure::NoSignChange(_, at_upper)) => {
                let reason = format!(
                    "the path is too long: at a tendon force of {upper} F_max the fiber still pulls \
                     {:e} F_max harder (OpenSim's bracket ends at 5 F_max)",
                    -at_upper
                );
                Err(self.infeasible(activation, mt_length, reason))
            }
            Err(RootFailure::NotFinite(force)) => {
                let reason = format!(
                    "the force balance is not finite at a normalized tendon force of {force}"
                );
                Err(self.infeasible(activation, mt_length, reason))
            }
            Err(RootFailure::NotConverged(best)) => Err(MuscleError::NotConverged {
                muscle: self.name.clone(),
                activation,
                mt_length,
                iterations: best.iterations,
                residual: best.residual * self.max_isometric_force,
            }),
        }
    }

    /// The muscle at zero fiber velocity in the length state `length`; the tendon force is
    /// F_max f̃_T for a compliant tendon, the fiber force along the tendon for a rigid one.
    fn static_state(
        &self,
        activation: f64,
        mt_length: f64,
        length: &LengthInfo,
        normalized_tendon_force: Option<f64>,
    ) -> FiberEquilibrium {
        let curves = &self.curves;
        let f_max = self.max_isometric_force;
        let active_force_length_multiplier =
            curves.calc_active_force_length_multiplier(length.normalized_fiber_length);
        let passive_force_multiplier =
            curves.calc_passive_force_multiplier(length.normalized_fiber_length);
        let force_velocity_multiplier = DeGrooteCurves::calc_force_velocity_multiplier(0.0);
        let active_fiber_force =
            f_max * (activation * active_force_length_multiplier * force_velocity_multiplier);
        let passive_fiber_force = f_max * passive_force_multiplier;
        let fiber_force = active_fiber_force + passive_fiber_force;
        let fiber_force_along_tendon = fiber_force * length.cos_pennation_angle;
        FiberEquilibrium {
            activation,
            mt_length,
            fiber_length: length.fiber_length,
            normalized_fiber_length: length.normalized_fiber_length,
            pennation_angle: length.sin_pennation_angle.asin(),
            cos_pennation_angle: length.cos_pennation_angle,
            fiber_length_along_tendon: length.fiber_length_along_tendon,
            tendon_length: length.tendon_length,
            tendon_strain: length.normalized_tendon_length - 1.0,
            tendon_force: normalized_tendon_force
                .map_or(fiber_force_along_tendon, |force| f_max * force),
            active_fiber_force,
            passive_fiber_force,
            fiber_force,
            fiber_force_along_tendon,
            active_force_length_multiplier,
            passive_force_multiplier,
            force_velocity_multiplier,
            normalized_fiber_velocity: 0.0,
            status: EquilibriumStatus::Converged,
        }
    }

    fn infeasible(&self, activation: f64, mt_length: f64, reason: String) -> MuscleError {
        MuscleError::Infeasible {
            muscle: self.name.clone(),
            activation,
            mt_length,
            reason,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn muscle(pennation_angle_at_optimal: f64) -> DeGrooteFregly2016Muscle {
        super::super::test_muscle(pennation_angle_at_optimal, 0.0)
    }

    #[test]
    fn the_newton_slope_matches_central_differences() {
        let h = 1e-7;
        for pennation in [0.0, 0.4] {
            let muscle = muscle(pennation);
            for (activation, mt_length, force) in [
                (0.1, 0.3, 0.05),
                (0.7, 0.36, 0.4),
                (1.0, 0.42, 1.2),
                (0.4, 0.45, 3.0),
            ] {
                let (_, slope) = muscle.residual(activation, mt_length, force);
                let numeric = (muscle.calc_equilibrium_residual(activation, mt_length, force + h)
                    - muscle.calc_equilibrium_residual(activation, mt_length, force - h))
                    / (2.0 * h);
                assert!(
                    (slope - numeric).abs() < 1e-6 * (1.0 + slope.abs()),
                    "{slope} vs {numeric}"
                );
            }
        }
    }

    #[test]
    fn the_bracket_ends_where_the_tendon_fills_the_path() {
        for pennation in [0.0, 0.4] {
            let muscle = muscle(pennation);
            for mt_length in [0.2500001, 0.255, 0.262] {
                let upper = muscle.upper_normalized_tendon_force(mt_length);
                assert!(
                    muscle
                        .length_info(mt_length, upper)
                        .fiber_length_along_tendon
                        <= 0.0
                );
                let filling = muscle.curves.calc_tendon_force_multiplier(mt_length / 0.25);
                assert!(
                    (upper - filling).abs() <= 1e-14 * filling,
                    "{upper} vs {filling}"
                );
                assert_eq!(
                    muscle.calc_equilibrium_residual(0.5, mt_length, upper),
                    upper
                );
            }
            assert_eq!(
                muscle.upper_normalized_tendon_force(0.5),
                DeGrooteCurves::MAX_NORMALIZED_TENDON_FORCE
            );
        }
    }
}
