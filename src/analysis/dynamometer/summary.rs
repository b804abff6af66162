//! The trial's summary (thesis §5.3): how far the knee's axis sits from the dynamometer's,
//! whether the pad pushes perpendicular to the crank, how Mdyn and M2D agree with M3D per
//! effort direction, and the sensitivity rows.

use super::agreement::{agreement, Agreement};
use super::sensitivity::SensitivityRow;
use super::DynamometerResult;

/// Angles between F_tc and the crank's normal below this count as perpendicular (the thesis'
/// criterion), rad.
pub const PERPENDICULAR_TOLERANCE: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// Mean, standard deviation (n − 1) and largest of a per-frame quantity.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Spread {
    pub mean: f64,
    pub sd: f64,
    pub max: f64,
}

impl Spread {
    fn of(values: impl Iterator<Item = f64>) -> Spread {
        let values: Vec<f64> = values.collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let sd = if values.len() > 1 { (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() } else { 0.0 };
        Spread { mean, sd, max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max) }
    }
}

/// A moment's agreement with M3D over the frames of positive and of negative M3D.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Agreements {
    pub positive: Option<Agreement>,
    pub negative: Option<Agreement>,
}

/// The summary of a [`DynamometerResult`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DynamometerSummary {
    pub frames: usize,
    /// s.
    pub time_range: [f64; 2],
    /// r_knee's distance from the dynamometer's axis, m.
    pub axis_offset: Spread,
    /// The angle between the axes, degrees.
    pub axis_angle: Spread,
    /// F_tc's angle to the crank's normal, degrees.
    pub pad_force_angle: Spread,
    /// The share of frames where that angle is below 15°.
    pub perpendicular_share: f64,
    /// Mdyn − M3D, when Mdyn was measured.
    pub dynamometer: Option<Agreements>,
    /// M2D − M3D, when Mdyn was measured.
    pub herzog: Option<Agreements>,
    pub sensitivity: Vec<SensitivityRow>,
}

impl DynamometerResult {
    /// The trial's summary.
    pub fn summary(&self) -> DynamometerSummary {
        let knee: Vec<f64> = self.frames.iter().map(|f| f.knee_moment).collect();
        let agreements = |other: &[f64]| Agreements { positive: agreement(&self.times, &knee, other, 1.0), negative: agreement(&self.times, &knee, other, -1.0) };
        let angles: Vec<f64> = self.frames.iter().map(|f| f.pad_force_angle()).collect();
        DynamometerSummary {
            frames: self.frames.len(),
            time_range: [self.times[0], self.times[self.times.len() - 1]],
            axis_offset: Spread::of(self.frames.iter().map(|f| f.axis_offset())),
            axis_angle: Spread::of(self.frames.iter().map(|f| f.axis_angle().to_degrees())),
            pad_force_angle: Spread::of(angles.iter().map(|a| a.to_degrees())),
            perpendicular_share: angles.iter().filter(|&&a| a < PERPENDICULAR_TOLERANCE).count() as f64 / angles.len() as f64,
            dynamometer: self.dynamometer.as_deref().map(agreements),
            herzog: self.herzog.as_ref().map(|h| agreements(&h.iter().map(|e| e.knee_moment).collect::<Vec<f64>>())),
            sensitivity: self.sensitivity.clone(),
        }
    }
}
