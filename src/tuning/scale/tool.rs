//! OpenSim's `ScaleTool`: generic model maker (marker set), model scaler (measurements and
//! manual factors in the setup's order, then `Model::scale`) and marker placer.

use std::path::Path;

use super::error::ScaleError;
use super::marker_placer::{place_markers, MarkerPlacement};
use super::marker_set::{read_marker_set, update_marker_set};
use super::measurement::{measure, DefaultPoseMarkers, MeasuredFactor};
use super::model_scaler::{scale_model, ScaledModel};
use super::scale_set::ScaleSet;
use crate::io::osim::OsimDocument;
use crate::io::table::MarkerTable;
use crate::mechanics::Multibody;
use crate::model::{upgrade, ModelSpec};
use crate::setup::{ModelScaler, ScaleSetup, ScalingStep};
use crate::solvers::{CoordinateValues, IkTasks};

/// Scale factors outside [1/3, 3] are refused: such a factor comes from a unit mix-up or a
/// mislabelled marker, not from a subject.
pub const LARGEST_SCALE_FACTOR: f64 = 3.0;

/// Everything the Scale step produced.
#[derive(Debug, Clone)]
pub struct ScaleOutcome {
    pub scale_set: ScaleSet,
    pub measurements: Vec<MeasuredFactor>,
    /// Bodies named by measurements or manual scales that the model does not have (OpenSim
    /// ignores them too).
    pub unknown_bodies: Vec<String>,
    /// The scaled model before marker placement (`None` when the model scaler is off).
    pub scaled: Option<ScaledModel>,
    pub placement: Option<MarkerPlacement>,
    /// The final model: placed, else scaled, else the generic model with its marker set.
    pub document: OsimDocument,
}

/// Runs the Scale step of `setup` on `generic` (the setup's `model_file` is not read, so a
/// caller may pass another model; a 2.x/3.x one is converted to OpenSim 4's format first, as
/// OpenSim 4's ScaleTool loads it). `progress` receives one line per step.
pub fn run_scale_tool(generic: &OsimDocument, setup: &ScaleSetup, progress: &mut dyn FnMut(&str)) -> Result<ScaleOutcome, ScaleError> {
    let mut document = upgrade(generic)?.into_owned();
    if let Some(file) = setup.generic_model_maker.as_ref().and_then(|m| m.marker_set_file.as_ref()) {
        progress(&format!("markers: {}", file.written));
        document = update_marker_set(&document, &read_marker_set(&file.resolved)?)?;
    }
    let mut outcome = ScaleOutcome { scale_set: ScaleSet { bodies: Vec::new() }, measurements: Vec::new(), unknown_bodies: Vec::new(), scaled: None, placement: None, document };
    if let Some(scaler) = setup.model_scaler.as_ref().filter(|s| s.apply) {
        progress("scaling the model");
        check_subject_mass(setup)?;
        let document = outcome.document.clone();
        scale_set(&document, scaler, setup, &mut outcome)?;
        let scaled = scale_model(&outcome.document, &outcome.scale_set, scaler.preserve_mass_distribution, Some(setup.mass))?;
        outcome.document = scaled.document.clone();
        outcome.scaled = Some(scaled);
    }
    if let Some(placer) = setup.marker_placer.as_ref().filter(|p| p.apply) {
        let file = placer.marker_file.as_ref().ok_or_else(|| missing(setup, "MarkerPlacer", "marker_file"))?;
        progress(&format!("placing markers on {}", file.written));
        let trial = MarkerTable::read(&file.resolved)?;
        let tasks = IkTasks::from_task_set(&placer.ik_tasks, &setup.file, CoordinateValues::read_setup_file(placer.coordinate_file.as_ref())?)?;
        let placement = place_markers(&outcome.document, &trial, &file.resolved, &tasks, placer.time_range)?;
        outcome.document = placement.document.clone();
        outcome.placement = Some(placement);
    }
    Ok(outcome)
}

/// The scale set of `scaler`'s steps in order, each measurement's factor checked.
fn scale_set(model: &OsimDocument, scaler: &ModelScaler, setup: &ScaleSetup, outcome: &mut ScaleOutcome) -> Result<(), ScaleError> {
    let spec = ModelSpec::read(model)?;
    let mut set = ScaleSet::unit(spec.bodies.iter().map(|b| b.name.as_str()));
    for step in &scaler.scaling_order {
        match step {
            ScalingStep::Measurements => {
                let file = scaler.marker_file.as_ref().ok_or_else(|| missing(setup, "ModelScaler", "marker_file"))?;
                let trial = MarkerTable::read(&file.resolved)?.in_meters();
                let multibody = Multibody::new(&spec)?;
                let markers = DefaultPoseMarkers::new(&multibody)?;
                for measurement in scaler.measurements.iter().filter(|m| m.apply) {
                    let measured = measure(&markers, &trial, &file.resolved, scaler.time_range, measurement)?;
                    check_factor(&file.resolved, &measured.measurement, measured.factor)?;
                    for body_scale in &measurement.body_scales {
                        if !set.set_axes(&body_scale.body, body_scale.axes, measured.factor) {
                            outcome.unknown_bodies.push(body_scale.body.clone());
                        }
                    }
                    outcome.measurements.push(measured);
                }
            }
            ScalingStep::ManualScale => {
                for manual in scaler.manual_scales.iter().filter(|m| m.apply) {
                    for factor in manual.scales {
                        check_factor(&setup.file, &format!("manual scale of {}", manual.segment), factor)?;
                    }
                    if !set.set(&manual.segment, manual.scales) {
                        outcome.unknown_bodies.push(manual.segment.clone());
                    }
                }
            }
        }
    }
    outcome.scale_set = set;
    Ok(())
}

fn check_factor(file: &Path, what: &str, factor: f64) -> Result<(), ScaleError> {
    if factor.is_finite() && (1.0 / LARGEST_SCALE_FACTOR..=LARGEST_SCALE_FACTOR).contains(&factor) {
        return Ok(());
    }
    Err(ScaleError::BadValue {
        file: file.into(),
        what: format!("scale factor of {what}"),
        value: factor,
        expected: format!("a factor between 1/{LARGEST_SCALE_FACTOR} and {LARGEST_SCALE_FACTOR} (check the trial's length unit and the marker names)"),
    })
}

fn check_subject_mass(setup: &ScaleSetup) -> Result<(), ScaleError> {
    if setup.mass > 0.0 && setup.mass.is_finite() {
        return Ok(());
    }
    Err(ScaleError::BadValue { file: setup.file.clone(), what: "subject <mass>".into(), value: setup.mass, expected: "the subject's mass in kg, > 0".into() })
}

fn missing(setup: &ScaleSetup, object: &str, property: &str) -> ScaleError {
    ScaleError::Input { file: setup.file.clone(), problem: format!("{object}: <{property}> is not set but the step is applied") }
}
