//! `ControlSet`: the controls a `ControlSetController` applies — read from a `<ControlSet>` of
//! `ControlLinear` controls, or from a `.sto` table (a linear control per column, as OpenSim's
//! `ControlSet(Storage)` builds it) — and their values in time as `ControlLinear` gives them.

use std::path::{Path, PathBuf};

use super::error::SetupError;
use super::object::{expect_class, read_document};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::model::{ComponentReader, PropertySources};

/// One `ControlLinear`: nodes (time s, value) in time order.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlLinear {
    pub name: String,
    /// Piecewise constant, node i+1's value over (t_i, t_i+1] (default false: linear).
    pub use_steps: bool,
    /// Linear extrapolation beyond the nodes (default true), else the end values.
    pub extrapolate: bool,
    pub nodes: Vec<(f64, f64)>,
    /// The control's bounds in time.
    pub bounds: ControlBounds,
}

/// A control's bounds: `default_min`/`default_max` (OpenSim's defaults 0.02 and 1), or nodes in
/// time (`min_nodes`, `max_nodes`) where it has them.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlBounds {
    pub default_min: f64,
    pub default_max: f64,
    pub min_nodes: Vec<(f64, f64)>,
    pub max_nodes: Vec<(f64, f64)>,
}

impl Default for ControlBounds {
    fn default() -> Self {
        ControlBounds { default_min: 0.02, default_max: 1.0, min_nodes: Vec::new(), max_nodes: Vec::new() }
    }
}

impl ControlLinear {
    /// The control at time `t` (s), as `ControlLinear::getControlValue`: NaN without nodes.
    pub fn value(&self, t: f64) -> f64 {
        self.along(&self.nodes, t)
    }

    /// The lower and upper bound at `t` (s) (`getControlValueMin`/`Max`): the default without
    /// nodes, else the nodes as [`ControlLinear::value`] follows its own.
    pub fn bounds_at(&self, t: f64) -> (f64, f64) {
        let bound = |nodes: &[(f64, f64)], default: f64| if nodes.is_empty() { default } else { self.along(nodes, t) };
        (bound(&self.bounds.min_nodes, self.bounds.default_min), bound(&self.bounds.max_nodes, self.bounds.default_max))
    }

    /// `nodes` (time order) at `t`: linear or in steps, extrapolated or held, as this control
    /// interpolates; NaN without nodes.
    fn along(&self, nodes: &[(f64, f64)], t: f64) -> f64 {
        let n = nodes.len();
        let Some(&(_, first)) = nodes.first() else { return f64::NAN };
        // The last node at or before t (exact comparisons, OpenSim's binary search).
        let at_or_before = nodes.partition_point(|&(time, _)| time <= t).checked_sub(1);
        let line = |(t1, v1): (f64, f64), (t2, v2): (f64, f64)| if t1 == t2 { v1 } else { v1 + (t - t1) * (v2 - v1) / (t2 - t1) };
        let extrapolating = !self.use_steps && self.extrapolate && n > 1;
        match at_or_before {
            None if extrapolating => line(nodes[0], nodes[1]),
            None => first,
            Some(i) if i + 1 >= n => {
                if extrapolating {
                    line(nodes[n - 2], nodes[n - 1])
                } else {
                    nodes[n - 1].1
                }
            }
            Some(i) if !self.use_steps => line(nodes[i], nodes[i + 1]),
            Some(i) if t == nodes[i].0 => nodes[i].1,
            Some(i) => nodes[i + 1].1,
        }
    }
}

/// A control set and the file it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlSet {
    pub file: PathBuf,
    pub controls: Vec<ControlLinear>,
}

impl ControlSet {
    /// Reads `path`: a `.sto` table, else a `<ControlSet>` document of `ControlLinear`s (another
    /// control class is an error naming it).
    pub fn read(path: &Path) -> Result<ControlSet, SetupError> {
        if path.extension().is_some_and(|e| e == "sto") {
            return Ok(ControlSet::from_table(&StorageTable::read(path)?, path));
        }
        Self::from_document(&read_document(path)?)
    }

    /// The `<ControlSet>` of `document` (another control class is an error naming it).
    pub fn from_document(document: &OsimDocument) -> Result<ControlSet, SetupError> {
        let set = ComponentReader::new(document, document.object);
        expect_class(set, "ControlSet")?;
        let mut controls = Vec::new();
        for element in set.listed_objects(document.object) {
            let control = set.at(element);
            expect_class(control, "ControlLinear")?;
            // A property the control leaves out comes from the set's `<defaults>` ControlLinear.
            let properties = PropertySources::new(control);
            let defaults = ControlBounds::default();
            let bounds = ControlBounds {
                default_min: properties.number("default_min", defaults.default_min)?,
                default_max: properties.number("default_max", defaults.default_max)?,
                min_nodes: nodes(control, "min_nodes")?,
                max_nodes: nodes(control, "max_nodes")?,
            };
            controls.push(ControlLinear { name: control.name(), use_steps: properties.boolean("use_steps", false)?, extrapolate: properties.boolean("extrapolate", true)?, nodes: nodes(control, "x_nodes")?, bounds });
        }
        Ok(ControlSet { file: document.xml.file().into(), controls })
    }

    /// The control named `name` or `<name>.excitation`, as `ControlSetController` finds it.
    pub fn find(&self, name: &str) -> Option<&ControlLinear> {
        let exact = self.controls.iter().find(|c| c.name == name);
        exact.or_else(|| self.controls.iter().find(|c| c.name.strip_suffix(".excitation") == Some(name)))
    }

    /// A linear control per column of `table` (read from `file`), nodes at its rows.
    pub fn from_table(table: &StorageTable, file: &Path) -> ControlSet {
        let times = table.times();
        let controls = table.labels()[1..]
            .iter()
            .map(|name| ControlLinear { name: name.clone(), use_steps: false, extrapolate: true, nodes: times.iter().copied().zip(table.column(name).unwrap_or_default()).collect(), bounds: ControlBounds::default() })
            .collect();
        ControlSet { file: file.into(), controls }
    }

    /// The control of actuator `actuator` — named so, or `<actuator>.excitation` — at `t` (s), as
    /// `ControlSetController` finds it; `None` when the set has none.
    pub fn control(&self, actuator: &str, t: f64) -> Option<f64> {
        self.find(actuator).map(|c| c.value(t))
    }
}

/// The `ControlLinearNode`s (time s, value) of the node list `list` of `control`, in time order.
fn nodes(control: ComponentReader, list: &str) -> Result<Vec<(f64, f64)>, SetupError> {
    let mut nodes = Vec::new();
    if let Some(list) = control.child(list) {
        for node in control.listed_objects(list) {
            let node = control.at(node);
            nodes.push((node.number("t")?, node.number("value")?));
        }
    }
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(nodes)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{ControlBounds, ControlLinear, ControlSet};
    use crate::io::osim::OsimDocument;

    /// A control leaves out what the set's `<defaults>` ControlLinear states (opensim-core's CMC
    /// control constraints give every muscle its bounds and steps so).
    #[test]
    fn a_control_takes_what_it_leaves_out_from_the_sets_defaults() {
        let xml = r#"<OpenSimDocument Version="20302"><ControlSet name="c"><defaults><ControlLinear name="default"><default_min>0.05</default_min><use_steps>true</use_steps></ControlLinear></defaults>
            <objects><ControlLinear name="m.excitation" /><ControlLinear name="r.excitation"><default_min>-1</default_min><use_steps>false</use_steps></ControlLinear></objects></ControlSet></OpenSimDocument>"#;
        let set = ControlSet::from_document(&OsimDocument::parse(xml.into(), Path::new("c.xml")).unwrap()).unwrap();
        let [muscle, reserve] = [&set.controls[0], &set.controls[1]];
        assert_eq!((muscle.bounds.default_min, muscle.bounds.default_max, muscle.use_steps), (0.05, 1.0, true));
        assert_eq!((reserve.bounds.default_min, reserve.use_steps), (-1.0, false));
    }

    fn control(use_steps: bool, extrapolate: bool) -> ControlLinear {
        ControlLinear { name: "a".into(), use_steps, extrapolate, nodes: vec![(0.0, 1.0), (1.0, 3.0), (2.0, 2.0)], bounds: ControlBounds::default() }
    }

    /// Bounds are the defaults without nodes, else their nodes interpolated as the control's.
    #[test]
    fn bounds_follow_their_nodes_or_defaults() {
        let mut linear = control(false, true);
        assert_eq!(linear.bounds_at(0.5), (0.02, 1.0));
        linear.bounds.max_nodes = vec![(0.0, 2.0), (1.0, 4.0)];
        linear.bounds.default_min = -5.0;
        assert_eq!(linear.bounds_at(0.5), (-5.0, 3.0));
    }

    /// `ControlLinear::getControlValue`'s cases: between nodes, at them, before and after them.
    #[test]
    fn controls_interpolate_step_and_extrapolate_as_opensims() {
        let linear = control(false, true);
        assert_eq!([linear.value(0.5), linear.value(1.0), linear.value(1.5)], [2.0, 3.0, 2.5]);
        assert_eq!([linear.value(-1.0), linear.value(3.0)], [-1.0, 1.0]);
        let held = control(false, false);
        assert_eq!([held.value(-1.0), held.value(3.0)], [1.0, 2.0]);
        // Steps: node i+1's value over (t_i, t_i+1], the node's own at t_i.
        let steps = control(true, true);
        assert_eq!([steps.value(0.0), steps.value(0.5), steps.value(1.0), steps.value(1.5), steps.value(-1.0), steps.value(3.0)], [1.0, 3.0, 3.0, 2.0, 1.0, 2.0]);
    }
}
