//! `Measurement`: a scale factor from marker-pair distances, applied to bodies along chosen axes.

use std::path::Path;

use serde::Serialize;

use super::error::SetupError;
use super::object::{read_object, set_members};
use super::property::{name_or_empty, required_name};
use crate::model::ComponentReader;

/// One measurement of a `MeasurementSet`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Measurement {
    /// For messages (may be empty).
    pub name: String,
    /// Whether the measurement is used (default true).
    pub apply: bool,
    /// `MarkerPairSet`: the two marker names of each pair; the scale factor is the mean over the
    /// pairs of experimental / model distance.
    pub marker_pairs: Vec<[String; 2]>,
    /// `BodyScaleSet`: the bodies the factor scales.
    pub body_scales: Vec<BodyScale>,
}

/// `BodyScale`: a body and the axes of its frame the measurement scales it along.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodyScale {
    pub body: String,
    /// Scaled along X, Y, Z (`axes`, e.g. `X Y Z` or `Y`; lower case accepted as by OpenSim;
    /// absent: none).
    pub axes: [bool; 3],
}

impl Measurement {
    /// Reads a `<Measurement>`; its sets may be given by `file` relative to `directory`.
    pub(super) fn read(measurement: ComponentReader, directory: &Path) -> Result<Measurement, SetupError> {
        let marker_pairs = read_object(measurement, "MarkerPairSet", directory, |set| {
            set_members(set, &["MarkerPair"])?.into_iter().map(read_marker_pair).collect()
        })?;
        let body_scales = read_object(measurement, "BodyScaleSet", directory, |set| {
            set_members(set, &["BodyScale"])?.into_iter().map(BodyScale::read).collect()
        })?;
        Ok(Measurement {
            name: name_or_empty(measurement),
            apply: measurement.boolean_or("apply", true)?,
            marker_pairs: marker_pairs.unwrap_or_default(),
            body_scales: body_scales.unwrap_or_default(),
        })
    }
}

/// A `<MarkerPair>`'s `markers`: exactly two names.
fn read_marker_pair(pair: ComponentReader) -> Result<[String; 2], SetupError> {
    match <[String; 2]>::try_from(pair.words("markers")) {
        Ok(names) => Ok(names),
        Err(_) => Err(pair.bad("markers", "exactly two marker names", &pair.optional_text("markers").unwrap_or_default()).into()),
    }
}

impl BodyScale {
    fn read(body_scale: ComponentReader) -> Result<BodyScale, SetupError> {
        let mut axes = [false; 3];
        for axis in body_scale.words("axes") {
            let Some(index) = ["X", "Y", "Z"].iter().position(|name| axis.eq_ignore_ascii_case(name)) else {
                let text = body_scale.optional_text("axes").unwrap_or_default();
                return Err(body_scale.bad("axes", "axis names X, Y or Z", &text).into());
            };
            axes[index] = true;
        }
        Ok(BodyScale { body: required_name(body_scale, "body")?, axes })
    }
}
