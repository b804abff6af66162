//! Kalman-smoothed inverse kinematics, as the thesis computes joint kinematics (after De Groote
//! et al. 2008): every frame's markers through the model (the IK residuals, their weights
//! included) and a process model whose coordinates have a constant 4th derivative
//! (`kalman_smoother.rs`), smoothed over the whole trial.
//!
//! The measurement model of a frame is the IK objective linearised about a trajectory (first
//! the per-frame IK solution, then each pass's result: an iterated extended smoother): the
//! residuals r ≈ r₀ + J(x − x₀) over the free values x have variance σ²/W, W the frame's
//! total weight of markers with data, σ the noise of a marker of weight 1. Each free value's
//! spectral density is set from the cutoff f_c: S = (2πf_c)¹⁰·σ_x²·Δt with σ_x² its median
//! per-frame variance (the inverse of W·JᵀJ), so σ itself cancels and every coordinate is
//! smoothed to about f_c. The smoothed values are clamped to the clamped coordinates' ranges.
//!
//! Links between bodies held exactly (the IK's default) enter each frame's measurements as
//! residuals a million times surer than a marker's, and each smoothed pose, its speeds and its
//! accelerations are then projected onto the links, the least change over the free speeds
//! ([`crate::mechanics::Multibody::project_onto_links`],
//! [`crate::mechanics::Multibody::project_accelerations_onto_links`]); links under a finite
//! weight stay goals.

use nalgebra::{DMatrix, DVector};

use super::report::IkSolution;
use super::solver::{InverseKinematics, Linearisation};
use crate::solvers::kalman_smoother::{derivative, information_update, mean_interval, rts_smooth, spectral_density_for_cutoff, ORDER};
use crate::solvers::IkError;

/// How the smoother runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalmanIkSettings {
    /// The smoother's bandwidth, Hz.
    pub cutoff: f64,
    /// Passes, each linearised about the previous one's result. Default 2.
    pub iterations: usize,
}

impl KalmanIkSettings {
    /// `cutoff` Hz, two passes.
    pub fn with_cutoff(cutoff: f64) -> KalmanIkSettings {
        KalmanIkSettings { cutoff, iterations: 2 }
    }
}

/// The prior variance of every state entry at the first frame, in units of its value's median
/// per-frame variance: diffuse.
const PRIOR_VARIANCE: f64 = 1e8;
/// Relative regularisation of W·JᵀJ when inverting it for a value's variance.
const REGULARISATION: f64 = 1e-12;
/// The largest link error (m; a weld's orientation error) a smoothed pose keeps: each is
/// projected onto the links, as per-frame IK holds them.
const HELD_LINK_TOLERANCE: f64 = 1e-10;

/// Kalman-smoothed kinematics: the poses with their marker errors, and the smoother's speeds and
/// accelerations of every coordinate per frame (rad/s, rad/s² or m/s, m/s²; [`Multibody`]
/// coordinate order).
///
/// [`Multibody`]: crate::mechanics::Multibody
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothedKinematics {
    pub solution: IkSolution,
    pub speeds: Vec<Vec<f64>>,
    pub accelerations: Vec<Vec<f64>>,
}

impl InverseKinematics<'_> {
    /// The Kalman-smoothed kinematics of the frames `solution` solved (consecutive trial frames
    /// from [`InverseKinematics::solve`]): their poses and errors (each frame keeps its IK
    /// status, its iterations are the smoother's passes), speeds and accelerations.
    pub fn smooth(&self, solution: &IkSolution, settings: &KalmanIkSettings) -> Result<SmoothedKinematics, IkError> {
        if !(settings.cutoff.is_finite() && settings.cutoff > 0.0) || settings.iterations == 0 {
            return Err(IkError::Smoother { problem: format!("cutoff {} Hz and {} passes; expected a cutoff > 0 and at least one pass", settings.cutoff, settings.iterations) });
        }
        let frames: Vec<usize> = solution.frames.iter().map(|f| f.frame).collect();
        let times: Vec<f64> = solution.frames.iter().map(|f| f.time).collect();
        let mut workspace = self.workspace();
        let mut states: Vec<FreeState> = solution.frames.iter().map(|f| FreeState { value: self.free_values(&f.q), rate: Vec::new(), acceleration: Vec::new() }).collect();
        let mut variances = Vec::new();
        for pass in 0..settings.iterations {
            let linearised = frames.iter().zip(&states).map(|(&frame, x)| self.linearise(frame, &self.pose_of(&x.value), &mut workspace)).collect::<Result<Vec<_>, _>>()?;
            if pass == 0 {
                variances = median_variances(&linearised);
            }
            states = smooth_pass(&linearised, &times, &variances, settings.cutoff).map_err(|k| IkError::Smoother { problem: format!("the predicted covariance at t = {} s is singular", times[k]) })?;
        }
        let multibody = self.model.multibody;
        let (mut smoothed, mut speeds, mut accelerations) = (Vec::with_capacity(frames.len()), Vec::new(), Vec::new());
        for (((&frame, &time), x), solved) in frames.iter().zip(&times).zip(&states).zip(&solution.frames) {
            let mut q = self.clamped_pose(&x.value);
            let (mut u, mut udot) = self.rates(&q, &x.rate, &x.acceleration);
            if self.exact_links() {
                multibody.project_onto_links(&mut q, &mut u, HELD_LINK_TOLERANCE).map_err(|e| IkError::Smoother { problem: format!("at t = {time} s: {e}") })?;
                multibody.project_accelerations_onto_links(&q, &u, &mut udot);
            }
            smoothed.push(self.frame_at_pose(frame, &q, &mut workspace, settings.iterations, solved.status)?);
            speeds.push(u);
            accelerations.push(udot);
        }
        Ok(SmoothedKinematics { solution: IkSolution { markers: solution.markers.clone(), coordinates: solution.coordinates.clone(), frames: smoothed }, speeds, accelerations })
    }
}

/// One frame's smoothed free values and their first two time derivatives.
struct FreeState {
    value: Vec<f64>,
    rate: Vec<f64>,
    acceleration: Vec<f64>,
}

/// One smoothing pass over the linearised frames, each free value with its median per-frame
/// variance `variances`; the smoothed free values and derivatives per frame.
fn smooth_pass(linearised: &[Linearisation], times: &[f64], variances: &[f64], cutoff: f64) -> Result<Vec<FreeState>, usize> {
    let n = variances.len();
    let dt = mean_interval(times);
    let spectral_density: Vec<f64> = variances.iter().map(|&v| spectral_density_for_cutoff(cutoff, v, dt)).collect();
    let mut state = DVector::zeros(ORDER * n);
    state.rows_mut(0, n).copy_from_slice(&linearised[0].x);
    let prior = (state, DMatrix::from_fn(ORDER * n, ORDER * n, |r, c| if r == c { PRIOR_VARIANCE * variances[r % n] } else { 0.0 }));
    let update = |k: usize, predicted: &DVector<f64>, covariance: &DMatrix<f64>| {
        let l = &linearised[k];
        let information = l.information();
        let offset = predicted.rows(0, n) - DVector::from_column_slice(&l.x);
        let residual = -(l.jacobian.transpose() * (&l.residuals + &l.jacobian * offset)) * l.total_weight;
        information_update(predicted, covariance, &information, &residual).unwrap_or_else(|| (predicted.clone(), covariance.clone()))
    };
    let smoothed = rts_smooth(times, &spectral_density, prior, update)?;
    Ok(smoothed.iter().map(|x| FreeState { value: derivative(x, n, 0, dt), rate: derivative(x, n, 1, dt), acceleration: derivative(x, n, 2, dt) }).collect())
}

/// Each free value's median per-frame variance, the diagonal of (W·JᵀJ)⁻¹ (regularised where
/// the markers leave a value undetermined), in units of σ².
fn median_variances(linearised: &[Linearisation]) -> Vec<f64> {
    let n = linearised[0].x.len();
    let mut variances: Vec<Vec<f64>> = vec![Vec::with_capacity(linearised.len()); n];
    for l in linearised {
        let information = l.information();
        let scale = information.diagonal().max().max(f64::MIN_POSITIVE);
        let regularised = &information + DMatrix::identity(n, n) * (REGULARISATION * scale);
        if let Some(inverse) = regularised.cholesky().map(|c| c.inverse()) {
            for (j, v) in variances.iter_mut().enumerate() {
                v.push(inverse[(j, j)]);
            }
        }
    }
    variances
        .into_iter()
        .map(|mut v| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(1.0)
        })
        .collect()
}
