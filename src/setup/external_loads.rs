//! `ExternalLoadsSetup`: an `<ExternalLoads>` file (force-plate data applied to bodies), typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::object::{expect_class, read_document, set_members};
use super::path::{directory_of, SetupPath};
use super::property::{name_or_empty, optional_path, optional_string};
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An ExternalLoads object with OpenSim's defaults for absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExternalLoadsSetup {
    /// The file, for messages.
    pub file: PathBuf,
    /// The data (`.mot`/`.sto`) every force reads its columns from.
    pub datafile: Option<SetupPath>,
    /// Kinematics to re-express points given in ground in the bodies (OpenSim 3.x); refused
    /// when set, see [`ExternalLoadsSetup::read`].
    pub model_kinematics_file: Option<SetupPath>,
    /// The forces that apply (disabled ones are left out).
    pub forces: Vec<ExternalForceSpec>,
}

/// One `ExternalForce`: columns of the data file, named by their common prefix, applied to a body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExternalForceSpec {
    pub name: String,
    /// Line of the element, for messages.
    pub line: usize,
    pub applied_to_body: String,
    /// Frame the force and torque columns are expressed in (default `ground`).
    pub force_expressed_in_body: String,
    /// Frame the point columns are expressed in (default `ground`).
    pub point_expressed_in_body: String,
    /// Prefix of the three force columns; `None` (empty or `Unassigned`): no force.
    pub force_identifier: Option<String>,
    /// Prefix of the three point columns; `None`: the force acts at the body's origin.
    pub point_identifier: Option<String>,
    /// Prefix of the three torque columns; `None`: no torque.
    pub torque_identifier: Option<String>,
}

impl ExternalLoadsSetup {
    /// Reads the ExternalLoads file `path`, with its `external_loads_model_kinematics_file` (an
    /// OpenSim 3.x option OpenSim 4 ignores with a warning).
    pub fn read(path: &Path) -> Result<ExternalLoadsSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<ExternalLoadsSetup, SetupError> {
        let loads = ComponentReader::new(document, document.object);
        expect_class(loads, "ExternalLoads")?;
        let directory = directory_of(document.xml.file());
        let mut forces = Vec::new();
        for member in set_members(loads, &["ExternalForce"])? {
            let disabled = member.boolean_or("isDisabled", false)? || !member.boolean_or("appliesForce", true)?;
            if !disabled {
                forces.push(ExternalForceSpec::read(member)?);
            }
        }
        Ok(ExternalLoadsSetup {
            file: document.xml.file().into(),
            datafile: optional_path(loads, "datafile", &directory),
            model_kinematics_file: optional_path(loads, "external_loads_model_kinematics_file", &directory),
            forces,
        })
    }
}

impl ExternalForceSpec {
    fn read(force: ComponentReader) -> Result<ExternalForceSpec, SetupError> {
        let applied_to_body = optional_string(force, "applied_to_body").unwrap_or_default();
        if applied_to_body.is_empty() {
            return Err(force.bad("applied_to_body", "the name of the body the force acts on", "").into());
        }
        let frame = |property: &str| optional_string(force, property).unwrap_or_else(|| "ground".into());
        let identifier = |property: &str| optional_string(force, property);
        let spec = ExternalForceSpec {
            name: name_or_empty(force),
            line: force.line(),
            applied_to_body,
            force_expressed_in_body: frame("force_expressed_in_body"),
            point_expressed_in_body: frame("point_expressed_in_body"),
            force_identifier: identifier("force_identifier"),
            point_identifier: identifier("point_identifier"),
            torque_identifier: identifier("torque_identifier"),
        };
        if spec.force_identifier.is_none() && spec.torque_identifier.is_none() {
            return Err(force.bad("force_identifier", "a force or a torque identifier (OpenSim refuses a force that applies neither)", "").into());
        }
        if spec.force_identifier.is_none() && spec.point_identifier.is_some() {
            return Err(force.bad("point_identifier", "no point without a force (OpenSim refuses it)", spec.point_identifier.as_deref().unwrap_or("")).into());
        }
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/subject01").join(name)
    }

    #[test]
    fn subject01_ground_reactions_are_read() {
        let loads = ExternalLoadsSetup::read(&fixture("subject01_walk1_grf.xml")).unwrap();
        assert_eq!(loads.datafile.unwrap().resolved, fixture("subject01_walk1_grf.mot"));
        assert_eq!(loads.model_kinematics_file, None);
        assert_eq!(loads.forces.len(), 2);
        let left = &loads.forces[1];
        assert_eq!((left.applied_to_body.as_str(), left.force_expressed_in_body.as_str()), ("calcn_l", "ground"));
        assert_eq!(left.force_identifier.as_deref(), Some("1_ground_force_v"));
        assert_eq!(left.point_identifier.as_deref(), Some("1_ground_force_p"));
        assert_eq!(left.torque_identifier.as_deref(), Some("1_ground_torque_"));
    }
}
