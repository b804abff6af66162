//! `AnalyzeSetup`: an `<AnalyzeTool>` setup file with `StaticOptimization`, `JointReaction`,
//! `MuscleAnalysis`, `Kinematics`, `BodyKinematics`, `PointKinematics`, `ForceReporter`, `Actuation`,
//! `StatesReporter`, `ProbeReporter` and `InducedAccelerations` analyses, typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::induced_accelerations::InducedAccelerationsSetup;
use super::object::{expect_class, read_document};
use super::path::{directory_of, SetupPath};
use super::property::{results_directory_or_here, checked_number_or, name_or_empty, optional_path};
use crate::io::osim::OsimDocument;
use crate::model::{ComponentReader, ControllerSpec};

/// An AnalyzeTool setup with OpenSim's defaults (`AbstractTool.cpp`, `AnalyzeTool.cpp`) for
/// absent properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalyzeSetup {
    /// The setup file, for messages.
    pub file: PathBuf,
    pub name: String,
    pub model_file: Option<SetupPath>,
    /// `ForceSet` files added to (or, with `replace_force_set`, replacing) the model's forces.
    pub force_set_files: Vec<SetupPath>,
    /// Default true, as OpenSim's.
    pub replace_force_set: bool,
    /// Where the results go (default `./`).
    pub results_directory: SetupPath,
    /// s (default 0).
    pub initial_time: f64,
    /// s (default 1).
    pub final_time: f64,
    pub coordinates_file: Option<SetupPath>,
    /// A states file (every state variable per row; OpenSim then ignores `coordinates_file`),
    /// which `analyze --setup` reads and the other commands refuse.
    pub states_file: Option<SetupPath>,
    /// Speeds to use instead of the coordinates' derivatives, which osim-tune does not read
    /// (refused by the commands).
    pub speeds_file: Option<SetupPath>,
    pub external_loads_file: Option<SetupPath>,
    /// Hz; negative: no filtering (default −1).
    pub lowpass_cutoff_frequency_for_coordinates: f64,
    /// Muscles' fibers put in equilibrium at each state (`equilibrateMuscles`) rather than left
    /// at their default lengths (default false).
    pub solve_for_equilibrium_for_auxiliary_states: bool,
    /// The enabled controllers of the tool's `ControllerSet` (files resolved against the setup's
    /// directory). (A `controls_file` outside a controller OpenSim 4 ignores, and so does
    /// osim-tune.)
    pub controllers: Vec<ControllerSpec>,
    /// The `StaticOptimization` analysis, if the set has one that is on.
    pub static_optimization: Option<StaticOptimizationSetup>,
    /// The `JointReaction` analysis, if the set has one that is on.
    pub joint_reaction: Option<JointReactionSetup>,
    /// The `MuscleAnalysis`, if the set has one that is on.
    pub muscle_analysis: Option<MuscleAnalysisSetup>,
    /// The `Kinematics` analysis, if the set has one that is on.
    pub kinematics: Option<KinematicsSetup>,
    /// The `BodyKinematics` analysis, if the set has one that is on.
    pub body_kinematics: Option<BodyKinematicsSetup>,
    /// Every `PointKinematics` analysis that is on.
    pub point_kinematics: Vec<PointKinematicsSetup>,
    /// The `ForceReporter`, `Actuation` and `StatesReporter` analyses, if the set has one that
    /// is on.
    pub force_reporter: Option<ReporterSetup>,
    pub actuation: Option<ReporterSetup>,
    pub states_reporter: Option<ReporterSetup>,
    /// The `ProbeReporter`, if the set has one that is on.
    pub probe_reporter: Option<ReporterSetup>,
    /// The `InducedAccelerations` analysis, if the set has one that is on.
    pub induced_accelerations: Option<InducedAccelerationsSetup>,
    /// Classes of the other analyses in the set (not run by osim-tune).
    pub other_analyses: Vec<String>,
}

/// OpenSim's `StaticOptimization` analysis properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StaticOptimizationSetup {
    /// The analysis's name, which OpenSim puts in its output files' names
    /// (`<tool name>_<analysis name>_…`); empty when the element has none, as OpenSim reads it.
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Default true; false (coordinate actuators for every coordinate) is refused by the command.
    pub use_model_force_set: bool,
    /// The exponent p of Σ|a|ᵖ (default 2).
    pub activation_exponent: f64,
    /// Muscle forces from the force–length–velocity curves (default true), else F_max.
    pub use_muscle_physiology: bool,
}

/// OpenSim's `JointReaction` analysis properties.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointReactionSetup {
    /// The analysis's name, which OpenSim puts in its output files' names
    /// (`<tool name>_<analysis name>_…`); empty when the element has none, as OpenSim reads it.
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// The actuators' forces (e.g. static optimisation's `_force.sto`); OpenSim computes them
    /// from the states without one, which osim-tune does not.
    pub forces_file: Option<SetupPath>,
    /// Joints to report, or `ALL` (default, when empty).
    pub joint_names: Vec<String>,
    /// `child` or `parent`, one for all or one per joint (default child).
    pub apply_on_bodies: Vec<String>,
    /// `ground`, a body, `child` or `parent`, one for all or one per joint (default ground).
    pub express_in_frame: Vec<String>,
}

/// OpenSim's `MuscleAnalysis` properties (`MuscleAnalysis.cpp`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuscleAnalysisSetup {
    /// The analysis's name, which OpenSim puts in its output files' names
    /// (`<tool name>_<analysis name>_…`); empty when the element has none, as OpenSim reads it.
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Muscles analysed, or `all` (default; spelled exactly so, as OpenSim compares it).
    pub muscle_list: Vec<String>,
    /// Coordinates of the moment arms, or `all` (default; any case).
    pub moment_arm_coordinate_list: Vec<String>,
    /// Whether moment arms (and moments) are computed (default true).
    pub compute_moments: bool,
}

/// OpenSim's `Kinematics` analysis properties (`Kinematics.cpp`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KinematicsSetup {
    /// The analysis's name, in its output files' names (empty when the element has none).
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Coordinates recorded, or `all` (default).
    pub coordinates: Vec<String>,
    /// Rotational values in degrees (default true).
    pub in_degrees: bool,
}

/// OpenSim's `BodyKinematics` analysis properties (`BodyKinematics.cpp`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodyKinematicsSetup {
    /// The analysis's name, in its output files' names (empty when the element has none).
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// Bodies recorded, `all` (default; with the whole model's mass center) or
    /// `center_of_mass`.
    pub bodies: Vec<String>,
    /// Velocities in each body's frame instead of ground (default false).
    pub express_in_local_frame: bool,
    /// Angles and angular velocities in degrees (default true).
    pub in_degrees: bool,
}

/// OpenSim's `PointKinematics` analysis properties (`PointKinematics.cpp`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointKinematicsSetup {
    /// The analysis's name, in its output files' names (empty when the element has none).
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// The body the point is fixed in (default `ground`).
    pub body: String,
    /// m, in the body (default 0 0 0).
    pub point: [f64; 3],
    /// In the output files' names (default `NONAME`).
    pub point_name: String,
    /// The body whose frame the results are expressed in; `None` for ground (`none`, the default).
    pub relative_to: Option<String>,
}

/// A reporter analysis (`ForceReporter`, `Actuation`, `StatesReporter`, `ProbeReporter`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReporterSetup {
    /// The analysis's name, in its output files' names (empty when the element has none).
    pub name: String,
    /// Records only every n-th state (default 1).
    pub step_interval: usize,
    /// ForceReporter's `include_constraint_forces` (default false; false for the others).
    pub include_constraint_forces: bool,
}

impl AnalyzeSetup {
    /// Reads the AnalyzeTool setup file `path`.
    pub fn read(path: &Path) -> Result<AnalyzeSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// Whether an analysis `analyze --setup` runs is on (all but StaticOptimization and a
    /// JointReaction with a forces file).
    pub fn has_analyze_tables(&self) -> bool {
        let reporters = [&self.force_reporter, &self.actuation, &self.states_reporter, &self.probe_reporter];
        self.muscle_analysis.is_some() || self.induced_accelerations.is_some() || self.kinematics.is_some() || self.body_kinematics.is_some() || !self.point_kinematics.is_empty() || reporters.iter().any(|r| r.is_some()) || self.joint_reaction_from_states()
    }

    /// Whether the JointReaction is on without a forces file: its forces are then the model's at
    /// the states (`analyze --setup`), not a file's (`reaction`).
    pub fn joint_reaction_from_states(&self) -> bool {
        self.joint_reaction.as_ref().is_some_and(|r| r.forces_file.is_none())
    }

    /// The object of `document` (its file names resolve against the document's directory).
    pub fn from_document(document: &OsimDocument) -> Result<AnalyzeSetup, SetupError> {
        Self::from_tool(document, "AnalyzeTool", true)
    }

    /// The `AbstractTool` properties, controllers and analyses of `document`'s tool of `class`
    /// (an `AnalyzeTool`, or a `ForwardTool`'s, whose `replace_force_set` defaults to false).
    pub(super) fn from_tool(document: &OsimDocument, class: &str, replace_by_default: bool) -> Result<AnalyzeSetup, SetupError> {
        let tool = ComponentReader::new(document, document.object);
        expect_class(tool, class)?;
        let directory = directory_of(document.xml.file());
        let Analyses { static_optimization, joint_reaction, muscle_analysis, kinematics, body_kinematics, point_kinematics, force_reporter, actuation, states_reporter, probe_reporter, induced_accelerations, others: other_analyses } =
            analyses(tool, &directory)?;
        Ok(AnalyzeSetup {
            file: document.xml.file().into(),
            name: name_or_empty(tool),
            model_file: optional_path(tool, "model_file", &directory),
            force_set_files: tool.words("force_set_files").iter().map(|f| SetupPath::resolve(f, &directory)).collect(),
            replace_force_set: tool.boolean_or("replace_force_set", replace_by_default)?,
            results_directory: results_directory_or_here(tool, &directory),
            initial_time: tool.number_or("initial_time", 0.0)?,
            final_time: tool.number_or("final_time", 1.0)?,
            coordinates_file: optional_path(tool, "coordinates_file", &directory),
            states_file: optional_path(tool, "states_file", &directory),
            speeds_file: optional_path(tool, "speeds_file", &directory),
            external_loads_file: optional_path(tool, "external_loads_file", &directory),
            lowpass_cutoff_frequency_for_coordinates: tool.number_or("lowpass_cutoff_frequency_for_coordinates", -1.0)?,
            solve_for_equilibrium_for_auxiliary_states: tool.boolean_or("solve_for_equilibrium_for_auxiliary_states", false)?,
            controllers: controllers(tool, &directory)?,
            static_optimization,
            joint_reaction,
            muscle_analysis,
            kinematics,
            body_kinematics,
            point_kinematics,
            force_reporter,
            actuation,
            states_reporter,
            probe_reporter,
            induced_accelerations,
            other_analyses,
        })
    }
}

/// The analyses of an `AnalysisSet` that are on.
#[derive(Default)]
struct Analyses {
    static_optimization: Option<StaticOptimizationSetup>,
    joint_reaction: Option<JointReactionSetup>,
    muscle_analysis: Option<MuscleAnalysisSetup>,
    kinematics: Option<KinematicsSetup>,
    body_kinematics: Option<BodyKinematicsSetup>,
    point_kinematics: Vec<PointKinematicsSetup>,
    force_reporter: Option<ReporterSetup>,
    actuation: Option<ReporterSetup>,
    states_reporter: Option<ReporterSetup>,
    probe_reporter: Option<ReporterSetup>,
    induced_accelerations: Option<InducedAccelerationsSetup>,
    /// Classes of the others (and of a second analysis of a class already read).
    others: Vec<String>,
}

/// The members of the tool's set `set` (`AnalysisSet`, `ControllerSet`) whose flag `flag` (`on`,
/// `enabled`; default true) is set.
fn active_members<'a>(tool: ComponentReader<'a>, set: &str, flag: &str) -> Result<Vec<ComponentReader<'a>>, SetupError> {
    let Some(set) = tool.child(set) else { return Ok(Vec::new()) };
    let mut active = Vec::new();
    for member in tool.at(set).listed_objects(set).into_iter().map(|element| tool.at(element)) {
        if member.boolean_or(flag, true)? {
            active.push(member);
        }
    }
    Ok(active)
}

/// The first `StaticOptimization`, `JointReaction`, `MuscleAnalysis`, `Kinematics`,
/// `BodyKinematics`, `ForceReporter`, `Actuation` and `StatesReporter` that are on, every
/// `PointKinematics` that is on, and the classes of the other analyses; `directory` resolves the
/// forces file.
fn analyses(tool: ComponentReader, directory: &Path) -> Result<Analyses, SetupError> {
    let mut found = Analyses::default();
    for analysis in active_members(tool, "AnalysisSet", "on")? {
        let step_interval = || checked_number_or(analysis, "step_interval", 1.0, |n| n >= 1.0 && n.fract() == 0.0, "a whole number ≥ 1").map(|n| n as usize);
        let name = || name_or_empty(analysis);
        let or_all = |words: Vec<String>| if words.is_empty() { vec!["all".to_string()] } else { words };
        match analysis.class() {
            "StaticOptimization" if found.static_optimization.is_none() => {
                found.static_optimization = Some(StaticOptimizationSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    use_model_force_set: analysis.boolean_or("use_model_force_set", true)?,
                    activation_exponent: checked_number_or(analysis, "activation_exponent", 2.0, |p| p >= 1.0, "a number ≥ 1")?,
                    use_muscle_physiology: analysis.boolean_or("use_muscle_physiology", true)?,
                });
            }
            "JointReaction" if found.joint_reaction.is_none() => {
                found.joint_reaction = Some(JointReactionSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    forces_file: optional_path(analysis, "forces_file", directory),
                    joint_names: analysis.words("joint_names"),
                    apply_on_bodies: analysis.words("apply_on_bodies"),
                    express_in_frame: analysis.words("express_in_frame"),
                });
            }
            "MuscleAnalysis" if found.muscle_analysis.is_none() => {
                found.muscle_analysis = Some(MuscleAnalysisSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    muscle_list: or_all(analysis.words("muscle_list")),
                    moment_arm_coordinate_list: or_all(analysis.words("moment_arm_coordinate_list")),
                    compute_moments: analysis.boolean_or("compute_moments", true)?,
                });
            }
            "Kinematics" if found.kinematics.is_none() => {
                found.kinematics = Some(KinematicsSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    coordinates: or_all(analysis.words("coordinates")),
                    in_degrees: analysis.boolean_or("in_degrees", true)?,
                });
            }
            "BodyKinematics" if found.body_kinematics.is_none() => {
                found.body_kinematics = Some(BodyKinematicsSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    bodies: or_all(analysis.words("bodies")),
                    express_in_local_frame: analysis.boolean_or("express_results_in_body_local_frame", false)?,
                    in_degrees: analysis.boolean_or("in_degrees", true)?,
                });
            }
            "PointKinematics" => {
                let relative_to = analysis.optional_text("relative_to_body_name").filter(|b| !b.is_empty() && b != "none");
                found.point_kinematics.push(PointKinematicsSetup {
                    name: name(),
                    step_interval: step_interval()?,
                    body: analysis.optional_text("body_name").filter(|b| !b.is_empty()).unwrap_or_else(|| "ground".into()),
                    point: analysis.vec3_or("point", [0.0; 3])?,
                    point_name: analysis.optional_text("point_name").filter(|p| !p.is_empty()).unwrap_or_else(|| "NONAME".into()),
                    relative_to,
                });
            }
            "ForceReporter" | "Actuation" | "StatesReporter" | "ProbeReporter" if reporter(&mut found, analysis.class()).is_none() => {
                let include_constraint_forces = analysis.class() == "ForceReporter" && analysis.boolean_or("include_constraint_forces", false)?;
                *reporter(&mut found, analysis.class()) = Some(ReporterSetup { name: name(), step_interval: step_interval()?, include_constraint_forces });
            }
            "InducedAccelerations" if found.induced_accelerations.is_none() => found.induced_accelerations = Some(InducedAccelerationsSetup::read(analysis)?),
            class => found.others.push(class.to_string()),
        }
    }
    Ok(found)
}

/// The enabled controllers of the tool's `ControllerSet` (`directory` resolves their files).
fn controllers(tool: ComponentReader, directory: &Path) -> Result<Vec<ControllerSpec>, SetupError> {
    let mut controllers = Vec::new();
    for controller in active_members(tool, "ControllerSet", "enabled")? {
        controllers.extend(ControllerSpec::read(controller, directory)?);
    }
    Ok(controllers)
}

/// The slot of reporter class `class` (`ForceReporter`, `Actuation`, `ProbeReporter`, else
/// `StatesReporter`).
fn reporter<'a>(found: &'a mut Analyses, class: &str) -> &'a mut Option<ReporterSetup> {
    match class {
        "ForceReporter" => &mut found.force_reporter,
        "Actuation" => &mut found.actuation,
        "ProbeReporter" => &mut found.probe_reporter,
        _ => &mut found.states_reporter,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subject01_static_optimization_setup_is_read() {
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/subject01");
        let setup = AnalyzeSetup::read(&folder.join("setup_static_optimization.xml")).unwrap();
        assert!(!setup.replace_force_set);
        assert_eq!(setup.force_set_files.len(), 1);
        let so = setup.static_optimization.unwrap();
        assert_eq!((so.step_interval, so.activation_exponent, so.use_muscle_physiology), (10, 2.0, true));
        assert_eq!((setup.initial_time, setup.final_time), (0.5, 2.0));
        assert!(setup.joint_reaction.is_none());
    }

    #[test]
    fn joint_reaction_properties_are_read() {
        let xml = r#"<OpenSimDocument Version="40000"><AnalyzeTool name="walk"><AnalysisSet><objects>
            <JointReaction name="JointReaction"><on>true</on><step_interval>2</step_interval>
            <forces_file>results/walk_StaticOptimization_force.sto</forces_file>
            <joint_names> knee_r hip_r</joint_names><apply_on_bodies>parent</apply_on_bodies>
            <express_in_frame>child ground</express_in_frame></JointReaction>
            <JointReaction name="second"><on>true</on></JointReaction>
            </objects></AnalysisSet></AnalyzeTool></OpenSimDocument>"#;
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("setup.xml");
        std::fs::write(&file, xml).unwrap();
        let setup = AnalyzeSetup::read(&file).unwrap();
        let reaction = setup.joint_reaction.unwrap();
        assert_eq!(reaction.step_interval, 2);
        assert_eq!(reaction.forces_file.unwrap().resolved, folder.path().join("results/walk_StaticOptimization_force.sto"));
        assert_eq!(reaction.joint_names, ["knee_r", "hip_r"]);
        assert_eq!((reaction.apply_on_bodies, reaction.express_in_frame), (vec!["parent".to_string()], vec!["child".to_string(), "ground".to_string()]));
        assert_eq!(setup.other_analyses, ["JointReaction"]);
    }

    #[test]
    fn muscle_analysis_properties_are_read_with_opensims_defaults() {
        let xml = r#"<OpenSimDocument Version="40000"><AnalyzeTool name="walk"><AnalysisSet><objects>
            <MuscleAnalysis name="a"><on>true</on><step_interval>3</step_interval><muscle_list> vas_lat_r rect_fem_r</muscle_list>
            <moment_arm_coordinate_list>knee_angle_r</moment_arm_coordinate_list><compute_moments>false</compute_moments></MuscleAnalysis>
            <Kinematics name="k"><on>true</on><coordinates>knee_angle_r</coordinates><in_degrees>false</in_degrees></Kinematics><BodyKinematics/><Actuation/><OutputReporter/>
            </objects></AnalysisSet></AnalyzeTool></OpenSimDocument>"#;
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("setup.xml");
        std::fs::write(&file, xml).unwrap();
        let analysis = AnalyzeSetup::read(&file).unwrap().muscle_analysis.unwrap();
        assert_eq!((analysis.name.as_str(), analysis.step_interval, analysis.compute_moments), ("a", 3, false));
        assert_eq!((analysis.muscle_list, analysis.moment_arm_coordinate_list), (vec!["vas_lat_r".to_string(), "rect_fem_r".to_string()], vec!["knee_angle_r".to_string()]));
        std::fs::write(&file, xml.replace(r#"<MuscleAnalysis name="a"><on>true</on><step_interval>3</step_interval><muscle_list> vas_lat_r rect_fem_r</muscle_list>
            <moment_arm_coordinate_list>knee_angle_r</moment_arm_coordinate_list><compute_moments>false</compute_moments></MuscleAnalysis>"#, "<MuscleAnalysis/>")).unwrap();
        let setup = AnalyzeSetup::read(&file).unwrap();
        let analysis = setup.muscle_analysis.unwrap();
        // Unnamed, as OpenSim reads it: its files are `walk__Length.sto`.
        assert_eq!((analysis.name.as_str(), analysis.step_interval, analysis.compute_moments), ("", 1, true));
        assert_eq!((analysis.muscle_list, analysis.moment_arm_coordinate_list), (vec!["all".to_string()], vec!["all".to_string()]));
        assert_eq!(setup.other_analyses, ["OutputReporter"]);
        assert_eq!(setup.actuation.map(|a| (a.name, a.step_interval)), Some((String::new(), 1)));
        let kinematics = setup.kinematics.unwrap();
        assert_eq!((kinematics.name.as_str(), kinematics.coordinates, kinematics.in_degrees), ("k", vec!["knee_angle_r".to_string()], false));
        let bodies = setup.body_kinematics.unwrap();
        assert_eq!((bodies.name.as_str(), bodies.bodies, bodies.express_in_local_frame, bodies.in_degrees), ("", vec!["all".to_string()], false, true));
    }
}
