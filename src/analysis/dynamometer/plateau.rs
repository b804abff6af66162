//! An isometric contraction on the dynamometer as one functional-scaling trial (thesis ch. 5 →
//! ch. 6): its plateau — the frames around the largest |M3D| while |M3D| stays at least a
//! fraction of it — and the plateau's mean M3D and coordinates.

use std::ops::RangeInclusive;

use super::{frames_of, DynamometerError, DynamometerModel};
use crate::analysis::external_loads::ExternalLoads;
use crate::analysis::splined_motion::SplinedMotion;
use crate::mechanics::Multibody;

/// An isometric contraction's plateau, averaged.
#[derive(Debug, Clone, PartialEq)]
pub struct IsometricContraction {
    /// The plateau's frame times, s.
    pub times: Vec<f64>,
    /// The mean M3D over the plateau, N·m (the knee coordinate's generalized force).
    pub knee_moment: f64,
    /// The largest |M3D| of the contraction, N·m.
    pub peak: f64,
    /// Every coordinate's mean value over the plateau ([`Multibody::coordinates`] order; rad or m).
    pub coordinates: Vec<f64>,
    /// How far the crank turned over the plateau (largest minus smallest angle), rad.
    pub crank_motion: f64,
}

impl IsometricContraction {
    /// The plateau's first and last frame times, s.
    pub fn time_range(&self) -> [f64; 2] {
        [self.times[0], self.times[self.times.len() - 1]]
    }
}

/// The frames around the largest |moment| while |moment| ≥ `fraction` of it; `None` without
/// frames or when every moment is 0.
pub fn plateau(moments: &[f64], fraction: f64) -> Option<RangeInclusive<usize>> {
    let (peak_frame, peak) = moments.iter().map(|m| m.abs()).enumerate().max_by(|a, b| a.1.total_cmp(&b.1))?;
    if peak <= 0.0 {
        return None;
    }
    let held = |i: &usize| moments[*i].abs() >= fraction * peak;
    let first = (0..peak_frame).rev().take_while(held).last().unwrap_or(peak_frame);
    let last = (peak_frame + 1..moments.len()).take_while(held).last().unwrap_or(peak_frame);
    Some(first..=last)
}

/// The contraction along `motion` with the load cell in `loads`: M3D at every frame of the
/// motion, its plateau at `fraction` of the peak, and the plateau's means.
pub fn isometric_contraction(multibody: &Multibody, model: &DynamometerModel, motion: &SplinedMotion, loads: &ExternalLoads, fraction: f64) -> Result<IsometricContraction, DynamometerError> {
    let motion = model.measured_motion(multibody, motion, [f64::NEG_INFINITY, f64::INFINITY])?;
    let moments: Vec<f64> = frames_of(multibody, model, &motion, loads).iter().map(|f| f.knee_moment).collect();
    let rows = plateau(&moments, fraction).ok_or_else(|| DynamometerError::Data { file: motion.file.clone(), problem: "M3D is zero at every frame: no contraction".into() })?;
    let states = &motion.states[rows.clone()];
    let n = states.len() as f64;
    let mut coordinates = vec![0.0; multibody.coordinates.len()];
    for state in states {
        coordinates.iter_mut().zip(&state.q).for_each(|(mean, value)| *mean += value / n);
    }
    let crank = states.iter().map(|state| state.q[model.crank_coordinate]);
    let crank_motion = crank.clone().fold(f64::NEG_INFINITY, f64::max) - crank.fold(f64::INFINITY, f64::min);
    Ok(IsometricContraction {
        times: motion.times[rows.clone()].to_vec(),
        knee_moment: moments[rows].iter().sum::<f64>() / n,
        peak: moments.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
        coordinates,
        crank_motion,
    })
}

#[cfg(test)]
mod tests {
    use super::plateau;

    #[test]
    fn the_plateau_is_the_run_around_the_peak_above_the_fraction() {
        let moments = [0.0, -5.0, -9.5, -10.0, -9.2, -8.0, -9.9, -1.0];
        assert_eq!(plateau(&moments, 0.9), Some(2..=4));
        assert_eq!(plateau(&moments, 0.5), Some(1..=6));
        assert_eq!(plateau(&[3.0], 0.9), Some(0..=0));
        assert_eq!(plateau(&[0.0, 0.0], 0.9), None);
        assert_eq!(plateau(&[], 0.9), None);
    }
}
