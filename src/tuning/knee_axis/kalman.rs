//! Kalman (Rauch–Tung–Striebel) smoothing of one segment's pose over a whole trial, as the
//! thesis uses it (after De Groote et al. 2008).
//!
//! **Generalized coordinates.** Six per segment, q = (t, θ): the frame origin t in the lab (m)
//! and a rotation vector θ (rad) such that the segment → lab rotation is R = exp([θ]×)·R_ref,
//! where R_ref is the chordal mean of the per-frame least-squares rotations (so θ stays small
//! and continuous; rotations up to [`MAX_ROTATION_FROM_MEAN`] from the mean are accepted).
//!
//! **Process model.** Per coordinate, the state is the value and its first four time
//! derivatives; the fourth derivative is constant up to white noise on its rate (spectral
//! density S, SI units: m²/s⁹ for translations, rad²/s⁹ for rotations). Between frames the
//! interval Δt comes from the trial's time column. Internally derivative k is stored scaled by
//! h^k/k! (h the mean frame interval) so that every state has the units of its coordinate.
//!
//! **Measurement model.** The visible cluster markers: p = exp([θ]×)·R_ref·l + t + v, with
//! l the marker's local coordinates and v ~ N(0, σ²·I), σ the marker's noise (its weight is
//! 1/σ²). Missing markers are simply absent from that frame's measurement. The model is
//! linearised about the previous pass's trajectory (first pass: the least-squares poses,
//! interpolated over frames without one) and the pass repeated [`KalmanSettings::iterations`]
//! times (an iterated extended smoother).
//!
//! With the defaults, 5 markers with 1 mm noise and 100 Hz sampling the smoother behaves as a
//! low-pass filter of about 6 Hz (ω_c¹⁰ ≈ S/(σ_q²·Δt), σ_q² the per-frame pose variance).

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Rotation3, SMatrix, Vector3, Vector6};

use crate::solvers::kalman_smoother::{information_update, rts_smooth, ORDER};

use super::rotation::{chordal_mean, exp, left_jacobian, log};
use super::segment_pose::{NoPose, SegmentPose};
use super::trajectory::{FrameContext, FramePose};
use super::{AxisError, SegmentCluster};

/// Largest rotation of a segment from its mean orientation that the smoother accepts (170°):
/// the rotation vector is singular at 180°.
pub const MAX_ROTATION_FROM_MEAN: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// Coordinates per segment: three translations, then three rotation-vector components.
const DOFS: usize = 6;
const STATES: usize = ORDER * DOFS;

/// The smoother's noise model (SI units throughout).
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanSettings {
    /// Spectral density of the white noise driving the rate of the 4th derivative of each
    /// translation, m²/s⁹. Default 1e7 (see the module doc: about 6 Hz bandwidth).
    pub process_noise_translation: f64,
    /// The same for each rotation-vector component, rad²/s⁹. Default 1e9 (markers about 0.1 m
    /// from the cluster centre).
    pub process_noise_rotation: f64,
    /// Standard deviation of each marker coordinate, m. Default 1e-3.
    pub marker_noise: f64,
    /// Per-marker standard deviations (m) that replace `marker_noise`, by marker name: a larger
    /// value gives a marker less weight (e.g. markers over much soft tissue).
    pub marker_noise_by_name: BTreeMap<String, f64>,
    /// Smoothing passes, each linearised about the previous one's result. Default 2.
    pub iterations: usize,
}

impl Default for KalmanSettings {
    fn default() -> Self {
        KalmanSettings {
            process_noise_translation: 1e7,
            process_noise_rotation: 1e9,
            marker_noise: 1e-3,
            marker_noise_by_name: BTreeMap::new(),
            iterations: 2,
        }
    }
}

impl KalmanSettings {
    /// Every noise value finite and > 0, at least one iteration.
    pub fn check(&self) -> Result<(), AxisError> {
        let positive = |name: &str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(AxisError::InvalidSetting { name: name.to_owned(), value, expected: "a finite number > 0".into() })
            }
        };
        positive("process_noise_translation", self.process_noise_translation)?;
        positive("process_noise_rotation", self.process_noise_rotation)?;
        positive("marker_noise", self.marker_noise)?;
        for (name, &value) in &self.marker_noise_by_name {
            positive(&format!("marker_noise_by_name[{name}]"), value)?;
        }
        if self.iterations == 0 {
            return Err(AxisError::InvalidSetting { name: "iterations".into(), value: 0.0, expected: "at least 1".into() });
        }
        Ok(())
    }

    /// The standard deviation (m) of marker `name`.
    pub fn noise_of(&self, name: &str) -> f64 {
        self.marker_noise_by_name.get(name).copied().unwrap_or(self.marker_noise)
    }
}

/// Smoothed poses of one segment in every frame. `positions[frame][marker]` are the cluster
/// markers' lab positions (m); `initial` the per-frame least-squares poses.
pub(super) fn smooth_segment(
    cluster: &SegmentCluster,
    positions: &[Vec<Option<Vector3<f64>>>],
    initial: &[Result<FramePose, NoPose>],
    settings: &KalmanSettings,
    context: &FrameContext,
) -> Result<Vec<SegmentPose>, AxisError> {
    settings.check()?;
    let Some(reference) = chordal_mean(initial.iter().flatten().map(|f| &f.pose.rotation)) else {
        let what = format!("segment `{}`: Kalman smoother start (frames with ≥ 3 visible markers)", cluster.segment);
        return Err(AxisError::TooFewFrames { what, frames: 0, needed: 1 });
    };
    let model = SegmentModel {
        local: cluster.local.iter().map(|l| reference * l).collect(),
        noise: cluster.markers.iter().map(|name| settings.noise_of(name)).collect(),
        spectral_density: Vector6::new(
            settings.process_noise_translation,
            settings.process_noise_translation,
            settings.process_noise_translation,
            settings.process_noise_rotation,
            settings.process_noise_rotation,
            settings.process_noise_rotation,
        ),
    };
    let mut trajectory = initial_coordinates(initial, &reference, context)?;
    for _ in 0..settings.iterations {
        trajectory = model.smooth(positions, &trajectory, context)?;
    }
    Ok(trajectory.iter().map(|q| pose_of(q, &reference)).collect())
}

/// The pose of coordinates q = (t, θ): rotation exp(θ)·R_ref, origin t.
fn pose_of(q: &Vector6<f64>, reference: &Rotation3<f64>) -> SegmentPose {
    SegmentPose { rotation: exp(&q.fixed_rows::<3>(3).into_owned()) * reference, translation: q.fixed_rows::<3>(0).into_owned() }
}

/// The least-squares poses as coordinates, linearly interpolated in time over frames without a
/// pose (held constant before the first and after the last).
fn initial_coordinates(initial: &[Result<FramePose, NoPose>], reference: &Rotation3<f64>, context: &FrameContext) -> Result<Vec<Vector6<f64>>, AxisError> {
    let mut known = Vec::new();
    for (frame, pose) in initial.iter().enumerate() {
        let Ok(pose) = pose else { continue };
        let theta = log(&(pose.pose.rotation * reference.inverse()));
        if theta.norm() > MAX_ROTATION_FROM_MEAN {
            return Err(AxisError::RotationOutOfRange {
                segment: context.segment.to_owned(),
                frame: context.frame_numbers[frame],
                time: context.times[frame],
                angle: theta.norm(),
                limit: MAX_ROTATION_FROM_MEAN,
            });
        }
        let t = pose.pose.translation;
        known.push((frame, Vector6::new(t.x, t.y, t.z, theta.x, theta.y, theta.z)));
    }
    let mut next = 0;
    let coordinates = (0..initial.len())
        .map(|frame| {
            while next < known.len() && known[next].0 < frame {
                next += 1;
            }
            match (next.checked_sub(1).map(|i| known[i]), known.get(next).copied()) {
                (_, Some((at, q))) if at == frame => q,
                (Some((before, a)), Some((after, b))) => {
                    let s = (context.times[frame] - context.times[before]) / (context.times[after] - context.times[before]);
                    a + (b - a) * s
                }
                (Some((_, q)), None) | (None, Some((_, q))) => q,
                (None, None) => Vector6::zeros(),
            }
        })
        .collect();
    Ok(coordinates)
}

/// What the smoother knows about one segment.
struct SegmentModel {
    /// R_ref·l of each cluster marker (lab-aligned local coordinates, m).
    local: Vec<Vector3<f64>>,
    /// σ of each cluster marker (m).
    noise: Vec<f64>,
    /// S of each coordinate (m²/s⁹ or rad²/s⁹).
    spectral_density: Vector6<f64>,
}

impl SegmentModel {
    /// One iterated-extended RTS pass linearised about `linearisation`; returns the smoothed
    /// coordinates of every frame.
    fn smooth(
        &self,
        positions: &[Vec<Option<Vector3<f64>>>],
        linearisation: &[Vector6<f64>],
        context: &FrameContext,
    ) -> Result<Vec<Vector6<f64>>, AxisError> {
        let update = |frame: usize, predicted: &DVector<f64>, covariance: &DMatrix<f64>| self.update(predicted, covariance, &positions[frame], &linearisation[frame]);
        let smoothed = rts_smooth(context.times, self.spectral_density.as_slice(), self.prior(&linearisation[0]), update)
            .map_err(|frame| AxisError::Covariance { segment: context.segment.to_owned(), frame: context.frame_numbers[frame] })?;
        Ok(smoothed.iter().map(|x| Vector6::from_iterator(x.rows(0, DOFS).iter().copied())).collect())
    }

    /// The first frame's prior: the linearisation point, zero derivatives, and a wide
    /// covariance (σ = 1 m for translations, π rad for rotations, for every scaled derivative).
    fn prior(&self, start: &Vector6<f64>) -> (DVector<f64>, DMatrix<f64>) {
        let mut state = DVector::zeros(STATES);
        state.rows_mut(0, DOFS).copy_from(start);
        let variance = |dof: usize| if dof < 3 { 1.0 } else { std::f64::consts::PI.powi(2) };
        let covariance = DMatrix::from_diagonal(&DVector::from_fn(STATES, |i, _| variance(i % DOFS)));
        (state, covariance)
    }

    /// The measurement update with the visible markers, in information form on the six
    /// coordinates: with I = Hᵀ W H and r = Hᵀ W (y − h(q₀) − H (q̄ − q₀)),
    /// x⁺ = x̄ + P E (I₆ + I P_qq)⁻¹ r and P⁺ = P − P E (I₆ + I P_qq)⁻¹ I Eᵀ P (E selects q).
    fn update(
        &self,
        predicted: &DVector<f64>,
        covariance: &DMatrix<f64>,
        observed: &[Option<Vector3<f64>>],
        around: &Vector6<f64>,
    ) -> (DVector<f64>, DMatrix<f64>) {
        let (theta, origin) = (around.fixed_rows::<3>(3).into_owned(), around.fixed_rows::<3>(0).into_owned());
        let (rotation, jacobian) = (exp(&theta), left_jacobian(&theta));
        let prior_q = Vector6::from_iterator(predicted.rows(0, DOFS).iter().copied());
        let (mut information, mut residual) = (Matrix6::<f64>::zeros(), Vector6::<f64>::zeros());
        let mut visible = 0;
        for ((local, sigma), position) in self.local.iter().zip(&self.noise).zip(observed) {
            let Some(measured) = position else { continue };
            visible += 1;
            let u = rotation * local;
            let mut h = SMatrix::<f64, 3, 6>::zeros();
            h.fixed_view_mut::<3, 3>(0, 0).copy_from(&Matrix3::identity());
            h.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-u.cross_matrix() * jacobian));
            let innovation = measured - (u + origin) - h * (prior_q - around);
            let weight = 1.0 / (sigma * sigma);
            information += h.transpose() * h * weight;
            residual += h.transpose() * innovation * weight;
        }
        if visible == 0 {
            return (predicted.clone(), covariance.clone());
        }
        let information = DMatrix::from_iterator(DOFS, DOFS, information.iter().copied());
        let residual = DVector::from_iterator(DOFS, residual.iter().copied());
        information_update(predicted, covariance, &information, &residual).unwrap_or_else(|| (predicted.clone(), covariance.clone()))
    }
}
