//! `osim-tune axis TRIAL.trc --femur M1,M2,… --tibia M3,M4,… [--method gal|sara] [--poses least-squares|kalman]
//! [--epicondyles LAT,MED] [--model MODEL.osim [--swap knee_r [--reference-angle DEG] -o OUT.osim]] [--json]`

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use serde_json::{json, Value};

use crate::cli::{create_output_folders, AxisMethodArgument, Failure, Outcome, PoseArgument};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::MarkerTable;
use crate::mechanics::Multibody;
use crate::model::ModelSpec;
use crate::tuning::knee_axis::{
    compare_axes, fit_axis, swap_knee, AnatomicalFrame, Axis, AxisComparison, AxisFit, AxisHint, AxisMethod, JointAxis, KalmanSettings, KneeMotion,
    PoseMethod, SegmentCluster, SwappedKnee,
};

/// What `axis` was asked to do.
pub struct Request {
    pub femur: Vec<String>,
    pub tibia: Vec<String>,
    pub method: AxisMethodArgument,
    pub poses: PoseArgument,
    pub epicondyles: Option<Vec<String>>,
    pub model: Option<PathBuf>,
    pub swap: Option<Swap>,
    pub json: bool,
}

/// `--swap JOINT -o OUT [--reference-angle]`, the angle in rad.
pub struct Swap {
    pub joint: String,
    pub output: PathBuf,
    pub reference_angle: Option<f64>,
}

/// The clusters' source: the model (body-frame marker locations) or the trial's first frame.
struct Clusters {
    femur: SegmentCluster,
    tibia: SegmentCluster,
}

pub fn run(trial_file: &Path, request: &Request) -> Result<Outcome, Failure> {
    let inputs: Vec<&Path> = [trial_file].into_iter().chain(request.model.as_deref()).collect();
    if let Some(swap) = &request.swap {
        ensure_not_an_input(&swap.output, &inputs)?;
    }
    let epicondyles = epicondyle_pair(request.epicondyles.as_deref())?;
    let trial = crate::cli::read_marker_trial(trial_file)?;
    let model = request.model.as_deref().map(OsimDocument::read).transpose()?;
    let clusters = match &model {
        Some(document) => model_clusters(document, &trial, &request.femur, &request.tibia)?,
        None => Clusters { femur: SegmentCluster::from_trial("femur", &request.femur, &trial)?, tibia: SegmentCluster::from_trial("tibia", &request.tibia, &trial)? },
    };
    let poses = match request.poses {
        PoseArgument::LeastSquares => PoseMethod::LeastSquares,
        PoseArgument::Kalman => PoseMethod::KalmanSmoother(KalmanSettings::default()),
    };
    let motion = KneeMotion::track(&trial, &clusters.femur, &clusters.tibia, &poses)?;
    let transepicondylar = epicondyles.map(|[lateral, medial]| Axis::transepicondylar(&motion.femur, lateral, medial, &trial)).transpose()?;
    let hint = AxisHint { lateral: transepicondylar.as_ref().map_or(Vector3::z(), |a| a.direction), ..AxisHint::default() };
    let method = match request.method {
        AxisMethodArgument::Gal => AxisMethod::Gal,
        AxisMethodArgument::Sara => AxisMethod::Sara,
    };
    let fit = fit_axis(&motion, method, &hint)?;
    let comparison = transepicondylar.as_ref().map(|t| compare_axes(t, &fit.femur, &AnatomicalFrame::default(), None)).transpose()?;
    let swapped = match (&request.swap, &model) {
        (Some(swap), Some(document)) => Some(swap_and_write(document, &clusters.femur.segment, &fit, swap, &inputs)?),
        _ => None,
    };
    let first = (0..motion.n_frames()).find_map(|f| motion.femur.pose(f).copied()).ok_or("no frame has a femur pose")?;
    let report = Report { request, method, motion: &motion, fit: &fit, lab: fit.femur.in_lab(&first), transepicondylar: transepicondylar.as_ref(), comparison, swapped: swapped.as_ref() };
    if request.json {
        println!("{}", serde_json::to_string_pretty(&report.json())?);
    } else {
        report.print();
    }
    Ok(Outcome::Success)
}

fn epicondyle_pair(names: Option<&[String]>) -> Result<Option<[&str; 2]>, Failure> {
    match names {
        None => Ok(None),
        Some([lateral, medial]) => Ok(Some([lateral.as_str(), medial.as_str()])),
        Some(other) => Err(format!("--epicondyles: expected two markers LAT,MED, got {}", other.len()).into()),
    }
}

/// Clusters from the model's markers: each argument is one body name (its markers the trial
/// has) or marker names, all on one body.
fn model_clusters(document: &OsimDocument, trial: &MarkerTable, femur: &[String], tibia: &[String]) -> Result<Clusters, Failure> {
    let multibody = Multibody::new(&ModelSpec::read(document)?)?;
    let cluster = |names: &[String], what: &str| -> Result<SegmentCluster, Failure> {
        let markers: Vec<usize> = match names {
            [body] if multibody.body_index(body).is_some() => {
                let body = multibody.body_index(body).unwrap_or_default();
                (0..multibody.markers.len()).filter(|&m| multibody.markers[m].body == body && trial.marker_index(&multibody.markers[m].name).is_some()).collect()
            }
            _ => names
                .iter()
                .map(|name| multibody.markers.iter().position(|m| &m.name == name).ok_or_else(|| format!("--{what}: {name:?} is neither a body nor a marker of {}", document.xml.file().display())))
                .collect::<Result<_, _>>()?,
        };
        let bodies: Vec<usize> = markers.iter().map(|&m| multibody.markers[m].body).collect();
        if bodies.windows(2).any(|pair| pair[0] != pair[1]) {
            let listed: Vec<String> = markers.iter().map(|&m| format!("{} on {}", multibody.markers[m].name, multibody.bodies[multibody.markers[m].body].name)).collect();
            return Err(format!("--{what}: the cluster's markers must be on one body ({})", listed.join(", ")).into());
        }
        let segment = bodies.first().map_or(what.to_string(), |&b| multibody.bodies[b].name.clone());
        let names = markers.iter().map(|&m| multibody.markers[m].name.clone()).collect();
        Ok(SegmentCluster::from_local(&segment, names, markers.iter().map(|&m| multibody.markers[m].location).collect())?)
    };
    Ok(Clusters { femur: cluster(femur, "femur")?, tibia: cluster(tibia, "tibia")? })
}

/// Swaps the joint about the femur-frame axis and writes the model.
fn swap_and_write(document: &OsimDocument, femur_body: &str, fit: &AxisFit, swap: &Swap, inputs: &[&Path]) -> Result<SwappedKnee, Failure> {
    let spec = ModelSpec::read(document)?;
    if let Some(joint) = spec.joints.iter().find(|j| j.name == swap.joint) {
        if joint.parent.body != femur_body {
            return Err(format!("--swap {}: the joint's parent body is {}, but the femur cluster is on {femur_body}; the axis must be in the parent's frame", swap.joint, joint.parent.body).into());
        }
    }
    let axis = JointAxis { point: fit.femur.point, direction: fit.femur.direction };
    let swapped = swap_knee(document, &swap.joint, &axis, swap.reference_angle)?;
    create_output_folders([swap.output.as_path()])?;
    write_atomically(&swap.output, &swapped.document.xml.serialize(), inputs)?;
    Ok(swapped)
}

/// Everything `axis` prints.
struct Report<'a> {
    request: &'a Request,
    method: AxisMethod,
    motion: &'a KneeMotion,
    fit: &'a AxisFit,
    /// The axis in the lab frame of the first frame with a femur pose.
    lab: Axis,
    transepicondylar: Option<&'a Axis>,
    comparison: Option<AxisComparison>,
    swapped: Option<&'a SwappedKnee>,
}

fn axis_json(axis: &Axis) -> Value {
    json!({ "point": axis.point.as_slice(), "direction": axis.direction.as_slice() })
}

impl Report<'_> {
    fn method_name(&self) -> &'static str {
        match self.method {
            AxisMethod::Gal => "gal",
            AxisMethod::Sara => "sara",
        }
    }

    fn json(&self) -> Value {
        let mut value = json!({
            "method": self.method_name(),
            "poses": match self.request.poses { PoseArgument::LeastSquares => "least-squares", PoseArgument::Kalman => "kalman" },
            "axis": axis_json(&self.lab),
            "femur": { "segment": self.motion.femur.segment, "markers": self.motion.femur_cluster.markers, "axis": axis_json(&self.fit.femur) },
            "tibia": { "segment": self.motion.tibia.segment, "markers": self.motion.tibia_cluster.markers, "axis": axis_json(&self.fit.tibia) },
            "residual_rms": self.fit.residual_rms,
            "rotation_range_deg": self.fit.rotation_range.to_degrees(),
            "frames_used": self.fit.frames_used,
            "frames": self.motion.n_frames(),
        });
        if let (Some(axis), Some(c)) = (self.transepicondylar, &self.comparison) {
            value["transepicondylar"] = json!({
                "femur": axis_json(axis),
                "transversal_angle_deg": c.transversal_angle.to_degrees(),
                "frontal_angle_deg": c.frontal_angle.to_degrees(),
                "sagittal_distance": c.sagittal_distance,
            });
        }
        if let (Some(s), Some(swap)) = (self.swapped, &self.request.swap) {
            value["swap"] = json!({
                "joint": s.joint,
                "coordinate": s.coordinate,
                "output": swap.output.display().to_string(),
                "reference_angle_deg": s.reference_angle.to_degrees(),
                "parent_frame": s.parent_frame,
                "child_frame": s.child_frame,
                "reference_pose_error": s.reference_pose_error,
                "paths": s.paths,
            });
        }
        value
    }

    fn print(&self) {
        let (fit, lab) = (self.fit, &self.lab);
        let vector = |v: &Vector3<f64>| format!("({:.5}, {:.5}, {:.5})", v.x, v.y, v.z);
        println!("functional knee axis ({}, {} of {} frames, rotation range {:.1}°, residual RMS {:.2} mm)", self.method_name(), fit.frames_used, self.motion.n_frames(), fit.rotation_range.to_degrees(), fit.residual_rms * 1e3);
        println!("  lab (first frame): point {} m, direction {}", vector(&lab.point), vector(&lab.direction));
        println!("  {} frame: point {} m, direction {}", self.motion.femur.segment, vector(&fit.femur.point), vector(&fit.femur.direction));
        println!("  {} frame: point {} m, direction {}", self.motion.tibia.segment, vector(&fit.tibia.point), vector(&fit.tibia.direction));
        if let Some(c) = &self.comparison {
            println!("versus the transepicondylar axis: transversal {:.2}°, frontal {:.2}°, sagittal distance {:.1} mm", c.transversal_angle.to_degrees(), c.frontal_angle.to_degrees(), c.sagittal_distance * 1e3);
        }
        if let (Some(s), Some(swap)) = (self.swapped, &self.request.swap) {
            println!("{} → PinJoint about the axis, {} kept; tibia pose at {:.2}° kept within {:.1e} m; written {}", s.joint, s.coordinate, s.reference_angle.to_degrees(), s.reference_pose_error, swap.output.display());
            for path in &s.paths {
                println!("  {:<12} path length change ≤ {:.2} mm, moment arm change ≤ {:.2} mm (RMS {:.2} mm)", path.muscle, path.max_length_change * 1e3, path.max_moment_arm_change * 1e3, path.rms_moment_arm_change * 1e3);
            }
        }
    }
}
