//! OpenSim's `Model::scale`: geometry, then inertial properties (mass distribution preserved
//! or not), then the total mass, then path-based forces, each a set of document edits.

use super::edits::{apply, numbers_edit, Edit};
use super::error::ScaleError;
use super::geometry::geometry_edits;
use super::inertia::Inertial;
use super::path_lengths::{default_pose_lengths, rescale_edits, PathRescale};
use super::scale_set::ScaleSet;
use crate::io::osim::OsimDocument;
use crate::model::{upgrade, ComponentReader, ModelSpec};

/// The scaled model and what changed in it.
#[derive(Debug, Clone)]
pub struct ScaledModel {
    pub document: OsimDocument,
    /// Total mass before the final mass adjustment and the factor applied to every body (1 when
    /// no subject mass is given).
    pub mass_before_adjustment: f64,
    pub mass_factor: f64,
    pub paths: Vec<PathRescale>,
}

/// Scales `document` (a 2.x/3.x model converted to OpenSim 4's format first) by `scale_set`.
/// Masses follow the volume (|sx·sy·sz|) unless `preserve_mass_distribution`; then every mass
/// and inertia is multiplied so the model weighs `subject_mass` (kg) when it is given.
pub fn scale_model(document: &OsimDocument, scale_set: &ScaleSet, preserve_mass_distribution: bool, subject_mass: Option<f64>) -> Result<ScaledModel, ScaleError> {
    let upgraded = upgrade(document)?;
    let document: &OsimDocument = &upgraded;
    let model = ModelSpec::read(document)?;
    let lengths_before = default_pose_lengths(&model)?;
    let mut scaled = document.clone();
    apply(&mut scaled, &geometry_edits(document, scale_set)?)?;
    let (inertial_edits, mass_before_adjustment, mass_factor) = inertial_edits(document, &model, scale_set, preserve_mass_distribution, subject_mass)?;
    apply(&mut scaled, &inertial_edits)?;
    let measured = reparse(&scaled)?;
    let lengths_after = default_pose_lengths(&ModelSpec::read(&measured)?)?;
    let (length_edits, paths) = rescale_edits(document, &model, &lengths_before, &lengths_after)?;
    apply(&mut scaled, &length_edits)?;
    Ok(ScaledModel { document: reparse(&scaled)?, mass_before_adjustment, mass_factor, paths })
}

/// The edited text as a new document (element ids of the edited one stay valid only for it).
pub fn reparse(document: &OsimDocument) -> Result<OsimDocument, ScaleError> {
    Ok(OsimDocument::from_bytes(document.xml.serialize(), document.xml.file())?)
}

/// Mass and inertia edits of every body, with the total mass before the subject-mass factor and
/// that factor.
fn inertial_edits(document: &OsimDocument, model: &ModelSpec, scale_set: &ScaleSet, preserve: bool, subject_mass: Option<f64>) -> Result<(Vec<Edit>, f64, f64), ScaleError> {
    let scaled: Vec<Inertial> = model
        .bodies
        .iter()
        .map(|body| {
            let inertial = Inertial { mass: body.mass, inertia: body.inertia };
            scale_set.factors(&body.name).map_or(inertial, |factors| inertial.scaled(factors, !preserve))
        })
        .collect();
    let total: f64 = scaled.iter().map(|b| b.mass).sum();
    let factor = match subject_mass {
        Some(mass) if mass > 0.0 && total > 0.0 => mass / total,
        _ => 1.0,
    };
    let xml = &document.xml;
    let mut edits = Vec::new();
    for (body, inertial) in model.bodies.iter().zip(scaled) {
        let element = xml.ids().find(|&e| xml.tag(e) == "Body" && xml.name(e) == Some(body.name.as_str()));
        let Some(reader) = element.map(|e| ComponentReader::new(document, e)) else { continue };
        let inertial = if factor == 1.0 { inertial } else { inertial.mass_scaled(factor) };
        edits.extend(numbers_edit(reader, "mass", &[inertial.mass])?);
        edits.extend(numbers_edit(reader, "inertia", &inertial.inertia)?);
    }
    Ok((edits, total, factor))
}
