//! Functional scaling (thesis ch. 3 and 6): muscle-tendon parameters (L_opt, L_ts) fitted to
//! measured isometric knee moments.
//!
//! - `trials.rs`: a dynamometry subject folder (`subject.json`, one `.mot` per trial set and
//!   direction) as [`DynamometryData`] of [`IsometricTrial`]s, angles in rad; the RMS of
//!   moment residuals (`root_mean_square`).
//! - `knee_moment.rs`: [`KneeMomentModel`], the knee moment Σ F_t·r of every knee-crossing
//!   muscle in static equilibrium for each trial, with the geometry precomputed; the estimated
//!   muscles are evaluated through the workspace [`EstimatedMuscles`].
//! - `parameters.rs`: [`MuscleParameters`] (L_opt, L_ts, F_max, α_opt, v_max) and [`Parameter`].
//! - `sensitivity.rs`: [`SensitivityTable`], eq. 3.3–3.4 with the low/medium/high classes.
//! - `feasible_set.rs`: Phase I, the feasible (L_opt, L_ts) grid per muscle, the regression line
//!   1/L_opt ≈ c1·(L_ts/L_opt) + c2 and the δ and L_ts/L_opt bounds ([`feasible_sets`]);
//!   `hot_start.rs`: the feasible combination closest to the measured moments ([`hot_start`]).
//! - `phase_two.rs`: Phase II, the constrained NLP of eq. 6.15–6.24 on the SQP solver, in the
//!   transformed variables (L_ts/L_opt, δ) with the equilibria solved exactly ([`solve_phase_two`]).
//! - `rest_curve.rs`: a muscle's [`RestCurve`], the (L_opt, L_ts) that reproduce its reference
//!   rest fiber length; `rest_curve_search.rs` the global search on tabulated contributions;
//!   `rest_curve_fit.rs` the fit on the rest curves after Phase II ([`fit_rest_curves`]);
//!   `rest_curve_map.rs` that fit as the estimator runs it, with the prior and the σ it is
//!   weighed against (`fit_on_rest_curves`); `rest_curve_posterior.rs` the posterior mean of
//!   the curve coordinates under the prior, the default estimate;
//!   `rest_curve_information.rs` the Fisher information, Cramér–Rao bounds, posterior and
//!   prior pull of the curve coordinates ([`RestCurveInformation`]); `noise_evidence.rs` the
//!   moment noise σ from its marginal likelihood under the prior (the posterior mean).
//! - `garner_pandy.rs`: the Garner & Pandy (2003) baseline ([`fit_garner_pandy`]).
//! - `identifiability.rs`: Fisher information, D- and E-criteria and unidentifiable directions
//!   per parameterisation ([`fisher_information`]).
//! - `sigma_points.rs`: the 2n²+1 sigma points of Appendix 6.6 and noise propagation through any
//!   estimator ([`propagate_noise`]).
//! - `cause.rs`: the single change that best explains the measured moments ([`Cause`]: a
//!   muscle's L_ts, L_opt, F_max or α_opt or, with `cause_group.rs`, a muscle group's L_ts, L_opt
//!   or F_max, the knee's axis moved (`cause_axis.rs`), or from `cause_protocol.rs` an angle
//!   offset, an activation level or an offset of the measured moments;
//!   [`candidate_causes`], [`single_causes`]); `cause_verdict.rs` whether that names the cause at the noise σ
//!   (Bayes factors of the candidates, [`cause_verdict`]); `cause_held_out.rs` the best
//!   cause's gain on trials its fit did not see (two-fold cross-validation, [`held_out_gain`]);
//!   `cause_model.rs` the model extended by it ([`apply_cause`]).
//! - `estimator.rs`: the estimators and their settings ([`estimate`], [`FitSettings`]): the
//!   thesis' method with the rest-curve fit, or Garner & Pandy.
//! - `analyses.rs`: the analyses at an estimate ([`analyse`]: sensitivity, identifiability,
//!   uncertainty), each reported as unavailable rather than failing the fit.
//! - `residuals.rs`: what the initial and the fitted model get wrong, per direction
//!   ([`residuals_by_direction`]).
//! - `fit.rs`: one run ([`fit`]): input checks (coordinate ranges, enough angles, sign
//!   convention), the single causes, the estimator and the analyses.
//! - `error.rs`: [`FunctionalError`].

mod analyses;
mod cause;
mod cause_axis;
mod cause_protocol;
mod cause_group;
mod cause_model;
mod cause_held_out;
mod cause_verdict;
mod error;
mod estimator;
mod garner_pandy;
mod identifiability;
mod feasible_set;
mod fit;
mod hot_start;
mod knee_moment;
mod noise_evidence;
mod parameters;
mod phase_two;
mod residuals;
mod rest_curve;
mod rest_curve_fit;
mod rest_curve_information;
mod rest_curve_map;
mod rest_curve_posterior;
mod rest_curve_search;
mod sensitivity;
mod sigma_points;
mod trials;

pub use cause::{candidate_causes, single_causes, Cause, SingleCause, CANDIDATE_PARAMETERS};
pub use cause_axis::{AxisMove, AXIS_OFFSET_LIMIT_MM};
pub use cause_protocol::OFFSET_LIMIT_DEG;
pub use cause_model::{apply_cause, CauseEdit};
pub use residuals::{residuals_by_direction, DirectionResiduals, ErrorStatistics};
pub use cause_held_out::{held_out_gain, HeldOutGain, FOLDS};
pub use cause_verdict::{cause_verdict, CauseVerdict, NoiseLevel, Verdict, MOMENT_RESOLUTION, STRONG_EVIDENCE};
pub use error::FunctionalError;
pub use garner_pandy::{
    fit_garner_pandy, GarnerPandyFit, GarnerPandyOptions, JointRange, MusculotendonRange, NormalizedFiberLengthRange, RangeExtreme, RANGE_SAMPLES,
};
pub use identifiability::{
    fisher_information, FisherCriteria, FisherInformation, FisherOptions, Identifiability, NullComponent, NullDirection,
    ParameterLabel, Parameterisation, TransformedParameter, UnidentifiableParameter, DEFAULT_FISHER_STEP, DEFAULT_RANK_TOLERANCE,
    NULL_COMPONENT_CUTOFF, UNIDENTIFIABLE_SHARE,
};
pub use analyses::{analyse, AnalysisFailure, Analyses, FitInputs, ParameterisationReport, RestCurveUncertainty, Uncertainty, LAPLACE, SAMPLED};
pub use estimator::{estimate, Estimate, FitMethod, FitSettings, DEFAULT_PRIOR_SD};
pub use fit::{fit, FunctionalFit, TrialFit};
pub use feasible_set::{feasible_sets, FeasibleSetSettings, MuscleFeasibleSet, RegressionLine, DELTA_FLOOR};
pub use hot_start::{hot_start, HotStart};
pub use knee_moment::{EquilibriumMethod, EstimatedMuscles, KneeMomentModel, KneeMuscle};
pub use parameters::{MuscleParameters, Parameter};
pub use rest_curve::RestCurve;
pub use rest_curve_fit::{fit_rest_curves, RestCurveFit, RestCurvePrior, RestCurveSettings};
pub use rest_curve_posterior::PosteriorSettings;
pub use rest_curve_map::AppliedPrior;
pub use rest_curve_information::{RestCurveInformation, COORDINATE_STEP, REST_CURVE_PARAMETERISATION};
pub use rest_curve_search::SearchBudget;
pub use phase_two::{solve_phase_two, PhaseTwo, PhaseTwoSettings, RATIO_GROUPS};
pub use sensitivity::{Applicability, SensitivityClass, SensitivityEntry, SensitivityTable, DEFAULT_RELATIVE_STEP, LOW_BELOW, MEDIUM_BELOW};
pub use sigma_points::{noise_from_residuals, propagate_noise, NoisePropagation, SigmaPoint, SigmaPointError, SigmaPoints};
pub use trials::{DynamometryData, Direction, IsometricTrial, SetSelection, Side, TrialColumns, TrialOptions, ACTIVATION_SUFFIX, SUBJECT_FILE};
pub(crate) use trials::root_mean_square;

/// The shared test data of the unit tests: the scaled subject01 model and train01's trials.
#[cfg(test)]
pub(crate) mod test_data {
    use std::path::Path;

    use super::{DynamometryData, TrialOptions};
    use crate::io::osim::OsimDocument;
    use crate::model::ModelSpec;

    /// `fixtures/golden/scale/subject01_simbody.osim`, OpenSim 4.6's scaled subject01.
    pub fn subject01() -> ModelSpec {
        ModelSpec::read(&OsimDocument::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/golden/scale/subject01_simbody.osim")).unwrap()).unwrap()
    }

    /// `fixtures/dynamometry/train01` read with `options`.
    pub fn train01(options: &TrialOptions) -> DynamometryData {
        DynamometryData::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/dynamometry/train01"), options).unwrap()
    }
}
