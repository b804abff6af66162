//! OpenSim's `Thelen2003Muscle::initMuscleState`, the fiber length `equilibrateMuscles` gives a
//! Thelen muscle at the start of a forward simulation, step by step: the path's lengthening
//! speed is shared between fiber and tendon by their stiffnesses (a heuristic of OpenSim's),
//! the force–velocity multiplier follows from the fiber's share (`calcfvInv`), and damped Newton
//! steps on the fiber length balance F_m cos α against F_t to 1e-8 F_max.

use super::Thelen2003Muscle;
use crate::mechanics::muscle::pennation::SIGNIFICANT_REAL;
use crate::mechanics::muscle::root::sign;
use crate::mechanics::muscle::MuscleError;

const MAX_ITERATIONS: usize = 20;
/// `calcfvInv`'s Newton steps in the velocity update.
const FORCE_VELOCITY_ITERATIONS: usize = 100;

/// The loop's quantities, named as in OpenSim.
#[derive(Default)]
struct Loop {
    lce: f64,
    phi: f64,
    cosphi: f64,
    tl: f64,
    fse: f64,
    fal: f64,
    fpe: f64,
    fv: f64,
    fm: f64,
    ferr: f64,
    d_fm_at_d_lce: f64,
    d_fm_at_d_lce_at: f64,
    d_ft_d_tl: f64,
    d_ft_d_lce: f64,
}

impl Thelen2003Muscle {
    /// L_m (m) at activation `activation` (as the state holds it) on a path of length
    /// `mt_length` (m) lengthening at `lengthening_speed` (m/s), as OpenSim initialises it; at
    /// the minimum fiber length when the iteration ends there; an error when it does not
    /// converge or `calcfvInv` fails (OpenSim throws).
    pub fn initial_fiber_length(&self, activation: f64, mt_length: f64, lengthening_speed: f64) -> Result<f64, MuscleError> {
        let tolerance = (1e-8 * self.max_isometric_force()).max(SIGNIFICANT_REAL * 10.0);
        let mut s = Loop { lce: self.pennation().fiber_length(mt_length, self.tendon_slack_length() * 1.01), fv: 1.0, ..Loop::default() };
        self.position(&mut s, mt_length);
        self.partials(&mut s, activation);
        self.velocity(&mut s, activation, lengthening_speed, tolerance)?;
        self.force_error(&mut s, activation);
        self.partials(&mut s, activation);
        let (mut ferr_previous, mut lce_previous) = (s.ferr, s.lce);
        let mut iteration = 0;
        while s.ferr.abs() > tolerance && iteration < MAX_ITERATIONS {
            let d_ferr_d_lce = s.d_fm_at_d_lce - s.d_ft_d_lce;
            let mut h = 1.0;
            while s.ferr.abs() >= ferr_previous.abs() {
                let delta = -h * ferr_previous / d_ferr_d_lce;
                if delta.abs() > SIGNIFICANT_REAL {
                    s.lce = lce_previous + delta;
                } else {
                    s.lce = lce_previous - sign(delta) * f64::EPSILON.sqrt();
                    h = 0.0;
                }
                s.lce = s.lce.max(self.minimum_fiber_length());
                self.position(&mut s, mt_length);
                self.force_error(&mut s, activation);
                if h <= f64::EPSILON.sqrt() {
                    break;
                }
                h *= 0.5;
            }
            (ferr_previous, lce_previous) = (s.ferr, s.lce);
            self.partials(&mut s, activation);
            self.velocity(&mut s, activation, lengthening_speed, tolerance)?;
            iteration += 1;
        }
        if s.ferr.abs() < tolerance {
            return Ok(s.lce);
        }
        if s.lce <= self.minimum_fiber_length() {
            return Ok(self.minimum_fiber_length());
        }
        Err(MuscleError::NotConverged { muscle: self.name().to_string(), activation, mt_length, iterations: MAX_ITERATIONS, residual: s.ferr })
    }

    /// `positionFunc` and `multipliersFunc`.
    fn position(&self, s: &mut Loop, mt_length: f64) {
        s.phi = self.pennation().pennation_angle(s.lce);
        s.cosphi = s.phi.cos();
        s.tl = mt_length - s.lce * s.cosphi;
        s.fse = self.curves().tendon_force_length(s.tl / self.tendon_slack_length());
        s.fal = self.curves().active_force_length(s.lce / self.optimal_fiber_length());
        s.fpe = self.curves().passive_force_length(s.lce / self.optimal_fiber_length());
    }

    /// `ferrFunc`: F_m cos α − F_t.
    fn force_error(&self, s: &mut Loop, activation: f64) {
        s.fm = (activation * s.fal * s.fv + s.fpe) * self.max_isometric_force();
        s.ferr = s.fm * s.cosphi - s.fse * self.max_isometric_force();
    }

    /// `partialsFunc`: `calcDFmDlce`, `calcDFmATDlce`, `calcDFseDtl`, `calcDFseDlce`.
    fn partials(&self, s: &mut Loop, activation: f64) {
        let (fiso, ofl, tsl, vol) = (self.max_isometric_force(), self.optimal_fiber_length(), self.tendon_slack_length(), self.pennation().parallelogram_height);
        let lce_n = s.lce / ofl;
        let d_fm_d_lce = ((activation * s.fv) * self.curves().active_force_length_derivative(lce_n) + self.curves().passive_force_length_derivative(lce_n)) * fiso * (1.0 / ofl);
        let (vol2, lce2) = (vol * vol, s.lce * s.lce);
        let d_cosphi_d_lce = vol2 / (lce2 * s.lce * (1.0 - vol2 / lce2).powf(0.5));
        s.d_fm_at_d_lce = d_fm_d_lce * s.cosphi + s.fm * d_cosphi_d_lce;
        s.d_fm_at_d_lce_at = s.d_fm_at_d_lce * s.cosphi;
        let d_fse = self.curves().tendon_force_length_derivative(s.tl / tsl);
        s.d_ft_d_tl = d_fse * (fiso / tsl);
        let ratio = vol / s.lce;
        let d_phi_d_lce = -vol / (lce2 * (1.0 - ratio * ratio).powf(0.5));
        let d_tl_d_lce = -s.phi.cos() + s.lce * s.phi.sin() * d_phi_d_lce;
        s.d_ft_d_lce = d_fse * d_tl_d_lce * (fiso / tsl);
    }

    /// `velocityFunc`: the fiber's share of the path speed, and f_V there by `calcfvInv`.
    fn velocity(&self, s: &mut Loop, activation: f64, lengthening_speed: f64, tolerance: f64) -> Result<(), MuscleError> {
        let stiffness = s.d_fm_at_d_lce_at + s.d_ft_d_tl;
        let tendon_speed = if stiffness.abs() > SIGNIFICANT_REAL && s.tl > self.tendon_slack_length() {
            (s.d_fm_at_d_lce_at / stiffness) * lengthening_speed
        } else {
            lengthening_speed
        };
        let fiber_speed = (lengthening_speed - tendon_speed) * s.cosphi;
        let normalized = fiber_speed / (self.max_contraction_velocity() * self.optimal_fiber_length());
        s.fv = self.curves().force_velocity_by_newton(activation, s.fal, normalized, tolerance, FORCE_VELOCITY_ITERATIONS).ok_or_else(|| MuscleError::Infeasible {
            muscle: self.name().to_string(),
            activation,
            mt_length: s.tl + s.lce * s.cosphi,
            reason: format!("no force–velocity multiplier gives the normalized fiber velocity {normalized} (OpenSim's calcfvInv fails)"),
        })?;
        Ok(())
    }
}
