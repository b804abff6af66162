//! Identifiability of the estimated muscles' L_opt and L_ts from the trial moments (thesis
//! eq. 2.26–2.30 and table 6.4): the Fisher information F = JᵀJ/σ² (C_y = σ²I) with
//! J = ∂M/∂p, its D-criterion det F (reported as log10 det F), E-criterion λ_min(F), condition
//! number, the Cramér–Rao standard deviations √(F⁻¹)_ii, and — when J has lower rank than the
//! number of parameters, as whenever there are fewer trials than parameters — which parameters
//! cannot be identified and along which directions.
//!
//! Three parameterisations p per muscle ([`Parameterisation`]):
//! - [L_opt, L_ts] (m, m);
//! - [L̃m_min, L̃m_max], Garner & Pandy's (dimensionless; map in `garner_pandy.rs`);
//! - [L_ts/L_opt, δ] with δ = 1/L_opt − c1·L_ts/L_opt − c2 (1/m) and the muscle's regression
//!   line (c1, c2) of Phase I (eq. 6.13–6.14); inversely L_opt = 1/(δ + c1·r + c2), L_ts = r·L_opt.
//!
//! **Derivatives**: central differences of the perturbed muscle's contribution F_t·r (the other
//! muscles' terms cancel), with step h = ε·scale, ε = [`FisherOptions::relative_step`] (1e-4 by
//! default: truncation error ~ε² relative, rounding ~1e-11 N·m / h) and scale = |p| for L_opt,
//! L_ts, L̃m and L_ts/L_opt, and 1/L_opt for δ (δ is a deviation of 1/L_opt and is often 0).
//!
//! **Units**: the absolute criteria are in the parameterisation's units (they change with the
//! unit of length); the relative criteria are those of diag(s)·F·diag(s), the information per
//! relative change (s the scales above), comparable across parameterisations. Rank, null-space
//! directions and identifiability are decided on the relative Jacobian: singular values at most
//! [`FisherOptions::rank_tolerance`] times the largest count as zero, and there are never more
//! nonzero ones than trials. A parameter is identifiable when its unit vector has no component
//! in the null space (share ≤ [`UNIDENTIFIABLE_SHARE`]); its Cramér–Rao standard deviation is
//! then √(e_iᵀF⁺e_i) (F's pseudo-inverse: the bound of an estimable parameter), otherwise none.

use nalgebra::DMatrix;
use serde::Serialize;

use super::error::FunctionalError;
use super::garner_pandy::{JointRange, NormalizedFiberLengthRange};
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;

/// Default relative central-difference step.
pub const DEFAULT_FISHER_STEP: f64 = 1e-4;

/// Default relative singular-value threshold of the rank (well above the ~1e-8 accuracy of the
/// differences).
pub const DEFAULT_RANK_TOLERANCE: f64 = 1e-6;

/// A parameter whose squared unit-vector component in the null space exceeds this is not
/// identifiable.
pub const UNIDENTIFIABLE_SHARE: f64 = 1e-6;

/// Null-direction components smaller than this (in magnitude) are not listed.
pub const NULL_COMPONENT_CUTOFF: f64 = 0.01;

/// How each estimated muscle's (L_opt, L_ts) is parameterised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Parameterisation<'a> {
    /// [L_opt, L_ts].
    Hill,
    /// [L̃m_min, L̃m_max] over this joint range (one entry per estimated muscle).
    GarnerPandy(&'a JointRange),
    /// [L_ts/L_opt, δ] with these (c1, c2) in 1/m, one per estimated muscle, in order.
    SlackRatioDelta(&'a [(f64, f64)]),
}

/// A transformed parameter of one muscle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum TransformedParameter {
    /// L_opt, m.
    OptimalFiberLength,
    /// L_ts, m.
    TendonSlackLength,
    /// L̃m_min (dimensionless).
    MinimumNormalizedFiberLength,
    /// L̃m_max (dimensionless).
    MaximumNormalizedFiberLength,
    /// L_ts/L_opt (dimensionless).
    SlackToOptimalRatio,
    /// δ = 1/L_opt − c1·L_ts/L_opt − c2, 1/m.
    Delta,
    /// s, the coordinate on the muscle's rest curve (`rest_curve.rs`; dimensionless).
    RestCurveCoordinate,
}

impl TransformedParameter {
    pub fn symbol(self) -> &'static str {
        match self {
            TransformedParameter::OptimalFiberLength => "L_opt",
            TransformedParameter::TendonSlackLength => "L_ts",
            TransformedParameter::MinimumNormalizedFiberLength => "L̃m_min",
            TransformedParameter::MaximumNormalizedFiberLength => "L̃m_max",
            TransformedParameter::SlackToOptimalRatio => "L_ts/L_opt",
            TransformedParameter::Delta => "δ",
            TransformedParameter::RestCurveCoordinate => "s",
        }
    }

    /// SI unit ("" when dimensionless).
    pub fn unit(self) -> &'static str {
        match self {
            TransformedParameter::OptimalFiberLength | TransformedParameter::TendonSlackLength => "m",
            TransformedParameter::Delta => "1/m",
            _ => "",
        }
    }
}

/// The name of [`Parameterisation::GarnerPandy`].
pub const GARNER_PANDY_PARAMETERS: &str = "[L̃m_min, L̃m_max]";

impl Parameterisation<'_> {
    /// `[L_opt, L_ts]`, `[L̃m_min, L̃m_max]` or `[L_ts/L_opt, δ]`.
    pub fn name(&self) -> &'static str {
        match self {
            Parameterisation::Hill => "[L_opt, L_ts]",
            Parameterisation::GarnerPandy(_) => GARNER_PANDY_PARAMETERS,
            Parameterisation::SlackRatioDelta(_) => "[L_ts/L_opt, δ]",
        }
    }

    /// The two parameters of a muscle.
    pub fn parameters(&self) -> [TransformedParameter; 2] {
        match self {
            Parameterisation::Hill => [TransformedParameter::OptimalFiberLength, TransformedParameter::TendonSlackLength],
            Parameterisation::GarnerPandy(_) => {
                [TransformedParameter::MinimumNormalizedFiberLength, TransformedParameter::MaximumNormalizedFiberLength]
            }
            Parameterisation::SlackRatioDelta(_) => [TransformedParameter::SlackToOptimalRatio, TransformedParameter::Delta],
        }
    }

    /// The two values of estimated muscle `e` with parameters `p`.
    pub fn encode(&self, e: usize, p: &MuscleParameters) -> Result<[f64; 2], FunctionalError> {
        let (optimal, slack) = (p.optimal_fiber_length, p.tendon_slack_length);
        match self {
            Parameterisation::Hill => Ok([optimal, slack]),
            Parameterisation::GarnerPandy(range) => {
                let lengths = muscle_range(range, e, p)?.normalized_fiber_lengths(p)?;
                Ok([lengths.minimum, lengths.maximum])
            }
            Parameterisation::SlackRatioDelta(lines) => {
                let (c1, c2) = line(lines, e, p)?;
                let ratio = slack / optimal;
                Ok([ratio, 1.0 / optimal - c1 * ratio - c2])
            }
        }
    }

    /// `base` (estimated muscle `e`) with L_opt and L_ts of `values`.
    pub fn decode(&self, e: usize, values: [f64; 2], base: &MuscleParameters) -> Result<MuscleParameters, FunctionalError> {
        let mut p = base.clone();
        match self {
            Parameterisation::Hill => [p.optimal_fiber_length, p.tendon_slack_length] = values,
            Parameterisation::GarnerPandy(range) => {
                p = muscle_range(range, e, base)?.apply(NormalizedFiberLengthRange { minimum: values[0], maximum: values[1] }, base)?;
            }
            Parameterisation::SlackRatioDelta(lines) => {
                let (c1, c2) = line(lines, e, base)?;
                let [ratio, delta] = values;
                p.optimal_fiber_length = 1.0 / (delta + c1 * ratio + c2);
                p.tendon_slack_length = ratio * p.optimal_fiber_length;
            }
        }
        p.check()?;
        Ok(p)
    }

    /// The scales of the two values (see the module documentation).
    pub fn scales(&self, values: [f64; 2], p: &MuscleParameters) -> [f64; 2] {
        match self {
            Parameterisation::SlackRatioDelta(_) => [values[0].abs(), 1.0 / p.optimal_fiber_length],
            _ => [values[0].abs(), values[1].abs()],
        }
    }
}

fn muscle_range<'r>(range: &'r JointRange, e: usize, p: &MuscleParameters) -> Result<&'r super::garner_pandy::MusculotendonRange, FunctionalError> {
    range.muscles.get(e).filter(|r| r.muscle == p.name).ok_or_else(|| FunctionalError::Parameters {
        muscle: p.name.clone(),
        problem: format!("the joint range has no entry for estimated muscle {e}"),
    })
}

fn line(lines: &[(f64, f64)], e: usize, p: &MuscleParameters) -> Result<(f64, f64), FunctionalError> {
    lines.get(e).copied().filter(|(c1, c2)| c1.is_finite() && c2.is_finite()).ok_or_else(|| FunctionalError::Parameters {
        muscle: p.name.clone(),
        problem: format!("no finite regression line (c1, c2) for estimated muscle {e}; expected one per estimated muscle"),
    })
}

/// Settings of [`fisher_information`].
#[derive(Debug, Clone, PartialEq)]
pub struct FisherOptions {
    /// σ of the moment noise, N·m (C_y = σ²I).
    pub noise_sd: f64,
    /// ε of the central differences.
    pub relative_step: f64,
    /// Relative singular-value threshold of the rank.
    pub rank_tolerance: f64,
    /// Estimated muscles (indices) whose parameters are analysed; `None`: all. The others are
    /// fixed at the given values.
    pub muscles: Option<Vec<usize>>,
    /// Trials (indices into [`KneeMomentModel::trials`]) used as observations; `None`: all.
    pub trials: Option<Vec<usize>>,
}

impl FisherOptions {
    /// All muscles and trials, default step and tolerance, noise σ = `noise_sd` N·m.
    pub fn new(noise_sd: f64) -> FisherOptions {
        FisherOptions { noise_sd, relative_step: DEFAULT_FISHER_STEP, rank_tolerance: DEFAULT_RANK_TOLERANCE, muscles: None, trials: None }
    }
}

/// A parameter of the analysis: its muscle, which parameter, its value and scale.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParameterLabel {
    pub muscle: String,
    pub parameter: TransformedParameter,
    /// Value at which F is evaluated, in the parameter's unit.
    pub value: f64,
    /// Scale of the relative criteria and of the difference step.
    pub scale: f64,
}

/// Scalar criteria of an information matrix, from its eigenvalues λ (= s²/σ², s the singular
/// values of the Jacobian).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FisherCriteria {
    /// log10 det F (D-criterion); −∞ when F is singular by structure (fewer observations than
    /// parameters).
    pub log10_determinant: f64,
    /// λ_min(F) (E-criterion); 0 when singular by structure.
    pub min_eigenvalue: f64,
    pub max_eigenvalue: f64,
    /// λ_max/λ_min (∞ when λ_min = 0).
    pub condition_number: f64,
    /// log10 of the product of the min(m, n) largest eigenvalues (m observations, n
    /// parameters): the D-criterion of what the observations can see; equals
    /// `log10_determinant` when m ≥ n. Compares parameterisations when there are fewer
    /// trials than parameters.
    pub log10_pseudo_determinant: f64,
    /// The min(m, n)-th eigenvalue: the E-criterion restricted likewise.
    pub min_observable_eigenvalue: f64,
}

/// One component of a null-space direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NullComponent {
    pub muscle: String,
    pub parameter: TransformedParameter,
    /// Component of the unit direction in relative coordinates (Δp/scale).
    pub weight: f64,
}

/// A direction in parameter space along which the moments do not change (to first order).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NullDirection {
    /// Relative singular value of the direction (0 for the structural ones).
    pub singular_value: f64,
    /// Components with |weight| ≥ [`NULL_COMPONENT_CUTOFF`], largest first.
    pub components: Vec<NullComponent>,
}

/// A parameter that the observations cannot determine.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnidentifiableParameter {
    /// Index into [`FisherInformation::labels`].
    pub index: usize,
    pub muscle: String,
    pub parameter: TransformedParameter,
    /// ‖P_null e_i‖² ∈ (0, 1]: 1 = the moments carry no information on it at all.
    pub null_space_share: f64,
}

/// Rank and null space of the (relative) Jacobian.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identifiability {
    pub observations: usize,
    pub parameters: usize,
    /// Numerical rank of J.
    pub rank: usize,
    /// Relative singular values of J/σ, largest first (`parameters` values; beyond
    /// `observations` exactly 0).
    pub singular_values: Vec<f64>,
    /// A basis of the null space (`parameters − rank` directions).
    pub null_directions: Vec<NullDirection>,
    pub unidentifiable: Vec<UnidentifiableParameter>,
}

impl Identifiability {
    /// Every parameter identifiable (J of full column rank).
    pub fn is_identifiable(&self) -> bool {
        self.rank == self.parameters
    }

    /// Fewer observations (trials) than parameters: never identifiable.
    pub fn fewer_observations_than_parameters(&self) -> bool {
        self.observations < self.parameters
    }
}

/// The Fisher information of a parameterisation at given parameters, and what follows from it.
#[derive(Debug, Clone, PartialEq)]
pub struct FisherInformation {
    /// The parameterisation's name ([`Parameterisation::name`]).
    pub parameterisation: &'static str,
    pub noise_sd: f64,
    /// The parameters, muscle by muscle, two each.
    pub labels: Vec<ParameterLabel>,
    /// J = ∂M/∂p, observations × parameters, N·m per unit of each parameter.
    pub jacobian: DMatrix<f64>,
    /// F = JᵀJ/σ².
    pub matrix: DMatrix<f64>,
    /// Criteria of F.
    pub absolute: FisherCriteria,
    /// Criteria of diag(scale)·F·diag(scale).
    pub relative: FisherCriteria,
    /// Cramér–Rao standard deviation of each parameter in its unit; `None` where not
    /// identifiable.
    pub standard_deviations: Vec<Option<f64>>,
    pub identifiability: Identifiability,
}

impl FisherInformation {
    /// Everything from a Jacobian J (observations × parameters, one label per column; the
    /// labels' scales define the relative criteria and must be positive).
    pub fn from_jacobian(
        parameterisation: &'static str,
        jacobian: DMatrix<f64>,
        labels: Vec<ParameterLabel>,
        noise_sd: f64,
        rank_tolerance: f64,
    ) -> Result<FisherInformation, FunctionalError> {
        let bad = FunctionalError::all_muscles;
        if !(noise_sd > 0.0 && noise_sd.is_finite()) {
            return Err(bad(format!("noise standard deviation {noise_sd} N·m; expected a positive finite number")));
        }
        if labels.len() != jacobian.ncols() || labels.is_empty() {
            return Err(bad(format!("{} labels for {} Jacobian columns; expected one per column, at least one", labels.len(), jacobian.ncols())));
        }
        if let Some(label) = labels.iter().find(|l| !(l.scale > 0.0 && l.scale.is_finite())) {
            return Err(FunctionalError::Parameters {
                muscle: label.muscle.clone(),
                problem: format!("{} has scale {}; expected a positive finite number", label.parameter.symbol(), label.scale),
            });
        }
        if jacobian.iter().any(|v| !v.is_finite()) {
            return Err(bad("the Jacobian has non-finite entries".into()));
        }
        let (m, n) = jacobian.shape();
        let matrix = jacobian.tr_mul(&jacobian) / (noise_sd * noise_sd);
        let absolute_spectrum = RightSingular::of(&jacobian);
        let mut relative_jacobian = jacobian.clone();
        for (mut column, label) in relative_jacobian.column_iter_mut().zip(&labels) {
            column *= label.scale;
        }
        let spectrum = RightSingular::of(&relative_jacobian);
        let largest = spectrum.values[0];
        let rank = spectrum.values.iter().take(m).filter(|&&s| s > rank_tolerance * largest && s > 0.0).count();
        let null: Vec<usize> = (rank..n).collect();
        let null_directions = null
            .iter()
            .map(|&k| {
                let vector = spectrum.vectors.column(k);
                let mut components: Vec<NullComponent> = labels
                    .iter()
                    .zip(vector.iter())
                    .filter(|(_, w)| w.abs() >= NULL_COMPONENT_CUTOFF)
                    .map(|(label, &weight)| NullComponent { muscle: label.muscle.clone(), parameter: label.parameter, weight })
                    .collect();
                components.sort_by(|a, b| b.weight.abs().total_cmp(&a.weight.abs()));
                NullDirection { singular_value: spectrum.values[k] / noise_sd, components }
            })
            .collect();
        let shares: Vec<f64> = (0..n).map(|i| null.iter().map(|&k| spectrum.vectors[(i, k)].powi(2)).sum()).collect();
        let unidentifiable = shares
            .iter()
            .enumerate()
            .filter(|(_, &share)| share > UNIDENTIFIABLE_SHARE)
            .map(|(index, &share)| UnidentifiableParameter {
                index,
                muscle: labels[index].muscle.clone(),
                parameter: labels[index].parameter,
                null_space_share: share,
            })
            .collect();
        let standard_deviations = (0..n)
            .map(|i| {
                (shares[i] <= UNIDENTIFIABLE_SHARE).then(|| {
                    let variance: f64 = (0..rank).map(|k| (spectrum.vectors[(i, k)] / spectrum.values[k]).powi(2)).sum();
                    noise_sd * labels[i].scale * variance.sqrt()
                })
            })
            .collect();
        let identifiability = Identifiability {
            observations: m,
            parameters: n,
            rank,
            singular_values: spectrum.values.iter().map(|s| s / noise_sd).collect(),
            null_directions,
            unidentifiable,
        };
        Ok(FisherInformation {
            parameterisation,
            noise_sd,
            absolute: absolute_spectrum.criteria(m, noise_sd),
            relative: spectrum.criteria(m, noise_sd),
            labels,
            jacobian,
            matrix,
            standard_deviations,
            identifiability,
        })
    }
}

/// Singular values (descending; n of them, those beyond the row count exactly 0) and right
/// singular vectors (columns, n × n) of an m × n matrix.
struct RightSingular {
    values: Vec<f64>,
    vectors: DMatrix<f64>,
}

impl RightSingular {
    fn of(matrix: &DMatrix<f64>) -> RightSingular {
        let (m, n) = matrix.shape();
        // Zero rows up to a square matrix give the full set of right singular vectors.
        let mut padded = DMatrix::zeros(m.max(n), n);
        padded.rows_mut(0, m).copy_from(matrix);
        let svd = padded.svd(false, true);
        let v_t = svd.v_t.expect("requested");
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
        let values = order.iter().enumerate().map(|(rank, &k)| if rank < m { svd.singular_values[k] } else { 0.0 }).collect();
        let vectors = DMatrix::from_fn(n, n, |i, j| v_t[(order[j], i)]);
        RightSingular { values, vectors }
    }

    /// Criteria of F = JᵀJ/σ² from J's singular values (m observations).
    fn criteria(&self, m: usize, noise_sd: f64) -> FisherCriteria {
        let eigenvalues: Vec<f64> = self.values.iter().map(|s| (s / noise_sd).powi(2)).collect();
        let n = eigenvalues.len();
        let (max, min) = (eigenvalues[0], eigenvalues[n - 1]);
        let observable = &eigenvalues[..m.min(n)];
        let log10_pseudo_determinant = observable.iter().map(|l| l.log10()).sum();
        let log10_determinant = if m < n { f64::NEG_INFINITY } else { log10_pseudo_determinant };
        FisherCriteria {
            log10_determinant,
            min_eigenvalue: min,
            max_eigenvalue: max,
            condition_number: max / min,
            log10_pseudo_determinant,
            min_observable_eigenvalue: observable.last().copied().unwrap_or(0.0),
        }
    }
}

/// The Fisher information of `parameterisation` at `parameters` (one per estimated muscle, in
/// order) for the trial moments of `knee`.
pub fn fisher_information(
    knee: &KneeMomentModel,
    parameters: &[MuscleParameters],
    parameterisation: &Parameterisation,
    options: &FisherOptions,
) -> Result<FisherInformation, FunctionalError> {
    let n_estimated = knee.estimated_names().count();
    let n_trials = knee.trials().len();
    let bad = FunctionalError::all_muscles;
    let muscles: Vec<usize> = options.muscles.clone().unwrap_or_else(|| (0..n_estimated).collect());
    let trials: Vec<usize> = options.trials.clone().unwrap_or_else(|| (0..n_trials).collect());
    if let Some(e) = muscles.iter().find(|&&e| e >= n_estimated) {
        return Err(bad(format!("muscle index {e}; expected one below {n_estimated}")));
    }
    if let Some(t) = trials.iter().find(|&&t| t >= n_trials) {
        return Err(bad(format!("trial index {t}; expected one below {n_trials}")));
    }
    if muscles.is_empty() || trials.is_empty() {
        return Err(bad("no muscles or no trials selected".into()));
    }
    if !(options.relative_step > 0.0 && options.relative_step < 0.1) {
        return Err(bad(format!("relative step {}; expected a fraction in (0, 0.1)", options.relative_step)));
    }
    let mut workspace = knee.estimated_muscles(parameters)?;
    let mut labels = Vec::with_capacity(2 * muscles.len());
    let mut jacobian = DMatrix::zeros(trials.len(), 2 * muscles.len());
    for (i, &e) in muscles.iter().enumerate() {
        let base = &parameters[e];
        let values = parameterisation.encode(e, base)?;
        let scales = parameterisation.scales(values, base);
        let k = knee.estimated_knee_index(e);
        for j in 0..2 {
            let h = options.relative_step * scales[j];
            let mut contributions = [vec![0.0; trials.len()], vec![0.0; trials.len()]];
            for (sign, out) in [1.0, -1.0].into_iter().zip(contributions.iter_mut()) {
                let mut shifted = values;
                shifted[j] += sign * h;
                workspace.set(knee, e, &parameterisation.decode(e, shifted, base)?)?;
                for (slot, &t) in out.iter_mut().zip(&trials) {
                    *slot = knee.contribution(k, workspace.muscle(e), t)?;
                }
            }
            for (row, (plus, minus)) in contributions[0].iter().zip(&contributions[1]).enumerate() {
                jacobian[(row, 2 * i + j)] = (plus - minus) / (2.0 * h);
            }
            let parameter = parameterisation.parameters()[j];
            labels.push(ParameterLabel { muscle: base.name.clone(), parameter, value: values[j], scale: scales[j] });
        }
        workspace.set(knee, e, base)?;
    }
    FisherInformation::from_jacobian(parameterisation.name(), jacobian, labels, options.noise_sd, options.rank_tolerance)
}
