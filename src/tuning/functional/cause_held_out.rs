//! The best single cause's gain on trials its fit did not see: two-fold cross-validation by
//! alternate angles (fold = position in its trial file mod 2, so each fold spans every set,
//! direction and the whole angle range). Each fold's trials are predicted by the candidate fitted
//! to the other fold's; the RMS of those predictions against the initial model's is the gain
//! the model extended by the cause would have on new trials. A gain that holds on data the fit
//! did not use is a cause, not a fit to the noise.

use serde::Serialize;

use super::cause::{candidate_for, fit_candidate, initial_rms, SingleCause};
use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::trials::{root_mean_square, DynamometryData};
use crate::model::ModelSpec;

/// Folds of the cross-validation.
pub const FOLDS: usize = 2;

/// The held-out moments of one candidate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOutGain {
    /// RMS of M_mod − M_meas over every trial, each predicted without being fitted, N·m: by the
    /// initial model and by the model with the cause fitted to the other fold.
    pub rms_before: f64,
    pub rms_after: f64,
    /// The value fitted in each fold (trained on the others), in the cause's unit.
    pub fitted: Vec<f64>,
}

/// [`HeldOutGain`] of `cause` (a candidate of [`candidate_causes`](super::candidate_causes) on
/// `data`, whose knee-moment model is `model`, from `initial`).
pub fn held_out_gain(
    spec: &ModelSpec,
    model: &KneeMomentModel,
    data: &DynamometryData,
    initial: &[MuscleParameters],
    measured: &[f64],
    cause: &SingleCause,
) -> Result<HeldOutGain, FunctionalError> {
    let moments = model.moments(initial)?;
    let fold: Vec<usize> = model.trials().iter().map(|t| (t.number + FOLDS - 1) % FOLDS).collect();
    let (mut predicted, mut fitted) = (vec![0.0; measured.len()], Vec::with_capacity(FOLDS));
    for held in 0..FOLDS {
        let training: Vec<bool> = fold.iter().map(|&f| f != held).collect();
        let candidate = candidate_for(&cause.cause, (spec, model, data), initial, &moments, measured)?;
        let fit = fit_candidate(candidate, &training)?;
        for (t, r) in fit.residuals.iter().enumerate().filter(|(t, _)| !training[*t]) {
            predicted[t] = *r;
        }
        fitted.push(fit.value);
    }
    Ok(HeldOutGain {
        rms_before: initial_rms(&moments, measured),
        rms_after: root_mean_square(predicted.iter().copied()),
        fitted,
    })
}
