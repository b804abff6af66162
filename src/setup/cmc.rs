//! The setups of OpenSim's tracking tools: `TrackingSetup`, what a `<CMCTool>` and an
//! `<RRATool>` share (the AbstractTool part, the integrator, the desired kinematics, the task and
//! constraint files, the filter), `CmcSetup` (a CMCTool: its window and optimisation target), and
//! the `CMC_TaskSet` of their tracking tasks, typed with OpenSim's defaults (`CMCTool.cpp`,
//! `CMC_Joint.cpp`).

use std::path::Path;

use super::analyze::AnalyzeSetup;
use super::error::SetupError;
use super::forward::IntegratorSettings;
use super::object::{expect_one_of, read_document, set_members};
use super::path::{directory_of, SetupPath};
use super::property::{optional_path, optional_string, required_name};
use crate::io::osim::OsimDocument;
use crate::model::{ComponentReader, PropertySources};

/// What a CMCTool and an RRATool share.
#[derive(Debug, Clone)]
pub struct TrackingSetup {
    /// The `AbstractTool` part: model, force-set files (added to the model's forces unless
    /// `replace_force_set`, whose default is false in both tools), results directory, time range,
    /// external loads, controllers, analyses.
    pub tool: AnalyzeSetup,
    pub integrator: IntegratorSettings,
    /// The kinematics tracked (required: osim-tune does not track `desired_points_file`s).
    pub desired_kinematics_file: Option<SetupPath>,
    pub desired_points_file: Option<SetupPath>,
    pub task_set_file: Option<SetupPath>,
    /// A `ControlSet` bounding the actuators' controls.
    pub constraints_file: Option<SetupPath>,
    /// Hz; negative: no filtering (default −1).
    pub lowpass_cutoff_frequency: f64,
    /// Controls of an earlier RRA to bound these by (OpenSim reads the name but does not
    /// implement it).
    pub rra_controls_file: Option<SetupPath>,
}

impl TrackingSetup {
    /// The tracking part of `document`, whose object is a `class` (its file names resolve
    /// against the document's directory).
    pub fn read(document: &OsimDocument, class: &str) -> Result<TrackingSetup, SetupError> {
        let tool = AnalyzeSetup::from_tool(document, class, false)?;
        let reader = ComponentReader::new(document, document.object);
        let directory = directory_of(document.xml.file());
        Ok(TrackingSetup {
            tool,
            integrator: IntegratorSettings::read(reader)?,
            desired_kinematics_file: optional_path(reader, "desired_kinematics_file", &directory),
            desired_points_file: optional_path(reader, "desired_points_file", &directory),
            task_set_file: optional_path(reader, "task_set_file", &directory),
            constraints_file: optional_path(reader, "constraints_file", &directory),
            lowpass_cutoff_frequency: reader.number_or("lowpass_cutoff_frequency", -1.0)?,
            rra_controls_file: optional_path(reader, "rra_controls_file", &directory),
        })
    }
}

/// A CMCTool setup.
#[derive(Debug, Clone)]
pub struct CmcSetup {
    pub tracking: TrackingSetup,
    /// CMC's window T, s (`cmc_time_window`, default 0.01).
    pub time_window: f64,
    /// Whether the fast target (accelerations met exactly) chooses the forces, else the slow
    /// one (`use_fast_optimization_target`, default true).
    pub use_fast_optimization_target: bool,
    /// Actuators (or groups) CMC leaves uncontrolled (`actuators_to_exclude`).
    pub actuators_to_exclude: Vec<String>,
}

impl CmcSetup {
    /// Reads the CMCTool setup file `path`.
    pub fn read(path: &Path) -> Result<CmcSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The object of `document`.
    pub fn from_document(document: &OsimDocument) -> Result<CmcSetup, SetupError> {
        let tracking = TrackingSetup::read(document, "CMCTool")?;
        let reader = ComponentReader::new(document, document.object);
        let time_window = reader.number_or("cmc_time_window", 0.01)?;
        if time_window.is_nan() || time_window <= 0.0 {
            return Err(reader.bad("cmc_time_window", "a window longer than 0 s", &time_window.to_string()).into());
        }
        Ok(CmcSetup { tracking, time_window, use_fast_optimization_target: reader.boolean_or("use_fast_optimization_target", true)?, actuators_to_exclude: reader.words("actuators_to_exclude") })
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

/// A `MuscleStateTrackingTask`: a muscle's state, named `<muscle>.<state>` (e.g.
/// `BIClong.activation`), pulled towards the task set's `datafile` column of that name.
#[derive(Debug, Clone, PartialEq)]
pub struct StateTask {
    pub name: String,
    /// The first of its weights (default 1).
    pub weight: f64,
}

/// The tracking tasks of a `CMC_TaskSet` file.
#[derive(Debug, Clone, PartialEq)]
pub struct CmcTaskSet {
    /// The active `CMC_Joint`s.
    pub tasks: Vec<JointTask>,
    /// Every `MuscleStateTrackingTask` (OpenSim's target reads them whatever their flags).
    pub state_tasks: Vec<StateTask>,
    /// The `datafile` of the states they track, as written (OpenSim opens it from the setup's
    /// directory).
    pub datafile: Option<String>,
}

impl CmcTaskSet {
    /// Reads the `<CMC_TaskSet>` file `path` (OpenSim 1.x's `rdCMC_TaskSet` and `rdCMC_Joint`
    /// read as their current classes, `Object::RenameType`): its `CMC_Joint`s whose first
    /// `active` flag is true, each property from the task or else its class' `<defaults>`, its
    /// `MuscleStateTrackingTask`s and its `datafile`; a task of another class (points,
    /// orientations) is an error naming it.
    pub fn read(path: &Path) -> Result<CmcTaskSet, SetupError> {
        let document = read_document(path)?;
        let set = ComponentReader::new(&document, document.object);
        expect_one_of(set, &["CMC_TaskSet", "rdCMC_TaskSet"])?;
        let (mut tasks, mut state_tasks) = (Vec::new(), Vec::new());
        for task in set_members(set, &["CMC_Joint", "rdCMC_Joint", "MuscleStateTrackingTask"])? {
            let properties = PropertySources::new(task);
            // Gains and weights are arrays of 3 (one per component); a task has one component.
            let first = |property: &str, default: f64| {
                let source = properties.of(property);
                match source.child(property) {
                    Some(_) => source.numbers(property, None).map(|values| values.first().copied().unwrap_or(default)),
                    None => Ok(default),
                }
            };
            if task.class() == "MuscleStateTrackingTask" {
                state_tasks.push(StateTask { name: required_name(task, "task")?, weight: first("weight", 1.0)? });
                continue;
            }
            // OpenSim tracks a task whose first `active` flag is true (default false); it never
            // reads `on`.
            if !properties.of("active").words("active").first().is_some_and(|flag| flag.eq_ignore_ascii_case("true")) {
                continue;
            }
            let name = required_name(task, "task")?;
            let coordinate = optional_string(properties.of("coordinate"), "coordinate").ok_or_else(|| task.missing("coordinate"))?;
            let limit = properties.of("limit").number_or("limit", 0.0)?;
            tasks.push(JointTask { name, coordinate, weight: first("weight", 1.0)?, kp: first("kp", 1.0)?, kv: first("kv", 0.5)?, ka: first("ka", 1.0)?, limit });
        }
        Ok(CmcTaskSet { tasks, state_tasks, datafile: optional_string(set, "datafile") })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(body: &str) -> Result<CmcSetup, SetupError> {
        let xml = format!(r#"<OpenSimDocument Version="40000"><CMCTool name="cmc">{body}</CMCTool></OpenSimDocument>"#);
        CmcSetup::from_document(&OsimDocument::parse(xml, Path::new("/data/setup.xml")).unwrap())
    }

    #[test]
    fn a_cmc_tools_defaults_are_opensims() {
        let cmc = setup("<desired_kinematics_file>ik.mot</desired_kinematics_file>").unwrap();
        assert!(!cmc.tracking.tool.replace_force_set);
        assert_eq!((cmc.time_window, cmc.use_fast_optimization_target, cmc.tracking.lowpass_cutoff_frequency), (0.01, true, -1.0));
        assert_eq!(cmc.tracking.desired_kinematics_file.unwrap().resolved, Path::new("/data/ik.mot"));
        assert!(cmc.actuators_to_exclude.is_empty() && cmc.tracking.rra_controls_file.is_none());
        let slow = setup("<cmc_time_window>0.005</cmc_time_window><use_fast_optimization_target>false</use_fast_optimization_target><actuators_to_exclude>BRA reserve</actuators_to_exclude>").unwrap();
        assert_eq!((slow.time_window, slow.use_fast_optimization_target), (0.005, false));
        assert_eq!(slow.actuators_to_exclude, ["BRA", "reserve"]);
        let error = setup("<cmc_time_window>0</cmc_time_window>").unwrap_err().to_string();
        assert!(error.contains("cmc_time_window"), "{error}");
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

    #[test]
    fn opensim_1_task_sets_are_read_with_their_defaults() {
        // opensim-core's runningModel CMC tasks: an rdCMC_TaskSet of rdCMC_Joints whose
        // <defaults> give what a task leaves out.
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("tasks.xml");
        std::fs::write(&file, "<rdCMC_TaskSet name=\"t\"><defaults><rdCMC_Joint name=\"default\"><active> true false false </active><kp> 100 1 1 </kp><kv> 20 1 1 </kv></rdCMC_Joint></defaults>
            <objects><rdCMC_Joint name=\"knee\"><coordinate> knee_angle_r </coordinate><kp> 400 1 1 </kp></rdCMC_Joint>
            <rdCMC_Joint name=\"hip\"><coordinate> hip_flexion_r </coordinate><active> false false false </active></rdCMC_Joint></objects></rdCMC_TaskSet>").unwrap();
        let set = CmcTaskSet::read(&file).unwrap();
        assert_eq!(set.tasks, [JointTask { name: "knee".into(), coordinate: "knee_angle_r".into(), weight: 1.0, kp: 400.0, kv: 20.0, ka: 1.0, limit: 0.0 }]);
    }

    #[test]
    fn muscle_state_tasks_are_read_whatever_their_flags() {
        // opensim-core's arm26 EMG tasks: a datafile and one MuscleStateTrackingTask.
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("tasks.xml");
        std::fs::write(&file, "<CMC_TaskSet name=\"arm26\"><datafile>muscle_emg.sto</datafile><objects>
            <CMC_Joint name=\"elbow\"><coordinate>r_elbow_flex</coordinate><active>true false false</active></CMC_Joint>
            <MuscleStateTrackingTask name=\"BIClong.activation\"><on>true</on><active>true false false</active><weight>100.00 0. 0.</weight></MuscleStateTrackingTask>
            <MuscleStateTrackingTask name=\"TRIlong.activation\"><active>false false false</active></MuscleStateTrackingTask></objects></CMC_TaskSet>").unwrap();
        let set = CmcTaskSet::read(&file).unwrap();
        assert_eq!(set.tasks.len(), 1);
        assert_eq!(set.state_tasks, [StateTask { name: "BIClong.activation".into(), weight: 100.0 }, StateTask { name: "TRIlong.activation".into(), weight: 1.0 }]);
        assert_eq!(set.datafile.as_deref(), Some("muscle_emg.sto"));
    }
}
