//! Linear scaling from a trials folder: `subject.json` names the subject's mass and static
//! trial (and optionally a marker set, a time range and a ScaleTool setup); without a setup the
//! built-in gait2392 measurement set (`default_scale_setup.xml`) is used.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::error::ScaleError;
use crate::io::osim::OsimDocument;
use crate::setup::{GenericModelMaker, ScaleSetup, SetupPath, TimeRange};

/// The subject file of a trials folder.
pub const SUBJECT_FILE: &str = "subject.json";

/// The built-in ScaleTool setup: OpenSim's subject01 example without its manual factors.
const DEFAULT_SETUP: &str = include_str!("default_scale_setup.xml");

/// `subject.json`: file names relative to the folder.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubjectFile {
    /// kg.
    pub mass: f64,
    /// The static `.trc` trial.
    pub static_trial: String,
    /// Seconds of the static trial to average; the whole trial when absent.
    pub time_range: Option<[f64; 2]>,
    /// A `MarkerSet` file put on the model before scaling.
    pub marker_set: Option<String>,
    /// A ScaleTool setup whose measurements, manual factors and IK tasks are used.
    pub setup: Option<String>,
}

/// The ScaleTool setup for the trials folder `folder`.
pub fn trials_setup(folder: &Path) -> Result<ScaleSetup, ScaleError> {
    let file = folder.join(SUBJECT_FILE);
    let bad = |problem: String| ScaleError::Input { file: file.clone(), problem };
    let text = std::fs::read_to_string(&file).map_err(|e| bad(format!("cannot read the subject file: {e}")))?;
    let subject: SubjectFile = serde_json::from_str(&text).map_err(|e| bad(format!("line {}: {e}", e.line())))?;
    let mut setup = match &subject.setup {
        Some(name) => ScaleSetup::read(&folder.join(name)).map_err(|e| bad(e.to_string()))?,
        None => {
            let document = OsimDocument::parse(DEFAULT_SETUP.to_string(), &folder.join("(built-in gait2392 scale setup)"))?;
            ScaleSetup::from_document(&document).map_err(|e| bad(e.to_string()))?
        }
    };
    setup.mass = subject.mass;
    let range = subject.time_range.map_or(TimeRange { start: f64::NEG_INFINITY, end: f64::INFINITY }, |[start, end]| TimeRange { start, end });
    if range.start > range.end {
        return Err(bad(format!("time_range {} > {}", range.start, range.end)));
    }
    let trial = Some(SetupPath::resolve(&subject.static_trial, folder));
    if let Some(scaler) = setup.model_scaler.as_mut() {
        scaler.marker_file = trial.clone();
        scaler.time_range = range;
    }
    if let Some(placer) = setup.marker_placer.as_mut() {
        placer.marker_file = trial;
        placer.time_range = range;
    }
    if let Some(marker_set) = &subject.marker_set {
        let maker = setup.generic_model_maker.get_or_insert(GenericModelMaker { model_file: None, marker_set_file: None });
        maker.marker_set_file = Some(SetupPath::resolve(marker_set, folder));
    }
    setup.file = PathBuf::from(&file);
    Ok(setup)
}
