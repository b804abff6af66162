//! `RraSetup`: an `<RRATool>` setup file — OpenSim's residual reduction algorithm (a mass-center
//! adjustment from the average residuals of inverse dynamics, then CMC tracking of the desired
//! kinematics with the residual and coordinate actuators) — typed with OpenSim's defaults
//! (`RRATool.cpp`).

use std::path::Path;

use super::cmc::TrackingSetup;
use super::error::SetupError;
use super::object::read_document;
use super::path::{directory_of, SetupPath};
use super::property::{optional_path, optional_string};
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An RRATool setup.
#[derive(Debug, Clone)]
pub struct RraSetup {
    /// The tracking: tool (whose `replace_force_set` defaults to false in an RRATool),
    /// integrator, desired kinematics, tasks, control constraints, filter.
    pub tracking: TrackingSetup,
    /// Whether the mass center of `adjusted_com_body` moves to cancel the average MX and MZ
    /// residuals (default false).
    pub adjust_com_to_reduce_residuals: bool,
    /// The time range averaged for that adjustment, s (default: the tool's).
    pub com_adjustment_time_range: Option<[f64; 2]>,
    pub adjusted_com_body: Option<String>,
    /// The adjusted model (default `adjusted_model.osim` beside the setup).
    pub output_model_file: Option<SetupPath>,
}

impl RraSetup {
    /// Reads the RRATool setup file `path`.
    pub fn read(path: &Path) -> Result<RraSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<RraSetup, SetupError> {
        let reader = ComponentReader::new(document, document.object);
        let directory = directory_of(document.xml.file());
        let com_range = [reader.number_or("initial_time_for_com_adjustment", -1.0)?, reader.number_or("final_time_for_com_adjustment", -1.0)?];
        Ok(RraSetup {
            tracking: TrackingSetup::read(document, "RRATool")?,
            adjust_com_to_reduce_residuals: reader.boolean_or("adjust_com_to_reduce_residuals", false)?,
            com_adjustment_time_range: (com_range != [-1.0, -1.0]).then_some(com_range),
            adjusted_com_body: optional_string(reader, "adjusted_com_body"),
            output_model_file: optional_path(reader, "output_model_file", &directory),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(body: &str) -> Result<RraSetup, SetupError> {
        let xml = format!(r#"<OpenSimDocument Version="40000"><RRATool name="rra">{body}</RRATool></OpenSimDocument>"#);
        RraSetup::from_document(&OsimDocument::parse(xml, Path::new("/data/setup.xml")).unwrap())
    }

    #[test]
    fn opensims_defaults_are_taken() {
        let rra = setup("<model_file>m.osim</model_file><desired_kinematics_file>ik.mot</desired_kinematics_file>").unwrap();
        assert!(!rra.tracking.tool.replace_force_set, "RRATool::setNull leaves replace_force_set false");
        assert_eq!((rra.tracking.lowpass_cutoff_frequency, rra.adjust_com_to_reduce_residuals, rra.com_adjustment_time_range), (-1.0, false, None));
        assert_eq!(rra.tracking.desired_kinematics_file.unwrap().resolved, Path::new("/data/ik.mot"));
        assert_eq!((rra.tracking.task_set_file, rra.tracking.constraints_file, rra.adjusted_com_body), (None, None, None));
    }

    #[test]
    fn the_com_adjustment_and_its_time_range_are_read() {
        let rra = setup("<adjust_com_to_reduce_residuals>true</adjust_com_to_reduce_residuals><adjusted_com_body>torso</adjusted_com_body><initial_time_for_com_adjustment>0.5</initial_time_for_com_adjustment><final_time_for_com_adjustment>1.5</final_time_for_com_adjustment><output_model_file>out/a.osim</output_model_file>").unwrap();
        assert_eq!((rra.adjust_com_to_reduce_residuals, rra.com_adjustment_time_range, rra.adjusted_com_body.as_deref()), (true, Some([0.5, 1.5]), Some("torso")));
        assert_eq!(rra.output_model_file.unwrap().resolved, Path::new("/data/out/a.osim"));
        assert!(setup("<adjust_com_to_reduce_residuals>perhaps</adjust_com_to_reduce_residuals>").is_err());
    }
}
