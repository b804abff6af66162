//! A Rauch–Tung–Striebel smoother for `dims` coordinates whose fourth time derivative is
//! constant up to white noise on its rate (De Groote et al. 2008's process model, used by the
//! thesis for segment poses and inverse kinematics).
//!
//! **State.** Per coordinate the value and its first four derivatives, derivative-major
//! (entry k·dims + j is derivative k of coordinate j), derivative k scaled by h^k/k! (h the
//! mean frame interval) so that every entry has its coordinate's unit.
//!
//! **Process noise.** Coordinate j's spectral density S_j (unit²/s⁹). As a filter the smoother
//! passes frequencies below about ω_c, with ω_c¹⁰ ≈ S/(σ_q²·Δt) for a coordinate measured with
//! per-frame variance σ_q² ([`spectral_density_for_cutoff`]).
//!
//! **Measurements** enter in information form ([`information_update`]): the caller's
//! linearised model gives I = HᵀR⁻¹H and r = HᵀR⁻¹(y − h(x₀) − H(x̄ − x₀)) on the values.

use nalgebra::{DMatrix, DVector, SMatrix};

/// State entries per coordinate: the value and four derivatives.
pub const ORDER: usize = 5;

/// S (unit²/s⁹) that gives a coordinate measured with per-frame variance `variance` (unit²)
/// every `dt` seconds a bandwidth of about `cutoff` Hz.
pub fn spectral_density_for_cutoff(cutoff: f64, variance: f64, dt: f64) -> f64 {
    (2.0 * std::f64::consts::PI * cutoff).powi(2 * ORDER as i32) * variance * dt
}

/// The mean frame interval h of `times` (s) that scales the state's derivatives (1 for a
/// single frame).
pub fn mean_interval(times: &[f64]) -> f64 {
    match times {
        [first, .., last] => (last - first) / (times.len() - 1) as f64,
        _ => 1.0,
    }
}

/// Derivative k of each of the `dims` coordinates in `state`, unscaled (in unit/s^k) for the
/// mean frame interval `h`.
pub fn derivative(state: &DVector<f64>, dims: usize, k: usize, h: f64) -> Vec<f64> {
    let factor = (1..=k).product::<usize>() as f64 / h.powi(k as i32);
    state.rows(k * dims, dims).iter().map(|v| v * factor).collect()
}

/// Smooths over frames at `times` (s) with spectral densities `spectral_density` (one per
/// coordinate): `prior` is the first frame's predicted state and covariance, `update(frame,
/// predicted, covariance)` returns the frame's filtered ones (a pure function: the backward pass
/// calls it again). Returns every frame's smoothed state, or the frame whose predicted
/// covariance could not be inverted.
///
/// Memory: the filtered states of all N frames, but the (5·dims)² covariances of only about
/// 2√N: the forward pass keeps those of every ⌈√N⌉-th frame, and the backward pass refilters
/// one stretch between checkpoints at a time (one more update per frame).
pub fn rts_smooth(
    times: &[f64],
    spectral_density: &[f64],
    prior: (DVector<f64>, DMatrix<f64>),
    update: impl Fn(usize, &DVector<f64>, &DMatrix<f64>) -> (DVector<f64>, DMatrix<f64>),
) -> Result<Vec<DVector<f64>>, usize> {
    let n = times.len();
    let h = mean_interval(times);
    let transition = |frame: usize| {
        let dt = times[frame + 1] - times[frame];
        (transition(spectral_density.len(), dt, h), process_noise(spectral_density, dt, h))
    };
    // The filtered state and covariance of `frame` from those of the frame before it.
    let filter = |frame: usize, previous: Option<(&DVector<f64>, &DMatrix<f64>)>| match previous {
        None => update(frame, &prior.0, &prior.1),
        Some((state, covariance)) => {
            let (f, q) = transition(frame - 1);
            update(frame, &(&f * state), &(&f * covariance * f.transpose() + q))
        }
    };
    let stride = checkpoint_stride(n);
    let (mut states, mut checkpoints) = (Vec::with_capacity(n), Vec::with_capacity(n.div_ceil(stride)));
    let mut covariance = DMatrix::zeros(0, 0);
    for frame in 0..n {
        let (state, next) = filter(frame, states.last().map(|state| (state, &covariance)));
        if frame % stride == 0 {
            checkpoints.push(next.clone());
        }
        states.push(state);
        covariance = next;
    }
    // x_s(k) = x_f(k) + P_f(k)·Fᵀ·P_p(k+1)⁻¹·(x_s(k+1) − F·x_f(k)), stretch by stretch backwards.
    let mut smoothed = vec![DVector::zeros(prior.0.len()); n];
    smoothed[n - 1] = states[n - 1].clone();
    while let Some(first) = checkpoints.pop() {
        let start = checkpoints.len() * stride;
        let mut covariances = vec![first];
        for frame in start + 1..(start + stride).min(n) {
            let refiltered = filter(frame, Some((&states[frame - 1], &covariances[covariances.len() - 1]))).1;
            covariances.push(refiltered);
        }
        for (frame, covariance) in (start..start + covariances.len()).zip(&covariances).rev().filter(|(frame, _)| frame + 1 < n) {
            let (f, q) = transition(frame);
            let predicted_covariance = &f * covariance * f.transpose() + q;
            let difference = &smoothed[frame + 1] - &f * &states[frame];
            let gain_input = solve_symmetric(&predicted_covariance, &difference).ok_or(frame + 1)?;
            smoothed[frame] = &states[frame] + covariance * (f.transpose() * gain_input);
        }
    }
    Ok(smoothed)
}

/// Frames between the covariances the forward pass keeps: ⌈√N⌉ for N frames.
fn checkpoint_stride(frames: usize) -> usize {
    (frames as f64).sqrt().ceil().max(1.0) as usize
}

/// The measurement update in information form on the values (the first `dims` entries):
/// x⁺ = x̄ + P E (I + 𝓘 P_qq)⁻¹ r and P⁺ = P − P E (I + 𝓘 P_qq)⁻¹ 𝓘 Eᵀ P, E selecting the values;
/// `None` when I + 𝓘 P_qq is singular.
pub fn information_update(predicted: &DVector<f64>, covariance: &DMatrix<f64>, information: &DMatrix<f64>, residual: &DVector<f64>) -> Option<(DVector<f64>, DMatrix<f64>)> {
    let dims = residual.len();
    let p_qq = covariance.view((0, 0), (dims, dims));
    let lu = (DMatrix::identity(dims, dims) + information * p_qq).lu();
    let (gain_residual, gain_information) = (lu.solve(residual)?, lu.solve(information)?);
    let pe = covariance.columns(0, dims);
    let state = predicted + pe * gain_residual;
    let updated = covariance - pe * gain_information * pe.transpose();
    Some((state, (&updated + updated.transpose()) * 0.5))
}

/// Solves P·y = b for a symmetric positive-definite P (Cholesky, falling back to LU).
fn solve_symmetric(p: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let y = match p.clone().cholesky() {
        Some(cholesky) => cholesky.solve(b),
        None => p.clone().lu().solve(b)?,
    };
    y.iter().all(|v| v.is_finite()).then_some(y)
}

/// F = F₁ ⊗ I_dims over `dt` seconds for states scaled by h^k/k!.
fn transition(dims: usize, dt: f64, h: f64) -> DMatrix<f64> {
    let f1 = transition_1d(dt, h);
    DMatrix::from_fn(ORDER * dims, ORDER * dims, |r, c| if r % dims == c % dims { f1[(r / dims, c / dims)] } else { 0.0 })
}

/// Q = Q₁ ⊗ diag(S) over `dt` seconds.
fn process_noise(spectral_density: &[f64], dt: f64, h: f64) -> DMatrix<f64> {
    let (dims, q1) = (spectral_density.len(), noise_1d(dt, h));
    DMatrix::from_fn(ORDER * dims, ORDER * dims, |r, c| if r % dims == c % dims { q1[(r / dims, c / dims)] * spectral_density[r % dims] } else { 0.0 })
}

/// The scaled state's transition for one coordinate: F₁[i][j] = C(j, i)·(Δt/h)^(j−i), j ≥ i.
fn transition_1d(dt: f64, h: f64) -> SMatrix<f64, ORDER, ORDER> {
    let ratio = dt / h;
    SMatrix::from_fn(|i, j| if j >= i { binomial(j, i) * ratio.powi((j - i) as i32) } else { 0.0 })
}

/// The scaled process noise for one coordinate per unit spectral density:
/// Q₁[i][j] = s_i·s_j·Δt^(9−i−j) / ((4−i)!·(4−j)!·(9−i−j)), s_k = h^k/k!.
fn noise_1d(dt: f64, h: f64) -> SMatrix<f64, ORDER, ORDER> {
    let scale = |k: usize| h.powi(k as i32) / factorial(k);
    SMatrix::from_fn(|i, j| {
        let power = 2 * (ORDER - 1) + 1 - i - j;
        scale(i) * scale(j) * dt.powi(power as i32) / (factorial(ORDER - 1 - i) * factorial(ORDER - 1 - j) * power as f64)
    })
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

fn binomial(n: usize, k: usize) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::AddAssign;

    /// F₁ must propagate a quartic polynomial exactly: with q(t) = Σ c_k t^k, the scaled state at
    /// t + Δt equals F₁ times the scaled state at t.
    #[test]
    fn transition_propagates_a_quartic_exactly() {
        let (h, dt, t): (f64, f64, f64) = (0.01, 0.013, 0.7);
        let c = [0.3, -1.2, 2.5, 4.0, -7.0];
        let scaled_state = |t: f64| {
            SMatrix::<f64, ORDER, 1>::from_fn(|k, _| {
                let derivative: f64 = (k..ORDER).map(|p| c[p] * factorial(p) / factorial(p - k) * t.powi((p - k) as i32)).sum();
                derivative * h.powi(k as i32) / factorial(k)
            })
        };
        let propagated = transition_1d(dt, h) * scaled_state(t);
        assert!((propagated - scaled_state(t + dt)).amax() < 1e-12);
    }

    /// Q₁ is the integral of F₁(s)·e₅·e₅ᵀ·F₁(s)ᵀ over the interval (checked by the midpoint rule).
    #[test]
    fn process_noise_is_the_integrated_fifth_derivative_noise() {
        let (h, dt) = (0.01, 0.01);
        let steps = 20_000;
        let mut integral = SMatrix::<f64, ORDER, ORDER>::zeros();
        for step in 0..steps {
            let s = (step as f64 + 0.5) * dt / steps as f64;
            // The unscaled input e₅ (noise on the 4th derivative's rate) scaled by s₄ = h⁴/4!.
            let column = transition_1d(s, h).column(ORDER - 1) * (h.powi(4) / 24.0);
            integral += column * column.transpose() * (dt / steps as f64);
        }
        let q = noise_1d(dt, h);
        assert!(((integral - q).amax() / q.amax()) < 1e-6, "{integral}\n{q}");
    }

    /// For a linear model the RTS smoother's states are the posterior mean of all states given
    /// all measurements: the minimiser of the batch least squares ‖x₀ − m₀‖²_P₀⁻¹ +
    /// Σ ‖x_k+1 − F_k x_k‖²_Q_k⁻¹ + Σ (y_k − x_k,0)²/r, solved here as one linear system. Two
    /// coordinates, uneven frame intervals, N = 1 (no stretch), 2, 17 (a short last stretch)
    /// and 36 (a square). They agree to 10⁻⁴ of the states' size: Q₁ alone has a condition
    /// number near 10⁶, and the batch system inverts it (the difference stays below 10⁻⁵; a
    /// stretch refiltered from the wrong covariance misses by far more).
    #[test]
    fn smoothed_states_are_the_batch_least_squares_solution() {
        let (dims, r) = (2, 0.04);
        let spectral_density = [0.02, 0.5];
        for frames in [1, 2, 17, 36] {
            let times: Vec<f64> = (0..frames).map(|k| k as f64 + 0.3 * (k as f64 * 1.7).sin()).collect();
            let h = mean_interval(&times);
            let y: Vec<[f64; 2]> = times.iter().map(|t| [t.sin() + 0.1 * (7.0 * t).cos(), 0.5 * t - 0.2 * (3.0 * t).sin()]).collect();
            let m = ORDER * dims;
            let prior_mean = DVector::from_fn(m, |i, _| if i < dims { y[0][i] } else { 0.0 });
            let prior_covariance = DMatrix::from_diagonal_element(m, m, 4.0);
            let update = |k: usize, predicted: &DVector<f64>, covariance: &DMatrix<f64>| {
                let information = DMatrix::from_diagonal_element(dims, dims, 1.0 / r);
                let residual = DVector::from_fn(dims, |j, _| (y[k][j] - predicted[j]) / r);
                information_update(predicted, covariance, &information, &residual).unwrap()
            };
            let smoothed = rts_smooth(&times, &spectral_density, (prior_mean.clone(), prior_covariance.clone()), update).unwrap();
            // Normal equations A x = b of the batch problem over all N·m states.
            let (mut a, mut b) = (DMatrix::zeros(frames * m, frames * m), DVector::zeros(frames * m));
            let p0 = prior_covariance.clone().try_inverse().unwrap();
            a.view_mut((0, 0), (m, m)).add_assign(&p0);
            b.rows_mut(0, m).add_assign(&(&p0 * &prior_mean));
            for k in 0..frames {
                for j in 0..dims {
                    a[(k * m + j, k * m + j)] += 1.0 / r;
                    b[k * m + j] += y[k][j] / r;
                }
                if k + 1 < frames {
                    let dt = times[k + 1] - times[k];
                    let (f, q) = (transition(dims, dt, h), process_noise(&spectral_density, dt, h));
                    let w = q.try_inverse().unwrap();
                    // The residual x_k+1 − F x_k = [−F  I]·[x_k; x_k+1].
                    let mut g = DMatrix::zeros(m, 2 * m);
                    g.view_mut((0, 0), (m, m)).copy_from(&(-&f));
                    g.view_mut((0, m), (m, m)).copy_from(&DMatrix::identity(m, m));
                    a.view_mut((k * m, k * m), (2 * m, 2 * m)).add_assign(&(g.transpose() * &w * &g));
                }
            }
            let batch = a.cholesky().unwrap().solve(&b);
            for (k, state) in smoothed.iter().enumerate() {
                let expected = batch.rows(k * m, m);
                assert!((state - expected).amax() < 1e-4 * expected.amax().max(1.0), "N = {frames}, frame {k}: {state} against {expected}");
            }
        }
    }

    /// The Kronecker layouts: coordinate j's entries are k·dims + j.
    #[test]
    fn kronecker_layout() {
        let (f, q) = (transition(2, 0.01, 0.01), process_noise(&[1.0, 4.0], 0.01, 0.01));
        let (f1, q1) = (transition_1d(0.01, 0.01), noise_1d(0.01, 0.01));
        assert_eq!((f[(0, 2)], f[(1, 3)], f[(0, 3)]), (f1[(0, 1)], f1[(0, 1)], 0.0));
        assert_eq!((q[(1, 3)], q[(0, 1)]), (4.0 * q1[(0, 1)], 0.0));
    }
}
