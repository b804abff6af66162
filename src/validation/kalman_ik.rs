//! How much Kalman-smoothed IK (`ik --kalman`) helps inverse dynamics' input: a synthetic walk
//! with known kinematics — subject01's IK motion low-pass filtered at 6 Hz through the scaled
//! model — its markers with Gaussian noise, solved by per-frame IK and by the smoother; the
//! coordinates and their accelerations (degree-5 GCV splines, as the ID tool takes them, with or
//! without its 6 Hz low-pass) against the truth.

use std::path::Path;

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

use crate::analysis::Series;
use crate::io::osim::OsimDocument;
use crate::io::table::{LengthUnit, MarkerTable, StorageTable, TrcHeader};
use crate::mechanics::{Function, Motion, Multibody};
use crate::model::ModelSpec;
use crate::solvers::{IkSettings, IkSolution, IkTasks, InverseKinematics, KalmanIkSettings};

/// The coordinates the study reports.
pub const STUDY_COORDINATES: [&str; 4] = ["pelvis_tilt", "hip_flexion_r", "knee_angle_r", "ankle_angle_r"];
/// Frames left out at each end (the splines' and filters' edges).
const EDGE: usize = 6;
/// The low-pass cutoff of the truth and of the ID tool's filter, Hz.
const CUTOFF: f64 = 6.0;

/// RMS errors per [`STUDY_COORDINATES`] entry (rad and rad/s²) of three estimates: per-frame
/// IK, the same low-pass filtered as the ID tool filters, and Kalman-smoothed IK.
#[derive(Debug, Clone, PartialEq)]
pub struct KalmanIkStudy {
    pub frames: usize,
    /// [IK, IK + 6 Hz, Kalman] per coordinate.
    pub coordinate: Vec<[f64; 3]>,
    pub acceleration: Vec<[f64; 3]>,
}

/// The study at marker noise `noise_sd` (m) with seed `seed`, the smoother at `cutoff` Hz, over
/// the first `frames` frames of the walk (60 Hz).
pub fn kalman_ik_study(root: &Path, noise_sd: f64, seed: u64, cutoff: f64, frames: usize) -> Result<KalmanIkStudy, Box<dyn std::error::Error>> {
    let model = root.join("fixtures/golden/scale/subject01_simbody.osim");
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&model)?)?)?;
    let motion_file = root.join("fixtures/golden/ik/subject01_walk1_ik.mot");
    let motion = Motion::from_table(&StorageTable::read(&motion_file)?, &motion_file, &multibody, false)?;
    let count = frames.min(motion.len());
    let times = motion.times[..count].to_vec();
    let truth = splines(&times, (0..multibody.coordinates.len()).map(|c| (0..count).map(|i| motion.pose(i)[c]).collect()).collect(), Some(CUTOFF))?;
    let poses: Vec<Vec<f64>> = times.iter().map(|&t| truth.iter().map(|f| f.value(t)).collect()).collect();
    let trial = noisy_markers(&multibody, &times, &poses, noise_sd, seed)?;
    let ik = InverseKinematics::new(&multibody, &trial, Path::new("synthetic.trc"), &IkTasks::every_marker(), IkSettings::default())?;
    let solved = ik.solve(None)?;
    let smoothed = ik.smooth(&solved, &KalmanIkSettings::with_cutoff(cutoff))?.solution;
    let mut study = KalmanIkStudy { frames: count, coordinate: Vec::new(), acceleration: Vec::new() };
    for name in STUDY_COORDINATES {
        let c = multibody.coordinate_index(name).ok_or_else(|| format!("{}: no coordinate {name}", model.display()))?;
        let estimates = [(&solved, None), (&solved, Some(CUTOFF)), (&smoothed, None)];
        let (mut coordinate, mut acceleration) = ([0.0; 3], [0.0; 3]);
        for (k, (solution, filter)) in estimates.into_iter().enumerate() {
            let spline = &splines(&times, vec![column(solution, c)], filter)?[0];
            coordinate[k] = rms(&times, |t| spline.value(t) - truth[c].value(t));
            acceleration[k] = rms(&times, |t| spline.second_derivative(t) - truth[c].second_derivative(t));
        }
        study.coordinate.push(coordinate);
        study.acceleration.push(acceleration);
    }
    Ok(study)
}

/// Degree-5 GCV splines of `columns` over `times`, low-pass filtered first when asked (as the
/// ID tool prepares coordinates).
fn splines(times: &[f64], columns: Vec<Vec<f64>>, cutoff: Option<f64>) -> Result<Vec<Function>, Box<dyn std::error::Error>> {
    Ok(Series::new(times.to_vec(), columns, 6)?.filtered(cutoff)?.splines()?)
}

fn column(solution: &IkSolution, c: usize) -> Vec<f64> {
    solution.frames.iter().map(|f| f.q[c]).collect()
}

/// RMS of `error` over the frames between the edges.
fn rms(times: &[f64], error: impl Fn(f64) -> f64) -> f64 {
    let inner = &times[EDGE..times.len() - EDGE];
    (inner.iter().map(|&t| error(t).powi(2)).sum::<f64>() / inner.len() as f64).sqrt()
}

/// Every model marker at `poses`, each coordinate with N(0, σ²) noise (seeded).
fn noisy_markers(multibody: &Multibody, times: &[f64], poses: &[Vec<f64>], noise_sd: f64, seed: u64) -> Result<MarkerTable, Box<dyn std::error::Error>> {
    let (noise, mut rng) = (Normal::new(0.0, noise_sd)?, rand::rngs::StdRng::seed_from_u64(seed));
    let mut kinematics = multibody.kinematics();
    let mut positions = Vec::with_capacity(poses.len() * multibody.markers.len());
    for q in poses {
        multibody.realize(q, &mut kinematics);
        for m in 0..multibody.markers.len() {
            let p = kinematics.marker_location(multibody, m);
            positions.push(Some([p.x + noise.sample(&mut rng), p.y + noise.sample(&mut rng), p.z + noise.sample(&mut rng)]));
        }
    }
    let names = multibody.markers.iter().map(|m| m.name.clone()).collect();
    let rate = (times.len() - 1) as f64 / (times[times.len() - 1] - times[0]);
    Ok(MarkerTable::new(TrcHeader::new(rate, LengthUnit::Meters), names, times.to_vec(), positions)?)
}
