//! OpenSim's `ControlSet` document (`<name>_StaticOptimization_controls.xml`): one
//! `ControlLinear` per column of a control table, its nodes the table's rows — what a
//! `ForwardTool` or `CMCTool` reads as `controls_file`.

use crate::io::table::StorageTable;
use crate::io::xml::escape_attribute;

/// `table`'s columns (time first, a control per column) as a `ControlSet` document, with the
/// `ControlLinear` defaults OpenSim 4.6's StaticOptimization writes (bounds 0.02–1, gains 100
/// and 20, linear interpolation, extrapolated).
pub fn control_set_document(table: &StorageTable) -> String {
    let limits = vec![ControlLimits { min: 0.02, max: 1.0, use_steps: false }; table.labels().len().saturating_sub(1)];
    bounded_control_set_document(table, "Control Set", &limits)
}

/// A control's `default_min`, `default_max` and whether it steps from node to node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlLimits {
    pub min: f64,
    pub max: f64,
    pub use_steps: bool,
}

/// [`control_set_document`] named `set_name`, each control with its `limits` (one per column
/// after time) — as OpenSim's CMC and RRA write theirs.
pub fn bounded_control_set_document(table: &StorageTable, set_name: &str, limits: &[ControlLimits]) -> String {
    let mut text = format!("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40600\">\n\t<ControlSet name=\"{}\">\n\t\t<objects>\n", escape_attribute(set_name));
    for ((column, name), &ControlLimits { min, max, use_steps }) in table.labels().iter().enumerate().skip(1).zip(limits) {
        text.push_str(&format!("\t\t\t<ControlLinear name=\"{}\">\n", escape_attribute(name)));
        text.push_str(&format!("\t\t\t\t<is_model_control>true</is_model_control>\n\t\t\t\t<extrapolate>true</extrapolate>\n\t\t\t\t<default_min>{min}</default_min>\n\t\t\t\t<default_max>{max}</default_max>\n\t\t\t\t<filter_on>false</filter_on>\n\t\t\t\t<use_steps>{use_steps}</use_steps>\n\t\t\t\t<x_nodes>\n"));
        for row in table.rows() {
            text.push_str(&format!("\t\t\t\t\t<ControlLinearNode>\n\t\t\t\t\t\t<t>{}</t>\n\t\t\t\t\t\t<value>{}</value>\n\t\t\t\t\t</ControlLinearNode>\n", row[0], row[column]));
        }
        text.push_str("\t\t\t\t</x_nodes>\n\t\t\t\t<min_nodes />\n\t\t\t\t<max_nodes />\n\t\t\t\t<kp>100</kp>\n\t\t\t\t<kv>20</kv>\n\t\t\t</ControlLinear>\n");
    }
    text.push_str("\t\t</objects>\n\t\t<groups />\n\t</ControlSet>\n</OpenSimDocument>\n");
    text
}
