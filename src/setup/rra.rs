//! `RraSetup`: an `<RRATool>` setup file — OpenSim's residual reduction algorithm (a mass-center
//! adjustment from the average residuals of inverse dynamics, then CMC tracking of the desired
//! kinematics with the residual and coordinate actuators) — and the `CMC_TaskSet` of its
//! tracking tasks, typed with OpenSim's defaults (`RRATool.cpp`, `CMC_Joint.cpp`).

use std::path::Path;

use super::analyze::AnalyzeSetup;
use super::error::SetupError;
use super::forward::IntegratorSettings;
use super::object::{expect_class, read_document, set_members};
use super::path::{directory_of, SetupPath};
use super::property::{optional_path, optional_string, required_name};
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// An RRATool setup.
#[derive(Debug, Clone)]
pub struct RraSetup {
    /// The `AbstractTool` part: model, force-set files (added to the model's forces unless
    /// `replace_force_set`, whose default is false in an RRATool), results directory, time range,
    /// external loads, controllers, analyses.
    pub tool: AnalyzeSetup,
    pub integrator: IntegratorSettings,
    /// The kinematics tracked (required: osim-tune does not track `desired_points_file`s).
    pub desired_kinematics_file: Option<SetupPath>,
    pub desired_points_file: Option<SetupPath>,
    pub task_set_file: Option<SetupPath>,
    /// A `ControlSet` bounding the actuators' controls (deprecated in OpenSim, still read).
    pub constraints_file: Option<SetupPath>,
    /// Hz; negative: no filtering (default −1).
    pub lowpass_cutoff_frequency: f64,
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
        let tool = AnalyzeSetup::from_tool(document, "RRATool", false)?;
        let reader = ComponentReader::new(document, document.object);
        let directory = directory_of(document.xml.file());
        let com_range = [reader.number_or("initial_time_for_com_adjustment", -1.0)?, reader.number_or("final_time_for_com_adjustment", -1.0)?];
        Ok(RraSetup {
            tool,
            integrator: IntegratorSettings::read(reader)?,
            desired_kinematics_file: optional_path(reader, "desired_kinematics_file", &directory),
            desired_points_file: optional_path(reader, "desired_points_file", &directory),
            task_set_file: optional_path(reader, "task_set_file", &directory),
            constraints_file: optional_path(reader, "constraints_file", &directory),
            lowpass_cutoff_frequency: reader.number_or("lowpass_cutoff_frequency", -1.0)?,
            adjust_com_to_reduce_residuals: reader.boolean_or("adjust_com_to_reduce_residuals", false)?,
            com_adjustment_time_range: (com_range != [-1.0, -1.0]).then_some(com_range),
            adjusted_com_body: optional_string(reader, "adjusted_com_body"),
            output_model_file: optional_path(reader, "output_model_file", &directory),
        })
    }
}

/// A `CMC_Joint` task: a coordinate tracked by its desired acceleration
/// ka·q̈_d(t + Δt) + kv·(q̇_d − q̇)(t) + kp·(q_d − q)(t).
#[derive(Debug, Clone, PartialEq)]
pub struct JointTask {
    /// The task's name (the column of `_pErr.sto`).
    pub name: String,
    pub coordinate: String,
    /// Weight of the squared acceleration error in the optimisation (default 1).
    pub weight: f64,
    /// Gains: 1/s², 1/s and 1 (defaults 1, 0.5, 1 — OpenSim's `CMC_Task`).
    pub kp: f64,
    pub kv: f64,
    pub ka: f64,
    /// Error limit above which the actuators' stress term loses weight (0: none).
    pub limit: f64,
}

/// The active tracking tasks of a `CMC_TaskSet` file.
#[derive(Debug, Clone, PartialEq)]
pub struct CmcTaskSet {
    pub tasks: Vec<JointTask>,
}

impl CmcTaskSet {
    /// Reads the `<CMC_TaskSet>` file `path`: its `CMC_Joint`s whose first `active` flag is
    /// true; a task of another class (points, orientations) is an error naming it.
    pub fn read(path: &Path) -> Result<CmcTaskSet, SetupError> {
        let document = read_document(path)?;
        let set = ComponentReader::new(&document, document.object);
        expect_class(set, "CMC_TaskSet")?;
        let mut tasks = Vec::new();
        for task in set_members(set, &["CMC_Joint"])? {
            // Gains and weights are arrays of 3 (one per component); a joint has one component.
            let first = |property: &str, default: f64| match task.child(property) {
                Some(_) => task.numbers(property, None).map(|values| values.first().copied().unwrap_or(default)),
                None => Ok(default),
            };
            // OpenSim tracks a task whose first `active` flag is true (default false); it never
            // reads `on`.
            if !task.words("active").first().is_some_and(|flag| flag.eq_ignore_ascii_case("true")) {
                continue;
            }
            let name = required_name(task, "task")?;
            let coordinate = optional_string(task, "coordinate").ok_or_else(|| task.missing("coordinate"))?;
            tasks.push(JointTask { name, coordinate, weight: first("weight", 1.0)?, kp: first("kp", 1.0)?, kv: first("kv", 0.5)?, ka: first("ka", 1.0)?, limit: task.number_or("limit", 0.0)? });
        }
        Ok(CmcTaskSet { tasks })
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
        assert!(!rra.tool.replace_force_set, "RRATool::setNull leaves replace_force_set false");
        assert_eq!((rra.lowpass_cutoff_frequency, rra.adjust_com_to_reduce_residuals, rra.com_adjustment_time_range), (-1.0, false, None));
        assert_eq!(rra.desired_kinematics_file.unwrap().resolved, Path::new("/data/ik.mot"));
        assert_eq!((rra.task_set_file, rra.constraints_file, rra.adjusted_com_body), (None, None, None));
    }

    #[test]
    fn the_com_adjustment_and_its_time_range_are_read() {
        let rra = setup("<adjust_com_to_reduce_residuals>true</adjust_com_to_reduce_residuals><adjusted_com_body>torso</adjusted_com_body><initial_time_for_com_adjustment>0.5</initial_time_for_com_adjustment><final_time_for_com_adjustment>1.5</final_time_for_com_adjustment><output_model_file>out/a.osim</output_model_file>").unwrap();
        assert_eq!((rra.adjust_com_to_reduce_residuals, rra.com_adjustment_time_range, rra.adjusted_com_body.as_deref()), (true, Some([0.5, 1.5]), Some("torso")));
        assert_eq!(rra.output_model_file.unwrap().resolved, Path::new("/data/out/a.osim"));
        assert!(setup("<adjust_com_to_reduce_residuals>perhaps</adjust_com_to_reduce_residuals>").is_err());
    }

    #[test]
    fn joint_tasks_are_read_and_others_refused() {
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("tasks.xml");
        let joint = |name: &str, extra: &str| format!("<CMC_Joint name=\"{name}\"><coordinate>{name}</coordinate>{extra}</CMC_Joint>");
        let active = "<active>true false false</active>";
        let tasks = [joint("a", &format!("<weight>5 1 1</weight><kp>400 1 1</kp><kv>40 1 1</kv>{active}")), joint("b", "<on>true</on>"), joint("c", "<active>false false false</active>"), joint("d", &format!("<on>false</on>{active}"))];
        std::fs::write(&file, format!("<OpenSimDocument Version=\"30000\"><CMC_TaskSet name=\"t\"><objects>{}</objects></CMC_TaskSet></OpenSimDocument>", tasks.concat())).unwrap();
        let set = CmcTaskSet::read(&file).unwrap();
        assert_eq!(set.tasks.len(), 2, "inactive tasks are left out (`on` is not read, as OpenSim does not)");
        assert_eq!(set.tasks[0], JointTask { name: "a".into(), coordinate: "a".into(), weight: 5.0, kp: 400.0, kv: 40.0, ka: 1.0, limit: 0.0 });
        assert_eq!((set.tasks[1].name.as_str(), set.tasks[1].weight, set.tasks[1].kp, set.tasks[1].kv), ("d", 1.0, 1.0, 0.5));
        std::fs::write(&file, "<OpenSimDocument Version=\"30000\"><CMC_TaskSet name=\"t\"><objects><CMC_Point name=\"p\"/></objects></CMC_TaskSet></OpenSimDocument>").unwrap();
        let error = CmcTaskSet::read(&file).unwrap_err().to_string();
        assert!(error.contains("CMC_Point") && error.contains("CMC_Joint"), "{error}");
    }
}
