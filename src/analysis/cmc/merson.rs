//! Simbody's Runge–Kutta–Merson step (OpenSim's default integrator; Hairer, Nørsett & Wanner,
//! Solving ODEs I, table 4.1): five stages, the 4th-order solution propagated, |y − ŷ|/5 against
//! the embedded 3rd-order ŷ as its error estimate, normed as Simbody norms it (the larger of the
//! coordinates' RMS error, the speeds' and the auxiliary states' RMS errors relative to |y|
//! where |y| > 1). A window is
//! one step when that norm is within the tolerance, else two half windows, recursively (Simbody
//! instead shrinks its step size and keeps it: its internal steps are not ours, though both meet
//! the tolerance).

use crate::analysis::simulation::{Plant, Workspace};

/// What the integrator advances: ẏ at (t, y), and how many coordinates lead `y` (then as many
/// speeds, then the auxiliary states).
pub trait Rates {
    fn rates(&mut self, time: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String>;
    fn coordinates(&self) -> usize;
}

/// A plant's whole state moved by its dynamics.
pub struct PlantRates<'p, 'a> {
    pub plant: &'p Plant<'a>,
    pub work: Workspace,
}

impl Rates for PlantRates<'_, '_> {
    fn rates(&mut self, time: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        self.plant.derivatives(time, y, dy, &mut self.work)
    }

    fn coordinates(&self) -> usize {
        self.plant.coordinate_states()
    }
}

/// Deepest halving of a window before the integration gives up (without a minimum step).
const MAX_HALVINGS: u32 = 40;
/// Most steps (taken or rejected) one integration makes before it gives up: a thousand times
/// what a CMC window or settling takes, so that an error estimate that stops falling as the
/// steps shrink ends the run with its reason instead of halving towards 2^40 pieces.
const MAX_STEPS: usize = 100_000;

/// The state `y` at `from` (s) of `system` carried to `to` (s) with steps no longer than
/// `max_step` (s) and errors within `tolerance`; an error names the time and the reason.
/// A step as short as `min_step` (s) is taken whatever its error, as Simbody takes a step at the
/// user's minimum step size (a control stepping at a window's start otherwise defeats every step
/// there: its first stage sees the old control).
pub fn integrate(system: &mut impl Rates, y: &[f64], [from, to]: [f64; 2], [min_step, max_step]: [f64; 2], tolerance: f64) -> Result<Vec<f64>, (f64, String)> {
    let pieces = ((to - from) / max_step - 1e-9).ceil().max(1.0) as usize;
    let mut y = y.to_vec();
    let mut steps_left = MAX_STEPS;
    for k in 0..pieces {
        let (a, b) = (from + (to - from) * k as f64 / pieces as f64, from + (to - from) * (k + 1) as f64 / pieces as f64);
        y = adaptive(system, &y, [a, b], min_step, tolerance, 0, &mut steps_left)?;
    }
    Ok(y)
}

/// One step over [from, to], or two halves when its error estimate exceeds `tolerance`; each
/// attempt spends one of `steps_left`.
fn adaptive(system: &mut impl Rates, y: &[f64], [from, to]: [f64; 2], min_step: f64, tolerance: f64, depth: u32, steps_left: &mut usize) -> Result<Vec<f64>, (f64, String)> {
    if *steps_left == 0 {
        return Err((from, format!("{MAX_STEPS} steps did not carry the state through (the error estimate does not fall below the tolerance {tolerance:e} as the steps shrink; here {:e} s)", to - from)));
    }
    *steps_left -= 1;
    let at_minimum = to - from <= min_step;
    // A step whose stages leave the states' domain (a muscle's fiber length below 0) is
    // retried in halves, as one whose error is too large.
    let (y1, norm) = match step(system, y, from, to - from) {
        Ok((y1, error)) => {
            let norm = error_norm(&error, y, system.coordinates());
            (y1, norm)
        }
        Err(failure) if depth >= MAX_HALVINGS || at_minimum => return Err(failure),
        Err(_) => (Vec::new(), f64::INFINITY),
    };
    if norm <= tolerance || at_minimum {
        return Ok(y1);
    }
    if depth >= MAX_HALVINGS {
        return Err((from, format!("the step error {norm:e} stays above the tolerance {tolerance:e} at steps of {:e} s", to - from)));
    }
    let middle = 0.5 * (from + to);
    let half = adaptive(system, y, [from, middle], min_step, tolerance, depth + 1, steps_left)?;
    adaptive(system, &half, [middle, to], min_step, tolerance, depth + 1, steps_left)
}

/// Simbody's `calcErrorNorm` with unit weights: the RMS of the coordinates' errors, of the
/// speeds' errors and of the auxiliary states' errors, the latter two scaled by 1/|y| where
/// |y| > 1 at the step's start `y`; the largest of the three (`n` coordinates, then as many
/// speeds, then the auxiliary states).
fn error_norm(error: &[f64], y: &[f64], n: usize) -> f64 {
    let rms = |values: &mut dyn Iterator<Item = f64>| {
        let (sum, count) = values.fold((0.0, 0usize), |(s, c), v| (s + v * v, c + 1));
        if count == 0 { 0.0 } else { (sum / count as f64).sqrt() }
    };
    let q = rms(&mut error[..n].iter().copied());
    let relative = |(e, y): (&f64, &f64)| if y.abs() > 1.0 { e / y.abs() } else { *e };
    let u = rms(&mut error[n..2 * n].iter().zip(&y[n..2 * n]).map(relative));
    let z = rms(&mut error[2 * n..].iter().zip(&y[2 * n..]).map(relative));
    q.max(u).max(z)
}

/// One Merson step of `h` (s) from `y` at `t0`: the 4th-order y₁ and the error estimate per state.
fn step(system: &mut impl Rates, y0: &[f64], t0: f64, h: f64) -> Result<(Vec<f64>, Vec<f64>), (f64, String)> {
    let mut rate = |t: f64, y: &[f64]| {
        let mut dy = vec![0.0; y.len()];
        system.rates(t, y, &mut dy).map(|()| dy).map_err(|reason| (t, reason))
    };
    let combine = |terms: &[(f64, &[f64])]| -> Vec<f64> { (0..y0.len()).map(|i| y0[i] + terms.iter().map(|(c, f)| c * f[i]).sum::<f64>()).collect() };
    let f0 = rate(t0, y0)?;
    let f1 = rate(t0 + h / 3.0, &combine(&[(h / 3.0, &f0)]))?;
    let f2 = rate(t0 + h / 3.0, &combine(&[(h / 6.0, &f0), (h / 6.0, &f1)]))?;
    let f3 = rate(t0 + h / 2.0, &combine(&[(h / 8.0, &f0), (3.0 * h / 8.0, &f2)]))?;
    let saved = combine(&[(h / 2.0, &f0), (-1.5 * h, &f2), (2.0 * h, &f3)]);
    let f4 = rate(t0 + h, &saved)?;
    let y1 = combine(&[(h / 6.0, &f0), (4.0 * h / 6.0, &f3), (h / 6.0, &f4)]);
    let error = y1.iter().zip(&saved).map(|(a, b)| 0.2 * (a - b).abs()).collect();
    Ok((y1, error))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ẏ = λy (one auxiliary state), or, when `rough`, rates that jump between calls, so the
    /// error estimate never falls with the step.
    struct Decay {
        rate: f64,
        rough: bool,
        calls: usize,
    }

    impl Rates for Decay {
        fn rates(&mut self, _time: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
            self.calls += 1;
            dy[0] = if self.rough { if self.calls.is_multiple_of(2) { 1e3 } else { -1e3 } } else { self.rate * y[0] };
            Ok(())
        }

        fn coordinates(&self) -> usize {
            0
        }
    }

    #[test]
    fn meets_the_tolerance_against_the_exact_solution() {
        let mut decay = Decay { rate: -30.0, rough: false, calls: 0 };
        let y = integrate(&mut decay, &[1.0], [0.0, 0.2], [0.0, 1e-3], 1e-8).unwrap();
        let exact = (-30.0f64 * 0.2).exp();
        // Local errors within 1e-8 per step, 200 steps or more.
        assert!((y[0] - exact).abs() < 200.0 * 1e-8, "{} vs {exact}", y[0]);
    }

    #[test]
    fn gives_up_with_its_reason_when_the_error_never_falls() {
        let mut rough = Decay { rate: 0.0, rough: true, calls: 0 };
        let (time, reason) = integrate(&mut rough, &[0.0], [0.0, 0.01], [0.0, 1e-3], 1e-8).unwrap_err();
        assert!((0.0..0.01).contains(&time) && reason.contains("steps did not carry the state through"), "{time}: {reason}");
        assert!(rough.calls <= 5 * MAX_STEPS + 5, "{} rate evaluations", rough.calls);
    }
}
