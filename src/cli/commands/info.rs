//! `osim-tune info MODEL [--json]`

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::cli::{Failure, Outcome};
use crate::io::osim::OsimDocument;
use crate::model::{CoordinateSpec, ModelSpec};

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
    constraints: Vec<&'a str>,
    wrap_objects: Vec<&'a str>,
}

#[derive(Serialize)]
struct JointLine<'a> {
    name: &'a str,
    class: &'a str,
    parent: &'a str,
    child: &'a str,
}

pub fn run(model: &Path, json: bool) -> Result<Outcome, Failure> {
    let document = OsimDocument::read(model)?;
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
        constraints: spec.constraints.iter().map(|c| c.name.as_str()).collect(),
        wrap_objects: spec.wrap_objects.iter().map(|w| w.name.as_str()).collect(),
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
        let flags = [("locked", c.locked), ("clamped", c.clamped), ("prescribed", c.prescribed)]
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
    text += &format!("constraints ({}): {}\n", summary.constraints.len(), list(&summary.constraints));
    text += &format!("wrap objects ({}): {}\n", summary.wrap_objects.len(), list(&summary.wrap_objects));
    text
}
