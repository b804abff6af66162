//! Typed ScaleTool and InverseKinematicsTool setups: subject01's files in the old dialects (2.x
//! Scale, 3.x IK, as distributed) and in 4.x (as OpenSim 4.6 printed them,
//! `fixtures/golden/{scale,ik}/setup_*_used.xml`), objects given by reference (`fixtures/setup/`),
//! OpenSim's defaults, and refused input. Expected values are read off the XML files.

mod common;

use std::path::{Path, PathBuf};

use osim_tune::model::{BadProperty, ModelError};
use osim_tune::setup::{
    BodyScale, CoordinateTarget, IkSetup, IkTaskSet, ScaleSetup, ScalingStep, SetupError, SetupPath, TimeRange,
};

const SCALE_V2: &str = "subject01/subject01_Setup_Scale.xml";
const SCALE_V4: &str = "golden/scale/setup_scale_used.xml";
const SCALE_BY_REFERENCE: &str = "setup/subject01_Setup_Scale_by_reference.xml";
const IK_V3: &str = "subject01/subject01_Setup_IK.xml";
const IK_V4: &str = "golden/ik/setup_ik_used.xml";
const IK_BY_REFERENCE: &str = "setup/subject01_Setup_IK_by_reference.xml";

fn scale(relative: &str) -> ScaleSetup {
    ScaleSetup::read(&common::fixture(relative)).unwrap_or_else(|e| panic!("{e}"))
}

fn ik(relative: &str) -> IkSetup {
    IkSetup::read(&common::fixture(relative)).unwrap_or_else(|e| panic!("{e}"))
}

fn written(path: &Option<SetupPath>) -> Option<&str> {
    path.as_ref().map(|p| p.written.as_str())
}

/// The file a resolved path names, for comparing paths that contain `..`.
fn real(path: &Option<SetupPath>) -> PathBuf {
    path.as_ref().unwrap().resolved.canonicalize().unwrap()
}

fn marker_weight(tasks: &IkTaskSet, name: &str) -> f64 {
    tasks.marker_tasks.iter().find(|t| t.name == name).unwrap_or_else(|| panic!("no task {name}")).weight
}

// ---- ScaleTool ----

#[test]
fn scale_setup_of_subject01_in_the_2x_dialect() {
    let setup = scale(SCALE_V2);
    assert_eq!((setup.version, setup.name.as_str()), (20302, "subject01"));
    assert_eq!((setup.mass, setup.height, setup.age), (72.6, 1803.4, 99.0));
    assert_eq!(setup.notes.as_deref(), Some("This is an example setup file for scale.exe."));
    assert_eq!(setup.directory, common::fixture("subject01"));

    let maker = setup.generic_model_maker.as_ref().unwrap();
    assert_eq!(written(&maker.model_file), Some("gait2392_simbody.osim"));
    assert_eq!(maker.model_file.as_ref().unwrap().resolved, common::fixture("subject01/gait2392_simbody.osim"));
    assert_eq!(maker.marker_set_file.as_ref().unwrap().resolved, common::fixture("subject01/gait2392_Scale_MarkerSet.xml"));

    let scaler = setup.model_scaler.as_ref().unwrap();
    assert!(scaler.apply && scaler.preserve_mass_distribution);
    assert_eq!(scaler.scaling_order, [ScalingStep::Measurements, ScalingStep::ManualScale]);
    let names: Vec<&str> = scaler.measurements.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["torso", "pelvis", "thigh", "shank", "foot"]);
    let thigh = &scaler.measurements[2];
    assert!(thigh.apply);
    assert_eq!(thigh.marker_pairs, [["R.ASIS", "R.Knee.Lat"], ["L.ASIS", "L.Knee.Lat"]]);
    let all_axes = |body: &str| BodyScale { body: body.into(), axes: [true; 3] };
    assert_eq!(thigh.body_scales, ["femur_r", "femur_l", "patella_r", "patella_l"].map(all_axes));
    assert_eq!(scaler.measurements[0].marker_pairs, [["V.Sacral", "Top.Head"]]);

    let manual: Vec<(&str, [f64; 3], bool)> = scaler.manual_scales.iter().map(|s| (s.segment.as_str(), s.scales, s.apply)).collect();
    assert_eq!(
        manual,
        [
            ("femur_r", [1.14724; 3], true),
            ("femur_l", [1.14724; 3], true),
            ("tibia_r", [0.988523; 3], true),
            ("tibia_l", [0.988523; 3], true)
        ]
    );
    assert_eq!(scaler.marker_file.as_ref().unwrap().resolved, common::fixture("subject01/subject01_static.trc"));
    assert_eq!(scaler.time_range, TimeRange { start: 1.0, end: 2.0 });
    assert_eq!(written(&scaler.output_model_file), Some("subject01_scaledOnly.osim"));
    assert_eq!(scaler.output_scale_file.as_ref().unwrap().resolved, common::fixture("subject01/subject01_scaleSet_applied.xml"));

    let placer = setup.marker_placer.as_ref().unwrap();
    assert!(placer.apply);
    assert_eq!((placer.ik_tasks.marker_tasks.len(), placer.ik_tasks.coordinate_tasks.len()), (39, 5));
    assert_eq!(placer.ik_tasks.marker_tasks[0].name, "Sternum");
    assert_eq!((marker_weight(&placer.ik_tasks, "Sternum"), marker_weight(&placer.ik_tasks, "R.ASIS")), (1.0, 1000.0));
    assert_eq!(marker_weight(&placer.ik_tasks, "R.Toe.Tip"), 1000.0);
    let lumbar = &placer.ik_tasks.coordinate_tasks[4];
    assert_eq!((lumbar.name.as_str(), lumbar.weight, lumbar.target), ("lumbar_extension", 1000.0, CoordinateTarget::ManualValue(0.0)));
    let subtalar = &placer.ik_tasks.coordinate_tasks[0];
    assert_eq!((subtalar.name.as_str(), subtalar.target), ("subtalar_angle_r", CoordinateTarget::DefaultValue));
    assert_eq!(written(&placer.marker_file), Some("subject01_static.trc"));
    assert_eq!(placer.coordinate_file, None, "<coordinate_file> </coordinate_file> is not given");
    assert_eq!(placer.output_marker_file, None, "Unassigned is not given");
    assert_eq!(placer.time_range, TimeRange { start: 1.0, end: 2.0 });
    assert_eq!(written(&placer.output_motion_file), Some("subject01_static_output.mot"));
    assert_eq!(placer.output_model_file.as_ref().unwrap().resolved, common::fixture("subject01/subject01_simbody.osim"));
    assert_eq!(placer.max_marker_movement, -1.0);
}

/// The setup with its location removed: resolved paths replaced by what was written.
fn scale_without_location(mut setup: ScaleSetup) -> ScaleSetup {
    setup.file = PathBuf::new();
    setup.directory = PathBuf::new();
    setup.version = 0;
    let mut paths = Vec::new();
    if let Some(maker) = setup.generic_model_maker.as_mut() {
        paths.extend([&mut maker.model_file, &mut maker.marker_set_file]);
    }
    if let Some(scaler) = setup.model_scaler.as_mut() {
        paths.extend([&mut scaler.marker_file, &mut scaler.output_model_file, &mut scaler.output_scale_file]);
    }
    if let Some(placer) = setup.marker_placer.as_mut() {
        paths.extend([
            &mut placer.marker_file,
            &mut placer.coordinate_file,
            &mut placer.output_motion_file,
            &mut placer.output_model_file,
            &mut placer.output_marker_file,
        ]);
    }
    for path in paths.into_iter().flatten() {
        path.resolved = PathBuf::from(&path.written);
    }
    setup
}

#[test]
fn scale_setup_printed_by_opensim_4_says_what_the_2x_file_says() {
    let old = scale(SCALE_V2);
    let new = scale(SCALE_V4);
    assert_eq!(new.version, 40600);
    assert_eq!(new.mass, 72.6, "72.599999999999994 is the same double");
    assert_eq!(scale_without_location(new), scale_without_location(old));
}

#[test]
fn scale_setup_with_sets_given_by_reference() {
    let inline = scale(SCALE_V2);
    let setup = scale(SCALE_BY_REFERENCE);
    let (scaler, inline_scaler) = (setup.model_scaler.as_ref().unwrap(), inline.model_scaler.as_ref().unwrap());
    assert_eq!(scaler.measurements, inline_scaler.measurements, "gait2354_Scale_MeasurementSet.xml");
    assert_eq!(scaler.manual_scales, inline_scaler.manual_scales, "subject01_Scale_ScaleSet.xml");
    let placer = setup.marker_placer.as_ref().unwrap();
    assert_eq!(placer.ik_tasks, inline.marker_placer.as_ref().unwrap().ik_tasks, "gait2354_Scale_Tasks.xml");

    let maker = setup.generic_model_maker.as_ref().unwrap();
    assert_eq!(real(&maker.model_file), common::root().join("models/gait2354_simbody.osim").canonicalize().unwrap());
    assert_eq!(real(&scaler.marker_file), common::fixture("subject01/subject01_static.trc").canonicalize().unwrap());
    assert_eq!(placer.coordinate_file, None, "Unassigned");
    assert_eq!(placer.output_marker_file, None, "empty");
    assert_eq!(placer.max_marker_movement, -1.0, "OpenSim's default");
}

// ---- InverseKinematicsTool ----

#[test]
fn ik_setup_of_subject01_in_the_3x_dialect() {
    let setup = ik(IK_V3);
    assert_eq!((setup.version, setup.name.as_str()), (30000, "subject01"));
    assert_eq!(setup.model_file.as_ref().unwrap().resolved, common::fixture("subject01/subject01_simbody.osim"));
    assert_eq!((setup.constraint_weight, setup.accuracy), (20.0, 1e-5));
    let tasks = &setup.tasks;
    assert_eq!((tasks.marker_tasks.len(), tasks.coordinate_tasks.len()), (31, 4));
    let weights = ["Sternum", "R.Acromium", "L.Acromium", "Top.Head", "R.ASIS", "R.Heel", "L.Toe.Tip"].map(|m| marker_weight(tasks, m));
    assert_eq!(weights, [1.0, 0.5, 0.5, 0.1, 10.0, 10.0, 10.0]);
    assert!(tasks.marker_tasks.iter().all(|t| t.apply));
    let coordinates: Vec<(&str, f64, CoordinateTarget)> =
        tasks.coordinate_tasks.iter().map(|t| (t.name.as_str(), t.weight, t.target)).collect();
    let default = |name| (name, 1000.0, CoordinateTarget::DefaultValue);
    assert_eq!(coordinates, ["subtalar_angle_r", "mtp_angle_r", "subtalar_angle_l", "mtp_angle_l"].map(default));
    assert_eq!(setup.marker_file.as_ref().unwrap().resolved, common::fixture("subject01/subject01_walk1.trc"));
    assert_eq!(setup.coordinate_file, None);
    assert_eq!(setup.time_range, TimeRange { start: 0.5, end: 2.5 });
    assert!(setup.report_errors && !setup.report_marker_locations, "report_marker_locations absent: false");
    assert_eq!(written(&setup.output_motion_file), Some("subject01_walk1_ik.mot"));
    assert_eq!(written(&setup.results_directory), Some("./"));
    assert_eq!(setup.results_directory.as_ref().unwrap().resolved, common::fixture("subject01"));
}

fn ik_without_location(mut setup: IkSetup) -> IkSetup {
    assert_eq!(setup.results_directory.as_ref().unwrap().resolved, setup.directory, "./ and . are the setup's directory");
    setup.results_directory = None;
    setup.file = PathBuf::new();
    setup.directory = PathBuf::new();
    setup.version = 0;
    for path in [&mut setup.model_file, &mut setup.marker_file, &mut setup.coordinate_file, &mut setup.output_motion_file]
        .into_iter()
        .flatten()
    {
        path.resolved = PathBuf::from(&path.written);
    }
    setup
}

#[test]
fn ik_setup_printed_by_opensim_4_says_what_the_3x_file_says_but_the_start_time() {
    let old = ik(IK_V3);
    let mut new = ik(IK_V4);
    assert_eq!(new.version, 40600);
    assert_eq!(new.accuracy, 1e-5, "1.0000000000000001e-05 and 1e-005 are the same double");
    assert_eq!(new.time_range, TimeRange { start: 0.0, end: 2.5 }, "the oracle ran from 0 s");
    new.time_range = old.time_range;
    assert_eq!(ik_without_location(new), ik_without_location(old));
}

#[test]
fn ik_setup_with_tasks_by_reference_and_opensim_defaults() {
    let setup = ik(IK_BY_REFERENCE);
    assert_eq!(setup.tasks, ik(IK_V3).tasks, "sets/gait2392_IK_Tasks.xml");
    assert_eq!(real(&setup.model_file), common::fixture("subject01/OutputReference/subject01_simbody.osim").canonicalize().unwrap());
    assert_eq!(setup.accuracy, 1e-5);
    assert_eq!(setup.constraint_weight, f64::INFINITY);
    assert!(setup.report_errors && !setup.report_marker_locations);
    assert_eq!(written(&setup.results_directory), Some("./"));
    assert_eq!(setup.results_directory.as_ref().unwrap().resolved, common::fixture("setup"));
    assert_eq!(setup.coordinate_file, None, "<coordinate_file />");
}

// ---- defaults, references, coordinate values ----

fn temporary() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn write(directory: &Path, name: &str, text: &str) -> PathBuf {
    let path = directory.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, text).unwrap();
    path
}

fn document(object: &str) -> String {
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40600\">\n{object}\n</OpenSimDocument>\n")
}

#[test]
fn absent_properties_take_opensim_defaults() {
    let dir = temporary();
    let path = write(dir.path(), "scale.xml", &document("<ScaleTool><ModelScaler/><MarkerPlacer/></ScaleTool>"));
    let setup = ScaleSetup::read(&path).unwrap();
    assert_eq!((setup.name.as_str(), setup.mass, setup.height, setup.age, setup.notes), ("", -1.0, -1.0, -1.0, None));
    assert!(setup.generic_model_maker.is_none());
    let scaler = setup.model_scaler.unwrap();
    assert!(scaler.apply && !scaler.preserve_mass_distribution);
    assert!(scaler.scaling_order.is_empty() && scaler.measurements.is_empty() && scaler.manual_scales.is_empty());
    assert_eq!(scaler.time_range, TimeRange { start: -1.0, end: -1.0 });
    assert_eq!((scaler.marker_file, scaler.output_model_file, scaler.output_scale_file), (None, None, None));
    let placer = setup.marker_placer.unwrap();
    assert!(placer.apply && placer.ik_tasks == IkTaskSet::default());
    assert_eq!((placer.time_range, placer.max_marker_movement), (TimeRange { start: -1.0, end: -1.0 }, -1.0));

    let path = write(dir.path(), "ik.xml", &document("<InverseKinematicsTool name=\"t\"/>"));
    let setup = IkSetup::read(&path).unwrap();
    assert_eq!(setup.time_range, TimeRange { start: f64::NEG_INFINITY, end: f64::INFINITY });
    assert_eq!((setup.accuracy, setup.constraint_weight), (1e-5, f64::INFINITY));
    assert!(setup.report_errors && !setup.report_marker_locations);
    assert_eq!((setup.model_file, setup.marker_file, setup.output_motion_file), (None, None, None));
    assert_eq!(setup.results_directory.unwrap().resolved, dir.path());
}

#[test]
fn task_and_scale_defaults_and_coordinate_values_in_internal_units() {
    let dir = temporary();
    let tasks = "<IKTaskSet><objects>\
        <IKMarkerTask name=\"RASI\"/>\
        <IKCoordinateTask name=\"knee_angle_r\"><apply>false</apply><weight>5</weight>\
          <value_type>Manual_Value</value_type><value>0.35</value></IKCoordinateTask>\
        <IKCoordinateTask name=\"pelvis_tx\"><value_type>from_file</value_type></IKCoordinateTask>\
        </objects></IKTaskSet>";
    let scales = "<ModelScaler><ScaleSet><objects><Scale><segment>pelvis</segment></Scale></objects></ScaleSet></ModelScaler>";
    let body = "<MeasurementSet><objects><Measurement><BodyScaleSet><objects><BodyScale name=\"femur_r\"><axes>y</axes></BodyScale>\
        <BodyScale name=\"tibia_r\"/></objects></BodyScaleSet></Measurement></objects></MeasurementSet>";
    let scales = scales.replace("<ScaleSet>", &format!("{body}<ScaleSet>"));
    let text = document(&format!("<ScaleTool>{scales}<MarkerPlacer>{tasks}</MarkerPlacer></ScaleTool>"));
    let setup = ScaleSetup::read(&write(dir.path(), "scale.xml", &text)).unwrap();
    let tasks = setup.marker_placer.unwrap().ik_tasks;
    let marker = &tasks.marker_tasks[0];
    assert_eq!((marker.name.as_str(), marker.apply, marker.weight), ("RASI", true, 0.0));
    let knee = &tasks.coordinate_tasks[0];
    assert_eq!((knee.apply, knee.weight, knee.target), (false, 5.0, CoordinateTarget::ManualValue(0.35)), "rad, not converted");
    assert_eq!(tasks.coordinate_tasks[1].target, CoordinateTarget::FromFile);
    let scaler = setup.model_scaler.unwrap();
    let manual = &scaler.manual_scales[0];
    assert_eq!((manual.segment.as_str(), manual.scales, manual.apply), ("pelvis", [1.0; 3], true));
    let measurement = &scaler.measurements[0];
    assert_eq!((measurement.name.as_str(), measurement.apply, measurement.marker_pairs.len()), ("", true, 0));
    assert_eq!(measurement.body_scales[0].axes, [false, true, false], "lower-case axis names, as OpenSim");
    assert_eq!(measurement.body_scales[1].axes, [false; 3], "no axes: none");
}

#[test]
fn references_resolve_against_the_top_level_setup_directory_and_may_be_bare_documents() {
    let dir = temporary();
    let pairs = document("<MarkerPairSet><objects><MarkerPair><markers>A B</markers></MarkerPair></objects></MarkerPairSet>");
    write(dir.path(), "sets/pairs.xml", &pairs);
    let measurements = |pairs_reference: &str| {
        document(&format!(
            "<MeasurementSet><objects><Measurement name=\"m\"><MarkerPairSet file=\"{pairs_reference}\"/></Measurement></objects></MeasurementSet>"
        ))
    };
    // OpenSim reads nested references with the working directory still at the top-level setup.
    write(dir.path(), "sets/measurements.xml", &measurements("sets/pairs.xml"));
    // A task set without <OpenSimDocument>, as opensim-core's gait2354_IK_Tasks_uniform.xml.
    write(dir.path(), "tasks.xml", "<IKTaskSet><objects><IKMarkerTask name=\"A\"><weight>2</weight></IKMarkerTask></objects></IKTaskSet>");
    let setup_text = document(
        "<ScaleTool><ModelScaler><MeasurementSet file=\"sets/measurements.xml\"/></ModelScaler>\
         <MarkerPlacer><IKTaskSet file=\" tasks.xml \"/></MarkerPlacer></ScaleTool>",
    );
    let setup = ScaleSetup::read(&write(dir.path(), "setup.xml", &setup_text)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(setup.model_scaler.unwrap().measurements[0].marker_pairs, [["A", "B"]]);
    assert_eq!(marker_weight(&setup.marker_placer.unwrap().ik_tasks, "A"), 2.0);

    write(dir.path(), "sets/measurements.xml", &measurements("pairs.xml"));
    let error = ScaleSetup::read(&dir.path().join("setup.xml")).unwrap_err();
    let SetupError::Reference { line, element, reference, source, .. } = &error else { panic!("{error}") };
    assert_eq!((*line, element.as_str(), reference.as_str()), (3, "MeasurementSet", "sets/measurements.xml"));
    assert!(matches!(**source, SetupError::Reference { .. }), "{error}");
    assert!(error.to_string().contains("pairs.xml"), "{error}");
}

// ---- refused input ----

/// `relative` with the first occurrence of `from` replaced by `to`, written to a temporary
/// directory; also the 1-based line of that occurrence.
fn mutated(relative: &str, from: &str, to: &str) -> (tempfile::TempDir, PathBuf, usize) {
    mutated_after(relative, "", from, to)
}

/// As `mutated`, for the first occurrence of `from` after `anchor`.
fn mutated_after(relative: &str, anchor: &str, from: &str, to: &str) -> (tempfile::TempDir, PathBuf, usize) {
    let text = std::fs::read_to_string(common::fixture(relative)).unwrap();
    let start = text.find(anchor).unwrap_or_else(|| panic!("{anchor:?} not in {relative}"));
    let at = start + text[start..].find(from).unwrap_or_else(|| panic!("{from:?} not in {relative}"));
    let line = text[..at].matches('\n').count() + 1;
    let changed = format!("{}{to}{}", &text[..at], &text[at + from.len()..]);
    let dir = temporary();
    let path = write(dir.path(), Path::new(relative).file_name().unwrap().to_str().unwrap(), &changed);
    (dir, path, line)
}

/// Asserts a `BadProperty` error at `line` of `path` for `property`, whose message names the
/// file, the line, the element and what was expected.
fn assert_bad_property(error: SetupError, path: &Path, line: usize, property: &str, component: &str, expected: &str) {
    let message = error.to_string();
    let SetupError::Property(error) = error else { panic!("not a property error: {message}") };
    let ModelError::BadProperty(bad) = *error else { panic!("not a bad property: {message}") };
    let BadProperty { file, line: at, component: element, property: name, .. } = *bad;
    assert_eq!((file.as_path(), at, name.as_str()), (path, line, property), "{message}");
    assert!(element.contains(component), "{message}");
    assert!(message.contains(&format!("{}:{line}", path.display())) && message.contains(expected), "{message}");
}

#[test]
fn a_marker_pair_needs_exactly_two_names() {
    for markers in ["R.ASIS R.Knee.Lat L.ASIS", "R.ASIS", ""] {
        let (_dir, path, line) =
            mutated(SCALE_V2, "<markers> R.ASIS R.Knee.Lat </markers>", &format!("<markers>{markers}</markers>"));
        let error = ScaleSetup::read(&path).unwrap_err();
        assert_bad_property(error, &path, line, "markers", "/thigh/", "exactly two marker names");
    }
}

#[test]
fn axes_must_be_x_y_or_z() {
    let (_dir, path, line) = mutated_after(SCALE_V2, "<BodyScale name=\"femur_l\">", "<axes> X Y Z </axes>", "<axes> X W Z </axes>");
    let error = ScaleSetup::read(&path).unwrap_err();
    assert_bad_property(error, &path, line, "axes", "/thigh/BodyScaleSet/femur_l", "axis names X, Y or Z");
}

#[test]
fn numbers_must_be_numbers() {
    let (_dir, path, line) = mutated(SCALE_V2, "72.60000000", "72.6kg");
    assert_bad_property(ScaleSetup::read(&path).unwrap_err(), &path, line, "mass", "/", "a number");
    let (_dir, path, line) = mutated(SCALE_V2, "1.14724000       1.14724000       1.14724000", "1.14724 x 1.14724");
    assert_bad_property(ScaleSetup::read(&path).unwrap_err(), &path, line, "scales", "Scale", "3 numbers");
    let (_dir, path, line) = mutated(SCALE_V2, "0.98852300       0.98852300       0.98852300", "0.988523 0 0.988523");
    assert_bad_property(ScaleSetup::read(&path).unwrap_err(), &path, line, "scales", "Scale", "scale factors > 0");
    let (_dir, path, line) = mutated(IK_V3, "<accuracy>1e-005</accuracy>", "<accuracy>fine</accuracy>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "accuracy", "/", "a number");
    let (_dir, path, line) = mutated(IK_V3, "<constraint_weight>20</constraint_weight>", "<constraint_weight>-20</constraint_weight>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "constraint_weight", "/", "a number ≥ 0");
    let (_dir, path, line) = mutated(IK_V3, "<report_errors>true</report_errors>", "<report_errors>yes</report_errors>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "report_errors", "/", "true or false");
}

#[test]
fn a_time_range_is_two_times_in_order() {
    let (_dir, path, line) = mutated(IK_V3, "<time_range> 0.5 2.5</time_range>", "<time_range> 2.5 0.5</time_range>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "time_range", "/", "start ≤ end");
    let (_dir, path, line) = mutated(IK_V3, "<time_range> 0.5 2.5</time_range>", "<time_range> 0.5 1 2.5</time_range>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "time_range", "/", "2 numbers");
    let from = "<time_range>       1.00000000       2.00000000 </time_range>";
    let (_dir, path, line) = mutated(SCALE_V2, from, "<time_range> 2 1 </time_range>");
    assert_bad_property(ScaleSetup::read(&path).unwrap_err(), &path, line, "time_range", "/ModelScaler", "start ≤ end");
}

#[test]
fn weights_are_not_negative() {
    let (_dir, path, line) = mutated(IK_V3, "<weight>0.5</weight>", "<weight>-0.5</weight>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "weight", "R.Acromium", "a number ≥ 0");
    let (_dir, path, line) = mutated(IK_V3, "<weight>1000</weight>", "<weight>NaN</weight>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "weight", "subtalar_angle_r", "a number ≥ 0");
}

#[test]
fn scaling_order_words_are_measurements_and_manual_scale() {
    let (_dir, path, line) = mutated(SCALE_V2, "measurements manualScale </scaling_order>", "measurements manualscale </scaling_order>");
    let error = ScaleSetup::read(&path).unwrap_err();
    assert!(error.to_string().contains("\"manualscale\""), "{error}");
    assert_bad_property(error, &path, line, "scaling_order", "/ModelScaler", "measurements and/or manualScale");
}

#[test]
fn value_type_is_one_of_opensims_three() {
    let (_dir, path, line) = mutated(IK_V3, "<value_type>default_value</value_type>", "<value_type>default</value_type>");
    assert_bad_property(IkSetup::read(&path).unwrap_err(), &path, line, "value_type", "subtalar_angle_r", "manual_value");
}

#[test]
fn the_wrong_tool_is_refused() {
    let error = IkSetup::read(&common::fixture(SCALE_V2)).unwrap_err();
    let SetupError::UnexpectedObject { file, line, expected, found } = &error else { panic!("{error}") };
    assert_eq!((file, *line, expected.as_str(), found.as_str()), (&common::fixture(SCALE_V2), 3, "InverseKinematicsTool", "ScaleTool"));
    let error = ScaleSetup::read(&common::fixture(IK_V4)).unwrap_err();
    assert!(matches!(&error, SetupError::UnexpectedObject { found, .. } if found == "InverseKinematicsTool"), "{error}");
    let error = ScaleSetup::read(&common::fixture("subject01/gait2392_Scale_MarkerSet.xml")).unwrap_err();
    assert!(error.to_string().contains("expected <ScaleTool>, found <MarkerSet>"), "{error}");
}

#[test]
fn set_members_of_another_class_and_unnamed_tasks_are_refused() {
    let from = "<IKMarkerTask name=\"Sternum\">";
    let (_dir, path, line) = mutated(IK_V3, from, &format!("<IKMarkerTsk name=\"Sternum\"/>{from}"));
    let error = IkSetup::read(&path).unwrap_err();
    let SetupError::UnexpectedObject { line: at, found, .. } = &error else { panic!("{error}") };
    assert_eq!((*at, found.as_str()), (line, "IKMarkerTsk"));
    assert!(error.to_string().contains("<IKMarkerTask> or <IKCoordinateTask>"), "{error}");

    let (_dir, path, line) = mutated(IK_V3, from, "<IKMarkerTask>");
    let error = IkSetup::read(&path).unwrap_err();
    assert!(matches!(&error, SetupError::Unnamed { line: at, .. } if *at == line), "{error}");
    assert!(error.to_string().contains("name attribute naming its marker"), "{error}");
}

#[test]
fn unreadable_references_name_the_referring_line_and_the_file() {
    let text = std::fs::read_to_string(common::fixture(SCALE_BY_REFERENCE)).unwrap();
    let dir = temporary();
    let path = write(dir.path(), "setup.xml", &text);
    let line = text.lines().position(|l| l.contains("<MeasurementSet file=")).unwrap() + 1;
    let error = ScaleSetup::read(&path).unwrap_err();
    let SetupError::Reference { file, line: at, source, .. } = &error else { panic!("{error}") };
    assert_eq!((file.as_path(), *at), (path.as_path(), line));
    assert!(matches!(**source, SetupError::Document(_)), "{error}");
    assert!(error.to_string().contains("gait2354_Scale_MeasurementSet.xml") && error.to_string().contains("cannot read"), "{error}");

    // A reference to a file holding another object.
    let scale_set = std::fs::read_to_string(common::fixture("setup/sets/subject01_Scale_ScaleSet.xml")).unwrap();
    write(dir.path(), "sets/gait2354_Scale_MeasurementSet.xml", &scale_set);
    let error = ScaleSetup::read(&path).unwrap_err();
    let SetupError::Reference { source, .. } = &error else { panic!("{error}") };
    assert!(matches!(&**source, SetupError::UnexpectedObject { found, .. } if found == "ScaleSet"), "{error}");
}

/// Truncations and byte changes of the setups never panic (errors are fine).
#[test]
fn mangled_setups_do_not_panic() {
    let dir = temporary();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for relative in [SCALE_V2, IK_V4] {
        let original = std::fs::read(common::fixture(relative)).unwrap();
        for _ in 0..150 {
            let mut bytes = original.clone();
            let at = (next() % bytes.len() as u64) as usize;
            match next() % 3 {
                0 => bytes.truncate(at),
                1 => bytes[at] = b"<>/\"= -0.e9xX"[(next() % 13) as usize],
                _ => drop(bytes.splice(at..at, b"<time_range>9 1</time_range>".iter().copied())),
            }
            let path = dir.path().join("mangled.xml");
            std::fs::write(&path, &bytes).unwrap();
            let _ = ScaleSetup::read(&path);
            let _ = IkSetup::read(&path);
        }
    }
}
