//! The `osim-tune` binary: exit codes, outputs and bad input (clear message naming file and
//! line, exit 2, no output file).

mod common;

use std::path::Path;

use common::osim_tune;

fn temporary() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn set_without_assignments_copies_every_document_byte_for_byte() {
    let dir = temporary();
    for input in common::opensim_documents() {
        let output = dir.path().join(input.file_name().unwrap());
        let (code, _, stderr) = osim_tune(&["set", s(&input), "-o", s(&output)]);
        assert_eq!(code, 0, "{stderr}");
        assert!(std::fs::read(&input).unwrap() == std::fs::read(&output).unwrap(), "{}", input.display());
    }
}

#[test]
fn set_then_diff_reports_the_one_edit() {
    let dir = temporary();
    let input = common::root().join("models/gait2392_millard2012muscle.osim");
    let output = dir.path().join("edited.osim");
    let (code, _, stderr) = osim_tune(&["set", s(&input), "-o", s(&output), "/forceset/vas_lat_r/tendon_slack_length=0.17"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, _) = osim_tune(&["diff", s(&input), s(&output), "--json"]);
    assert_eq!(code, 1);
    let report: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let differences = report["differences"].as_array().unwrap();
    assert_eq!(differences.len(), 1);
    assert_eq!(differences[0]["path"], "/forceset/vas_lat_r/tendon_slack_length");
    assert_eq!(differences[0]["new"], "0.17");
    let (code, stdout, _) = osim_tune(&["diff", s(&input), s(&input)]);
    assert_eq!((code, stdout.as_str()), (0, ""));
}

#[test]
fn info_json_counts_the_model() {
    let (code, stdout, stderr) = osim_tune(&["info", "--json", s(&common::fixture("models/leg6dof9musc.osim"))]);
    assert_eq!(code, 0, "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["muscles"].as_array().unwrap().len(), 9);
    assert_eq!(summary["markers"].as_array().unwrap().len(), 12);
    assert_eq!(summary["constraints"][0]["name"], "pat_angle_r");
    assert_eq!(summary["constraints"][0]["class"], "CoordinateCouplerConstraint");
    assert_eq!(summary["joint_classes"]["WeldJoint"], 2);
}

/// `info` shows the default pose OpenSim's `initSystem` assembles: on the linked mechanisms the
/// coordinates it moves, with OpenSim 4.6's values (`golden/constraint_assembly.json`, to the
/// 8 printed decimals).
#[test]
fn info_shows_the_assembled_default_pose() {
    let (code, stdout, stderr) = osim_tune(&["info", s(&common::fixture("models/linked_mechanisms.osim"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("rod                      ConstantDistanceConstraint") && stdout.contains("free to satisfy constraints"), "{stdout}");
    let golden: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(common::fixture("golden/constraint_assembly.json")).unwrap()).unwrap();
    let golden = &golden["linked_mechanisms.osim"];
    let names: Vec<&str> = golden["coordinates"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    let rocker = names.iter().position(|n| *n == "rocker_angle").unwrap();
    let expected = format!("rocker_angle              -0.20000000 → {:>12.8}", golden["assembled"][rocker].as_f64().unwrap());
    assert!(stdout.contains("default pose, assembled as OpenSim's initSystem does") && stdout.contains(&expected), "{expected:?} not in {stdout}");
    let (_, plain, _) = osim_tune(&["info", s(&common::fixture("models/arm26.osim"))]);
    assert!(plain.contains("default pose: the default values") && plain.contains("controllers (0): -") && plain.contains("probes (0): -"), "{plain}");
    let (_, probes, _) = osim_tune(&["info", s(&common::fixture("models/arm26_probes.osim"))]);
    assert!(probes.contains("probes (9):\n  metabolics               Umberger2010MuscleMetabolicsProbe\n") && probes.contains("  idle                     Umberger2010MuscleMetabolicsProbe (disabled)\n"), "{probes}");
}

/// `info` lists the model's controllers and what they drive.
#[test]
fn info_lists_the_controllers() {
    let (code, stdout, stderr) = osim_tune(&["info", s(&common::fixture("golden/forward_tool/prescribed/arm26_prescribed.osim"))]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("controllers (2):\n  PrescribedController p_model: TRIlong BIClong BRA (3 functions)\n  PrescribedController p_all: ALL (6 functions)\n"), "{stdout}");
}

/// Writes `text` to a file, runs `set` on it and checks the failure.
fn assert_set_fails(text: &str, assignments: &[&str], expected: &[&str]) {
    let dir = temporary();
    let input = dir.path().join("bad.osim");
    std::fs::write(&input, text).unwrap();
    let output = dir.path().join("out.osim");
    let mut arguments = vec!["set", s(&input), "-o", s(&output)];
    arguments.extend_from_slice(assignments);
    let (code, stdout, stderr) = osim_tune(&arguments);
    assert_eq!(code, 2, "{stderr}");
    assert!(stdout.is_empty());
    for part in expected {
        assert!(stderr.contains(part), "{part:?} not in {stderr:?}");
    }
    assert!(!output.exists(), "output written despite the error");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "stray files left");
}

#[test]
fn malformed_xml_names_file_and_line() {
    let text = "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n<Model name=\"m\">\n<credits>x</credit>\n</Model>\n</OpenSimDocument>\n";
    assert_set_fails(text, &[], &["bad.osim:4:", "malformed XML"]);
    assert_set_fails("<OpenSimDocument Version=\"40000\"><Model name=\"m\">", &[], &["bad.osim:1:", "never closed"]);
    assert_set_fails("<a/><b/>", &[], &["second root"]);
}

#[test]
fn unknown_version_is_refused() {
    let text = "<OpenSimDocument Version=\"12345\">\n<Model name=\"m\"/>\n</OpenSimDocument>\n";
    assert_set_fails(text, &[], &["bad.osim:1:", "unsupported OpenSim document version \"12345\""]);
    // A bare object (no <OpenSimDocument>, as OpenSim 1.x wrote them and OpenSim still reads) is
    // read as such: copied unchanged, its properties found.
    let dir = temporary();
    let (input, output) = (dir.path().join("bare.xml"), dir.path().join("out.xml"));
    std::fs::write(&input, "<ActuatorSet name=\"a\"><objects><CoordinateActuator name=\"r\"><optimal_force>1</optimal_force></CoordinateActuator></objects></ActuatorSet>").unwrap();
    let (code, _, stderr) = osim_tune(&["set", s(&input), "-o", s(&output), "/r/optimal_force=2"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(std::fs::read_to_string(&output).unwrap().contains("<optimal_force>2</optimal_force>"));
}

#[test]
fn bad_assignments_write_nothing() {
    let text = std::fs::read_to_string(common::fixture("legacy/pendulum_leg_v30000.osim")).unwrap();
    assert_set_fails(&text, &["/ForceSet/vasti/optimal_fiber_length=abc"], &["bad.osim:187:", "optimal_fiber_length", "expected a number"]);
    assert_set_fails(&text, &["/ForceSet/nothing/optimal_fiber_length=0.1"], &["no component or property", "\"nothing\""]);
    assert_set_fails(&text, &["/ForceSet/vasti/optimal_fiber_length"], &["not PATH=VALUE"]);
    // The first edit is valid; the second is not: nothing at all is written.
    assert_set_fails(&text, &["/ForceSet/vasti/optimal_fiber_length=0.1", "/ForceSet/vasti/tendon_slack_length=x"], &["tendon_slack_length"]);
}

#[test]
fn a_missing_or_unparsable_required_property_is_named() {
    let text = std::fs::read_to_string(common::fixture("legacy/pendulum_leg_v30000.osim")).unwrap();
    let dir = temporary();
    let input = dir.path().join("broken.osim");
    std::fs::write(&input, text.replacen("<mass>8.5</mass>", "<mass>8,5</mass>", 1)).unwrap();
    let (code, _, stderr) = osim_tune(&["info", s(&input)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("broken.osim:") && stderr.contains("<mass> must be a number") && stderr.contains("thigh"), "{stderr}");
    // A body's mass has no default (OpenSim's is NaN); a coordinate's range has one (−10…10).
    std::fs::write(&input, text.replacen("<mass>8.5</mass>", "", 1)).unwrap();
    let (code, _, stderr) = osim_tune(&["info", s(&input)]);
    assert_eq!(code, 2);
    assert!(stderr.contains("thigh: missing <mass>"), "{stderr}");
    std::fs::write(&input, text.replacen("<range>-0.5 2.0</range>", "", 1)).unwrap();
    let (code, stdout, stderr) = osim_tune(&["info", s(&input)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("hip_flexion") && stdout.contains("-10"), "{stdout}");
}

#[test]
fn output_equal_to_input_is_refused() {
    let dir = temporary();
    let input = dir.path().join("model.osim");
    std::fs::copy(common::fixture("models/arm26.osim"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let same = dir.path().join(".").join("model.osim");
    let (code, _, stderr) = osim_tune(&["set", s(&input), "-o", s(&same), "/forceset/TRIlong/optimal_fiber_length=0.2"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("refusing to overwrite an input"), "{stderr}");
    assert_eq!(std::fs::read(&input).unwrap(), before);
}

/// `osim-tune diff A B --json | head -1`: the reader closes the pipe after one line while the
/// command still has output (164 kB here, more than a pipe holds). The process must end quietly,
/// by SIGPIPE as other Unix tools do, not panic on the failed write.
#[cfg(unix)]
#[test]
fn a_reader_closing_the_pipe_early_ends_diff_quietly() {
    use std::io::BufRead;
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    let (a, b) = (common::root().join("models/gait2392_millard2012muscle.osim"), common::root().join("models/gait2392_thelen2003muscle.osim"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_osim-tune"))
        .args(["diff", s(&a), s(&b), "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first_line = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap()).read_line(&mut first_line).unwrap();
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(first_line, "{\n");
    assert!(stderr.is_empty(), "{stderr}");
    const SIGPIPE: i32 = 13;
    assert_eq!(output.status.signal(), Some(SIGPIPE), "{:?}", output.status);
}

/// `convert` writes a 2.x model in the 4.x format (which `info` reads as version 40000 with the
/// same muscles), copies a 4.x model unchanged, and refuses to overwrite its input.
#[test]
fn convert_writes_an_older_model_in_opensim_4s_format() {
    let dir = temporary();
    let input = common::fixture("legacy/arm26_v20303.osim");
    let output = dir.path().join("arm26.osim");
    let (code, stdout, stderr) = osim_tune(&["convert", s(&input), "-o", s(&output)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("from version 20303 to 40000"), "{stdout}");
    let (code, stdout, _) = osim_tune(&["info", "--json", s(&output)]);
    assert_eq!(code, 0);
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["version"], 40000);
    assert_eq!(summary["muscles"].as_array().unwrap().len(), 6);
    let again = dir.path().join("again.osim");
    let (code, stdout, _) = osim_tune(&["convert", s(&output), "-o", s(&again)]);
    assert_eq!(code, 0);
    assert!(stdout.contains("already in OpenSim 4's format"), "{stdout}");
    assert_eq!(std::fs::read(&output).unwrap(), std::fs::read(&again).unwrap());
    let (code, _, stderr) = osim_tune(&["convert", s(&input), "-o", s(&input)]);
    assert_eq!(code, 2, "{stderr}");
}
