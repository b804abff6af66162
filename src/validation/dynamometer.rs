//! The extended dynamometer set-up against `oracle/gen_dynamometer.py`
//! (`fixtures/golden/dynamometer/<case>/`): OpenSim 4.6's InverseDynamicsTool with the pad's
//! load on the tibia known gives the truth M3D; the load cell is the crank's Newton–Euler on
//! OpenSim's splines. From the load cell alone we must find M3D, the pad's load and what the
//! dynamometer reads, and, where Herzog's assumptions hold, M2D = M3D.

use std::path::{Path, PathBuf};

use super::geometry::Worst;
use crate::analysis::{dynamometer_analysis, DynamometerModel, DynamometerResult, DynamometerSettings, ExternalLoads, MeasuredMoment, Perturbations, SplinedMotion};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::{Multibody, Vec3};
use crate::model::ModelSpec;

/// One golden case and the bound tests and validate hold it to.
pub struct DynamometerCase {
    pub case: &'static str,
    /// Whether Herzog's 2D estimate is exact here.
    pub herzog_exact: bool,
    /// Largest |ours − truth| of a moment or force (N·m, N).
    pub tolerance: f64,
}

/// `spatial`: axes 4–6° and 4–6 cm apart, a moving femur, an isokinetic sweep, the pad's force
/// off the crank's normal with a free torque. `planar`: aligned axes, the knee on the crank's
/// line, a perpendicular pad force, isometric. Found 2.3e-13 N·m; the bound allows for the
/// goldens' 17 digits.
pub const DYNAMOMETER_CASES: [DynamometerCase; 2] =
    [DynamometerCase { case: "spatial", herzog_exact: false, tolerance: 1e-9 }, DynamometerCase { case: "planar", herzog_exact: true, tolerance: 1e-9 }];

/// What a case's comparison found.
#[derive(Debug, Clone, Default)]
pub struct DynamometerComparison {
    /// M3D against OpenSim's knee moment.
    pub knee_moment: Worst,
    /// F_tc and its moment about D against the truth.
    pub pad_load: Worst,
    /// Z·(pad moment) − I_ZZ θ̈ against the dynamometer's reading.
    pub dynamometer_moment: Worst,
    /// M2D against OpenSim's knee moment, where Herzog is exact.
    pub herzog: Option<Worst>,
}

/// The golden case's files.
fn golden(root: &Path, case: &str, file: &str) -> PathBuf {
    root.join("fixtures/golden/dynamometer").join(case).join(file)
}

/// Our analysis of the golden case `case`, with the dynamometer's moment and table 5.1's
/// perturbations.
pub fn dynamometer_golden_run(root: &Path, case: &str) -> Result<(Multibody, DynamometerModel, DynamometerResult), Box<dyn std::error::Error>> {
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&root.join(format!("fixtures/models/dynamometer_{case}.osim")))?)?)?;
    let model = DynamometerModel::new(&multibody, "crank", "knee_angle_r")?;
    let (loads, data_file) = ExternalLoads::read(&golden(root, case, "loadcell.xml"), &multibody)?;
    let measured = MeasuredMoment::new(&StorageTable::read(&data_file)?, &data_file, "dynamometer_moment", 1.0)?;
    let coordinates = golden(root, case, "coordinates.mot");
    let motion = SplinedMotion::new(&multibody, &StorageTable::read(&coordinates)?, &coordinates, None)?;
    let settings = DynamometerSettings { time_range: [f64::NEG_INFINITY, f64::INFINITY], perturbations: Perturbations::THESIS };
    let result = dynamometer_analysis(&multibody, &model, &motion, &loads, Some(&measured), &settings)?;
    Ok((multibody, model, result))
}

impl DynamometerCase {
    /// Our run against the case's truth.
    pub fn compare(&self, root: &Path) -> Result<DynamometerComparison, Box<dyn std::error::Error>> {
        let (_, _, result) = dynamometer_golden_run(root, self.case)?;
        let truth = StorageTable::read(&golden(root, self.case, "inverse_dynamics.sto"))?.column("knee_angle_r_moment").ok_or("inverse_dynamics.sto lacks knee_angle_r_moment")?;
        let pads = pad_truth(&golden(root, self.case, "pad_truth.csv"))?;
        if truth.len() != result.frames.len() || pads.len() != result.frames.len() {
            return Err(format!("{} frames against {} golden rows", result.frames.len(), truth.len()).into());
        }
        let mut comparison = DynamometerComparison { herzog: self.herzog_exact.then(Worst::default), ..Default::default() };
        for (i, ((frame, &time), (&moment, pad))) in result.frames.iter().zip(&result.times).zip(truth.iter().zip(&pads)).enumerate() {
            let at = || format!("t = {time} s");
            comparison.knee_moment.update((frame.knee_moment - moment).abs(), at);
            let (force, point, torque) = (Vec3::new(pad[1], pad[2], pad[3]), Vec3::new(pad[4], pad[5], pad[6]), Vec3::new(pad[7], pad[8], pad[9]));
            let about_d = (point - frame.dynamometer_axis.point).cross(&force) + torque;
            comparison.pad_load.update((frame.pad_force - force).norm().max((frame.pad_moment - about_d).norm()), at);
            let reading = frame.dynamometer_axis.direction.dot(&frame.pad_moment) - frame.crank_inertial_moment;
            comparison.dynamometer_moment.update((reading - pad[10]).abs(), at);
            if let (Some(worst), Some(herzog)) = (&mut comparison.herzog, &result.herzog) {
                worst.update((herzog[i].knee_moment - moment).abs(), at);
            }
        }
        Ok(comparison)
    }
}

/// `pad_truth.csv`: per row time, F_tc (tibia on crank), its point p, its free torque T_tc (in
/// ground) and the dynamometer's moment.
fn pad_truth(file: &Path) -> Result<Vec<[f64; 11]>, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    text.lines()
        .skip(1)
        .enumerate()
        .map(|(i, line)| {
            let values: Result<Vec<f64>, _> = line.split(',').map(str::parse).collect();
            values.ok().and_then(|v| <[f64; 11]>::try_from(v).ok()).ok_or_else(|| format!("{}:{}: expected 11 numbers", file.display(), i + 2).into())
        })
        .collect()
}
