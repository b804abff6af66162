//! OpenSim 4.6's AnalyzeTool running MuscleAnalysis, Kinematics, BodyKinematics,
//! PointKinematics and reporter setups (`fixtures/golden/analyze_tool/<case>`,
//! `oracle/gen_analyze_tool.py`) against ours: the files it writes that we form, by name, and
//! their values.

use std::path::Path;

use super::geometry::Worst;
use crate::analysis::{analyze_tool_tables, AnalyzeModel, Controllers, ExternalLoads};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::{read_force_set, ModelSpec};
use crate::setup::{read_document, AnalyzeSetup};

/// The golden cases: every muscle and coordinate filtered at 6 Hz; listed muscles and coordinates
/// (with unknown names) every second row; the Kinematics and BodyKinematics of every coordinate
/// and body filtered at 6 Hz; listed ones, in radians, velocities in the bodies' frames, every
/// second row; three PointKinematics (a heel point, a shin point in the femur's frame every
/// second row, an unnamed one at ground's origin); MuscleAnalysis, ForceReporter, Actuation and
/// StatesReporter with the muscles at their default states (Thelen), equilibrated (Thelen,
/// Millard), and equilibrated on Rajagopal2016 (rigid and compliant tendons, damping,
/// CoordinateActuators, couplers, clamped knee); the walk with its ground reactions and the
/// static optimisation's residual actuators, and those driven by two ControlSetControllers (a
/// ControlSet and a table); arm26 from a states file (OpenSim's forward simulation) under OpenSim
/// 4's and OpenSim 3's labels; arm26 with DeGroote muscles from a states file, and equilibrated
/// with compliant and rigid tendons; a Ball and a Free joint from simulated states, a
/// CoordinateActuator driven by the model's PrescribedController; a Scapulothoracic and an
/// Ellipsoid joint from simulated states (an activation state below 0), also equilibrated at the
/// clamped activation; loops closed by point,
/// distance, point-on-line and weld constraints from simulated states ([`case_tolerance`]).
pub const ANALYZE_TOOL_CASES: [&str; 23] = [
    "all", "listed", "kinematics", "kinematics_listed", "points", "muscle_states", "equilibrium", "millard", "rajagopal", "loads", "controls", "states", "states_legacy", "degroote",
    "degroote_equilibrium", "degroote_rigid", "ball_free", "ellipsoid", "ellipsoid_equilibrium", "linked", "induced_rolling", "induced_potentials", "probes",
];

/// The files the golden setups name (models, force set, external loads and their data), with
/// where the repository keeps them.
pub const ANALYZE_TOOL_INPUTS: [(&str, &str); 22] = [
    ("subject01_simbody.osim", "fixtures/golden/scale/subject01_simbody.osim"),
    ("gait2392_millard2012muscle.osim", "models/gait2392_millard2012muscle.osim"),
    ("Rajagopal2016_scaled.osim", "fixtures/golden/scale_zoo/Rajagopal2016_scaled.osim"),
    ("gait2392_SO_Residual_Actuators.xml", "fixtures/subject01/gait2392_SO_Residual_Actuators.xml"),
    ("subject01_walk1_grf.xml", "fixtures/subject01/subject01_walk1_grf.xml"),
    ("subject01_walk1_grf.mot", "fixtures/subject01/subject01_walk1_grf.mot"),
    ("arm26.osim", "fixtures/models/arm26.osim"),
    ("arm26_degroote.osim", "fixtures/models/arm26_degroote.osim"),
    ("arm26_degroote_rigid.osim", "fixtures/models/arm26_degroote_rigid.osim"),
    ("arm26_motion.mot", "fixtures/golden/static_optimization/arm26/arm26_motion.mot"),
    ("arm26_degroote_states.sto", "fixtures/golden/analyze_tool/degroote/arm26_degroote_states.sto"),
    ("residual_controls.xml", "fixtures/golden/analyze_tool/controls/residual_controls.xml"),
    ("residual_controls.sto", "fixtures/golden/analyze_tool/controls/residual_controls.sto"),
    ("arm26_states.sto", "fixtures/golden/analyze_tool/states/arm26_states.sto"),
    ("arm26_states_legacy.sto", "fixtures/golden/analyze_tool/states_legacy/arm26_states_legacy.sto"),
    ("ball_free.osim", "fixtures/golden/forward_tool/ball_free/ball_free.osim"),
    ("ball_free_states.sto", "fixtures/golden/forward_tool/ball_free/ball_free_states.sto"),
    ("ellipsoid_joints.osim", "fixtures/models/ellipsoid_joints.osim"),
    ("ellipsoid_states.sto", "fixtures/golden/forward_tool/ellipsoid/ellipsoid_states.sto"),
    ("linked_mechanisms.osim", "fixtures/models/linked_mechanisms.osim"),
    ("linked_states.sto", "fixtures/golden/forward_tool/linked/linked_states.sto"),
    ("arm26_probes.osim", "fixtures/models/arm26_probes.osim"),
];

/// Where the repository at `root` keeps the input a golden setup names `written`.
fn input(root: &Path, case: &str, written: &str) -> Result<std::path::PathBuf, String> {
    let (_, path) = ANALYZE_TOOL_INPUTS.iter().find(|(name, _)| *name == written).ok_or_else(|| format!("{case}: the setup names {written}, which is no file of ANALYZE_TOOL_INPUTS"))?;
    Ok(root.join(path))
}

/// Value agreement with OpenSim's tables: absolute (m, N, W, …) up to magnitude 1000, relative
/// beyond (muscles far from their equilibrium carry forces and powers up to 3e7; OpenSim prints 8
/// decimals).
pub fn table_error(opensim: f64, ours: f64) -> f64 {
    if opensim.is_nan() && ours.is_nan() {
        return 0.0;
    }
    (opensim - ours).abs() / (1e-3 * opensim.abs()).max(1.0)
}

/// The errors of one row of the table in `file` (time first): [`table_error`] per value, but
/// accelerations (`_dudt`, `_acc…`, the induced accelerations' tables but the reactions')
/// relative to the row's largest (at least 1): Simbody and we solve the same forward dynamics by
/// different factorizations of a mass matrix whose condition (Rajagopal2016's hands against its
/// pelvis) leaves ~1e-9 of the largest acceleration uncertain, and a contact's velocity terms
/// (our Ġ·u by a central difference) ~1e-10 of the speeds' scale.
pub fn row_errors(file: &str, opensim: &[f64], ours: &[f64]) -> Vec<f64> {
    let induced = file.contains("_InducedAccelerations_") && !file.ends_with("_induced_constraint_reactions.sto");
    let acceleration = induced || ["_dudt.sto", "_acc_global.sto", "_acc_bodyLocal.sto", "_acc.sto"].iter().any(|end| file.ends_with(end));
    if !acceleration {
        return opensim.iter().zip(ours).map(|(&a, &b)| table_error(a, b)).collect();
    }
    let largest = opensim[1..].iter().fold(1.0f64, |m, a| m.max(a.abs()));
    opensim.iter().zip(ours).map(|(&a, &b)| if a.is_nan() && b.is_nan() { 0.0 } else { (a - b).abs() / largest }).collect()
}

/// Agreement with OpenSim's values, [`table_error`] (printed to 1e-8).
pub const VALUE_TOLERANCE: f64 = 2e-8;

/// Rows where OpenSim 4.6's assembler stops with a clamped coordinate inside its range, short of
/// the bound it was pushed against (Simbody's optimizer tolerance), where ours lands on the
/// bound: Rajagopal2016 at 0.59 s, `knee_angle_l` 1e-7 rad (the IK angle −1.7° is outside the
/// knee's range [0, 120°]), which moves the gastrocnemii's forces by up to 2e-5 N.
const OFF_BOUND_ROWS: [(&str, f64); 1] = [("rajagopal", 0.59)];

/// Agreement in those rows.
pub const OFF_BOUND_TOLERANCE: f64 = 5e-5;

/// Agreement where links close loops (`linked`), in [`table_error`]'s measure: OpenSim's
/// assembler closes each row's links only to Simbody's assembly accuracy (1e-9; ours to 1e-10),
/// which moves a closed loop's pose by ~1e-9 and its reactions — up to 1.2 kN, carried through
/// the constraint forces — by ~6e-9 of their size (measured: 5.9e-6 N on 1184 N).
pub const LINKED_TOLERANCE: f64 = 1e-5;

/// Cases whose values agree to another tolerance than [`VALUE_TOLERANCE`].
const CASE_TOLERANCES: [(&str, f64); 1] = [("linked", LINKED_TOLERANCE)];

/// The tolerance of `case`'s values (rows off a bound aside).
pub fn case_tolerance(case: &str) -> f64 {
    CASE_TOLERANCES.iter().find(|(c, _)| *c == case).map_or(VALUE_TOLERANCE, |&(_, tolerance)| tolerance)
}

/// The tolerance of `case`'s row at `time` (s).
pub fn row_tolerance(case: &str, time: f64) -> f64 {
    if OFF_BOUND_ROWS.iter().any(|&(c, t)| c == case && (t - time).abs() < 1e-9) {
        OFF_BOUND_TOLERANCE
    } else {
        case_tolerance(case)
    }
}

/// What the comparison found.
#[derive(Debug, Clone, Default)]
pub struct AnalyzeToolComparison {
    /// Tables compared value for value (OpenSim's kept in the golden folder).
    pub tables: usize,
    /// The largest [`table_error`] over their values, with the table, row and column.
    pub values: Worst,
    /// The same over the rows where OpenSim's assembly stops short of a bound
    /// ([`OFF_BOUND_TOLERANCE`]).
    pub off_bound: Worst,
    /// Tables OpenSim wrote that we do not, and ours it did not write.
    pub missing: Vec<String>,
    pub extra: Vec<String>,
}

/// Runs `case`'s setup on its model and subject01's IK motion (the files its setup names) in the
/// repository at `root` and compares with OpenSim's tables.
pub fn compare_analyze_tool_setup(root: &Path, case: &str) -> Result<AnalyzeToolComparison, String> {
    let golden = root.join("fixtures/golden/analyze_tool").join(case);
    let setup = AnalyzeSetup::read(&golden.join("setup.xml")).map_err(|e| e.to_string())?;
    let model = input(root, case, setup.model_file.as_ref().map_or("", |m| &m.written))?;
    let spec = ModelSpec::read(&OsimDocument::read(&model).map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
    let geometry = MuscleGeometry::new(&spec).map_err(|e| e.to_string())?;
    let motion_file = match (&setup.states_file, &setup.coordinates_file) {
        (Some(states), _) => input(root, case, &states.written)?,
        (None, Some(coordinates)) if coordinates.written != "subject01_walk1_ik.mot" => input(root, case, &coordinates.written)?,
        _ => root.join("fixtures/golden/ik/subject01_walk1_ik.mot"),
    };
    let table = StorageTable::read(&motion_file).map_err(|e| e.to_string())?;
    let mut added = Vec::new();
    for file in &setup.force_set_files {
        added.extend(read_force_set(&read_document(&input(root, case, &file.written)?).map_err(|e| e.to_string())?).map_err(|e| e.to_string())?);
    }
    let external = match &setup.external_loads_file {
        Some(file) => Some(ExternalLoads::read(&input(root, case, &file.written)?, &geometry.multibody).map_err(|e| e.to_string())?.0),
        None => None,
    };
    let replace = setup.replace_force_set && !setup.force_set_files.is_empty();
    let controls = Controllers::of_model(&spec, &setup.controllers, &added, replace)?;
    let model = AnalyzeModel { spec: &spec, geometry: &geometry, added: &added, replace, external: external.as_ref(), controls: &controls };
    let ours = analyze_tool_tables(&model, &table, &motion_file, &setup, &setup.name).map_err(|e| e.to_string())?.files;
    let written = std::fs::read_to_string(golden.join("files.txt")).map_err(|e| format!("{}: {e}", golden.join("files.txt").display()))?;
    let our_files: Vec<&str> = ours.iter().map(|(file, _)| file.as_str()).collect();
    let expected: Vec<&str> = written.lines().collect();
    let mut comparison = AnalyzeToolComparison {
        missing: expected.iter().filter(|f| !our_files.contains(f)).map(|f| f.to_string()).collect(),
        extra: our_files.iter().filter(|o| !expected.contains(o)).map(|o| o.to_string()).collect(),
        ..AnalyzeToolComparison::default()
    };
    for (file, table) in &ours {
        let golden_file = golden.join(file);
        if golden_file.exists() {
            let opensim = StorageTable::read(&golden_file).map_err(|e| e.to_string())?;
            compare_table(case, file, &opensim, table, &mut comparison)?;
            comparison.tables += 1;
        }
    }
    Ok(comparison)
}

/// Every value of `ours` against `opensim`'s (same labels and rows required), each row into
/// `comparison.values` or `comparison.off_bound`.
fn compare_table(case: &str, file: &str, opensim: &StorageTable, ours: &StorageTable, comparison: &mut AnalyzeToolComparison) -> Result<(), String> {
    if opensim.labels() != ours.labels() || opensim.n_rows() != ours.n_rows() {
        return Err(format!("{}: OpenSim has {} rows of {:?}, we {} rows of {:?}", ours.name(), opensim.n_rows(), opensim.labels(), ours.n_rows(), ours.labels()));
    }
    for (k, (theirs, mine)) in opensim.rows().zip(ours.rows()).enumerate() {
        let worst = if row_tolerance(case, theirs[0]) == case_tolerance(case) { &mut comparison.values } else { &mut comparison.off_bound };
        for (j, error) in row_errors(file, theirs, mine).into_iter().enumerate() {
            worst.update(error, || format!("{} row {k} {}", ours.name(), ours.labels()[j]));
        }
    }
    Ok(())
}
