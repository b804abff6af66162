//! `ModelScaler`: how the ScaleTool scales the generic model (measurements and manual scales).

use std::path::Path;

use serde::Serialize;

use super::error::SetupError;
use super::measurement::Measurement;
use super::object::{read_object, set_members};
use super::path::SetupPath;
use super::property::optional_path;
use super::time_range::TimeRange;
use crate::model::ComponentReader;

/// The `ModelScaler` of a ScaleTool setup, with OpenSim's defaults (`ModelScaler.cpp`) for
/// absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelScaler {
    /// Whether scaling runs (default true).
    pub apply: bool,
    /// The steps in the order they are applied (default none); a later step overrides the factors
    /// an earlier one set for the same body.
    pub scaling_order: Vec<ScalingStep>,
    /// `MeasurementSet` (default empty).
    pub measurements: Vec<Measurement>,
    /// `ScaleSet`: the factors of the `manualScale` step (default empty).
    pub manual_scales: Vec<ManualScale>,
    /// The `.trc` whose marker-pair distances the measurements average.
    pub marker_file: Option<SetupPath>,
    /// The frames of `marker_file` averaged (default −1 to −1).
    pub time_range: TimeRange,
    /// Keep the ratios of the body masses, scaling all to the subject's mass (default false).
    pub preserve_mass_distribution: bool,
    pub output_model_file: Option<SetupPath>,
    /// Where the applied scale factors are written (a `ScaleSet`).
    pub output_scale_file: Option<SetupPath>,
}

/// A word of `scaling_order` (spelled exactly so, as OpenSim compares them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ScalingStep {
    /// `measurements`: factors from the `MeasurementSet`.
    Measurements,
    /// `manualScale`: factors from the `ScaleSet`.
    ManualScale,
}

/// A `Scale` of the manual `ScaleSet`, with OpenSim's defaults (`Scale.cpp`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ManualScale {
    /// The body (default `unnamed_segment`, which names none).
    pub segment: String,
    /// Factors along the body frame's X, Y, Z, each finite and > 0 (default 1 1 1).
    pub scales: [f64; 3],
    /// Whether the factors are used (default true).
    pub apply: bool,
}

impl ModelScaler {
    /// Reads a `<ModelScaler>`; its sets may be given by `file` relative to `directory`.
    pub(super) fn read(scaler: ComponentReader, directory: &Path) -> Result<ModelScaler, SetupError> {
        let measurements = read_object(scaler, "MeasurementSet", directory, |set| {
            set_members(set, &["Measurement"])?.into_iter().map(|m| Measurement::read(m, directory)).collect()
        })?;
        let manual_scales = read_object(scaler, "ScaleSet", directory, |set| {
            set_members(set, &["Scale"])?.into_iter().map(ManualScale::read).collect()
        })?;
        Ok(ModelScaler {
            apply: scaler.boolean_or("apply", true)?,
            scaling_order: read_scaling_order(scaler)?,
            measurements: measurements.unwrap_or_default(),
            manual_scales: manual_scales.unwrap_or_default(),
            marker_file: optional_path(scaler, "marker_file", directory),
            time_range: TimeRange::read_or(scaler, TimeRange { start: -1.0, end: -1.0 })?,
            preserve_mass_distribution: scaler.boolean_or("preserve_mass_distribution", false)?,
            output_model_file: optional_path(scaler, "output_model_file", directory),
            output_scale_file: optional_path(scaler, "output_scale_file", directory),
        })
    }
}

fn read_scaling_order(scaler: ComponentReader) -> Result<Vec<ScalingStep>, SetupError> {
    let step = |word: String| match word.as_str() {
        "measurements" => Ok(ScalingStep::Measurements),
        "manualScale" => Ok(ScalingStep::ManualScale),
        _ => Err(SetupError::from(scaler.bad("scaling_order", "the words measurements and/or manualScale", &word))),
    };
    scaler.words("scaling_order").into_iter().map(step).collect()
}

impl ManualScale {
    fn read(scale: ComponentReader) -> Result<ManualScale, SetupError> {
        let scales = if scale.child("scales").is_some() { scale.vec3("scales")? } else { [1.0; 3] };
        if !scales.iter().all(|&s| s.is_finite() && s > 0.0) {
            return Err(scale.bad("scales", "three finite scale factors > 0", &scale.optional_text("scales").unwrap_or_default()).into());
        }
        Ok(ManualScale {
            segment: scale.optional_text("segment").unwrap_or_else(|| "unnamed_segment".into()),
            scales,
            apply: scale.boolean_or("apply", true)?,
        })
    }
}
