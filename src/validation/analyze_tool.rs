//! OpenSim 4.6's AnalyzeTool running MuscleAnalysis, Kinematics and BodyKinematics setups
//! (`fixtures/golden/analyze_tool/<case>`, `oracle/gen_analyze_tool.py`) against ours: the files
//! it writes that we form, by name, and their values.

use std::path::Path;

use super::geometry::Worst;
use crate::analysis::analyze_tool_tables;
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::ModelSpec;
use crate::setup::AnalyzeSetup;

/// The golden cases: every muscle and coordinate filtered at 6 Hz; listed muscles and coordinates
/// (with unknown names) every second row; the Kinematics and BodyKinematics of every coordinate
/// and body filtered at 6 Hz; listed ones, in radians, velocities in the bodies' frames, every
/// second row; three PointKinematics (a heel point, a shin point in the femur's frame every
/// second row, an unnamed one at ground's origin).
pub const ANALYZE_TOOL_CASES: [&str; 5] = ["all", "listed", "kinematics", "kinematics_listed", "points"];

/// The ends of the names of the files OpenSim writes that we form (the others depend on states a
/// coordinates file does not give: muscle states, controls).
const FORMED: [&str; 8] = ["_Length.sto", "_q.sto", "_u.sto", "_pos_global.sto", "_vel_global.sto", "_vel_bodyLocal.sto", "_pos.sto", "_vel.sto"];

/// What the comparison found.
#[derive(Debug, Clone, Default)]
pub struct AnalyzeToolComparison {
    /// Tables compared value for value (OpenSim's kept in the golden folder).
    pub tables: usize,
    /// The largest difference over their values (m, or m/m), with the table, row and column.
    pub values: Worst,
    /// Path-geometry tables OpenSim wrote that we do not, and ours it did not write.
    pub missing: Vec<String>,
    pub extra: Vec<String>,
}

/// Runs `case`'s setup on subject01's scaled model and IK motion (the files its setup names) in
/// the repository at `root` and compares with OpenSim's tables.
pub fn compare_analyze_tool_setup(root: &Path, case: &str) -> Result<AnalyzeToolComparison, String> {
    let golden = root.join("fixtures/golden/analyze_tool").join(case);
    let setup = AnalyzeSetup::read(&golden.join("setup.xml")).map_err(|e| e.to_string())?;
    let spec = ModelSpec::read(&OsimDocument::read(&root.join("fixtures/golden/scale/subject01_simbody.osim")).map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    let geometry = MuscleGeometry::new(&spec).map_err(|e| e.to_string())?;
    let motion_file = root.join("fixtures/golden/ik/subject01_walk1_ik.mot");
    let table = StorageTable::read(&motion_file).map_err(|e| e.to_string())?;
    let ours = analyze_tool_tables(&spec, &geometry, &table, &motion_file, &setup, &setup.name).map_err(|e| e.to_string())?.files;
    let written = std::fs::read_to_string(golden.join("files.txt")).map_err(|e| format!("{}: {e}", golden.join("files.txt").display()))?;
    let our_files: Vec<&str> = ours.iter().map(|(file, _)| file.as_str()).collect();
    let expected: Vec<&str> = written.lines().filter(|f| formed_by_us(f)).collect();
    let mut comparison = AnalyzeToolComparison {
        missing: expected.iter().filter(|f| !our_files.contains(f)).map(|f| f.to_string()).collect(),
        extra: our_files.iter().filter(|o| !expected.contains(o)).map(|o| o.to_string()).collect(),
        ..AnalyzeToolComparison::default()
    };
    for (file, table) in &ours {
        let golden_file = golden.join(file);
        if golden_file.exists() {
            compare_table(&StorageTable::read(&golden_file).map_err(|e| e.to_string())?, table, &mut comparison.values)?;
            comparison.tables += 1;
        }
    }
    Ok(comparison)
}

/// Whether we form the table of an AnalyzeTool output file named `file` (not those that depend on
/// states a coordinates file does not give).
pub fn formed_by_us(file: &str) -> bool {
    file.contains("_MomentArm_") || FORMED.iter().any(|end| file.ends_with(end))
}

/// Every value of `ours` against `opensim`'s (same labels and rows required).
fn compare_table(opensim: &StorageTable, ours: &StorageTable, worst: &mut Worst) -> Result<(), String> {
    if opensim.labels() != ours.labels() || opensim.n_rows() != ours.n_rows() {
        return Err(format!("{}: OpenSim has {} rows of {:?}, we {} rows of {:?}", ours.name(), opensim.n_rows(), opensim.labels(), ours.n_rows(), ours.labels()));
    }
    for (k, (theirs, mine)) in opensim.rows().zip(ours.rows()).enumerate() {
        for (j, (a, b)) in theirs.iter().zip(mine).enumerate() {
            worst.update((a - b).abs(), || format!("{} row {k} {}", ours.name(), ours.labels()[j]));
        }
    }
    Ok(())
}
