//! OpenSim's `InducedAccelerations` analysis (`InducedAccelerations.cpp`): what it reports and
//! the contact constraints that replace the external forces, one per force in the external
//! loads' order.

use serde::Serialize;

use super::error::SetupError;
use super::property::{checked_number_or, name_or_empty};
use crate::model::ComponentReader;

/// OpenSim's `InducedAccelerations` properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InducedAccelerationsSetup {
    /// The analysis's name, in its output files' names (empty when the element has none).
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Coordinates whose accelerations are reported, or `All` (any case; default none).
    pub coordinate_names: Vec<String>,
    /// Bodies whose accelerations are reported, `All`, and `center_of_mass` for the whole
    /// model's (default `center_of_mass`).
    pub body_names: Vec<String>,
    /// The constraints replacing the external forces, the k-th the k-th force's.
    pub constraints: Vec<ContactConstraintSetup>,
    /// N: an external force larger than this is replaced by its constraint (default 6).
    pub force_threshold: f64,
    /// Only each actuator's potential: muscles at 1 N, no `total` (default false).
    pub compute_potentials_only: bool,
    /// Also the constraint reactions each contributor induces (default false).
    pub report_constraint_reactions: bool,
    /// Accelerations in degrees (default true; OpenSim converts every coordinate's).
    pub in_degrees: bool,
}

/// One constraint of the analysis' `ConstraintSet`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactConstraintSetup {
    pub name: String,
    /// The setup file's line of the constraint, for messages.
    pub line: usize,
    pub contact: ContactSetup,
}

/// What a contact constraint holds (bodies by name).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSetup {
    /// `RollingOnSurfaceConstraint`: the rolling body's contact point stays on the surface's
    /// plane (`surface_normal`, a unit vector, and `surface_height`, m, in the surface body),
    /// neither slips along the surface's x and z axes nor spins about the normal — while the
    /// normal force pushes, the friction holds (`friction_coefficient`) and the spin torque
    /// stays within `contact_radius` (m) of friction.
    Rolling { rolling_body: String, surface_body: String, surface_normal: [f64; 3], friction_coefficient: f64, contact_radius: f64 },
    /// `PointConstraint`: `location_body_2` (m, in `body_2`) moves with `location_body_1` (m,
    /// in `body_1`). OpenSim 4.6 keeps these points: its contact-point update sets properties
    /// the built system never reads again.
    Point { body_1: String, body_2: String, locations: [[f64; 3]; 2] },
    /// Another class, which the analysis refuses naming it (OpenSim 4.6 itself fails on a
    /// `WeldConstraint` here).
    Other { class: String },
}

impl InducedAccelerationsSetup {
    /// The analysis `analysis` (an `InducedAccelerations` element).
    pub(super) fn read(analysis: ComponentReader) -> Result<InducedAccelerationsSetup, SetupError> {
        let bodies = analysis.words("body_names");
        let constraints = match analysis.child("ConstraintSet") {
            Some(set) => analysis.at(set).listed_objects(set).into_iter().map(|element| ContactConstraintSetup::read(analysis.at(element))).collect::<Result<_, _>>()?,
            None => Vec::new(),
        };
        Ok(InducedAccelerationsSetup {
            name: name_or_empty(analysis),
            step_interval: checked_number_or(analysis, "step_interval", 1.0, |n| n >= 1.0 && n.fract() == 0.0, "a whole number ≥ 1")? as usize,
            coordinate_names: analysis.words("coordinate_names"),
            body_names: if analysis.child("body_names").is_some() { bodies } else { vec!["center_of_mass".into()] },
            constraints,
            force_threshold: checked_number_or(analysis, "force_threshold", 6.0, |f| f >= 0.0, "a force ≥ 0 (N)")?,
            compute_potentials_only: analysis.boolean_or("compute_potentials_only", false)?,
            report_constraint_reactions: analysis.boolean_or("report_constraint_reactions", false)?,
            in_degrees: analysis.boolean_or("in_degrees", true)?,
        })
    }
}

impl ContactConstraintSetup {
    fn read(constraint: ComponentReader) -> Result<ContactConstraintSetup, SetupError> {
        // OpenSim reads an analysis' constraints by OpenSim 3's names (`rolling_body`); a 4.x
        // socket (`socket_rolling_body`, a path) is read as its last name.
        let body = |name: &str| -> Result<String, SetupError> {
            let text = constraint.optional_text(&format!("socket_{name}")).or_else(|| constraint.optional_text(name)).filter(|t| !t.is_empty());
            let text = text.ok_or_else(|| SetupError::from(constraint.missing(name)))?;
            Ok(text.rsplit('/').next().unwrap_or(&text).to_string())
        };
        let contact = match constraint.class() {
            "RollingOnSurfaceConstraint" => {
                let normal = nalgebra::Vector3::from(constraint.vec3_or("surface_normal", [0.0, 1.0, 0.0])?);
                if !(normal.norm() > 0.0 && normal.iter().all(|v| v.is_finite())) {
                    return Err(constraint.bad("surface_normal", "a non-zero direction", &format!("{:?}", normal.as_slice())).into());
                }
                ContactSetup::Rolling {
                    rolling_body: body("rolling_body")?,
                    surface_body: body("surface_body")?,
                    surface_normal: normal.normalize().into(),
                    friction_coefficient: checked_number_or(constraint, "friction_coefficient", 0.5, |m| m >= 0.0, "a coefficient ≥ 0")?,
                    contact_radius: checked_number_or(constraint, "contact_radius", 0.01, |r| r >= 0.0, "a radius ≥ 0 (m)")?,
                }
            }
            "PointConstraint" => {
                let locations = [constraint.vec3_or("location_body_1", [0.0; 3])?, constraint.vec3_or("location_body_2", [0.0; 3])?];
                ContactSetup::Point { body_1: body("body_1")?, body_2: body("body_2")?, locations }
            }
            class => ContactSetup::Other { class: class.to_string() },
        };
        Ok(ContactConstraintSetup { name: constraint.name(), line: constraint.line(), contact })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::AnalyzeSetup;

    fn read(analysis: &str) -> Result<InducedAccelerationsSetup, SetupError> {
        let xml = format!(r#"<OpenSimDocument Version="40000"><AnalyzeTool name="walk"><AnalysisSet><objects>{analysis}</objects></AnalysisSet></AnalyzeTool></OpenSimDocument>"#);
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("setup.xml");
        std::fs::write(&file, xml).unwrap();
        Ok(AnalyzeSetup::read(&file)?.induced_accelerations.expect("read"))
    }

    #[test]
    fn defaults_are_opensims() {
        let setup = read("<InducedAccelerations><on>true</on></InducedAccelerations>").unwrap();
        assert_eq!((setup.name.as_str(), setup.step_interval, setup.force_threshold), ("", 1, 6.0));
        assert!(setup.coordinate_names.is_empty() && setup.constraints.is_empty());
        assert_eq!(setup.body_names, ["center_of_mass"]);
        assert!(setup.in_degrees && !setup.compute_potentials_only && !setup.report_constraint_reactions);
    }

    #[test]
    fn contacts_are_read_by_opensim_3_names_and_4_sockets() {
        let setup = read(
            r#"<InducedAccelerations name="IAA"><body_names> </body_names><ConstraintSet><objects>
            <RollingOnSurfaceConstraint name="r"><rolling_body>calcn_r</rolling_body><surface_body>ground</surface_body><surface_normal>0 2 0</surface_normal></RollingOnSurfaceConstraint>
            <PointConstraint name="p"><socket_body_1>/ground</socket_body_1><socket_body_2>/bodyset/calcn_l</socket_body_2><location_body_2>0.1 0 0</location_body_2></PointConstraint>
            <WeldConstraint name="w"/></objects></ConstraintSet><force_threshold>20</force_threshold></InducedAccelerations>"#,
        )
        .unwrap();
        assert!(setup.body_names.is_empty());
        assert_eq!(setup.force_threshold, 20.0);
        let rolling = ContactSetup::Rolling { rolling_body: "calcn_r".into(), surface_body: "ground".into(), surface_normal: [0.0, 1.0, 0.0], friction_coefficient: 0.5, contact_radius: 0.01 };
        let point = ContactSetup::Point { body_1: "ground".into(), body_2: "calcn_l".into(), locations: [[0.0; 3], [0.1, 0.0, 0.0]] };
        let contacts: Vec<&ContactSetup> = setup.constraints.iter().map(|c| &c.contact).collect();
        assert_eq!(contacts, [&rolling, &point, &ContactSetup::Other { class: "WeldConstraint".into() }]);
        let missing = read(r#"<InducedAccelerations><ConstraintSet><objects><PointConstraint name="p"><body_1>ground</body_1></PointConstraint></objects></ConstraintSet></InducedAccelerations>"#);
        assert!(missing.unwrap_err().to_string().contains("body_2"));
        let flat = read(r#"<InducedAccelerations><ConstraintSet><objects><RollingOnSurfaceConstraint name="r"><rolling_body>a</rolling_body><surface_body>ground</surface_body><surface_normal>0 0 0</surface_normal></RollingOnSurfaceConstraint></objects></ConstraintSet></InducedAccelerations>"#);
        assert!(flat.unwrap_err().to_string().contains("a non-zero direction"));
    }
}
