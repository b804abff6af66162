//! `cargo xtask validate`, residual reduction: OpenSim 4.6's RRATool on subject01's walk
//! (`golden/rra/`) against ours — the mass-center adjustment and its report, the tracked motion
//! at every window's end.

use osim_tune::validation::{compare_rra_case, rra_tolerances, RRA_CASES, RRA_MASS_CENTER_TOLERANCE, RRA_REPORT_TOLERANCE};

use crate::validate::Row;
use crate::root;

pub fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for case in RRA_CASES {
        let reference = format!("OpenSim 4.6 RRATool, golden/rra/{case}");
        let (table_tolerance, error_tolerance) = rra_tolerances(case);
        match compare_rra_case(&root(), case) {
            Ok((c, _)) if c.missing_files.is_empty() && c.extra_files.is_empty() && c.missing_rows == 0 && c.extra_rows == 0 => {
                rows.push(Row { what: format!("RRA '{case}': adjusted mass center (m)"), reference: reference.clone(), worst: c.mass_center, tolerance: RRA_MASS_CENTER_TOLERANCE, at: String::new() });
                rows.push(Row { what: format!("RRA '{case}': {} report numbers (relative)", c.report.count), reference: reference.clone(), worst: c.report.error, tolerance: RRA_REPORT_TOLERANCE, at: c.report.at });
                rows.push(Row { what: format!("RRA '{case}': {} tracked values (of row)", c.tables.count), reference: reference.clone(), worst: c.tables.error, tolerance: table_tolerance, at: c.tables.at });
                rows.push(Row { what: format!("RRA '{case}': {} position errors (rad, m)", c.position_errors.count), reference, worst: c.position_errors.error, tolerance: error_tolerance, at: c.position_errors.at });
            }
            Ok((c, _)) => rows.push(Row { what: format!("RRA '{case}': files and rows"), reference, worst: f64::INFINITY, tolerance: 0.0, at: format!("{c:?}") }),
            Err(error) => rows.push(Row { what: format!("RRA '{case}'"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error }),
        }
    }
    rows
}
