//! The force–velocity relation of OpenSim's `Thelen2003Muscle` (Thelen 2003 eqs. 6–7, linearly
//! extrapolated below zero force and above `fv_linear_extrap_threshold · Flen`).
//!
//! OpenSim states it as velocity from force (`calcdlceN`): with c = 0.25 + 0.75 a, the active
//! force F = a f_L f_V (normalized by F_max) and a f_L the isometric active force,
//! ṽ = c (F − a f_L) / b with b = a f_L + F / Af when shortening (F ≤ a f_L) and
//! b = (2 + 2/Af)(Flen a f_L − F) / (Flen − 1) when lengthening. Velocities ṽ are normalized by
//! v_max · L_opt, lengthening positive (−1 ≈ maximum shortening). Forward simulation uses this
//! direction; the multiplier f_V(ṽ) is its exact inverse, which does not depend on f_L.

use super::ThelenCurves;
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;

impl ThelenCurves {
    /// ṽ, the normalized fiber velocity at which the fiber develops active force
    /// `active_force` = a f_L f_V at activation `activation` and active force–length multiplier
    /// `active_force_length` (`calcdlceN`).
    pub fn normalized_fiber_velocity(
        &self,
        activation: f64,
        active_force_length: f64,
        active_force: f64,
    ) -> f64 {
        let isometric = activation * active_force_length;
        match self.extrapolation_anchor(isometric, active_force) {
            None => self.thelen_velocity(activation, isometric, active_force).0,
            Some(anchor) => {
                let (velocity, slope) = self.thelen_velocity(activation, isometric, anchor);
                velocity + slope * (active_force - anchor)
            }
        }
    }

    /// ∂ṽ/∂F of [`ThelenCurves::normalized_fiber_velocity`] (`calcDdlceDaFalFv`).
    pub fn normalized_fiber_velocity_derivative(
        &self,
        activation: f64,
        active_force_length: f64,
        active_force: f64,
    ) -> f64 {
        let isometric = activation * active_force_length;
        let at = self
            .extrapolation_anchor(isometric, active_force)
            .unwrap_or(active_force);
        self.thelen_velocity(activation, isometric, at).1
    }

    /// f_V at normalized fiber velocity `normalized_fiber_velocity` as OpenSim's `calcfvInv`
    /// finds it: Newton steps on the active force F, from F = a f_L (f_V = 1), until the
    /// velocity error |ṽ(F) − ṽ| < `tolerance` or `max_iterations` steps are taken (a step with
    /// |∂ṽ/∂F| ≤ SignificantReal leaves F unchanged). The error is that of F before the last
    /// step, which is still applied. Returns max(0, F / (a f_L)); `None` when the error is not
    /// below `tolerance` (OpenSim throws). [`ThelenCurves::force_velocity`] is the exact inverse.
    pub fn force_velocity_by_newton(
        &self,
        activation: f64,
        active_force_length: f64,
        normalized_fiber_velocity: f64,
        tolerance: f64,
        max_iterations: usize,
    ) -> Option<f64> {
        let mut force = activation * active_force_length;
        let mut error = 1.0_f64;
        let mut iterations = 0;
        while error.abs() >= tolerance && iterations < max_iterations {
            error = self.normalized_fiber_velocity(activation, active_force_length, force)
                - normalized_fiber_velocity;
            let slope =
                self.normalized_fiber_velocity_derivative(activation, active_force_length, force);
            if slope.abs() > SIGNIFICANT_REAL {
                force += -error / slope;
            }
            iterations += 1;
        }
        // OpenSim's std::max(0.0, x): 0 unless x > 0 (NaN included).
        let multiplier = force / (activation * active_force_length);
        (error.abs() < tolerance).then_some(if 0.0 < multiplier { multiplier } else { 0.0 })
    }

    /// f_V(ṽ), the force–velocity multiplier at normalized fiber velocity ṽ and activation
    /// `activation`: the inverse of [`ThelenCurves::normalized_fiber_velocity`] (0 at ṽ = −c,
    /// 1 at ṽ = 0; negative below −c, where OpenSim's linear extrapolation continues).
    pub fn force_velocity(&self, activation: f64, normalized_fiber_velocity: f64) -> f64 {
        let v = normalized_fiber_velocity;
        let c = shortening_scale(activation);
        let k = self.eccentric_factor();
        let (start, end) = self.hyperbola_velocities(activation);
        if v <= start || v >= end {
            let anchor = if v <= start {
                0.0
            } else {
                self.eccentric_threshold()
            };
            let (velocity, slope) = self.thelen_velocity(activation, 1.0, anchor);
            anchor + (v - velocity) / slope
        } else if v <= 0.0 {
            (c + v) / (c - v / self.af)
        } else {
            (c + v * k * self.flen) / (c + v * k)
        }
    }

    /// df_V/dṽ of [`ThelenCurves::force_velocity`].
    pub fn force_velocity_derivative(
        &self,
        activation: f64,
        normalized_fiber_velocity: f64,
    ) -> f64 {
        let v = normalized_fiber_velocity;
        let c = shortening_scale(activation);
        let k = self.eccentric_factor();
        let (start, end) = self.hyperbola_velocities(activation);
        if v <= start || v >= end {
            let anchor = if v <= start {
                0.0
            } else {
                self.eccentric_threshold()
            };
            1.0 / self.thelen_velocity(activation, 1.0, anchor).1
        } else if v <= 0.0 {
            let denominator = c - v / self.af;
            c * (1.0 + 1.0 / self.af) / (denominator * denominator)
        } else {
            let denominator = c + v * k;
            k * c * (self.flen - 1.0) / (denominator * denominator)
        }
    }

    /// (ṽ, ∂ṽ/∂F) of Thelen's eq. 6 at active force `force` and isometric active force
    /// `isometric` = a f_L, in OpenSim's operation order.
    fn thelen_velocity(&self, activation: f64, isometric: f64, force: f64) -> (f64, f64) {
        let c = shortening_scale(activation);
        let (b, db) = if force <= isometric {
            (isometric + force / self.af, 1.0 / self.af)
        } else {
            let factor = 2.0 + 2.0 / self.af;
            (
                (factor * (isometric * self.flen - force)) / (self.flen - 1.0),
                -factor / (self.flen - 1.0),
            )
        };
        let velocity = c * (force - isometric) / b;
        let slope = c * 1.0 / b - (c * (force - isometric) / (b * b)) * db;
        (velocity, slope)
    }

    /// The force where OpenSim's linear extrapolation starts, when `force` lies outside
    /// Thelen's region (0, threshold · Flen · a f_L).
    fn extrapolation_anchor(&self, isometric: f64, force: f64) -> Option<f64> {
        let eccentric_limit = isometric * self.flen * self.fv_linear_extrap_threshold;
        if force > 0.0 && force < eccentric_limit {
            None
        } else if force <= 0.0 {
            Some(0.0)
        } else {
            Some(eccentric_limit)
        }
    }

    /// f_V where the eccentric extrapolation starts: threshold · Flen.
    fn eccentric_threshold(&self) -> f64 {
        self.flen * self.fv_linear_extrap_threshold
    }

    /// (2 + 2/Af) / (Flen − 1), the eccentric b per unit force below the asymptote.
    fn eccentric_factor(&self) -> f64 {
        (2.0 + 2.0 / self.af) / (self.flen - 1.0)
    }

    /// The velocities bounding Thelen's region at `activation`: −c (f_V = 0) and the velocity
    /// at f_V = threshold · Flen.
    fn hyperbola_velocities(&self, activation: f64) -> (f64, f64) {
        let end = self
            .thelen_velocity(activation, 1.0, self.eccentric_threshold())
            .0;
        (-shortening_scale(activation), end)
    }
}

/// c = 0.25 + 0.75 a: the maximum normalized shortening velocity at activation a.
fn shortening_scale(activation: f64) -> f64 {
    0.25 + 0.75 * activation
}

#[cfg(test)]
mod tests {
    use super::super::curves::tests::{central_difference, gait2392_curves};

    const ACTIVATIONS: [f64; 4] = [0.01, 0.05, 0.5, 1.0];

    #[test]
    fn isometric_and_zero_force_points() {
        let c = gait2392_curves();
        for a in ACTIVATIONS {
            assert_eq!(c.force_velocity(a, 0.0), 1.0);
            assert_eq!(c.normalized_fiber_velocity(a, 0.7, a * 0.7), 0.0);
            assert!((c.force_velocity(a, -(0.25 + 0.75 * a))).abs() < 1e-15);
        }
    }

    /// f_V inverts ṽ(F) on all four pieces, for several f_L (f_V does not depend on f_L).
    #[test]
    fn force_velocity_inverts_the_velocity_of_opensim() {
        let c = gait2392_curves();
        for a in ACTIVATIONS {
            for fal in [0.2, 0.7, 1.0] {
                for i in 0..=60 {
                    let multiplier = -0.2 + 0.04 * f64::from(i);
                    let velocity = c.normalized_fiber_velocity(a, fal, a * fal * multiplier);
                    let back = c.force_velocity(a, velocity);
                    assert!(
                        (back - multiplier).abs() < 1e-12,
                        "a {a} f_L {fal} f_V {multiplier}: {back}"
                    );
                }
            }
        }
    }

    /// OpenSim's iteration lands on the exact inverse (clipped at 0 past maximum shortening)
    /// on all four pieces; it fails when it cannot reach its tolerance.
    #[test]
    fn newton_force_velocity_converges_to_the_exact_inverse() {
        let c = gait2392_curves();
        for a in ACTIVATIONS {
            for i in 0..=70 {
                let v = -1.5 + 0.05 * f64::from(i);
                let iterated = c.force_velocity_by_newton(a, 0.8, v, 1e-6, 100).unwrap();
                let exact = c.force_velocity(a, v).max(0.0);
                assert!((iterated - exact).abs() < 1e-8, "a {a} v {v}: {iterated} vs {exact}");
            }
            assert_eq!(c.force_velocity_by_newton(a, 0.8, 0.5, 1e-6, 0), None);
            assert_eq!(c.force_velocity_by_newton(a, 0.8, f64::NAN, 1e-6, 100), None);
        }
    }

    /// Analytic derivatives against central differences (h = 1e-7, agreement 1e-6 relative to
    /// max(1, |f′|)), away from the kink at ṽ = 0 (F = a f_L), where Thelen's two branches meet
    /// with slopes differing by a factor 2.
    #[test]
    fn derivatives_match_central_differences() {
        let c = gait2392_curves();
        let h = 1e-7;
        for a in ACTIVATIONS {
            for i in 0..=80 {
                let v = -1.2 + 0.03 * f64::from(i) + 0.001;
                let numeric = central_difference(|v| c.force_velocity(a, v), v, h);
                let analytic = c.force_velocity_derivative(a, v);
                assert!(
                    (numeric - analytic).abs() < 1e-6 * analytic.abs().max(1.0),
                    "a {a} v {v}: {analytic} vs {numeric}"
                );
                let force = a * 0.8 * (-0.2 + 0.025 * f64::from(i) + 0.001);
                let numeric =
                    central_difference(|f| c.normalized_fiber_velocity(a, 0.8, f), force, h);
                let analytic = c.normalized_fiber_velocity_derivative(a, 0.8, force);
                assert!(
                    (numeric - analytic).abs() < 1e-6 * analytic.abs().max(1.0),
                    "a {a} F {force}: {analytic} vs {numeric}"
                );
            }
        }
    }

    #[test]
    fn pieces_join_continuously_with_matching_slopes_except_at_isometric() {
        let c = gait2392_curves();
        for a in ACTIVATIONS {
            let (start, end) = c.hyperbola_velocities(a);
            for knot in [start, end] {
                let step = 1e-9 * knot.abs();
                let (below, above) = (
                    c.force_velocity(a, knot - step),
                    c.force_velocity(a, knot + step),
                );
                assert!((below - above).abs() < 1e-8, "a {a} at {knot}");
                let (slope_below, slope_above) = (
                    c.force_velocity_derivative(a, knot - step),
                    c.force_velocity_derivative(a, knot + step),
                );
                assert!(
                    (slope_below - slope_above).abs() < 1e-6 * slope_above,
                    "a {a} at {knot}"
                );
            }
        }
    }
}
