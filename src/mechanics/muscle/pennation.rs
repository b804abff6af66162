//! OpenSim's `MuscleFixedWidthPennationModel`: the fiber keeps the height of its parallelogram,
//! h = L_opt · sin α_opt, so sin α = h / L_m, capped at the maximum pennation angle.

/// Fixed-width pennation of one muscle.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedWidthPennation {
    /// α_opt, rad.
    pub pennation_angle_at_optimal: f64,
    /// α_max, rad.
    pub maximum_pennation_angle: f64,
    /// h = L_opt · sin α_opt, m.
    pub parallelogram_height: f64,
    /// (sin α_max, cos α_max).
    maximum_sin_cos: (f64, f64),
    /// The shortest fiber the pennation model allows, m: h / sin α_max (1 % of L_opt when
    /// α_max = 0).
    pub minimum_fiber_length: f64,
    /// Its projection on the tendon, L_min cos α_max, m.
    minimum_fiber_length_along_tendon: f64,
}

impl FixedWidthPennation {
    pub fn new(
        optimal_fiber_length: f64,
        pennation_angle_at_optimal: f64,
        maximum_pennation_angle: f64,
    ) -> Self {
        let parallelogram_height = optimal_fiber_length * pennation_angle_at_optimal.sin();
        let maximum_sin_cos = (maximum_pennation_angle.sin(), maximum_pennation_angle.cos());
        let minimum_fiber_length = if maximum_pennation_angle > SIGNIFICANT_REAL {
            parallelogram_height / maximum_sin_cos.0
        } else {
            optimal_fiber_length * 0.01
        };
        FixedWidthPennation {
            pennation_angle_at_optimal,
            maximum_pennation_angle,
            parallelogram_height,
            maximum_sin_cos,
            minimum_fiber_length,
            minimum_fiber_length_along_tendon: minimum_fiber_length * maximum_sin_cos.1,
        }
    }

    /// α(L_m), rad: asin(h / L_m), or α_max at and below the minimum fiber length.
    pub fn pennation_angle(&self, fiber_length: f64) -> f64 {
        if self.pennation_angle_at_optimal <= f64::EPSILON {
            return 0.0;
        }
        if fiber_length > self.minimum_fiber_length {
            let sin_phi = self.parallelogram_height / fiber_length;
            if sin_phi < self.maximum_sin_cos.0 {
                return sin_phi.asin();
            }
        }
        self.maximum_pennation_angle
    }

    /// (sin α, cos α) of [`FixedWidthPennation::pennation_angle`] without its asin: sin α = h/L_m
    /// and cos α = √((1 − sin α)(1 + sin α)), equal to cos(asin(h/L_m)) to rounding.
    pub fn sin_cos(&self, fiber_length: f64) -> (f64, f64) {
        if self.pennation_angle_at_optimal <= f64::EPSILON {
            return (0.0, 1.0);
        }
        let sin_alpha = self.parallelogram_height / fiber_length;
        if fiber_length > self.minimum_fiber_length && sin_alpha < self.maximum_sin_cos.0 {
            (sin_alpha, ((1.0 - sin_alpha) * (1.0 + sin_alpha)).sqrt())
        } else {
            self.maximum_sin_cos
        }
    }

    /// dα/dL_m = −(h/L_m²)/√(1 − (h/L_m)²), rad/m, OpenSim's formula (not capped at α_max; 0 for
    /// unpennated muscles).
    pub fn d_pennation_d_fiber_length(&self, fiber_length: f64) -> f64 {
        let h_over_l = self.parallelogram_height / fiber_length;
        (-h_over_l / fiber_length) / (1.0 - h_over_l * h_over_l).sqrt()
    }

    /// dL_t/dL_m at fixed path length = L_m sin α · dα/dL_m − cos α.
    pub fn d_tendon_length_d_fiber_length(
        &self,
        fiber_length: f64,
        sin_alpha: f64,
        cos_alpha: f64,
    ) -> f64 {
        fiber_length * sin_alpha * self.d_pennation_d_fiber_length(fiber_length) - cos_alpha
    }

    /// The fiber length whose projection fills L_mt − L_t: √(h² + (L_mt − L_t)²), or the
    /// minimum fiber length when the projection is shorter than its minimum (m).
    pub fn fiber_length(&self, mt_length: f64, tendon_length: f64) -> f64 {
        let along_tendon = mt_length - tendon_length;
        if along_tendon >= self.minimum_fiber_length_along_tendon {
            (self.parallelogram_height * self.parallelogram_height + along_tendon * along_tendon)
                .sqrt()
        } else {
            self.minimum_fiber_length
        }
    }
}

/// SimTK::SignificantReal = ε^(7/8) for doubles.
pub const SIGNIFICANT_REAL: f64 = 2.0097183471152322e-14;

#[cfg(test)]
mod tests {
    use super::*;

    /// sin_cos is (sin α, cos α) of pennation_angle to rounding, inside the range, at its
    /// minimum fiber length limit and for an unpennated muscle.
    #[test]
    fn sin_cos_matches_the_pennation_angle() {
        let pennated = FixedWidthPennation::new(0.1, 0.3, 1.4);
        let unpennated = FixedWidthPennation::new(0.1, 0.0, 1.4);
        for pennation in [pennated, unpennated] {
            for fiber_length in [0.01, pennation.minimum_fiber_length, 0.05, 0.1, 0.2] {
                let alpha = pennation.pennation_angle(fiber_length);
                let (sin, cos) = pennation.sin_cos(fiber_length);
                assert!((sin - alpha.sin()).abs() < 1e-15 && (cos - alpha.cos()).abs() < 1e-15, "{fiber_length}: {alpha}");
            }
        }
    }
}
