//! `Thelen2003Muscle`: architecture, fixed-width pennation and the Thelen curves of one muscle;
//! its static equilibrium and OpenSim's fiber-length state derivative.
//!
//! Sign conventions: lengths in m, forces in N (tension positive), fiber velocity positive when
//! lengthening. At a fiber length L_m and path length L_mt, the force residual is
//! r(L_m) = F_m cos α − F_t = F_max [(a f_L + f_PE) cos α − f_SE], positive when the fiber pulls
//! harder than the tendon.
//!
//! **The minimum-fiber-length clamp (OpenSim 4.6 behaviour, reproduced).** OpenSim's
//! `Thelen2003Muscle::getMinimumFiberLength` is the pennation model's minimum only
//! (h / sin α_max; 0 for an unpennated muscle — the header's "maximum of two values" is not what
//! the code does). When r(L_min) > 0 no fiber length balances the tendon: the fiber would have to
//! shorten past its minimum. `initMuscleState` then stops at L_min (`Warning_FiberAtLowerBound`),
//! and `calcFiberVelocityInfo` finds the fiber state ≤ L_min with ṽ ≤ 0, so
//! `isFiberStateClamped` holds: f_V = 1, ṽ = 0, and `calcMuscleDynamicsInfo` reports zero active
//! and total fiber force — while the tendon force is still f_SE(L_mt − L_min cos α_max) F_max and
//! the passive force f_PE(L_min) F_max. If the path is long enough to stretch the tendon at
//! L_min (gait2392 `semimem_r` at `knee_h00_k-080`, a ≥ 0.5: 3.81 N), tendon and fiber forces
//! differ; otherwise the tendon is slack and every force is 0.
//! [`Thelen2003Muscle::equilibrium`] returns exactly this state, with
//! [`EquilibriumStatus::ClampedAtMinimumFiberLength`].

use super::ThelenCurves;
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;
use crate::mechanics::muscle::{
    bracketed_newton_from, check_inputs, BracketEnd, EquilibriumStatus, FiberEquilibrium, FixedWidthPennation,
    MuscleError, MuscleState, Root, RootFailure,
};
use crate::mechanics::muscle::state::PennatedMotion;
use crate::model::{MuscleSpec, ThelenSpec};

/// The equilibrium solver stops when |r| ≤ this (N) …
const FORCE_TOLERANCE: f64 = 1e-10;
/// … or when the bracket is this many machine epsilons of the fiber length wide (the
/// floating-point limit: then |r| ≤ |dr/dL_m| · 4 ε L_m, below 1e-9 N for every gait2392 and
/// arm26 muscle).
const BRACKET_EPSILONS: f64 = 4.0;
const MAX_ITERATIONS: usize = 200;

/// One `Thelen2003Muscle` (OpenSim 4.6), validated as OpenSim does when the model is finalized.
#[derive(Debug, Clone)]
pub struct Thelen2003Muscle {
    name: String,
    /// F_max, N.
    max_isometric_force: f64,
    /// L_opt, m.
    optimal_fiber_length: f64,
    /// L_ts, m.
    tendon_slack_length: f64,
    /// v_max, L_opt per second.
    max_contraction_velocity: f64,
    /// Activations below this are raised to it (`clampActivation`).
    minimum_activation: f64,
    /// τ_a, s.
    activation_time_constant: f64,
    /// τ_d, s.
    deactivation_time_constant: f64,
    pennation: FixedWidthPennation,
    curves: ThelenCurves,
}

/// The length-level quantities at one fiber length (OpenSim's `MuscleLengthInfo` plus f_SE).
#[derive(Debug, Clone, Copy)]
struct LengthInfo {
    fiber_length: f64,
    normalized_fiber_length: f64,
    pennation_angle: f64,
    cos_pennation_angle: f64,
    tendon_length: f64,
    active_force_length: f64,
    passive_force_length: f64,
    tendon_force_length: f64,
}

impl Thelen2003Muscle {
    /// The muscle `name` with architecture `spec` and Thelen parameters `class`; an
    /// [`MuscleError::InvalidParameter`] for every value OpenSim 4.6 refuses (see
    /// [`ThelenCurves::new`], the pennation and activation models, and the two flags
    /// `ActivationFiberLengthMuscle` does not implement).
    pub fn new(name: &str, spec: &MuscleSpec, class: &ThelenSpec) -> Result<Self, MuscleError> {
        let curves = ThelenCurves::new(name, class)?;
        check_architecture(name, spec)?;
        check_class(name, class)?;
        Ok(Thelen2003Muscle {
            name: name.into(),
            max_isometric_force: spec.max_isometric_force,
            optimal_fiber_length: spec.optimal_fiber_length,
            tendon_slack_length: spec.tendon_slack_length,
            max_contraction_velocity: spec.max_contraction_velocity,
            minimum_activation: class.minimum_activation,
            activation_time_constant: class.activation_time_constant,
            deactivation_time_constant: class.deactivation_time_constant,
            pennation: FixedWidthPennation::new(
                spec.optimal_fiber_length,
                spec.pennation_angle_at_optimal,
                class.maximum_pennation_angle,
            ),
            curves,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// F_max, N.
    pub fn max_isometric_force(&self) -> f64 {
        self.max_isometric_force
    }

    /// L_opt, m.
    pub fn optimal_fiber_length(&self) -> f64 {
        self.optimal_fiber_length
    }

    /// L_ts, m.
    pub fn tendon_slack_length(&self) -> f64 {
        self.tendon_slack_length
    }

    /// v_max, optimal fiber lengths per second.
    pub fn max_contraction_velocity(&self) -> f64 {
        self.max_contraction_velocity
    }

    pub fn curves(&self) -> &ThelenCurves {
        &self.curves
    }

    /// τ_a (`activation_time_constant`), s: the time constant of rising activation.
    pub fn activation_time_constant(&self) -> f64 {
        self.activation_time_constant
    }

    /// τ_d (`deactivation_time_constant`), s: the time constant of falling activation.
    pub fn deactivation_time_constant(&self) -> f64 {
        self.deactivation_time_constant
    }

    pub fn pennation(&self) -> &FixedWidthPennation {
        &self.pennation
    }

    /// `getMinimumFiberLength()`, m: the pennation model's minimum.
    pub fn minimum_fiber_length(&self) -> f64 {
        self.pennation.minimum_fiber_length
    }

    /// The activation OpenSim computes with: `activation` raised to `minimum_activation` and
    /// capped at 1 (`clampActivation`).
    pub fn clamp_activation(&self, activation: f64) -> f64 {
        activation.clamp(self.minimum_activation, 1.0)
    }

    /// r(L_m) = F_m cos α − F_t in N with f_V = 1, at the clamped activation, fiber length
    /// `fiber_length` (m, raised to the minimum as OpenSim's `clampFiberLength` does) and path
    /// length `mt_length` (m).
    pub fn static_force_residual(&self, activation: f64, fiber_length: f64, mt_length: f64) -> f64 {
        self.force_residual(self.clamp_activation(activation), fiber_length, mt_length)
            .0
    }

    /// The static equilibrium (fiber velocity 0, f_V = 1) at activation `activation` ∈ [0, 1]
    /// (clamped as [`Thelen2003Muscle::clamp_activation`]) and path length `mt_length` (m).
    ///
    /// The fiber length solves r(L_m) = 0 on [L_min, L_mt − L_ts + h] by bracketed Newton
    /// (r ≤ 0 at the lower end, else the clamped state below; r ≥ 0 at the upper end, where the
    /// tendon is slack). |r| ≤ 1e-10 N, or the floating-point limit |dr/dL_m| · 4 ε L_m when that
    /// is larger. Along the bracket r changes sign once for physiological parameters: the
    /// tendon stiffness outweighs the negative slope of the descending limb.
    ///
    /// OpenSim's `equilibrateMuscles` stops at |r| < 1e-8 F_max with a small fiber velocity left
    /// (f_V − 1 up to ~6e-7), so its states differ from this exact solution by that much.
    /// When r(L_min) > 0 the result is OpenSim's clamped state (see the module documentation),
    /// status [`EquilibriumStatus::ClampedAtMinimumFiberLength`].
    pub fn equilibrium(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<FiberEquilibrium, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        let a = self.clamp_activation(activation);
        let shortest = self.minimum_fiber_length();
        let residual = |fiber_length| self.force_residual(a, fiber_length, mt_length);
        let lo = BracketEnd { x: shortest, residual: residual(shortest).0 };
        if lo.residual > 0.0 {
            let info = self.length_info(shortest, mt_length);
            return Ok(self.report(
                a,
                mt_length,
                &info,
                EquilibriumStatus::ClampedAtMinimumFiberLength,
            ));
        }
        let longest = (mt_length - self.tendon_slack_length).max(shortest)
            + self.pennation.parallelogram_height;
        let x_tolerance = BRACKET_EPSILONS * f64::EPSILON * longest;
        let hi = BracketEnd { x: longest, residual: residual(longest).0 };
        let root = bracketed_newton_from(
            residual,
            0.5 * (shortest + longest),
            lo,
            hi,
            x_tolerance,
            FORCE_TOLERANCE,
            MAX_ITERATIONS,
        )
        .map_err(|failure| self.solver_error(activation, mt_length, failure))?;
        let info = self.length_info(root.x, mt_length);
        Ok(self.report(a, mt_length, &info, EquilibriumStatus::Converged))
    }

    /// dL_m/dt in m/s, the fiber-length state derivative of OpenSim's forward simulation
    /// (`calcFiberVelocityInfo`), at activation `activation` ∈ [0, 1], fiber length
    /// `fiber_length` (m, ≥ 0) and path length `mt_length` (m): [`Thelen2003Muscle::state`]'s.
    /// Independent of the path lengthening speed.
    pub fn fiber_velocity(
        &self,
        activation: f64,
        fiber_length: f64,
        mt_length: f64,
    ) -> Result<f64, MuscleError> {
        Ok(self.state(activation, fiber_length, mt_length, 0.0)?.fiber_velocity)
    }

    /// The muscle at activation `activation` ∈ [0, 1] (clamped), fiber-length state
    /// `fiber_length` (m, ≥ 0) on a path of length `mt_length` (m) lengthening at
    /// `lengthening_speed` (m/s), as OpenSim reports it (`calcFiberVelocityInfo`,
    /// `calcMuscleDynamicsInfo`).
    ///
    /// The fiber develops the force the tendon carries, a f_L f_V = f_SE / cos α − f_PE
    /// (normalized), and moves at Thelen's ṽ(a f_L f_V) · v_max · L_opt. Fiber lengths below the
    /// minimum are evaluated at the minimum; there (state ≤ L_min) a shortening fiber is held
    /// (`isFiberStateClamped`): at rest, no active or total fiber force, the passive force
    /// still reported.
    pub fn state(&self, activation: f64, fiber_length: f64, mt_length: f64, lengthening_speed: f64) -> Result<MuscleState, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        if !(fiber_length >= 0.0 && fiber_length.is_finite()) {
            return Err(MuscleError::invalid_input(&self.name, "fiber length", fiber_length, "a non-negative length in m"));
        }
        let a = self.clamp_activation(activation);
        let info = self.length_info(fiber_length, mt_length);
        let active_force = info.tendon_force_length / info.cos_pennation_angle - info.passive_force_length;
        let normalized = self.curves.normalized_fiber_velocity(a, info.active_force_length, active_force);
        if !normalized.is_finite() {
            let reason = format!("the fiber velocity is not finite (active force–length multiplier {})", info.active_force_length);
            return Err(MuscleError::Infeasible { muscle: self.name.clone(), activation, mt_length, reason });
        }
        let fmax = self.max_isometric_force;
        if fiber_length <= self.minimum_fiber_length() && normalized <= 0.0 {
            let report = self.report(a, mt_length, &info, EquilibriumStatus::ClampedAtMinimumFiberLength);
            return Ok(PennatedMotion::clamped(lengthening_speed).state(report, lengthening_speed, 0.0, report.passive_fiber_force));
        }
        let force_velocity = active_force / (a * info.active_force_length);
        let mut report = self.report(a, mt_length, &info, EquilibriumStatus::Converged);
        report.active_fiber_force = a * info.active_force_length * force_velocity * fmax;
        report.fiber_force = (a * info.active_force_length * force_velocity + info.passive_force_length) * fmax;
        report.fiber_force_along_tendon = report.fiber_force * info.cos_pennation_angle;
        report.force_velocity_multiplier = force_velocity;
        report.normalized_fiber_velocity = normalized;
        let velocity = normalized * self.max_contraction_velocity * self.optimal_fiber_length;
        let motion = PennatedMotion::new(info.fiber_length, info.pennation_angle, velocity, lengthening_speed);
        Ok(motion.state(report, lengthening_speed, report.active_fiber_force, report.passive_fiber_force))
    }

    /// F_t (N) with the fiber at `fiber_length` (m, raised to the minimum) on a path of
    /// length `mt_length` (m).
    pub fn tendon_force(&self, fiber_length: f64, mt_length: f64) -> f64 {
        self.length_info(fiber_length, mt_length).tendon_force_length * self.max_isometric_force
    }

    /// OpenSim's `calcMuscleLengthInfo` at fiber length `fiber_length` (clamped to the minimum).
    fn length_info(&self, fiber_length: f64, mt_length: f64) -> LengthInfo {
        let fiber_length = fiber_length.max(self.minimum_fiber_length());
        let normalized_fiber_length = fiber_length / self.optimal_fiber_length;
        let pennation_angle = self.pennation.pennation_angle(fiber_length);
        let cos_pennation_angle = pennation_angle.cos();
        let tendon_length = mt_length - fiber_length * cos_pennation_angle;
        LengthInfo {
            fiber_length,
            normalized_fiber_length,
            pennation_angle,
            cos_pennation_angle,
            tendon_length,
            active_force_length: self.curves.active_force_length(normalized_fiber_length),
            passive_force_length: self.curves.passive_force_length(normalized_fiber_length),
            tendon_force_length: self
                .curves
                .tendon_force_length(tendon_length / self.tendon_slack_length),
        }
    }

    /// (r, dr/dL_m) in N and N/m at activation `a` (already clamped), f_V = 1.
    fn force_residual(&self, a: f64, fiber_length: f64, mt_length: f64) -> (f64, f64) {
        let info = self.length_info(fiber_length, mt_length);
        let (l, cos) = (info.fiber_length, info.cos_pennation_angle);
        let sin = info.pennation_angle.sin();
        let d_pennation = self.d_pennation_d_fiber_length(&info);
        let fiber_force =
            (a * info.active_force_length + info.passive_force_length) * self.max_isometric_force;
        let lce_n = info.normalized_fiber_length;
        let d_fiber_force = (a * self.curves.active_force_length_derivative(lce_n)
            + self.curves.passive_force_length_derivative(lce_n))
            * self.max_isometric_force
            / self.optimal_fiber_length;
        let d_fiber_force_along_tendon = d_fiber_force * cos - fiber_force * sin * d_pennation;
        let d_tendon_length = l * sin * d_pennation - cos;
        let tendon_stiffness = self
            .curves
            .tendon_force_length_derivative(info.tendon_length / self.tendon_slack_length)
            * self.max_isometric_force
            / self.tendon_slack_length;
        let residual = fiber_force * cos - info.tendon_force_length * self.max_isometric_force;
        (
            residual,
            d_fiber_force_along_tendon - tendon_stiffness * d_tendon_length,
        )
    }

    /// dα/dL_m in rad/m: OpenSim's −(h/L_m²)/√(1 − (h/L_m)²) where α follows the fiber, 0 where
    /// it is held at α_max (at and below the minimum length, or everywhere when α_max = 0 — there
    /// the formula would take the root of a negative number).
    fn d_pennation_d_fiber_length(&self, info: &LengthInfo) -> f64 {
        if info.pennation_angle >= self.pennation.maximum_pennation_angle {
            return 0.0;
        }
        self.pennation.d_pennation_d_fiber_length(info.fiber_length)
    }

    /// The equilibrium record of `info` at f_V = 1 and zero velocity. A state clamped at the
    /// minimum fiber length reports zero active and total fiber force, as OpenSim does.
    fn report(
        &self,
        a: f64,
        mt_length: f64,
        info: &LengthInfo,
        status: EquilibriumStatus,
    ) -> FiberEquilibrium {
        let fmax = self.max_isometric_force;
        let clamped = status == EquilibriumStatus::ClampedAtMinimumFiberLength;
        let (active_fiber_force, fiber_force) = if clamped {
            (0.0, 0.0)
        } else {
            (
                (a * info.active_force_length) * fmax,
                (a * info.active_force_length + info.passive_force_length) * fmax,
            )
        };
        let normalized_tendon_length = info.tendon_length / self.tendon_slack_length;
        FiberEquilibrium {
            activation: a,
            mt_length,
            fiber_length: info.fiber_length,
            normalized_fiber_length: info.normalized_fiber_length,
            pennation_angle: info.pennation_angle,
            cos_pennation_angle: info.cos_pennation_angle,
            fiber_length_along_tendon: info.fiber_length * info.cos_pennation_angle,
            tendon_length: info.tendon_length,
            tendon_strain: normalized_tendon_length - 1.0,
            tendon_force: info.tendon_force_length * fmax,
            active_fiber_force,
            passive_fiber_force: info.passive_force_length * fmax,
            fiber_force,
            fiber_force_along_tendon: fiber_force * info.cos_pennation_angle,
            active_force_length_multiplier: info.active_force_length,
            passive_force_multiplier: info.passive_force_length,
            force_velocity_multiplier: 1.0,
            normalized_fiber_velocity: 0.0,
            status,
        }
    }

    fn solver_error(&self, activation: f64, mt_length: f64, failure: RootFailure) -> MuscleError {
        let muscle = self.name.clone();
        match failure {
            RootFailure::NotConverged(Root { residual, .. }) => MuscleError::NotConverged {
                muscle,
                activation,
                mt_length,
                iterations: MAX_ITERATIONS,
                residual,
            },
            RootFailure::NoSignChange(lo, hi) => {
                let reason =
                    format!("the force residual does not change sign on the fiber-length bracket ({lo} N, {hi} N)");
                MuscleError::Infeasible {
                    muscle,
                    activation,
                    mt_length,
                    reason,
                }
            }
            RootFailure::NotFinite(x) => {
                let reason = format!("the force residual is not finite at fiber length {x} m");
                MuscleError::Infeasible {
                    muscle,
                    activation,
                    mt_length,
                    reason,
                }
            }
        }
    }
}

/// The architecture checks of `MuscleSpec::read` (repeated: a spec may be built in code) and of
/// the pennation model (`MuscleFixedWidthPennationModel::extendFinalizeFromProperties`).
fn check_architecture(name: &str, spec: &MuscleSpec) -> Result<(), MuscleError> {
    let positive = [
        ("max_isometric_force", spec.max_isometric_force),
        ("optimal_fiber_length", spec.optimal_fiber_length),
        ("tendon_slack_length", spec.tendon_slack_length),
        ("max_contraction_velocity", spec.max_contraction_velocity),
    ];
    MuscleError::require_positive(name, &positive, "a positive number")?;
    let alpha = spec.pennation_angle_at_optimal;
    if !(0.0..=std::f64::consts::FRAC_PI_2 - SIGNIFICANT_REAL).contains(&alpha) {
        return Err(MuscleError::invalid_parameter(
            name,
            "pennation_angle_at_optimal",
            alpha,
            "an angle in [0, π/2) rad",
        ));
    }
    let flags = [
        ("ignore_tendon_compliance", spec.ignore_tendon_compliance),
        (
            "ignore_activation_dynamics",
            spec.ignore_activation_dynamics,
        ),
    ];
    for (property, set) in flags {
        if set {
            let expected = "false (Thelen2003Muscle does not implement the flag; OpenSim throws)";
            return Err(MuscleError::invalid_parameter(
                name, property, 1.0, expected,
            ));
        }
    }
    Ok(())
}

/// The pennation and activation-model checks OpenSim applies to the class properties.
fn check_class(name: &str, class: &ThelenSpec) -> Result<(), MuscleError> {
    let maximum = class.maximum_pennation_angle;
    if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&maximum) {
        return Err(MuscleError::invalid_parameter(
            name,
            "maximum_pennation_angle",
            maximum,
            "an angle in [0, π/2] rad",
        ));
    }
    let minimum = class.minimum_activation;
    if !(0.01..=1.0 - SIGNIFICANT_REAL).contains(&minimum) {
        return Err(MuscleError::invalid_parameter(
            name,
            "minimum_activation",
            minimum,
            "a number in [0.01, 1)",
        ));
    }
    // `MuscleFirstOrderActivationDynamicModel` refuses time constants below SignificantReal.
    let time_constants = [("activation_time_constant", class.activation_time_constant), ("deactivation_time_constant", class.deactivation_time_constant)];
    for (property, value) in time_constants {
        if !(value >= SIGNIFICANT_REAL && value.is_finite()) {
            return Err(MuscleError::invalid_parameter(name, property, value, "a positive time in s"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::curves::tests::{central_difference, gait2392_spec};
    use super::*;
    use crate::model::MuscleModelSpec;

    /// gait2392's `semimem_r` architecture with pennation `alpha` and maximum `alpha_max` (rad).
    fn semimem(alpha: f64, alpha_max: f64) -> Thelen2003Muscle {
        let class = ThelenSpec {
            maximum_pennation_angle: alpha_max,
            ..gait2392_spec()
        };
        let spec = MuscleSpec {
            max_isometric_force: 1288.0,
            optimal_fiber_length: 0.08,
            tendon_slack_length: 0.359,
            pennation_angle_at_optimal: alpha,
            max_contraction_velocity: 10.0,
            ignore_tendon_compliance: false,
            ignore_activation_dynamics: false,
            model: MuscleModelSpec::Thelen2003(class.clone()),
        };
        Thelen2003Muscle::new("semimem_r", &spec, &class).unwrap()
    }

    /// dr/dL_m against central differences (h = 1e-9 m, agreement 1e-5 relative to
    /// max(1 N/m, |dr/dL_m|)), away from the kinks of f_PE (L_opt) and f_SE (slack tendon).
    #[test]
    fn residual_derivative_matches_central_differences() {
        let muscle = semimem(0.2617993878, 0.1f64.acos());
        let h = 1e-9;
        for a in [0.01, 0.5, 1.0] {
            for mt_length in [0.40, 0.44, 0.48] {
                for i in 0..40 {
                    let fiber_length = muscle.minimum_fiber_length() + 1e-4 + 0.004 * f64::from(i);
                    let tendon = muscle.length_info(fiber_length, mt_length).tendon_length;
                    if (fiber_length - 0.08).abs() < 1e-6 || (tendon - 0.359).abs() < 1e-6 {
                        continue;
                    }
                    let numeric = central_difference(
                        |l| muscle.force_residual(a, l, mt_length).0,
                        fiber_length,
                        h,
                    );
                    let analytic = muscle.force_residual(a, fiber_length, mt_length).1;
                    let tolerance = 1e-5 * analytic.abs().max(1.0);
                    assert!(
                        (numeric - analytic).abs() <= tolerance,
                        "a {a} L_mt {mt_length} L_m {fiber_length}: {analytic} vs {numeric}"
                    );
                }
            }
        }
    }

    /// α_max = 0 holds a pennated fiber straight (α = 0 at every length): OpenSim's dα/dL_m
    /// formula does not apply there, and the solver still converges.
    #[test]
    fn a_zero_maximum_pennation_angle_keeps_the_fiber_straight() {
        let muscle = semimem(0.26, 0.0);
        let e = muscle.equilibrium(0.5, 0.44).unwrap();
        assert_eq!(
            (e.status, e.pennation_angle),
            (EquilibriumStatus::Converged, 0.0)
        );
        assert!(
            muscle
                .static_force_residual(0.5, e.fiber_length, 0.44)
                .abs()
                <= 1e-9
        );
        assert_eq!(muscle.minimum_fiber_length(), 0.01 * 0.08);
    }

    /// Unpennated: the minimum fiber length is 0 (OpenSim: h / sin α_max with h = 0).
    #[test]
    fn an_unpennated_slack_muscle_rests_at_zero_fiber_length() {
        let muscle = semimem(0.0, 0.1f64.acos());
        assert_eq!(muscle.minimum_fiber_length(), 0.0);
        let e = muscle.equilibrium(1.0, 0.3).unwrap();
        assert_eq!(
            (e.status, e.fiber_length, e.tendon_force),
            (EquilibriumStatus::ClampedAtMinimumFiberLength, 0.0, 0.0)
        );
        let e = muscle.equilibrium(1.0, 0.44).unwrap();
        assert_eq!(e.status, EquilibriumStatus::Converged);
        assert!((e.tendon_force - e.fiber_force).abs() <= 1e-9);
    }

    #[test]
    fn activation_below_the_minimum_is_raised_to_it() {
        let muscle = semimem(0.26, 0.1f64.acos());
        let zero = muscle.equilibrium(0.0, 0.44).unwrap();
        assert_eq!(zero, muscle.equilibrium(0.01, 0.44).unwrap());
        assert_eq!(zero.activation, 0.01);
        assert_eq!(
            muscle.fiber_velocity(0.0, 0.07, 0.44),
            muscle.fiber_velocity(0.01, 0.07, 0.44)
        );
    }
}
