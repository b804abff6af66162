//! The best single cause's gain on trials its fit did not see: two-fold cross-validation by
//! alternate angles (fold = position in its trial file mod 2, so each fold spans every set,
//! direction and the whole angle range). Each fold's trials are predicted by the candidate fitted
//! to the other fold's; the RMS of those predictions against the initial model's is the gain
//! the model extended by the cause would have on new trials. A gain that holds on data the fit
//! did not use is a cause, not a fit to the noise.

use serde::Serialize;

use super::cause::{fit_candidate, SingleCause};
use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::trials::root_mean_square;

/// Folds of the cross-validation.
pub const FOLDS: usize = 2;

/// The held-out moments of one candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOutGain {
    /// RMS of M_mod − M_meas over every trial, each predicted without being fitted, N·m: by the
    /// initial model and by the model with the cause fitted to the other fold.
    pub rms_before: f64,
    pub rms_after: f64,
    /// The value fitted in each fold (trained on the others), m.
    pub fitted: Vec<f64>,
}

/// [`HeldOutGain`] of `cause` (a candidate of [`single_causes`](super::single_causes) on
/// `measured`, from `initial`).
pub fn held_out_gain(model: &KneeMomentModel, initial: &[MuscleParameters], measured: &[f64], cause: &SingleCause) -> Result<HeldOutGain, FunctionalError> {
    let e = initial
        .iter()
        .position(|p| p.name == cause.muscle)
        .ok_or_else(|| FunctionalError::all_muscles(format!("the cause's muscle {} is not estimated", cause.muscle)))?;
    let moments = model.moments(initial)?;
    let fold: Vec<usize> = model.trials().iter().map(|t| (t.number + FOLDS - 1) % FOLDS).collect();
    let (mut predicted, mut fitted) = (vec![0.0; measured.len()], Vec::with_capacity(FOLDS));
    for held in 0..FOLDS {
        let training: Vec<bool> = fold.iter().map(|&f| f != held).collect();
        let fit = fit_candidate(model, initial, &moments, (e, cause.parameter), measured, &training)?;
        for (t, r) in fit.residuals.iter().enumerate().filter(|(t, _)| !training[*t]) {
            predicted[t] = *r;
        }
        fitted.push(fit.value);
    }
    Ok(HeldOutGain {
        rms_before: root_mean_square(moments.iter().zip(measured).map(|(m, y)| m - y)),
        rms_after: root_mean_square(predicted.iter().copied()),
        fitted,
    })
}
