//! `ControlSet`: the controls a `ControlSetController` applies — read from a `<ControlSet>` of
//! `ControlLinear` controls, or from a `.sto` table (a linear control per column, as OpenSim's
//! `ControlSet(Storage)` builds it) — and their values in time as `ControlLinear` gives them.

use std::path::{Path, PathBuf};

use super::error::SetupError;
use super::object::{expect_class, read_document};
use crate::io::table::StorageTable;
use crate::model::ComponentReader;

/// One `ControlLinear`: nodes (time s, value) in time order.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlLinear {
    pub name: String,
    /// Piecewise constant, node i+1's value over (t_i, t_i+1] (default false: linear).
    pub use_steps: bool,
    /// Linear extrapolation beyond the nodes (default true), else the end values.
    pub extrapolate: bool,
    pub nodes: Vec<(f64, f64)>,
}

impl ControlLinear {
    /// The control at time `t` (s), as `ControlLinear::getControlValue`: NaN without nodes.
    pub fn value(&self, t: f64) -> f64 {
        let n = self.nodes.len();
        let Some(&(_, first)) = self.nodes.first() else { return f64::NAN };
        // The last node at or before t (exact comparisons, OpenSim's binary search).
        let at_or_before = self.nodes.partition_point(|&(time, _)| time <= t).checked_sub(1);
        let line = |(t1, v1): (f64, f64), (t2, v2): (f64, f64)| if t1 == t2 { v1 } else { v1 + (t - t1) * (v2 - v1) / (t2 - t1) };
        let extrapolating = !self.use_steps && self.extrapolate && n > 1;
        match at_or_before {
            None if extrapolating => line(self.nodes[0], self.nodes[1]),
            None => first,
            Some(i) if i + 1 >= n => {
                if extrapolating {
                    line(self.nodes[n - 2], self.nodes[n - 1])
                } else {
                    self.nodes[n - 1].1
                }
            }
            Some(i) if !self.use_steps => line(self.nodes[i], self.nodes[i + 1]),
            Some(i) if t == self.nodes[i].0 => self.nodes[i].1,
            Some(i) => self.nodes[i + 1].1,
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
        let document = read_document(path)?;
        let set = ComponentReader::new(&document, document.object);
        expect_class(set, "ControlSet")?;
        let mut controls = Vec::new();
        for element in set.listed_objects(document.object) {
            let control = set.at(element);
            expect_class(control, "ControlLinear")?;
            let mut nodes = Vec::new();
            if let Some(list) = control.child("x_nodes") {
                for node in control.listed_objects(list) {
                    let node = control.at(node);
                    nodes.push((node.number("t")?, node.number("value")?));
                }
            }
            nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
            controls.push(ControlLinear { name: control.name(), use_steps: control.boolean_or("use_steps", false)?, extrapolate: control.boolean_or("extrapolate", true)?, nodes });
        }
        Ok(ControlSet { file: path.into(), controls })
    }

    /// A linear control per column of `table` (read from `file`), nodes at its rows.
    pub fn from_table(table: &StorageTable, file: &Path) -> ControlSet {
        let times = table.times();
        let controls = table.labels()[1..]
            .iter()
            .map(|name| ControlLinear { name: name.clone(), use_steps: false, extrapolate: true, nodes: times.iter().copied().zip(table.column(name).unwrap_or_default()).collect() })
            .collect();
        ControlSet { file: file.into(), controls }
    }

    /// The control of actuator `actuator` — named so, or `<actuator>.excitation` — at `t` (s), as
    /// `ControlSetController` finds it; `None` when the set has none.
    pub fn control(&self, actuator: &str, t: f64) -> Option<f64> {
        let exact = self.controls.iter().find(|c| c.name == actuator);
        let excitation = || self.controls.iter().find(|c| c.name.strip_suffix(".excitation") == Some(actuator));
        exact.or_else(excitation).map(|c| c.value(t))
    }
}

#[cfg(test)]
mod tests {
    use super::ControlLinear;

    fn control(use_steps: bool, extrapolate: bool) -> ControlLinear {
        ControlLinear { name: "a".into(), use_steps, extrapolate, nodes: vec![(0.0, 1.0), (1.0, 3.0), (2.0, 2.0)] }
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
