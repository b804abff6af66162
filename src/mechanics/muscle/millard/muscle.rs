//! The Millard 2012 equilibrium muscle: OpenSim's parameter adjustments at finalisation
//! (damped vs classic Hill model), the static equilibrium between fiber and tendon, OpenSim's
//! `equilibrateMuscles` iteration reproduced step by step, and the fiber velocity of forward
//! simulation.

use super::curves::{self, CurveError};
use super::smooth_function::SmoothSegmentedFunction;
use crate::mechanics::muscle::pennation::{FixedWidthPennation, SIGNIFICANT_REAL};
use crate::mechanics::muscle::root::newton_between_predicting;
use crate::mechanics::muscle::{
    bracketed_newton_from, check_inputs, BracketEnd, EquilibriumStatus, FiberEquilibrium, MuscleError, RootFailure,
};
use crate::model::{ForceVelocityCurveSpec, MillardSpec, MuscleSpec};

/// Below this `fiber_damping` OpenSim uses the classic (undamped) Hill model.
const MIN_NONZERO_DAMPING_COEFFICIENT: f64 = 0.001;
/// Static-equilibrium force tolerance, N. The curves' x → u inversion stops at |Δx| ≤ 100 ε,
/// which puts a noise floor of ~F_max·k_T·2e-14 (≤ 5e-10 N for gait2392) on the balance.
const FORCE_TOLERANCE: f64 = 5e-10;
/// Largest change of the normalised fiber or tendon length over which the state at the root is
/// continued along the curves' slopes instead of evaluated: the second-order terms, f″ Δ²/2 ≤
/// 3e-15 for the default Millard curves (|f″| ≤ 5800, the tendon's toe), stay below the curves'
/// own resolution (their x → u inversion stops at |Δx| ≤ 100 ε: f is known to |f′| · 2e-14).
const CONTINUATION_LIMIT: f64 = 1e-9;

/// The five curves one Millard muscle evaluates.
#[derive(Debug, Clone)]
pub struct MillardCurves {
    /// Normalised fiber length → active force multiplier f_L.
    pub active_force_length: SmoothSegmentedFunction,
    /// Normalised fiber velocity → multiplier f_V.
    pub force_velocity: SmoothSegmentedFunction,
    /// f_V → normalised fiber velocity (end slopes ½ of the near-v_max slopes, as OpenSim).
    pub force_velocity_inverse: SmoothSegmentedFunction,
    /// Normalised fiber length → passive force multiplier f_PE.
    pub fiber_force_length: SmoothSegmentedFunction,
    /// Normalised tendon length → normalised tendon force f_T.
    pub tendon_force_length: SmoothSegmentedFunction,
    /// f_T → normalised tendon length: the equilibrium's first guess.
    pub tendon_length_at_force: SmoothSegmentedFunction,
}

/// A Millard 2012 muscle with its finalised parameters.
#[derive(Debug, Clone)]
pub struct Millard2012Muscle {
    pub name: String,
    /// F_max, N.
    pub max_isometric_force: f64,
    /// L_opt, m.
    pub optimal_fiber_length: f64,
    /// L_ts, m.
    pub tendon_slack_length: f64,
    /// v_max, L_opt/s.
    pub max_contraction_velocity: f64,
    /// β, 0 for the classic Hill model.
    pub fiber_damping: f64,
    pub minimum_activation: f64,
    pub ignore_tendon_compliance: bool,
    /// The pennation model's limit, rad.
    pub maximum_pennation_angle: f64,
    /// f_L's shortest active normalised length.
    pub min_norm_active_fiber_length: f64,
    pub pennation: FixedWidthPennation,
    /// max(f_L's minimum active length · L_opt, the pennation model's minimum), m.
    pub minimum_fiber_length: f64,
    pub curves: MillardCurves,
    /// f_V(0), the force–velocity multiplier of a fiber at rest.
    isometric_force_velocity: f64,
    /// The fiber part of every position at the minimum fiber length.
    shortest_fiber: Fiber,
}

/// Fiber quantities at one fiber length, whatever the path (`positionFunc` and
/// `multipliersFunc`, fiber part).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Fiber {
    pub(super) length: f64,
    pub(super) cos_alpha: f64,
    pub(super) sin_alpha: f64,
    pub(super) norm_length: f64,
    pub(super) active_force_length: f64,
    pub(super) fiber_force_length: f64,
    /// Slopes of the two fiber curves at the normalised length.
    pub(super) d_active_force_length: f64,
    pub(super) d_fiber_force_length: f64,
}

/// Fiber and tendon at one fiber length and path length (`positionFunc` + `multipliersFunc`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Position {
    pub(super) fiber: Fiber,
    pub(super) tendon_length: f64,
    pub(super) norm_tendon_length: f64,
    pub(super) tendon_force_length: f64,
    pub(super) d_tendon_force_length: f64,
}

impl Millard2012Muscle {
    pub fn new(name: &str, spec: &MuscleSpec, class: &MillardSpec) -> Result<Self, MuscleError> {
        check_pennation(name, spec.pennation_angle_at_optimal, class.maximum_pennation_angle)?;
        let damped = class.fiber_damping >= MIN_NONZERO_DAMPING_COEFFICIENT;
        let finalised = finalise(name, spec, class, damped)?;
        let curves = build_curves(name, class, &finalised)?;
        let isometric_force_velocity = curves.force_velocity.value(0.0);
        let mut muscle = Millard2012Muscle {
            name: name.to_string(),
            max_isometric_force: spec.max_isometric_force,
            optimal_fiber_length: spec.optimal_fiber_length,
            tendon_slack_length: spec.tendon_slack_length,
            max_contraction_velocity: spec.max_contraction_velocity,
            fiber_damping: if damped { class.fiber_damping } else { 0.0 },
            minimum_activation: finalised.minimum_activation,
            ignore_tendon_compliance: spec.ignore_tendon_compliance,
            maximum_pennation_angle: class.maximum_pennation_angle,
            min_norm_active_fiber_length: class.active_force_length.min_norm_active_fiber_length,
            pennation: FixedWidthPennation::new(1.0, 0.0, class.maximum_pennation_angle),
            minimum_fiber_length: 0.0,
            curves,
            isometric_force_velocity,
            shortest_fiber: Fiber::default(),
        };
        muscle.set_fiber_geometry(spec.optimal_fiber_length, spec.pennation_angle_at_optimal)?;
        Ok(muscle)
    }

    /// Sets L_opt (m) and α_opt (rad) and what derives from them (pennation width, minimum fiber
    /// length), as a rebuild from the changed properties would — the curves do not depend on
    /// them — without rebuilding the curves.
    pub fn set_fiber_geometry(&mut self, optimal_fiber_length: f64, pennation_angle_at_optimal: f64) -> Result<(), MuscleError> {
        check_pennation(&self.name, pennation_angle_at_optimal, self.maximum_pennation_angle)?;
        let pennation = FixedWidthPennation::new(optimal_fiber_length, pennation_angle_at_optimal, self.maximum_pennation_angle);
        let minimum_active = self.min_norm_active_fiber_length * optimal_fiber_length;
        self.minimum_fiber_length = SIGNIFICANT_REAL.max(minimum_active.max(pennation.minimum_fiber_length));
        self.optimal_fiber_length = optimal_fiber_length;
        self.pennation = pennation;
        self.shortest_fiber = self.fiber(self.minimum_fiber_length);
        Ok(())
    }

    /// Pennation and fiber curve values at fiber length `fiber_length` (m).
    fn fiber(&self, fiber_length: f64) -> Fiber {
        let (sin_alpha, cos_alpha) = self.pennation.sin_cos(fiber_length);
        let norm_length = fiber_length / self.optimal_fiber_length;
        let (active_force_length, d_active_force_length) = self.curves.active_force_length.value_and_derivative(norm_length);
        let (fiber_force_length, d_fiber_force_length) = self.curves.fiber_force_length.value_and_derivative(norm_length);
        Fiber {
            length: fiber_length,
            cos_alpha,
            sin_alpha,
            norm_length,
            active_force_length,
            fiber_force_length,
            d_active_force_length,
            d_fiber_force_length,
        }
    }

    /// Activation as the muscle's dynamics see it: clamped to [minimum_activation, 1].
    pub fn clamp_activation(&self, activation: f64) -> f64 {
        activation.clamp(self.minimum_activation, 1.0)
    }

    /// F_t (N) with the fiber at `fiber_length` (m, raised to the minimum) on a path of
    /// length `mt_length` (m).
    pub fn tendon_force(&self, fiber_length: f64, mt_length: f64) -> f64 {
        self.position(fiber_length.max(self.minimum_fiber_length), mt_length).tendon_force_length * self.max_isometric_force
    }

    /// `fiber` with the tendon that fills path length `mt_length`.
    fn on_path(&self, fiber: Fiber, mt_length: f64) -> Position {
        let tendon_length = mt_length - fiber.length * fiber.cos_alpha;
        let norm_tendon_length = tendon_length / self.tendon_slack_length;
        let (tendon_force_length, d_tendon_force_length) =
            self.curves.tendon_force_length.value_and_derivative(norm_tendon_length);
        Position { fiber, tendon_length, norm_tendon_length, tendon_force_length, d_tendon_force_length }
    }

    /// Geometry and curve values at fiber length `fiber_length` for path length `mt_length`;
    /// the minimum fiber length's fiber part is computed once, at construction.
    pub(super) fn position(&self, fiber_length: f64, mt_length: f64) -> Position {
        let fiber = if fiber_length == self.minimum_fiber_length { self.shortest_fiber } else { self.fiber(fiber_length) };
        self.on_path(fiber, mt_length)
    }

    /// The position at fiber length `fiber_length` (m) for path length `mt_length` (m), continued
    /// from the evaluated position `from` (a predicted last Newton step away): geometry exact,
    /// curve values along their slopes; `None` when the normalised fiber or tendon length
    /// changes by more than CONTINUATION_LIMIT.
    fn position_continued(&self, from: &Position, fiber_length: f64, mt_length: f64) -> Option<Position> {
        let (sin_alpha, cos_alpha) = self.pennation.sin_cos(fiber_length);
        let norm_length = fiber_length / self.optimal_fiber_length;
        let tendon_length = mt_length - fiber_length * cos_alpha;
        let norm_tendon_length = tendon_length / self.tendon_slack_length;
        let (d_norm_length, d_norm_tendon_length) = (norm_length - from.fiber.norm_length, norm_tendon_length - from.norm_tendon_length);
        if d_norm_length.abs().max(d_norm_tendon_length.abs()) > CONTINUATION_LIMIT {
            return None;
        }
        let f = &from.fiber;
        let fiber = Fiber {
            length: fiber_length,
            cos_alpha,
            sin_alpha,
            norm_length,
            active_force_length: f.active_force_length + f.d_active_force_length * d_norm_length,
            fiber_force_length: f.fiber_force_length + f.d_fiber_force_length * d_norm_length,
            ..from.fiber
        };
        let tendon_force_length = from.tendon_force_length + from.d_tendon_force_length * d_norm_tendon_length;
        Some(Position { fiber, tendon_length, norm_tendon_length, tendon_force_length, ..*from })
    }

    /// F_m = F_max (a f_L f_V) + (F_max f_PE + F_max β ṽ) (`calcFiberForce`), N.
    pub(super) fn fiber_force(
        &self,
        activation: f64,
        fiber: &Fiber,
        fv: f64,
        norm_velocity: f64,
    ) -> f64 {
        let f = self.max_isometric_force;
        f * (activation * fiber.active_force_length * fv)
            + (f * fiber.fiber_force_length + f * self.fiber_damping * norm_velocity)
    }

    /// Static force balance F_m cos α − F_t (N, positive when the fiber pulls harder than the
    /// tendon) and its derivative along the fiber length (N/m), at zero fiber velocity, for an
    /// activation already in [minimum_activation, 1].
    pub fn force_balance(&self, activation: f64, fiber_length: f64, mt_length: f64) -> (f64, f64) {
        self.balance(activation, &self.position(fiber_length, mt_length))
    }

    /// `force_balance` at a computed position.
    fn balance(&self, activation: f64, p: &Position) -> (f64, f64) {
        let fiber_force = self.fiber_force(activation, &p.fiber, 1.0, 0.0);
        let residual = fiber_force * p.fiber.cos_alpha - p.tendon_force_length * self.max_isometric_force;
        (residual, self.d_residual(activation, p, fiber_force))
    }

    /// d(F_m cos α − F_t)/dL_m (`partialsFunc`: fiber stiffness, pennation and tendon terms).
    pub(super) fn d_residual(&self, activation: f64, p: &Position, fiber_force: f64) -> f64 {
        let (f, l_opt) = (self.max_isometric_force, self.optimal_fiber_length);
        let fiber = &p.fiber;
        let fiber_stiffness = f
            * (activation * (fiber.d_active_force_length * (1.0 / l_opt))
                + fiber.d_fiber_force_length * (1.0 / l_opt));
        let d_alpha = self.pennation.d_pennation_d_fiber_length(fiber.length);
        let d_force_along_tendon =
            fiber_stiffness * fiber.cos_alpha + fiber_force * (-fiber.sin_alpha * d_alpha);
        let tendon_stiffness = p.d_tendon_force_length * f / self.tendon_slack_length;
        let d_tendon_force = tendon_stiffness
            * self.pennation.d_tendon_length_d_fiber_length(
                fiber.length,
                fiber.sin_alpha,
                fiber.cos_alpha,
            );
        d_force_along_tendon - d_tendon_force
    }

    /// Static equilibrium at fiber velocity 0: the fiber length in [L_min, L_slack] (L_slack:
    /// the tendon exactly at slack length) where F_m cos α = F_t, by safeguarded Newton to
    /// 5e-10 N (or to the resolution of the fiber length), started where the tendon carries the
    /// force the fiber has at L_slack; a last step predicted to land within the tolerance is
    /// not evaluated (`newton_between_predicting`). At the edges: when even the minimum
    /// fiber length leaves the tendon slack, or the fiber's force at its minimum length exceeds
    /// the tendon's (the pennation/active-length limit), the fiber stays at its minimum length
    /// with zero fiber force, as OpenSim clamps it (`ClampedAtMinimumFiberLength`). A rigid
    /// tendon (`ignore_tendon_compliance`) has L_t = L_ts and no solve.
    pub fn equilibrium(
        &self,
        activation: f64,
        mt_length: f64,
    ) -> Result<FiberEquilibrium, MuscleError> {
        check_inputs(&self.name, activation, mt_length)?;
        let a = self.clamp_activation(activation);
        let slack_fiber_length = self
            .pennation
            .fiber_length(mt_length, self.tendon_slack_length)
            .max(self.minimum_fiber_length);
        let at = |fiber_length| self.position(fiber_length, mt_length);
        if self.ignore_tendon_compliance {
            return Ok(self.report(a, mt_length, &at(slack_fiber_length), 0.0, true));
        }
        if slack_fiber_length <= self.minimum_fiber_length {
            return Ok(self.report(a, mt_length, &at(self.minimum_fiber_length), 0.0, false));
        }
        // The solver's last evaluation, at the root or a predicted last step before it: kept for
        // the report.
        let mut last = None;
        let mut residual = |fiber_length| {
            let p = at(fiber_length);
            last = Some(p);
            self.balance(a, &p)
        };
        // At the slack fiber the tendon pulls nothing, so the balance is the fiber's F_m cos α ≥ 0.
        // First guess: the tendon stretched by that force (OpenSim starts at 1 % strain; this
        // start saves Newton steps).
        let at_slack = self.force_along_tendon_at_rest(a, slack_fiber_length);
        let norm_tendon_length = self.curves.tendon_length_at_force.value((at_slack / self.max_isometric_force).max(0.0));
        let start = self.pennation.fiber_length(mt_length, self.tendon_slack_length * norm_tendon_length);
        let length_resolution = 4.0 * f64::EPSILON * slack_fiber_length;
        // The balance is negative at the shortest fiber unless the fiber outpulls the tendon even
        // there. Assume so first (the root inside is unique) and solve without the shortest end.
        let quick = newton_between_predicting(
            &mut residual, start, self.minimum_fiber_length, slack_fiber_length, length_resolution, FORCE_TOLERANCE, 60,
        );
        let solved = match quick {
            Ok(root) if root.residual.abs() <= FORCE_TOLERANCE => Ok(root),
            _ => {
                let at_shortest = self.balance(a, &at(self.minimum_fiber_length)).0;
                let lo = BracketEnd { x: self.minimum_fiber_length, residual: at_shortest };
                let hi = BracketEnd { x: slack_fiber_length, residual: at_slack };
                bracketed_newton_from(&mut residual, start, lo, hi, length_resolution, FORCE_TOLERANCE, 200)
            }
        };
        match solved {
            Ok(root) => {
                let p = match last {
                    Some(p) if p.fiber.length == root.x => Some(p),
                    Some(p) if root.predicted => self.position_continued(&p, root.x, mt_length),
                    _ => None,
                };
                let p = p.unwrap_or_else(|| at(root.x));
                Ok(self.report(a, mt_length, &p, 0.0, false))
            }
            // The fiber outpulls the tendon even at its shortest: OpenSim's clamp.
            Err(RootFailure::NoSignChange(at_shortest, _)) if at_shortest >= 0.0 => {
                Ok(self.report(a, mt_length, &at(self.minimum_fiber_length), 0.0, false))
            }
            Err(failure) => Err(self.solve_failure(activation, mt_length, failure)),
        }
    }

    /// F_m cos α (N) of the fiber at rest at fiber length `fiber_length` (m), activation `a`
    /// already clamped: the force balance where the tendon is slack, from the curve values alone.
    fn force_along_tendon_at_rest(&self, a: f64, fiber_length: f64) -> f64 {
        let f = self.max_isometric_force;
        let norm_length = fiber_length / self.optimal_fiber_length;
        let (_, cos_alpha) = self.pennation.sin_cos(fiber_length);
        let active = self.curves.active_force_length.value(norm_length);
        let passive = self.curves.fiber_force_length.value(norm_length);
        (f * (a * active) + f * passive) * cos_alpha
    }

    pub(super) fn solve_failure(
        &self,
        activation: f64,
        mt_length: f64,
        failure: RootFailure,
    ) -> MuscleError {
        let muscle = self.name.clone();
        match failure {
            RootFailure::NotConverged(best) => {
                MuscleError::NotConverged { muscle, activation, mt_length, iterations: best.iterations, residual: best.residual }
            }
            RootFailure::NoSignChange(lo, hi) => MuscleError::Infeasible {
                muscle,
                activation,
                mt_length,
                reason: format!("the force balance does not change sign between the shortest and the slack fiber ({lo} N, {hi} N)"),
            },
            RootFailure::NotFinite(x) => MuscleError::Infeasible {
                muscle,
                activation,
                mt_length,
                reason: format!("non-finite force at fiber length {x} m"),
            },
        }
    }

    /// The reported state at position `p` (fiber length at least the minimum) and normalised
    /// fiber velocity `norm_velocity` (`calcMuscleLengthInfo` + `calcMuscleDynamicsInfo`),
    /// activation already clamped. A fiber at its minimum length and not lengthening is
    /// clamped: zero fiber force.
    pub(super) fn report(
        &self,
        a: f64,
        mt_length: f64,
        p: &Position,
        norm_velocity: f64,
        rigid: bool,
    ) -> FiberEquilibrium {
        let fiber = &p.fiber;
        let f = self.max_isometric_force;
        let clamped = fiber.length <= self.minimum_fiber_length && norm_velocity <= 0.0;
        let (norm_velocity, fv) = if clamped {
            (0.0, 1.0)
        } else {
            (norm_velocity, self.force_velocity_multiplier(norm_velocity))
        };
        let (active, passive) = if clamped {
            (0.0, 0.0)
        } else {
            (
                f * (a * fiber.active_force_length * fv),
                f * fiber.fiber_force_length + f * self.fiber_damping * norm_velocity,
            )
        };
        let fiber_force = active + passive;
        let along_tendon = fiber_force * fiber.cos_alpha;
        let tendon_force = if rigid {
            along_tendon
        } else {
            p.tendon_force_length * f
        };
        FiberEquilibrium {
            activation: a,
            mt_length,
            fiber_length: fiber.length,
            normalized_fiber_length: fiber.norm_length,
            pennation_angle: self.pennation.pennation_angle(fiber.length),
            cos_pennation_angle: fiber.cos_alpha,
            fiber_length_along_tendon: fiber.length * fiber.cos_alpha,
            tendon_length: p.tendon_length,
            tendon_strain: p.norm_tendon_length - 1.0,
            tendon_force,
            active_fiber_force: active,
            passive_fiber_force: passive,
            fiber_force,
            fiber_force_along_tendon: along_tendon,
            active_force_length_multiplier: fiber.active_force_length,
            passive_force_multiplier: fiber.fiber_force_length,
            force_velocity_multiplier: fv,
            normalized_fiber_velocity: norm_velocity,
            status: if clamped {
                EquilibriumStatus::ClampedAtMinimumFiberLength
            } else {
                EquilibriumStatus::Converged
            },
        }
    }

    /// f_V at normalised fiber velocity `norm_velocity`; at +0 (the static state) the value
    /// computed once at construction.
    fn force_velocity_multiplier(&self, norm_velocity: f64) -> f64 {
        if norm_velocity == 0.0 && norm_velocity.is_sign_positive() {
            self.isometric_force_velocity
        } else {
            self.curves.force_velocity.value(norm_velocity)
        }
    }
}

/// The properties OpenSim's `extendFinalizeFromProperties` adjusts before building the curves.
struct Finalised {
    minimum_activation: f64,
    /// The active force–length curve's `minimum_value` in use.
    active_force_length_minimum: f64,
    force_velocity: ForceVelocityCurveSpec,
}

/// The classic Hill model (elastic tendon, no damping) needs a = 0.01 or more, f_L ≥ 0.1 and
/// end slopes of f_V of at least half the near-v_max slopes; the damped (or rigid-tendon)
/// model clamps the minimum activation into [0, 1] and sets f_L's minimum and f_V's end
/// slopes to 0.
fn finalise(name: &str, spec: &MuscleSpec, class: &MillardSpec, damped: bool) -> Result<Finalised, MuscleError> {
    let mut fv = class.force_velocity.clone();
    for (property, slope) in [
        ("concentric_slope_near_vmax", fv.concentric_slope_near_vmax),
        ("eccentric_slope_near_vmax", fv.eccentric_slope_near_vmax),
    ] {
        if slope < f64::EPSILON.sqrt() {
            let property = format!("ForceVelocityCurve.{property}");
            return Err(MuscleError::invalid_parameter(name, &property, slope, "a slope ≥ 1.49e-8"));
        }
    }
    let minimum = class.minimum_activation;
    let afl_minimum = class.active_force_length.minimum_value;
    if !spec.ignore_tendon_compliance && !damped {
        if minimum < 0.01 {
            let expected = "≥ 0.01 for the classic Hill model with an elastic tendon";
            return Err(MuscleError::invalid_parameter(name, "minimum_activation", minimum, expected));
        }
        fv.concentric_slope_at_vmax = fv.concentric_slope_at_vmax.max(fv.concentric_slope_near_vmax * 0.5);
        fv.eccentric_slope_at_vmax = fv.eccentric_slope_at_vmax.max(fv.eccentric_slope_near_vmax * 0.5);
        return Ok(Finalised { minimum_activation: minimum, active_force_length_minimum: afl_minimum.max(0.1), force_velocity: fv });
    }
    if minimum < 0.0 {
        return Err(MuscleError::invalid_parameter(name, "minimum_activation", minimum, "a value ≥ 0"));
    }
    fv.concentric_slope_at_vmax = fv.concentric_slope_at_vmax.min(0.0);
    fv.eccentric_slope_at_vmax = fv.eccentric_slope_at_vmax.min(0.0);
    Ok(Finalised { minimum_activation: minimum.min(1.0), active_force_length_minimum: afl_minimum.min(0.0), force_velocity: fv })
}

/// The five curves from the finalised properties (`*_in_use` derived where unset). The inverse
/// force–velocity curve has end slopes ½ of the near-v_max slopes, as OpenSim builds it.
fn build_curves(name: &str, class: &MillardSpec, finalised: &Finalised) -> Result<MillardCurves, MuscleError> {
    let invalid = |e: CurveError| MuscleError::invalid_parameter(name, &e.property, e.value, &e.expected);
    let afl = &class.active_force_length;
    let fv = &finalised.force_velocity;
    let inverse = ForceVelocityCurveSpec {
        concentric_slope_at_vmax: fv.concentric_slope_near_vmax * 0.5,
        eccentric_slope_at_vmax: fv.eccentric_slope_near_vmax * 0.5,
        ..fv.clone()
    };
    let fpe = &class.fiber_force_length;
    let (fpe_k_low, fpe_k_iso, fpe_curviness) = fiber_force_length_in_use(name, fpe)?;
    let tfl = &class.tendon_force_length;
    let (tfl_k_iso, tfl_f_toe, tfl_curviness) = tendon_force_length_in_use(name, tfl)?;
    let afl_x = [afl.min_norm_active_fiber_length, afl.transition_norm_fiber_length, 1.0, afl.max_norm_active_fiber_length];
    let tendon_force_length = curves::tendon_force_length(tfl.strain_at_one_norm_force, tfl_k_iso, tfl_f_toe, tfl_curviness).map_err(invalid)?;
    Ok(MillardCurves {
        active_force_length: curves::active_force_length(afl_x, finalised.active_force_length_minimum, afl.shallow_ascending_slope, 1.0)
            .map_err(invalid)?,
        force_velocity: curves::force_velocity(fv).map_err(invalid)?,
        force_velocity_inverse: curves::force_velocity_inverse(&inverse).map_err(invalid)?,
        fiber_force_length: curves::fiber_force_length(fpe.strain_at_zero_force, fpe.strain_at_one_norm_force, fpe_k_low, fpe_k_iso, fpe_curviness)
            .map_err(invalid)?,
        tendon_length_at_force: tendon_force_length.inverse(),
        tendon_force_length,
    })
}

/// OpenSim rejects α_opt outside [0, π/2) and α_max outside [0, π/2].
fn check_pennation(name: &str, optimal: f64, maximum: f64) -> Result<(), MuscleError> {
    let half_pi = std::f64::consts::FRAC_PI_2;
    if !(0.0..=half_pi - SIGNIFICANT_REAL).contains(&optimal) {
        return Err(MuscleError::invalid_parameter(
            name,
            "pennation_angle_at_optimal",
            optimal,
            "an angle in [0, π/2) rad",
        ));
    }
    if !(0.0..=half_pi).contains(&maximum) {
        return Err(MuscleError::invalid_parameter(
            name,
            "maximum_pennation_angle",
            maximum,
            "an angle in [0, π/2] rad",
        ));
    }
    Ok(())
}

/// (k_low, k_iso, curviness) in use: all three set, or all derived from the strains.
fn fiber_force_length_in_use(
    name: &str,
    fpe: &crate::model::FiberForceLengthCurveSpec,
) -> Result<(f64, f64, f64), MuscleError> {
    match (fpe.stiffness_at_low_force, fpe.stiffness_at_one_norm_force, fpe.curviness) {
        (Some(low), Some(iso), Some(c)) => Ok((low, iso, c)),
        (None, None, None) => Ok((0.2, 2.0 / (fpe.strain_at_one_norm_force - fpe.strain_at_zero_force), 0.75)),
        _ => Err(MuscleError::invalid_parameter(
            name,
            "FiberForceLengthCurve.stiffness_at_low_force",
            f64::NAN,
            "stiffness_at_low_force, stiffness_at_one_norm_force and curviness all set or all empty",
        )),
    }
}

/// (k_iso, f_toe, curviness) in use: all three set, or all derived from the strain.
fn tendon_force_length_in_use(
    name: &str,
    tfl: &crate::model::TendonForceLengthCurveSpec,
) -> Result<(f64, f64, f64), MuscleError> {
    match (
        tfl.stiffness_at_one_norm_force,
        tfl.norm_force_at_toe_end,
        tfl.curviness,
    ) {
        (Some(k), Some(f), Some(c)) => Ok((k, f, c)),
        (None, None, None) => Ok((1.375 / tfl.strain_at_one_norm_force, 2.0 / 3.0, 0.5)),
        _ => Err(MuscleError::invalid_parameter(
            name,
            "TendonForceLengthCurve.stiffness_at_one_norm_force",
            f64::NAN,
            "stiffness_at_one_norm_force, norm_force_at_toe_end and curviness all set or all empty",
        )),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::io::osim::OsimDocument;
    use crate::mechanics::muscle::HillMuscle;
    use crate::model::ModelSpec;

    /// Whether its last state was evaluated or continued from the one before, the reported
    /// equilibrium is the state evaluated at its fiber length, to rounding.
    #[test]
    fn the_reported_state_is_the_one_at_the_reported_fiber_length() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/gait2392_millard2012muscle.osim");
        let spec = ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap();
        for force in spec.forces.iter().filter(|f| f.muscle.is_some()).step_by(7) {
            let HillMuscle::Millard(m) = HillMuscle::from_force(force).unwrap() else { panic!("{} is not a Millard muscle", force.name) };
            for (a, stretch) in [(0.05, 0.6), (0.5, 0.9), (1.0, 1.2)] {
                let mt_length = m.tendon_slack_length + stretch * m.optimal_fiber_length;
                let e = m.equilibrium(a, mt_length).unwrap();
                let p = m.position(e.fiber_length, mt_length);
                let f = m.max_isometric_force;
                assert!((e.active_force_length_multiplier - p.fiber.active_force_length).abs() <= 1e-14, "{}", m.name);
                assert!((e.passive_force_multiplier - p.fiber.fiber_force_length).abs() <= 1e-14, "{}", m.name);
                assert!((e.tendon_force - p.tendon_force_length * f).abs() <= 1e-14 * f, "{}", m.name);
                assert_eq!((e.tendon_length, e.cos_pennation_angle), (p.tendon_length, p.fiber.cos_alpha), "{}", m.name);
            }
        }
    }
}
