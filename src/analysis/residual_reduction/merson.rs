//! Simbody's Runge–Kutta–Merson step (OpenSim's default integrator; Hairer, Nørsett & Wanner,
//! Solving ODEs I, table 4.1): five stages, the 4th-order solution propagated, |y − ŷ|/5 against
//! the embedded 3rd-order ŷ as its error estimate. A window is one step when that estimate is
//! within the tolerance (relative to |y|, at least 1), else two half windows, recursively.

use crate::analysis::simulation::{Plant, Workspace};

/// Deepest halving of a window before the integration gives up.
const MAX_HALVINGS: u32 = 12;

/// The state `y` at `from` (s) of `plant` carried to `to` (s) with steps no longer than
/// `max_step` (s) and errors within `tolerance`; an error names the time and the reason.
pub fn integrate(plant: &Plant, y: &[f64], [from, to]: [f64; 2], max_step: f64, tolerance: f64, work: &mut Workspace) -> Result<Vec<f64>, (f64, String)> {
    let pieces = ((to - from) / max_step - 1e-9).ceil().max(1.0) as usize;
    let mut y = y.to_vec();
    for k in 0..pieces {
        let (a, b) = (from + (to - from) * k as f64 / pieces as f64, from + (to - from) * (k + 1) as f64 / pieces as f64);
        y = adaptive(plant, &y, [a, b], tolerance, work, 0)?;
    }
    Ok(y)
}

/// One step over [from, to], or two halves when its error estimate exceeds `tolerance`.
fn adaptive(plant: &Plant, y: &[f64], [from, to]: [f64; 2], tolerance: f64, work: &mut Workspace, depth: u32) -> Result<Vec<f64>, (f64, String)> {
    let (y1, error) = step(plant, y, from, to - from, work)?;
    let norm = error.iter().zip(&y1).map(|(e, y)| e / y.abs().max(1.0)).fold(0.0, f64::max);
    if norm <= tolerance {
        return Ok(y1);
    }
    if depth >= MAX_HALVINGS {
        return Err((from, format!("the step error {norm:e} stays above the tolerance {tolerance:e} at steps of {:e} s", to - from)));
    }
    let middle = 0.5 * (from + to);
    let half = adaptive(plant, y, [from, middle], tolerance, work, depth + 1)?;
    adaptive(plant, &half, [middle, to], tolerance, work, depth + 1)
}

/// One Merson step of `h` (s) from `y` at `t0`: the 4th-order y₁ and the error estimate per state.
fn step(plant: &Plant, y0: &[f64], t0: f64, h: f64, work: &mut Workspace) -> Result<(Vec<f64>, Vec<f64>), (f64, String)> {
    let mut rate = |t: f64, y: &[f64]| {
        let mut dy = vec![0.0; y.len()];
        plant.derivatives(t, y, &mut dy, work).map(|()| dy).map_err(|reason| (t, reason))
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
