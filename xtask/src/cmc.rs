//! `cargo xtask validate`, computed muscle control: OpenSim 4.6's CMCTool on arm26
//! (`golden/cmc/`) against ours — the muscles' initial states and the first window's force range
//! to OpenSim's printed digits, the first window's target value, the tracked motion at every
//! window's end within each case's bounds.

use osim_tune::validation::{cmc_tolerances, compare_cmc_case, CMC_CASES, POSITION_ERROR_MARGIN};

use crate::root;
use crate::validate::Row;

pub fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for case in CMC_CASES {
        let reference = format!("OpenSim 4.6 CMCTool, golden/cmc/{case}");
        let bounds = cmc_tolerances(case);
        match compare_cmc_case(&root(), case) {
            Ok((c, _)) if c.missing_files.is_empty() && c.extra_files.is_empty() && c.missing_rows == 0 && c.extra_rows == 0 => {
                let row = |what: String, worst: f64, tolerance: f64, at: String| Row { what: format!("CMC '{case}': {what}"), reference: reference.clone(), worst, tolerance, at };
                let [ours, opensim] = c.performance;
                let [error, theirs] = c.position_errors;
                rows.push(row(format!("{} initial muscle states (abs)", c.initial_states.count), c.initial_states.error, bounds.initial_states, c.initial_states.at.clone()));
                rows.push(row(format!("{} first force-range forces (relative)", c.force_ranges.count), c.force_ranges.error, bounds.force_ranges, c.force_ranges.at.clone()));
                rows.push(row("first target value above OpenSim's (relative)".into(), (ours - opensim) / opensim, 1e-9, format!("ours {ours}, OpenSim {opensim}")));
                rows.push(row("largest position error above OpenSim's (relative)".into(), (error - theirs) / theirs, POSITION_ERROR_MARGIN, format!("ours {error}, OpenSim {theirs}")));
                let t = bounds.tracked;
                rows.push(row(format!("{} coordinates at window ends (rad, m)", c.coordinates.count), c.coordinates.error, t.coordinates, c.coordinates.at.clone()));
                rows.push(row(format!("{} speeds (rad/s, m/s)", c.speeds.count), c.speeds.error, t.speeds, c.speeds.at.clone()));
                rows.push(row(format!("{} muscle controls and activations", c.muscles.count), c.muscles.error, t.muscles, c.muscles.at.clone()));
                rows.push(row(format!("{} fiber lengths (m)", c.fibers.count), c.fibers.error, t.fibers, c.fibers.at.clone()));
                rows.push(row(format!("{} residual and reserve controls", c.reserves.count), c.reserves.error, t.reserves, c.reserves.at));
            }
            Ok((c, _)) => rows.push(Row { what: format!("CMC '{case}': files and rows"), reference, worst: f64::INFINITY, tolerance: 0.0, at: format!("{c:?}") }),
            Err(error) => rows.push(Row { what: format!("CMC '{case}'"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error }),
        }
    }
    rows
}
