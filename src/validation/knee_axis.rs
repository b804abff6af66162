//! Accuracy of the functional knee axis on synthetic trials with a known axis (issue 7): a
//! seeded generator of thigh and shank marker clusters moving about a known axis, with marker
//! noise and optionally soft-tissue artefact, and the study that the tests and
//! `cargo xtask validate` run over many seeds.
//!
//! Geometry (femur anatomical frame, OpenSim convention for a right leg: x anterior,
//! y superior, z right = lateral; origin at the hip joint centre):
//! - epicondyle markers at (0, −0.40, ±0.045) m; the true axis is placed off their line:
//!   its point 5–10 mm away in the sagittal plane, its direction tilted 2–5° in both the
//!   transversal and the frontal plane (random signs);
//! - the tibia frame coincides with the femur frame at 0° flexion; flexion θ rotates the tibia
//!   about the true axis by −θ (the shank swings posteriorly), sweeping θ from 20° to 100° and
//!   back (one cosine cycle over the trial);
//! - 4–6 femur markers spread 30 cm along the thigh (y from −0.07 to −0.37 m) and only
//!   ±7 cm across it (alternately 4–7 cm to either side), on its anterior side; 4–6 tibia
//!   markers likewise on the shin
//!   (y from −0.47 to −0.77 m, tibia frame);
//! - the femur moves in the lab too: a seated pose (thigh horizontal) with a few cm of
//!   translation and a few degrees of rotation about every axis.
//!
//! Measurement errors: Gaussian noise on every coordinate (σ = 1 mm by default) and, with
//! [`Condition::SoftTissue`], a smooth knee-angle-dependent displacement of every marker in its
//! segment frame, zero at 20° and peaking at 10–20 mm on the femur and 5–10 mm on the tibia
//! (each marker its own amplitude and profile; its direction ¾ shared by the segment's markers,
//! ¼ its own).
//! About 1 % of marker samples are dropped (missing), in runs of a few frames.

use std::ops::Range;

use nalgebra::{Rotation3, Vector3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal, UnitSphere};

use crate::io::table::{LengthUnit, MarkerTable, TrcHeader};
use crate::tuning::knee_axis::{
    compare_axes, fit_axis, AnatomicalFrame, Axis, AxisError, AxisHint, AxisMethod, KneeMotion, PoseMethod, SegmentCluster, SegmentPose,
};

const DEGREE: f64 = std::f64::consts::PI / 180.0;

/// Noise-only goal on both orientation angles in every trial (1.5°, rad).
pub const NOISE_ORIENTATION_GOAL: f64 = 1.5 * DEGREE;
/// Noise-only goal on the sagittal location error in every trial (5 mm, m).
pub const NOISE_LOCATION_GOAL: f64 = 5e-3;
/// With soft-tissue artefact, goal on GaL's mean orientation errors (5°, rad).
pub const ARTEFACT_GAL_ORIENTATION_MEAN_GOAL: f64 = 5.0 * DEGREE;
/// With soft-tissue artefact, goal on GaL's mean sagittal location error (15 mm, m).
pub const ARTEFACT_GAL_LOCATION_MEAN_GOAL: f64 = 15e-3;

/// Which measurement errors a synthetic trial has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Condition {
    /// Marker noise only.
    Noise,
    /// Marker noise and soft-tissue artefact.
    SoftTissue,
}

/// What to generate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticKneeSettings {
    /// Seed of every random choice (geometry, motion, noise, artefact, gaps).
    pub seed: u64,
    pub condition: Condition,
    /// σ of each marker coordinate (m). Default 1e-3.
    pub marker_noise: f64,
    /// Sampling rate (Hz). Default 100.
    pub rate: f64,
    /// Trial duration (s), one flexion–extension cycle. Default 4.
    pub duration: f64,
    /// Smallest and largest knee flexion (rad). Default 20° and 100°.
    pub flexion: (f64, f64),
    /// Fraction of marker samples dropped. Default 0.01.
    pub missing_fraction: f64,
    /// Range of the peak soft-tissue displacement of femur markers (m), with
    /// [`Condition::SoftTissue`]. Default 10–20 mm.
    pub femur_artefact: (f64, f64),
    /// The same for tibia markers (m). Default 5–10 mm.
    pub tibia_artefact: (f64, f64),
}

impl SyntheticKneeSettings {
    /// The defaults above for `seed` and `condition`.
    pub fn new(seed: u64, condition: Condition) -> Self {
        SyntheticKneeSettings {
            seed,
            condition,
            marker_noise: 1e-3,
            rate: 100.0,
            duration: 4.0,
            flexion: (20.0 * DEGREE, 100.0 * DEGREE),
            missing_fraction: 0.01,
            femur_artefact: (10e-3, 20e-3),
            tibia_artefact: (5e-3, 10e-3),
        }
    }

    fn check(&self) -> Result<(), AxisError> {
        let (low, high) = self.flexion;
        let checks = [
            ("marker_noise", self.marker_noise, self.marker_noise.is_finite() && self.marker_noise >= 0.0, "a finite σ ≥ 0 (m)"),
            ("rate", self.rate, self.rate.is_finite() && self.rate > 0.0, "a finite rate > 0 (Hz)"),
            ("duration", self.duration, self.duration > 0.0 && self.duration * self.rate < 1e6, "a duration > 0 (s), < 10⁶ frames"),
            ("flexion.1", high, low.is_finite() && high.is_finite() && high > low, "larger than flexion.0 (rad), both finite"),
            ("missing_fraction", self.missing_fraction, (0.0..=0.5).contains(&self.missing_fraction), "a fraction in [0, 0.5]"),
            ("femur_artefact.1", self.femur_artefact.1, valid_range(self.femur_artefact), "≥ femur_artefact.0 ≥ 0 (m), both finite"),
            ("tibia_artefact.1", self.tibia_artefact.1, valid_range(self.tibia_artefact), "≥ tibia_artefact.0 ≥ 0 (m), both finite"),
        ];
        match checks.into_iter().find(|(_, _, ok, _)| !ok) {
            Some((name, value, _, expected)) => Err(invalid(name, value, expected)),
            None => Ok(()),
        }
    }
}

/// A synthetic trial and the truth behind it.
#[derive(Debug, Clone)]
pub struct SyntheticKnee {
    /// The marker trial, written in millimetres (as motion-capture files usually are).
    pub trial: MarkerTable,
    /// The femur markers with their true coordinates in the femur anatomical frame (m).
    pub femur_cluster: SegmentCluster,
    /// The tibia markers with their true coordinates in the tibia anatomical frame (m).
    pub tibia_cluster: SegmentCluster,
    /// The generating axis in the femur frame (direction towards +z, lateral).
    pub true_axis_femur: Axis,
    /// The generating axis in the tibia frame (the same line: the frames coincide at 0°).
    pub true_axis_tibia: Axis,
    /// Names of the epicondyle markers in the trial (femur, not in the cluster).
    pub lateral_epicondyle: String,
    pub medial_epicondyle: String,
    /// True femur and tibia → lab poses per frame.
    pub femur_poses: Vec<SegmentPose>,
    pub tibia_poses: Vec<SegmentPose>,
    /// True knee flexion per frame (rad).
    pub flexion: Vec<f64>,
}

/// Generates the synthetic trial of `settings` (see the module doc). Errors for settings out of
/// their domain (negative noise, non-positive rate or duration, empty flexion range, a missing
/// fraction outside [0, 0.5]).
pub fn synthetic_knee(settings: &SyntheticKneeSettings) -> Result<SyntheticKnee, AxisError> {
    settings.check()?;
    let mut rng = StdRng::seed_from_u64(settings.seed);
    let true_axis = random_axis(&mut rng);
    let femur_local = random_cluster(&mut rng, -0.07, 0.06..0.09);
    let tibia_local = random_cluster(&mut rng, -0.47, 0.03..0.06);
    let epicondyles = [Vector3::new(0.0, -0.40, 0.045), Vector3::new(0.0, -0.40, -0.045)];
    let femur_artefact = random_artefacts(&mut rng, femur_local.len() + 2, settings.femur_artefact);
    let tibia_artefact = random_artefacts(&mut rng, tibia_local.len(), settings.tibia_artefact);
    let motion = FemurMotion::random(&mut rng);

    let frames = (settings.duration * settings.rate).round() as usize + 1;
    let times: Vec<f64> = (0..frames).map(|i| i as f64 / settings.rate).collect();
    let (low, high) = settings.flexion;
    let flexion: Vec<f64> = times.iter().map(|t| low + (high - low) * 0.5 * (1.0 - (2.0 * std::f64::consts::PI * t / settings.duration).cos())).collect();
    let femur_poses: Vec<SegmentPose> = times.iter().map(|&t| motion.pose(t)).collect();
    let tibia_poses: Vec<SegmentPose> = femur_poses.iter().zip(&flexion).map(|(femur, &angle)| femur.compose(&knee_pose(&true_axis, angle))).collect();

    let soft_tissue = settings.condition == Condition::SoftTissue;
    let noise = Normal::new(0.0, settings.marker_noise).map_err(|_| invalid("marker_noise", settings.marker_noise, "a finite σ ≥ 0 (m)"))?;
    let femur_points: Vec<Vector3<f64>> = femur_local.iter().chain(&epicondyles).copied().collect();
    let mut positions = Vec::with_capacity(frames * (femur_points.len() + tibia_local.len()));
    for frame in 0..frames {
        let stage = (flexion[frame] - low) / (high - low);
        let mut place = |pose: &SegmentPose, local: &Vector3<f64>, artefact: &Artefact| {
            let displaced = if soft_tissue { local + artefact.displacement(stage) } else { *local };
            let lab = pose.to_lab(&displaced) + Vector3::from_fn(|_, _| noise.sample(&mut rng));
            positions.push(Some((lab * 1000.0).into()));
        };
        for (local, artefact) in femur_points.iter().zip(&femur_artefact) {
            place(&femur_poses[frame], local, artefact);
        }
        for (local, artefact) in tibia_local.iter().zip(&tibia_artefact) {
            place(&tibia_poses[frame], local, artefact);
        }
    }
    let n_markers = femur_points.len() + tibia_local.len();
    drop_samples(&mut rng, &mut positions, n_markers, settings.missing_fraction);

    let femur_names: Vec<String> = (1..=femur_local.len()).map(|i| format!("THI{i}")).collect();
    let tibia_names: Vec<String> = (1..=tibia_local.len()).map(|i| format!("SHA{i}")).collect();
    let (lateral, medial) = ("LEPI".to_owned(), "MEPI".to_owned());
    let names: Vec<String> = femur_names.iter().cloned().chain([lateral.clone(), medial.clone()]).chain(tibia_names.iter().cloned()).collect();
    let trial = MarkerTable::new(TrcHeader::new(settings.rate, LengthUnit::Millimeters), names, times, positions)
        .map_err(|error| AxisError::InvalidSetting { name: "synthetic trial".into(), value: f64::NAN, expected: error.to_string() })?;
    Ok(SyntheticKnee {
        trial,
        femur_cluster: SegmentCluster::from_local("femur", femur_names, femur_local)?,
        tibia_cluster: SegmentCluster::from_local("tibia", tibia_names, tibia_local)?,
        true_axis_femur: true_axis,
        true_axis_tibia: true_axis,
        lateral_epicondyle: lateral,
        medial_epicondyle: medial,
        femur_poses,
        tibia_poses,
        flexion,
    })
}

fn valid_range((low, high): (f64, f64)) -> bool {
    low.is_finite() && high.is_finite() && 0.0 <= low && low <= high
}

fn invalid(name: &str, value: f64, expected: &str) -> AxisError {
    AxisError::InvalidSetting { name: name.to_owned(), value, expected: expected.to_owned() }
}

/// The true axis: through the epicondyle midpoint (0, −0.40, 0) moved 5–10 mm in the sagittal
/// plane, directed along +z tilted 2–5° about y (transversal) and about x (frontal).
fn random_axis(rng: &mut StdRng) -> Axis {
    let (distance, heading) = (rng.random_range(5e-3..10e-3), rng.random_range(0.0..2.0 * std::f64::consts::PI));
    let point = Vector3::new(distance * heading.cos(), -0.40 + distance * heading.sin(), 0.0);
    let mut tilt = || rng.random_range(2.0 * DEGREE..5.0 * DEGREE) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let (transversal, frontal) = (tilt(), tilt());
    let direction = Rotation3::from_axis_angle(&Vector3::y_axis(), transversal) * Rotation3::from_axis_angle(&Vector3::x_axis(), frontal) * Vector3::z();
    Axis::new(point, direction).expect("a unit direction")
}

/// 4–6 markers spread 30 cm down the segment from `top` (m, y), on its anterior side at depths
/// `anterior` (m, x), alternately 4–7 cm to either side (z), as clusters are placed to stay
/// well away from collinear.
fn random_cluster(rng: &mut StdRng, top: f64, anterior: Range<f64>) -> Vec<Vector3<f64>> {
    let count = rng.random_range(4..=6);
    (0..count)
        .map(|i| {
            let along = top - 0.30 * i as f64 / (count - 1) as f64 + rng.random_range(-0.01..0.01);
            let side = if i % 2 == 0 { 1.0 } else { -1.0 };
            Vector3::new(rng.random_range(anterior.clone()), along, side * rng.random_range(0.04..0.07))
        })
        .collect()
}

/// One marker's soft-tissue artefact: a displacement (segment frame, m) that is a smooth
/// function of the flexion stage s ∈ [0, 1] (0 at the smallest flexion).
#[derive(Debug, Clone, Copy)]
struct Artefact {
    /// Unit direction (segment frame).
    direction: Vector3<f64>,
    /// The largest displacement over the flexion range (m).
    amplitude: f64,
    /// Mix of a linear (0) and a half-sine (1) profile in s.
    bulge: f64,
}

impl Artefact {
    /// The displacement (m) at flexion stage `stage` ∈ [0, 1]: `amplitude` times the profile
    /// scaled to peak at 1.
    fn displacement(&self, stage: f64) -> Vector3<f64> {
        self.direction * (self.amplitude * self.profile(stage) / self.profile_peak())
    }

    /// (1 − b)·s + b·sin(πs), b = `bulge`: 0 at s = 0, peak in (0, 1].
    fn profile(&self, stage: f64) -> f64 {
        (1.0 - self.bulge) * stage + self.bulge * (std::f64::consts::PI * stage).sin()
    }

    /// The profile's largest value over s ∈ [0, 1]: where its derivative (1 − b) + bπ·cos(πs)
    /// vanishes, or at s = 1 if it does not (b ≤ 1/(1 + π)).
    fn profile_peak(&self) -> f64 {
        let cosine = -(1.0 - self.bulge) / (self.bulge * std::f64::consts::PI);
        self.profile(if cosine <= -1.0 { 1.0 } else { cosine.acos() / std::f64::consts::PI })
    }
}

/// Weight of the segment-wide direction in each marker's artefact direction (the rest is the
/// marker's own direction): skin moves largely as a whole, so most of the artefact is shared by
/// a segment's markers (a displacement of the cluster relative to the bone that no rigid fit
/// can remove), the rest deforms the cluster.
const COMMON_SHARE: f64 = 0.75;

/// Artefacts of `count` markers with peak amplitudes in `amplitude` (m); [`COMMON_SHARE`] of
/// each direction is shared by all markers of the segment.
fn random_artefacts(rng: &mut StdRng, count: usize, (low, high): (f64, f64)) -> Vec<Artefact> {
    let common = Vector3::from(UnitSphere.sample(rng));
    (0..count)
        .map(|_| {
            let own = Vector3::from(UnitSphere.sample(rng));
            let (amplitude, bulge) = (low + (high - low) * rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
            Artefact { direction: (common * COMMON_SHARE + own * (1.0 - COMMON_SHARE)).normalize(), amplitude, bulge }
        })
        .collect()
}

/// The tibia's pose in the femur frame at flexion `angle`: a rotation by −angle about `axis`.
fn knee_pose(axis: &Axis, angle: f64) -> SegmentPose {
    let rotation = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis.direction), -angle);
    SegmentPose { rotation, translation: axis.point - rotation * axis.point }
}

/// The femur's lab motion: seated (femur y along lab −x, femur x up), the hip at about
/// (0.3, 0.5, 0.2) m, with sinusoidal translations of 1–3 cm and rotations of 2–6° about each
/// lab axis at 0.2–0.6 Hz.
struct FemurMotion {
    base: Rotation3<f64>,
    hip: Vector3<f64>,
    /// (amplitude, frequency Hz, phase) per translation and rotation component.
    translation: [(f64, f64, f64); 3],
    rotation: [(f64, f64, f64); 3],
}

impl FemurMotion {
    fn random(rng: &mut StdRng) -> FemurMotion {
        let mut wave = |amplitude: Range<f64>| (rng.random_range(amplitude), rng.random_range(0.2..0.6), rng.random_range(0.0..2.0 * std::f64::consts::PI));
        let translation = [wave(0.01..0.03), wave(0.01..0.03), wave(0.01..0.03)];
        let rotation = [wave(2.0 * DEGREE..6.0 * DEGREE), wave(2.0 * DEGREE..6.0 * DEGREE), wave(2.0 * DEGREE..6.0 * DEGREE)];
        FemurMotion { base: Rotation3::from_axis_angle(&Vector3::z_axis(), 90.0 * DEGREE), hip: Vector3::new(0.3, 0.5, 0.2), translation, rotation }
    }

    fn pose(&self, time: f64) -> SegmentPose {
        let value = |(amplitude, frequency, phase): (f64, f64, f64)| amplitude * (2.0 * std::f64::consts::PI * frequency * time + phase).sin();
        let offset = Vector3::from_fn(|i, _| value(self.translation[i]));
        let tilt = Rotation3::new(Vector3::from_fn(|i, _| value(self.rotation[i])));
        SegmentPose { rotation: tilt * self.base, translation: self.hip + offset }
    }
}

/// Drops about `fraction` of the samples, in runs of 1–5 frames of one marker.
fn drop_samples(rng: &mut StdRng, positions: &mut [Option<[f64; 3]>], n_markers: usize, fraction: f64) {
    let frames = positions.len() / n_markers.max(1);
    let runs = (fraction * positions.len() as f64 / 3.0).round() as usize;
    for _ in 0..runs {
        let (marker, start, length) = (rng.random_range(0..n_markers), rng.random_range(0..frames), rng.random_range(1..=5));
        for frame in start..(start + length).min(frames) {
            positions[frame * n_markers + marker] = None;
        }
    }
}

/// One trial's errors of a fitted femur-frame axis against the true one ([`compare_axes`] in
/// the femur anatomical frame, sagittal plane through the true axis point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisErrors {
    /// rad
    pub transversal: f64,
    /// rad
    pub frontal: f64,
    /// m
    pub sagittal: f64,
}

/// Tracks `knee`'s trial with `pose` and fits the axis with each of `methods`; the errors
/// against the generating axis, in the order of `methods`.
pub fn axis_errors(knee: &SyntheticKnee, pose: &PoseMethod, methods: &[AxisMethod]) -> Result<Vec<AxisErrors>, AxisError> {
    let motion = KneeMotion::track(&knee.trial, &knee.femur_cluster, &knee.tibia_cluster, pose)?;
    let mut errors = Vec::with_capacity(methods.len());
    for &method in methods {
        let fit = fit_axis(&motion, method, &AxisHint::default())?;
        let comparison = compare_axes(&knee.true_axis_femur, &fit.femur, &AnatomicalFrame::default(), None)?;
        errors.push(AxisErrors { transversal: comparison.transversal_angle, frontal: comparison.frontal_angle, sagittal: comparison.sagittal_distance });
    }
    Ok(errors)
}

/// Mean and maximum of each error over the seeds of a study, for one method.
#[derive(Debug, Clone, PartialEq)]
pub struct StudySummary {
    pub method: AxisMethod,
    pub condition: Condition,
    /// Trials fitted.
    pub trials: usize,
    /// Trials whose fit returned an error (counted as failures by the goals), with the first error.
    pub failures: usize,
    pub first_failure: Option<String>,
    /// Means and maxima over the fitted trials (rad, rad, m).
    pub mean: AxisErrors,
    pub max: AxisErrors,
}

impl StudySummary {
    /// The goals for this summary's condition and method, as (what, value, goal)
    /// triples; a summary passes if every value ≤ goal and no trial failed.
    pub fn goals(&self) -> Vec<(&'static str, f64, f64)> {
        match (self.condition, self.method) {
            (Condition::Noise, _) => vec![
                ("max transversal (rad)", self.max.transversal, NOISE_ORIENTATION_GOAL),
                ("max frontal (rad)", self.max.frontal, NOISE_ORIENTATION_GOAL),
                ("max sagittal (m)", self.max.sagittal, NOISE_LOCATION_GOAL),
            ],
            (Condition::SoftTissue, AxisMethod::Gal) => vec![
                ("mean transversal (rad)", self.mean.transversal, ARTEFACT_GAL_ORIENTATION_MEAN_GOAL),
                ("mean frontal (rad)", self.mean.frontal, ARTEFACT_GAL_ORIENTATION_MEAN_GOAL),
                ("mean sagittal (m)", self.mean.sagittal, ARTEFACT_GAL_LOCATION_MEAN_GOAL),
            ],
            (Condition::SoftTissue, AxisMethod::Sara) => Vec::new(),
        }
    }

    /// True if no trial failed and every goal holds.
    pub fn passes(&self) -> bool {
        self.failures == 0 && self.goals().iter().all(|(_, value, goal)| value <= goal)
    }
}

/// The accuracy study: for every seed in `seeds`, the synthetic trial of `template` with that
/// seed, tracked with `pose`, fitted with GaL and with SARA. One summary per method (GaL first).
pub fn axis_study(template: &SyntheticKneeSettings, pose: &PoseMethod, seeds: Range<u64>) -> Vec<StudySummary> {
    let condition = template.condition;
    let methods = [AxisMethod::Gal, AxisMethod::Sara];
    let mut errors: Vec<Vec<AxisErrors>> = vec![Vec::new(); methods.len()];
    let (mut failures, mut first_failure, mut trials) = (vec![0; methods.len()], vec![None; methods.len()], 0);
    for seed in seeds {
        trials += 1;
        let results = synthetic_knee(&SyntheticKneeSettings { seed, ..*template }).and_then(|knee| axis_errors(&knee, pose, &methods));
        for index in 0..methods.len() {
            match results.as_ref().map(|list| list[index]) {
                Ok(e) => errors[index].push(e),
                Err(error) => {
                    failures[index] += 1;
                    first_failure[index].get_or_insert(format!("seed {seed}: {error}"));
                }
            }
        }
    }
    methods
        .iter()
        .enumerate()
        .map(|(index, &method)| {
            let list = &errors[index];
            let statistic = |pick: fn(&AxisErrors) -> f64, combine: fn(&[f64]) -> f64| combine(&list.iter().map(pick).collect::<Vec<_>>());
            let summary = |combine: fn(&[f64]) -> f64| AxisErrors {
                transversal: statistic(|e| e.transversal, combine),
                frontal: statistic(|e| e.frontal, combine),
                sagittal: statistic(|e| e.sagittal, combine),
            };
            let first_failure = first_failure[index].clone();
            StudySummary { method, condition, trials, failures: failures[index], first_failure, mean: summary(mean), max: summary(maximum) }
        })
        .collect()
}

fn mean(values: &[f64]) -> f64 {
    if values.is_empty() { f64::NAN } else { values.iter().sum::<f64>() / values.len() as f64 }
}

fn maximum(values: &[f64]) -> f64 {
    values.iter().copied().fold(if values.is_empty() { f64::NAN } else { 0.0 }, f64::max)
}
