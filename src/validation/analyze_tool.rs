//! OpenSim 4.6's AnalyzeTool running a MuscleAnalysis setup (`fixtures/golden/analyze_tool/<case>`,
//! `oracle/gen_muscle_analysis_tool.py`) against ours: the tables it asks for, by name, value for
//! value.

use std::path::Path;

use super::geometry::Worst;
use crate::analysis::{analyze_tool_motion, MuscleAnalysis};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::ModelSpec;
use crate::setup::AnalyzeSetup;

/// The golden cases: every muscle and coordinate filtered at 6 Hz; listed muscles and coordinates
/// (with unknown names) every second row.
pub const MUSCLE_ANALYSIS_CASES: [&str; 2] = ["all", "listed"];

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
pub fn compare_muscle_analysis_setup(root: &Path, case: &str) -> Result<AnalyzeToolComparison, String> {
    let golden = root.join("fixtures/golden/analyze_tool").join(case);
    let setup = AnalyzeSetup::read(&golden.join("setup.xml")).map_err(|e| e.to_string())?;
    let analysis = setup.muscle_analysis.clone().ok_or("the golden setup has no MuscleAnalysis")?;
    let spec = ModelSpec::read(&OsimDocument::read(&root.join("fixtures/golden/scale/subject01_simbody.osim")).map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    let geometry = MuscleGeometry::new(&spec).map_err(|e| e.to_string())?;
    let motion_file = root.join("fixtures/golden/ik/subject01_walk1_ik.mot");
    let table = StorageTable::read(&motion_file).map_err(|e| e.to_string())?;
    let cutoff = Some(setup.lowpass_cutoff_frequency_for_coordinates).filter(|&c| c >= 0.0);
    let motion = analyze_tool_motion(&geometry.multibody, &table, &motion_file, cutoff, [setup.initial_time, setup.final_time], analysis.step_interval).map_err(|e| e.to_string())?;
    let ours = MuscleAnalysis::run(&geometry, &motion).and_then(|a| a.setup_tables(&geometry.multibody, &analysis)).map_err(|e| e.to_string())?.tables;
    let prefix = format!("{}_{}_", setup.name, analysis.name);
    let file_name = |table: &str| format!("{prefix}{table}.sto");
    let written = std::fs::read_to_string(golden.join("files.txt")).map_err(|e| format!("{}: {e}", golden.join("files.txt").display()))?;
    let geometry_files: Vec<&str> = written.lines().filter(|f| f.starts_with(&format!("{prefix}Length.")) || f.starts_with(&format!("{prefix}MomentArm_"))).collect();
    let our_files: Vec<String> = ours.iter().map(|t| file_name(t.name())).collect();
    let mut comparison = AnalyzeToolComparison {
        missing: geometry_files.iter().filter(|f| !our_files.iter().any(|o| o == *f)).map(|f| f.to_string()).collect(),
        extra: our_files.iter().filter(|o| !geometry_files.contains(&o.as_str())).cloned().collect(),
        ..AnalyzeToolComparison::default()
    };
    for table in &ours {
        let file = golden.join(file_name(table.name()));
        if file.exists() {
            compare_table(&StorageTable::read(&file).map_err(|e| e.to_string())?, table, &mut comparison.values)?;
            comparison.tables += 1;
        }
    }
    Ok(comparison)
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
