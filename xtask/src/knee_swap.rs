//! Swapped-knee rows of the validation table: gait2392's knee_r replaced by a PinJoint about a
//! tilted axis, loaded and posed by OpenSim 4.6 (`oracle/knee_pose.py`) when Python can import it.

use std::process::Command;

use nalgebra::{Matrix3, Vector3};
use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::rotation_about;
use osim_tune::tuning::knee_axis::{swap_knee, JointAxis};

use crate::root;
use crate::validate::Row;

const REFERENCE: &str = "OpenSim 4.6, oracle/knee_pose.py";
const REFERENCE_ANGLE: f64 = -0.6;

/// A child pose in its parent: rotation and translation (m).
type Pose = (Matrix3<f64>, Vector3<f64>);

pub fn rows() -> Vec<Row> {
    if !Command::new("python3").args(["-c", "import opensim"]).output().is_ok_and(|o| o.status.success()) {
        return Vec::new();
    }
    let generic_file = root().join("models/gait2392_millard2012muscle.osim");
    let generic = OsimDocument::read(&generic_file).expect("gait2392");
    let axis = JointAxis { point: Vector3::new(0.004, -0.41, 0.006), direction: Vector3::new(0.05, -0.03, 1.0).normalize() };
    let swapped = swap_knee(&generic, "knee_r", &axis, Some(REFERENCE_ANGLE)).expect("knee_r swaps");
    let file = tempfile::Builder::new().suffix(".osim").tempfile().expect("temporary file");
    std::fs::write(file.path(), swapped.document.xml.serialize()).expect("written");
    let swapped_file = file.path().to_path_buf();
    let before = opensim_pose(&generic_file.display().to_string(), REFERENCE_ANGLE);
    let after = opensim_pose(&swapped_file.display().to_string(), REFERENCE_ANGLE);
    let mut rows = vec![Row {
        what: "swapped knee_r model loads in OpenSim 4.6".into(),
        reference: "opensim.Model(...).initSystem()".into(),
        worst: f64::from(u8::from(after.is_none())),
        tolerance: 0.0,
        at: String::new(),
    }];
    let (Some(before), Some(after)) = (before, after) else { return rows };
    rows.push(Row {
        what: "swapped knee: tibia pose at the reference angle (m)".into(),
        reference: REFERENCE.into(),
        worst: distance(&before, &after),
        tolerance: 1e-9,
        at: format!("knee_angle_r = {REFERENCE_ANGLE} rad"),
    });
    let mut worst: f64 = 0.0;
    for angle in [-2.0, -1.2, 0.1] {
        let turn = rotation_about(&axis.direction, angle - REFERENCE_ANGLE);
        let expected = (turn * before.0, turn * (before.1 - axis.point) + axis.point);
        worst = worst.max(opensim_pose(&swapped_file.display().to_string(), angle).map_or(f64::INFINITY, |pose| distance(&expected, &pose)));
    }
    rows.push(Row { what: "swapped knee: tibia turns about the fitted axis (m)".into(), reference: REFERENCE.into(), worst, tolerance: 1e-9, at: "knee_angle_r −2.0, −1.2, 0.1 rad".into() });
    rows
}

/// OpenSim's tibia_r pose in femur_r with knee_angle_r at `angle` (rad).
fn opensim_pose(model: &str, angle: f64) -> Option<Pose> {
    let script = root().join("oracle/knee_pose.py");
    let output = Command::new("python3").arg(script).args([model, "femur_r", "tibia_r", "knee_angle_r", &angle.to_string()]).output().ok()?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let json: serde_json::Value = serde_json::from_str(stdout.lines().last()?).ok()?;
    let number = |v: &serde_json::Value| v.as_f64();
    let rotation = json["rotation"].as_array()?.iter().map(|row| row.as_array().map(|r| r.iter().filter_map(number).collect::<Vec<_>>())).collect::<Option<Vec<_>>>()?;
    let translation: Vec<f64> = json["translation"].as_array()?.iter().filter_map(number).collect();
    Some((Matrix3::from_fn(|i, j| rotation[i][j]), Vector3::from_column_slice(&translation)))
}

/// Largest displacement of three points of the tibia (origin, 40 cm down the shaft, a point
/// beside it) between two poses.
fn distance(a: &Pose, b: &Pose) -> f64 {
    let points = [Vector3::zeros(), Vector3::new(0.0, -0.4, 0.0), Vector3::new(0.05, 0.02, -0.04)];
    points.iter().map(|p| ((a.0 * p + a.1) - (b.0 * p + b.1)).norm()).fold(0.0, f64::max)
}
