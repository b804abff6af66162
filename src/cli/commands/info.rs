//! `osim-tune info MODEL [--json]`: what the model holds, and the default pose OpenSim's
//! `initSystem` assembles where that differs from the default values.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::cli::{Failure, Outcome};
use crate::io::osim::OsimDocument;
use crate::mechanics::Multibody;
use crate::model::{ControllerSpec, CoordinateSpec, ModelSpec};
use crate::solvers::assembled_default_pose;

/// What `info` reports.
#[derive(Serialize)]
struct Summary<'a> {
    file: String,
    model: &'a str,
    version: u32,
    bodies: Vec<&'a str>,
    joints: Vec<JointLine<'a>>,
    joint_classes: BTreeMap<&'a str, usize>,
    coordinates: Vec<&'a CoordinateSpec>,
    muscles: Vec<&'a str>,
    muscle_classes: BTreeMap<&'a str, usize>,
    other_forces: Vec<&'a str>,
    markers: Vec<&'a str>,
    constraints: Vec<ConstraintLine<'a>>,
    wrap_objects: Vec<&'a str>,
    /// Each enabled controller: `<class> <name>`, what it drives, and why osim-tune would not
    /// apply it.
    controllers: Vec<ControllerLine>,
    /// The ProbeSet's probes, and whether they report (`enabled`, else why not).
    probes: Vec<ProbeLine<'a>>,
    assembly: Assembly,
}

#[derive(Serialize)]
struct ProbeLine<'a> {
    name: &'a str,
    class: &'a str,
    enabled: bool,
    invalid: Option<&'a str>,
}

#[derive(Serialize)]
struct ControllerLine {
    controller: String,
    drives: String,
    unsupported: Option<String>,
}

#[derive(Serialize)]
struct ConstraintLine<'a> {
    name: &'a str,
    class: &'a str,
    enforced: bool,
}

/// The default pose as `initSystem` assembles it: the coordinates it moves off their default
/// values (couplers' dependents, constraints between bodies), or why it cannot be assembled.
#[derive(Serialize, Default)]
struct Assembly {
    moved: Vec<MovedCoordinate>,
    error: Option<String>,
}

#[derive(Serialize)]
struct MovedCoordinate {
    coordinate: String,
    default_value: f64,
    assembled: f64,
}

/// A coordinate counts as moved by assembly beyond this (rad or m).
const MOVED: f64 = 1e-12;

#[derive(Serialize)]
struct JointLine<'a> {
    name: &'a str,
    class: &'a str,
    parent: &'a str,
    child: &'a str,
}

pub fn run(model: &Path, json: bool) -> Result<Outcome, Failure> {
    let document = OsimDocument::read(model)?;
    if document.object_class().ends_with("Tool") {
        return Err(format!("{}: <{}> is a tool setup, not a model; `osim-tune run --dry-run {}` shows what it runs", model.display(), document.object_class(), model.display()).into());
    }
    let spec = ModelSpec::read(&document)?;
    let summary = summarise(&spec, model);
    if json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print!("{}", render(&summary));
    }
    Ok(Outcome::Success)
}

fn summarise<'a>(spec: &'a ModelSpec, file: &Path) -> Summary<'a> {
    let count = |names: Vec<&'a str>| names.into_iter().fold(BTreeMap::new(), |mut m, n| { *m.entry(n).or_insert(0) += 1; m });
    Summary {
        file: file.display().to_string(),
        model: &spec.name,
        version: spec.version,
        bodies: spec.bodies.iter().map(|b| b.name.as_str()).collect(),
        joints: spec.joints.iter().map(|j| JointLine { name: &j.name, class: &j.class, parent: &j.parent.body, child: &j.child.body }).collect(),
        joint_classes: count(spec.joints.iter().map(|j| j.class.as_str()).collect()),
        coordinates: spec.coordinates().collect(),
        muscles: spec.muscles().map(|m| m.name.as_str()).collect(),
        muscle_classes: count(spec.muscles().map(|m| m.class.as_str()).collect()),
        other_forces: spec.forces.iter().filter(|f| !f.is_muscle()).map(|f| f.name.as_str()).collect(),
        markers: spec.markers.iter().map(|m| m.name.as_str()).collect(),
        constraints: spec.constraints.iter().map(|c| ConstraintLine { name: &c.name, class: &c.class, enforced: c.enforced }).collect(),
        wrap_objects: spec.wrap_objects.iter().map(|w| w.name.as_str()).collect(),
        controllers: spec.controllers.iter().map(controller_line).collect(),
        probes: spec.probes.iter().map(|p| ProbeLine { name: &p.name, class: &p.class, enabled: p.enabled, invalid: p.invalid.as_deref() }).collect(),
        assembly: assembly(spec),
    }
}

fn controller_line(controller: &ControllerSpec) -> ControllerLine {
    let file = |file: &Option<std::path::PathBuf>| file.as_ref().map(|f| format!("the columns of {}", f.display()));
    let (drives, unsupported) = match controller {
        ControllerSpec::PrescribedController(p) => {
            let listed = (!p.actuators.is_empty()).then(|| format!("{} ({} functions)", p.actuators.join(" "), p.functions.len()));
            (listed.into_iter().chain(file(&p.controls_file)).collect::<Vec<_>>().join(" and "), None)
        }
        ControllerSpec::ControlSetController { controls_file, .. } => (file(controls_file).unwrap_or_default(), None),
        ControllerSpec::Unsupported { reason, .. } => (String::new(), Some(reason.clone())),
    };
    ControllerLine { controller: controller.description(), drives, unsupported }
}

fn assembly(spec: &ModelSpec) -> Assembly {
    let assembled = Multibody::new(spec).map_err(|e| e.to_string()).and_then(|multibody| assembled_default_pose(&multibody).map(|q| (multibody, q)).map_err(|e| e.to_string()));
    match assembled {
        Ok((multibody, q)) => Assembly {
            moved: multibody
                .coordinates
                .iter()
                .zip(q)
                .filter(|(c, q)| (q - c.default_value).abs() > MOVED)
                .map(|(c, q)| MovedCoordinate { coordinate: c.name.clone(), default_value: c.default_value, assembled: q })
                .collect(),
            error: None,
        },
        Err(error) => Assembly { moved: Vec::new(), error: Some(error) },
    }
}

fn render(summary: &Summary) -> String {
    let classes = |counts: &BTreeMap<&str, usize>| counts.iter().map(|(c, n)| format!("{n} {c}")).collect::<Vec<_>>().join(", ");
    let list = |names: &[&str]| if names.is_empty() { "-".to_string() } else { names.join(" ") };
    let mut text = format!("model {} ({}, document Version {})\n", summary.model, summary.file, summary.version);
    text += &format!("bodies ({}): {}\n", summary.bodies.len(), list(&summary.bodies));
    text += &format!("joints ({}): {}\n", summary.joints.len(), classes(&summary.joint_classes));
    for joint in &summary.joints {
        text += &format!("  {:<24} {:<16} {} → {}\n", joint.name, joint.class, joint.parent, joint.child);
    }
    text += &format!("coordinates ({}):\n", summary.coordinates.len());
    text += &format!("  {:<24} {:<14} {:>10} {:>10} {:>10} {:<5} flags\n", "name", "motion", "default", "min", "max", "unit");
    for c in &summary.coordinates {
        let flags = [("locked", c.locked), ("clamped", c.clamped), ("prescribed", c.prescribed), ("free to satisfy constraints", c.free_to_satisfy_constraints)]
            .iter()
            .filter(|(_, on)| *on)
            .map(|(flag, _)| *flag)
            .collect::<Vec<_>>()
            .join(",");
        let motion = format!("{:?}", c.motion_type).to_lowercase();
        text += &format!(
            "  {:<24} {:<14} {:>10.6} {:>10.6} {:>10.6} {:<5} {}\n",
            c.name, motion, c.default_value, c.range[0], c.range[1], c.unit.symbol(), flags
        );
    }
    text += &format!("muscles ({}): {}\n", summary.muscles.len(), classes(&summary.muscle_classes));
    text += &format!("other forces ({}): {}\n", summary.other_forces.len(), list(&summary.other_forces));
    text += &format!("markers ({}): {}\n", summary.markers.len(), list(&summary.markers));
    text += &format!("constraints ({}):{}\n", summary.constraints.len(), if summary.constraints.is_empty() { " -" } else { "" });
    for c in &summary.constraints {
        text += &format!("  {:<24} {}{}\n", c.name, c.class, if c.enforced { "" } else { " (not enforced)" });
    }
    text += &format!("wrap objects ({}): {}\n", summary.wrap_objects.len(), list(&summary.wrap_objects));
    text += &format!("controllers ({}):{}\n", summary.controllers.len(), if summary.controllers.is_empty() { " -" } else { "" });
    for c in &summary.controllers {
        match &c.unsupported {
            Some(reason) => text += &format!("  {} (not applied by osim-tune: {reason})\n", c.controller),
            None => text += &format!("  {}: {}\n", c.controller, c.drives),
        }
    }
    text += &format!("probes ({}):{}\n", summary.probes.len(), if summary.probes.is_empty() { " -" } else { "" });
    for p in &summary.probes {
        let state = match (p.enabled, p.invalid) {
            (true, _) => String::new(),
            (false, Some(reason)) => format!(" (disabled: {reason})"),
            (false, None) => " (disabled)".into(),
        };
        text += &format!("  {:<24} {}{state}\n", p.name, p.class);
    }
    text += &render_assembly(&summary.assembly);
    text
}

fn render_assembly(assembly: &Assembly) -> String {
    if let Some(error) = &assembly.error {
        return format!("default pose: not assembled: {error}\n");
    }
    if assembly.moved.is_empty() {
        return "default pose: the default values (the constraints hold there)\n".to_string();
    }
    let mut text = format!("default pose, assembled as OpenSim's initSystem does (coordinates moved: {}):\n", assembly.moved.len());
    for m in &assembly.moved {
        text += &format!("  {:<24} {:>12.8} → {:>12.8}\n", m.coordinate, m.default_value, m.assembled);
    }
    text
}
