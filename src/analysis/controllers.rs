//! The controls the controllers give each actuator in time, as OpenSim's `Model::computeControls`
//! sums them (every controller adds its control, `addInControls`; an actuator no controller
//! drives has control 0): the model's `ControllerSet` and a tool's, `ControlSetController`s
//! through their [`ControlSet`]s and `PrescribedController`s through their functions of time.

use std::path::{Path, PathBuf};

use crate::io::table::StorageTable;
use crate::mechanics::Function;
use crate::model::{ActuatorSpec, ControllerSpec, FunctionSpec, ModelSpec, PrescribedControllerSpec};
use crate::setup::ControlSet;

/// The applied controllers, and those osim-tune cannot apply.
#[derive(Debug, Clone, Default)]
pub struct Controllers {
    members: Vec<Member>,
    /// Descriptions (with the reason) of the controllers not applied.
    pub unapplied: Vec<String>,
    /// The files the controllers were read from.
    pub files: Vec<PathBuf>,
}

#[derive(Debug, Clone)]
enum Member {
    ControlSet(ControlSet),
    /// Each driven actuator's name and its control in time (s).
    Prescribed(Vec<(String, Function)>),
}

impl Controllers {
    /// The controllers `specs` (the model's, then the tool's) over the model's `actuators` (names,
    /// in the model's order — what `ALL` connects). A controller osim-tune does not apply joins
    /// `unapplied`; one it cannot read (a file, an actuator the model lacks, functions not one per
    /// actuator) is an error naming it.
    pub fn new<'a>(specs: impl IntoIterator<Item = &'a ControllerSpec>, actuators: &[String]) -> Result<Controllers, String> {
        let mut controllers = Controllers::default();
        for spec in specs {
            let named = |error: String| format!("{}: {error}", spec.description());
            match spec {
                ControllerSpec::ControlSetController { controls_file: Some(file), .. } => {
                    controllers.members.push(Member::ControlSet(ControlSet::read(file).map_err(|e| e.to_string())?));
                    controllers.files.push(file.clone());
                }
                ControllerSpec::ControlSetController { controls_file: None, .. } => controllers.unapplied.push(format!("{} (no controls_file)", spec.description())),
                ControllerSpec::PrescribedController(prescribed) => {
                    controllers.members.push(Member::Prescribed(prescribed_controls(prescribed, actuators).map_err(named)?));
                    controllers.files.extend(prescribed.controls_file.clone());
                }
                ControllerSpec::Unsupported { reason, .. } => controllers.unapplied.push(format!("{} ({reason})", spec.description())),
            }
        }
        Ok(controllers)
    }

    /// The controllers of the model `spec` and a tool's `tool` over the model's actuators and those
    /// `added` by force-set files (the model's replaced when `replace`), as [`Controllers::new`].
    pub fn of_model(spec: &ModelSpec, tool: &[ControllerSpec], added: &[ActuatorSpec], replace: bool) -> Result<Controllers, String> {
        Controllers::new(spec.controllers.iter().chain(tool), &model_actuators(spec, added, replace))
    }

    /// One `ControlSetController` applying `set`.
    pub fn from_control_set(set: ControlSet) -> Controllers {
        Controllers { members: vec![Member::ControlSet(set)], ..Controllers::default() }
    }

    /// These controllers with `other`'s after them (their controls add up).
    pub fn and(mut self, other: &Controllers) -> Controllers {
        self.members.extend(other.members.iter().cloned());
        self.unapplied.extend(other.unapplied.iter().cloned());
        self.files.extend(other.files.iter().cloned());
        self
    }

    /// The control of `actuator` at `time` (s): the sum of the controllers', 0 without one.
    pub fn control(&self, actuator: &str, time: f64) -> f64 {
        self.members
            .iter()
            .filter_map(|member| match member {
                Member::ControlSet(set) => set.control(actuator, time),
                Member::Prescribed(functions) => functions.iter().find(|(name, _)| name == actuator).map(|(_, f)| f.value(time)),
            })
            .sum()
    }
}

/// The actuators of `spec` (its muscles and scalar actuators, in the ForceSet's order; none when
/// `replace`) and then those `added`: what a controller's `ALL` connects.
fn model_actuators(spec: &ModelSpec, added: &[ActuatorSpec], replace: bool) -> Vec<String> {
    let own = spec.forces.iter().filter(|f| !replace && (f.is_muscle() || spec.actuators.iter().any(|a| a.name == f.name)));
    own.map(|f| f.name.clone()).chain(added.iter().map(|a| a.name.clone())).collect()
}

/// A `PrescribedController`'s actuators, each with its function: the i-th function for the
/// i-th listed actuator (`ALL`: the model's actuators in order), then a function from each of
/// the controls file's columns for the actuator it names
/// (`PrescribedController::extendConnectToModel`).
fn prescribed_controls(spec: &PrescribedControllerSpec, actuators: &[String]) -> Result<Vec<(String, Function)>, String> {
    let all = spec.actuators.iter().any(|a| a.eq_ignore_ascii_case("ALL"));
    let listed: Vec<String> = if all { actuators.to_vec() } else { spec.actuators.iter().map(|a| actuator_name(a, actuators)).collect::<Result<_, _>>()? };
    if spec.functions.len() != listed.len() {
        return Err(format!("{} control functions for {} actuators (one per actuator)", spec.functions.len(), listed.len()));
    }
    let mut driven: Vec<(String, FunctionSpec)> = listed.into_iter().zip(spec.functions.iter().cloned()).collect();
    if let Some(file) = &spec.controls_file {
        let table = StorageTable::read(file).map_err(|e| e.to_string())?;
        for label in &table.labels()[1..] {
            let name = actuator_name(label, actuators).map_err(|e| format!("{}: column {label}: {e}", file.display()))?;
            if driven.iter().any(|(driven, _)| *driven == name) {
                return Err(format!("{}: column {label}: actuator {name} has a control function already (one per actuator)", file.display()));
            }
            driven.push((name, column_function(&table, label, spec.interpolation_method, file)?));
        }
    }
    Ok(driven.into_iter().map(|(name, function)| (name, Function::new(&function))).collect())
}

/// The actuator named `label` or at its absolute path (`/forceset/<name>`, `/<name>`).
fn actuator_name(label: &str, actuators: &[String]) -> Result<String, String> {
    let name = label.rsplit('/').next().unwrap_or(label);
    let known = actuators.iter().any(|a| a == name) && (!label.starts_with('/') || label == format!("/forceset/{name}") || label == format!("/{name}"));
    known.then(|| name.to_string()).ok_or_else(|| format!("no actuator of the model is named {label}"))
}

/// The controls file's column `label` as `createFunctionFromData` makes it: a piecewise constant
/// function (`method` 0) or an interpolating GCV spline of degree `method`.
fn column_function(table: &StorageTable, label: &str, method: usize, file: &Path) -> Result<FunctionSpec, String> {
    let (x, y) = (table.times(), table.column(label).unwrap_or_default());
    if x.windows(2).any(|w| w[1] <= w[0]) {
        return Err(format!("{}: the times are not strictly increasing", file.display()));
    }
    if x.len() < method + 1 {
        return Err(format!("{}: {} rows are too few for a spline of degree {method}", file.display(), x.len()));
    }
    Ok(if method == 0 { FunctionSpec::PiecewiseConstantFunction { x, y } } else { FunctionSpec::GCVSpline { degree: method, error_variance: 0.0, x, y } })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    fn prescribed(actuators: &[&str], functions: Vec<FunctionSpec>, controls_file: Option<PathBuf>, interpolation_method: usize) -> ControllerSpec {
        ControllerSpec::PrescribedController(PrescribedControllerSpec { name: "p".into(), actuators: names(actuators), functions, controls_file, interpolation_method })
    }

    fn constant(value: f64) -> FunctionSpec {
        FunctionSpec::Constant { value }
    }

    /// `ALL` takes the model's actuators in order, a path names its actuator, and controllers
    /// add up; an actuator no controller drives has control 0.
    #[test]
    fn controls_add_up_over_controllers_all_and_paths() {
        let model = names(&["a", "b", "c"]);
        let all = prescribed(&["all"], vec![constant(1.0), constant(2.0), constant(3.0)], None, 1);
        let some = prescribed(&["/forceset/c", "a"], vec![constant(10.0), FunctionSpec::LinearFunction { slope: 2.0, intercept: 0.0 }], None, 1);
        let controllers = Controllers::new([&all, &some], &model).unwrap();
        assert_eq!([controllers.control("a", 0.5), controllers.control("b", 0.5), controllers.control("c", 0.5), controllers.control("d", 0.5)], [2.0, 2.0, 13.0, 0.0]);
        assert!(controllers.unapplied.is_empty());
    }

    /// A controls file's columns join the listed functions: interpolation method 1 is linear
    /// between the rows, 0 holds each row's value until the next (and the last beyond it).
    #[test]
    fn a_controls_file_gives_linear_or_stepped_controls() {
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("controls.sto");
        std::fs::write(&file, "controls\nversion=1\nnRows=3\nnColumns=2\ninDegrees=no\nendheader\ntime\tb\n0\t0.2\n1\t0.6\n2\t0.1\n").unwrap();
        let model = names(&["a", "b"]);
        let linear = Controllers::new([&prescribed(&["a"], vec![constant(0.5)], Some(file.clone()), 1)], &model).unwrap();
        assert_eq!(linear.control("a", 1.5), 0.5);
        for (t, expected) in [(0.0, 0.2), (0.25, 0.3), (1.0, 0.6), (1.5, 0.35)] {
            assert!((linear.control("b", t) - expected).abs() < 1e-12, "linear at {t}: {}", linear.control("b", t));
        }
        let stepped = Controllers::new([&prescribed(&[], vec![], Some(file.clone()), 0)], &model).unwrap();
        assert_eq!(stepped.files, [file]);
        assert_eq!([stepped.control("b", 0.5), stepped.control("b", 1.5), stepped.control("b", 3.0)], [0.2, 0.6, 0.1]);
    }

    /// What OpenSim refuses is an error naming the controller; a class osim-tune does not apply
    /// is set aside as unapplied.
    #[test]
    fn bad_controllers_are_named() {
        let model = names(&["a", "b"]);
        let error = |spec: ControllerSpec| Controllers::new([&spec], &model).unwrap_err();
        assert!(error(prescribed(&["a", "b"], vec![constant(1.0)], None, 1)).contains("PrescribedController p: 1 control functions for 2 actuators"));
        assert!(error(prescribed(&["z"], vec![constant(1.0)], None, 1)).contains("no actuator of the model is named z"));
        assert!(error(prescribed(&["/bodyset/a"], vec![constant(1.0)], None, 1)).contains("/bodyset/a"));
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("controls.sto");
        std::fs::write(&file, "controls\nversion=1\nnRows=2\nnColumns=2\ninDegrees=no\nendheader\ntime\ta\n0\t0.2\n1\t0.6\n").unwrap();
        assert!(error(prescribed(&["a"], vec![constant(1.0)], Some(file), 1)).contains("has a control function already"));
        let other = ControllerSpec::Unsupported { class: "ToyReflexController".into(), name: "r".into(), reason: "not applied".into() };
        assert_eq!(Controllers::new([&other], &model).unwrap().unapplied, ["ToyReflexController r (not applied)"]);
    }
}
