//! Scale-step rows of the validation table: OpenSim 4.6's ScaleTool run on subject01
//! (`fixtures/golden/scale`, from `../shared/reference/pipelines/gait2392_subject01`) and by
//! manual factors on leg6dof9musc, joint_zoo, Rajagopal2016, arm26, the wrap zoo, the ellipsoid joints and the station frames (`fixtures/golden/scale_zoo`) and on
//! 2.x/3.x documents it converts as it loads them (with our conversion against OpenSim's,
//! `fixtures/golden/upgrade`), and by
//! measurements with marker placement on leg6dof9musc and a synthetic static trial
//! (`fixtures/golden/scale_measured`).

use std::path::Path;
use std::process::Command;

use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{MarkerTable, StorageTable};
use osim_tune::mechanics::Multibody;
use osim_tune::model::{upgrade, ModelSpec};
use osim_tune::review::{Difference, Tolerance};
use osim_tune::setup::ScaleSetup;
use osim_tune::tuning::scale::{averaged_frame, move_markers_to_pose, run_scale_tool, ScaleOutcome};
use osim_tune::validation::{compare_scaled_models, conversion_mismatches, marker_objective, SCALED_MODEL_TOLERANCE};

use crate::root;
use crate::validate::Row;

const REFERENCE: &str = "OpenSim 4.6 ScaleTool, subject01";

pub fn rows() -> Vec<Row> {
    let golden = |file: &str| root().join("fixtures/golden/scale").join(file);
    let (setup, outcome) = scale_by(&root().join("fixtures/subject01/subject01_Setup_Scale.xml"), &root().join("models/gait2392_millard2012muscle.osim"));
    let mut rows = vec![scale_factor_row(&outcome, &std::fs::read_to_string(golden("scale_factors.csv")).expect("scale_factors.csv"))];
    rows.push(scaled_model_row("scaled model, every property (1e-7 rel. or 1e-9)".into(), REFERENCE, &outcome, &golden("subject01_scaledOnly.osim")));
    rows.extend(placement_rows(&outcome, &setup, Placement { reference: REFERENCE, pose: "scale/subject01_static_output.mot", placed: "scale/subject01_simbody.osim" }));
    rows.extend(opensim_loads(&outcome));
    rows.extend(["leg6dof9musc", "joint_zoo", "Rajagopal2016", "arm26", "wrap_zoo", "ellipsoid_joints", "station_frames"].map(|m| manual_scale_row(m, &format!("models/{m}.osim"))));
    rows.extend(LEGACY_MODELS.map(|(model, path)| manual_scale_row(model, path)));
    rows.extend(["pendulum_leg_v30000_digits", "arm26_v20303", "leg6dof9musc_v20303"].map(conversion_row));
    rows.extend(measured_leg_rows());
    let (_, linked) = scale_by(&root().join("fixtures/golden/scale_linked/setup.xml"), &root().join("fixtures/models/linked_mechanisms.osim"));
    let golden = root().join("fixtures/golden/scale_linked/scaled.osim");
    rows.push(scaled_model_row("linked mechanisms by measurements at the assembled default pose, every property".into(), "OpenSim 4.6 ScaleTool, linked_mechanisms", &linked, &golden));
    rows
}

/// The setup at `setup` run on the model at `model`.
fn scale_by(setup: &Path, model: &Path) -> (ScaleSetup, ScaleOutcome) {
    let setup = ScaleSetup::read(setup).expect("scale setup");
    let generic = OsimDocument::read(model).expect("generic model");
    let outcome = run_scale_tool(&generic, &setup, &mut |_| {}).expect("the model scales");
    (setup, outcome)
}

/// A row counting the differences (`at`: the first) of ours from OpenSim's.
fn differences_row(what: String, reference: &str, differences: &[Difference]) -> Row {
    Row { what, reference: reference.into(), worst: differences.len() as f64, tolerance: 0.0, at: differences.first().map(|d| d.path.clone()).unwrap_or_default() }
}

/// The scaled model of `outcome` against OpenSim's at `golden`, every property.
fn scaled_model_row(what: String, reference: &str, outcome: &ScaleOutcome, golden: &Path) -> Row {
    let opensim = OsimDocument::read(golden).expect("golden scaled model");
    differences_row(what, reference, &compare_scaled_models(&opensim, &outcome.scaled.as_ref().expect("the setup scales").document, SCALED_MODEL_TOLERANCE))
}

/// leg6dof9musc scaled by measurements and its markers placed, against OpenSim's.
fn measured_leg_rows() -> Vec<Row> {
    const MEASURED: &str = "OpenSim 4.6 ScaleTool, leg6dof9musc";
    let golden = |file: &str| root().join("fixtures/golden/scale_measured").join(file);
    let (setup, outcome) = scale_by(&golden("setup.xml"), &root().join("fixtures/models/leg6dof9musc.osim"));
    let mut rows = vec![scaled_model_row("leg6dof9musc by measurements, every property".into(), MEASURED, &outcome, &golden("scaledOnly.osim"))];
    rows.extend(placement_rows(&outcome, &setup, Placement { reference: MEASURED, pose: "scale_measured/static_pose.mot", placed: "scale_measured/placed.osim" }));
    rows
}

/// 2.x/3.x documents (under `fixtures/`), which OpenSim's ScaleTool converts as it loads them.
const LEGACY_MODELS: [(&str, &str); 3] =
    [("arm26_v20303", "legacy/arm26_v20303.osim"), ("leg6dof9musc_v20303", "legacy/leg6dof9musc_v20303.osim"), ("abdbonepin_v30000", "ik_point_constraint/subject1_abdbonepin.osim")];

/// `model` (at `path` under `fixtures/`) scaled by its anisotropic manual factors, every property
/// against OpenSim's.
fn manual_scale_row(model: &str, path: &str) -> Row {
    let golden = |suffix: &str| root().join(format!("fixtures/golden/scale_zoo/{model}_{suffix}"));
    let (_, outcome) = scale_by(&golden("setup.xml"), &root().join("fixtures").join(path));
    scaled_model_row(format!("{model} by manual factors, every property"), "OpenSim 4.6 ScaleTool, manualScale", &outcome, &golden("scaled.osim"))
}

/// A 2.x/3.x model (`fixtures/legacy/<model>.osim`) converted to the 4.x format: components and
/// values written that OpenSim 4.6's own conversion (`fixtures/golden/upgrade`) does not write.
fn conversion_row(model: &str) -> Row {
    let generic = OsimDocument::read(&root().join(format!("fixtures/legacy/{model}.osim"))).expect("legacy model");
    let converted = upgrade(&generic).expect("the model converts");
    let opensim = OsimDocument::read(&root().join(format!("fixtures/golden/upgrade/{model}.osim"))).expect("golden conversion");
    let mismatches = conversion_mismatches(&opensim, &converted);
    Row { what: format!("{model} to 4.x, every value"), reference: "OpenSim 4.6 conversion".into(), worst: mismatches.len() as f64, tolerance: 0.0, at: mismatches.first().cloned().unwrap_or_default() }
}

fn scale_factor_row(outcome: &ScaleOutcome, csv: &str) -> Row {
    let (mut worst, mut at) = (0.0_f64, String::new());
    for line in csv.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let ours = outcome.scale_set.factors(fields[0]).unwrap_or([f64::NAN; 3]);
        for (k, value) in ours.iter().enumerate() {
            let golden: f64 = fields[k + 1].parse().expect("a factor");
            let error = ((value - golden) / golden).abs();
            if error > worst || error.is_nan() {
                (worst, at) = (if error.is_nan() { f64::INFINITY } else { error }, fields[0].to_string());
            }
        }
    }
    Row { what: "scale factors per body (relative)".into(), reference: REFERENCE.into(), worst, tolerance: 1e-9, at }
}

/// OpenSim's marker placement: its static pose and placed model (in `fixtures/golden`).
struct Placement {
    reference: &'static str,
    pose: &'static str,
    placed: &'static str,
}

/// Markers moved at OpenSim's static pose land on OpenSim's (to the 1e-8 print precision of
/// that pose), and our static pose is at least as good for MarkerPlacer's objective.
fn placement_rows(outcome: &ScaleOutcome, setup: &ScaleSetup, opensim: Placement) -> Vec<Row> {
    let scaled = &outcome.scaled.as_ref().expect("the setup scales").document;
    let multibody = Multibody::new(&ModelSpec::read(scaled).expect("scaled model")).expect("compiles");
    let pose = StorageTable::read(&root().join("fixtures/golden").join(opensim.pose)).expect("static pose");
    let value = |name: &str| pose.labels().iter().find(|l| l.ends_with(&format!("/{name}/value"))).and_then(|l| pose.column(l)).map_or(f64::NAN, |c| c[0]);
    let opensim_pose: Vec<f64> = multibody.coordinates.iter().map(|c| value(&c.name)).collect();
    let placer = setup.marker_placer.as_ref().expect("marker placer");
    let trial = MarkerTable::read(&placer.marker_file.as_ref().expect("static trial").resolved).expect("static trial").in_meters();
    let static_pose = averaged_frame(&trial, placer.time_range).expect("averaged");
    let moved = move_markers_to_pose(scaled, &static_pose, &opensim_pose).expect("markers move");
    let golden = OsimDocument::read(&root().join("fixtures/golden").join(opensim.placed)).expect("golden placed model");
    let differences = compare_scaled_models(&golden, &moved.document, Tolerance { relative: 0.0, absolute: 1e-7 });
    let ours = &outcome.placement.as_ref().expect("placement").frame.q;
    let objective = |q: &[f64]| marker_objective(&multibody, &placer.ik_tasks, &static_pose, q).unwrap_or(f64::NAN);
    let (ours, theirs) = (objective(ours), objective(&opensim_pose));
    vec![
        differences_row("placed markers at OpenSim's static pose (m)".into(), opensim.reference, &differences),
        Row {
            what: "static pose objective, ours − OpenSim's (relative)".into(),
            reference: format!("{} (OpenSim {theirs:.6} m²)", opensim.reference),
            worst: (ours - theirs) / theirs,
            tolerance: 0.0,
            at: String::new(),
        },
    ]
}

/// The final model loads and initialises in OpenSim 4.6, when Python can import it.
fn opensim_loads(outcome: &ScaleOutcome) -> Option<Row> {
    let python = |code: &str| Command::new("python3").args(["-c", code]).output().ok().filter(|o| o.status.success());
    python("import opensim")?;
    let file = tempfile::Builder::new().suffix(".osim").tempfile().expect("temporary file");
    std::fs::write(file.path(), outcome.document.xml.serialize()).expect("written");
    let code = format!("import opensim; m = opensim.Model(r'{}'); m.initSystem(); print(m.getNumBodies())", file.path().display());
    let loaded = python(&code).is_some();
    Some(Row { what: "scaled subject01 loads in OpenSim 4.6".into(), reference: "opensim.Model(...).initSystem()".into(), worst: f64::from(u8::from(!loaded)), tolerance: 0.0, at: String::new() })
}
