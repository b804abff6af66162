//! OpenSim's `MarkerPlacer`: the static trial averaged over the time range, inverse kinematics of
//! that one frame, then every non-fixed model marker moved onto its experimental position.

use std::path::Path;

use super::edits::{apply, numbers_edit};
use super::error::ScaleError;
use super::measurement::{check_range, frame_range};
use super::model_scaler::reparse;
use crate::io::osim::OsimDocument;
use crate::io::table::{MarkerTable, TrcHeader};
use crate::mechanics::{Multibody, Vec3};
use crate::model::{ComponentReader, ModelSpec};
use crate::setup::TimeRange;
use crate::solvers::{IkFrame, IkSettings, IkTasks, InverseKinematics};

/// The placed model and the static pose it was placed in.
#[derive(Debug, Clone)]
pub struct MarkerPlacement {
    pub document: OsimDocument,
    /// Time of the static pose: the start of the time range clamped to the trial (s).
    pub time: f64,
    /// The solved static frame: coordinates (rad or m, the model's CoordinateSet order) and the
    /// marker errors of the scaled model before its markers moved.
    pub frame: IkFrame,
    pub coordinates: Vec<String>,
    /// The markers the errors are over, in the order of `frame.errors.worst`.
    pub tracked_markers: Vec<String>,
    pub moved: Vec<String>,
    /// Model markers absent from the static trial, deleted as OpenSim deletes them.
    pub deleted: Vec<String>,
    /// Non-fixed markers without data in the time range, left where they were.
    pub without_data: Vec<String>,
}

/// Places the markers of `model` on the static trial `trial` (read from `trial_file`).
pub fn place_markers(model: &OsimDocument, trial: &MarkerTable, trial_file: &Path, tasks: &IkTasks, range: TimeRange) -> Result<MarkerPlacement, ScaleError> {
    let trial = trial.in_meters();
    let times = trial.times();
    check_range(times, range).map_err(|problem| ScaleError::Input { file: trial_file.into(), problem: format!("marker placement: {problem}") })?;
    let (first, last) = (times[0], times[times.len() - 1]);
    // At the setup's own start time, as OpenSim's state (`from_file` targets, the pose's time).
    let static_pose = averaged_frame(&trial, range)?;
    let range = TimeRange { start: range.start.max(first), end: range.end.min(last) };
    let (model, deleted) = delete_unused_markers(model, trial.marker_names())?;
    let spec = ModelSpec::read(&model)?;
    let multibody = Multibody::new(&spec)?;
    let ik = InverseKinematics::new(&multibody, &static_pose, trial_file, tasks, IkSettings::default())?;
    let mut q = ik.initial_pose();
    let frame = ik.solve_frame(0, &mut q, &mut ik.workspace())?;
    let moved = move_markers(&model, &spec, &multibody, &static_pose, &frame.q)?;
    Ok(MarkerPlacement {
        document: moved.document,
        time: range.start,
        frame,
        coordinates: multibody.coordinates.iter().map(|c| c.name.clone()).collect(),
        tracked_markers: ik.marker_names(),
        moved: moved.moved,
        deleted,
        without_data: moved.without_data,
    })
}

/// The model with its markers moved onto an observed pose.
#[derive(Debug, Clone)]
pub struct MovedMarkers {
    pub document: OsimDocument,
    pub moved: Vec<String>,
    /// Non-fixed markers without data in `static_pose`, left where they were.
    pub without_data: Vec<String>,
}

/// `MarkerPlacer::moveModelMarkersToPose`: with the model at coordinates `q` (rad or m,
/// CoordinateSet order), every non-fixed marker found in the first frame of `static_pose`
/// (m) gets that position, expressed in the marker's parent frame.
pub fn move_markers_to_pose(model: &OsimDocument, static_pose: &MarkerTable, q: &[f64]) -> Result<MovedMarkers, ScaleError> {
    let spec = ModelSpec::read(model)?;
    move_markers(model, &spec, &Multibody::new(&spec)?, static_pose, q)
}

/// [`move_markers_to_pose`] with the model already read and compiled.
fn move_markers(model: &OsimDocument, spec: &ModelSpec, multibody: &Multibody, static_pose: &MarkerTable, q: &[f64]) -> Result<MovedMarkers, ScaleError> {
    let mut kinematics = multibody.kinematics();
    multibody.realize(q, &mut kinematics);
    let (mut edits, mut moved, mut without_data) = (Vec::new(), Vec::new(), Vec::new());
    for (marker, element) in spec.markers.iter().zip(marker_elements(model)) {
        let Some(column) = static_pose.marker_index(&marker.name).filter(|_| !marker.fixed) else { continue };
        let Some(position) = static_pose.position(0, column).filter(|p| p.iter().all(|v| v.is_finite())) else {
            without_data.push(marker.name.clone());
            continue;
        };
        let (body, frame_in_body) = multibody.attach(&marker.frame, &marker.name)?;
        let in_frame = kinematics.bodies[body].compose(&frame_in_body).inverse().apply(&Vec3::from(position));
        edits.extend(numbers_edit(ComponentReader::new(model, element), "location", &[in_frame.x, in_frame.y, in_frame.z])?);
        moved.push(marker.name.clone());
    }
    let mut placed = model.clone();
    apply(&mut placed, &edits)?;
    Ok(MovedMarkers { document: reparse(&placed)?, moved, without_data })
}

/// `MarkerData::averageFrames`: one frame at `range.start` holding each marker's mean over the
/// frames of `range` where it is present (absent when it never is).
pub fn averaged_frame(trial: &MarkerTable, range: TimeRange) -> Result<MarkerTable, ScaleError> {
    let frames = frame_range(trial.times(), range);
    let positions = (0..trial.n_markers())
        .map(|m| {
            let present: Vec<[f64; 3]> = frames.clone().filter_map(|f| trial.position(f, m)).filter(|p| p.iter().all(|v| v.is_finite())).collect();
            let n = present.len() as f64;
            (!present.is_empty()).then(|| [0, 1, 2].map(|k| present.iter().map(|p| p[k]).sum::<f64>() / n))
        })
        .collect();
    let header = TrcHeader::new(trial.rate(), trial.units());
    Ok(MarkerTable::new(header, trial.marker_names().to_vec(), vec![range.start], positions)?)
}

/// `Model::deleteUnusedMarkers`: the model without the markers the trial does not have.
fn delete_unused_markers(model: &OsimDocument, trial_markers: &[String]) -> Result<(OsimDocument, Vec<String>), ScaleError> {
    let mut pruned = model.clone();
    let mut deleted = Vec::new();
    for element in marker_elements(model) {
        let name = model.xml.name(element).unwrap_or_default();
        if !trial_markers.iter().any(|m| m == name) {
            pruned.xml.replace_element(element, "")?;
            deleted.push(name.to_string());
        }
    }
    Ok((if deleted.is_empty() { pruned } else { reparse(&pruned)? }, deleted))
}

/// The `<Marker>` elements of the model's `MarkerSet`, in order (as `ModelSpec::markers`).
fn marker_elements(model: &OsimDocument) -> Vec<crate::io::xml::ElementId> {
    let reader = ComponentReader::new(model, model.object);
    reader.child("MarkerSet").map(|set| reader.listed_objects(set)).unwrap_or_default()
}
