//! `osim-tune scale MODEL (--setup SETUP.xml | TRIALS --linear) -o OUT.osim`

use std::path::{Path, PathBuf};

use serde_json::json;

use crate::cli::{create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;
use crate::mechanics::Multibody;
use crate::model::ModelSpec;
use crate::setup::ScaleSetup;
use crate::solvers::IkSolution;
use crate::tuning::scale::{marker_set_document, run_scale_tool, trials_setup, ScaleOutcome};

/// Files the command writes.
pub struct Outputs {
    pub model: PathBuf,
    pub scaled_only: Option<PathBuf>,
    pub scale_set: Option<PathBuf>,
    pub static_pose: Option<PathBuf>,
    /// The final model's markers as a MarkerSet document.
    pub marker_set: Option<PathBuf>,
}

/// The error for a trials argument that is not a folder: missing, or a file (e.g. the subject.json
/// itself).
fn not_a_folder(path: &Path) -> String {
    let what = if path.exists() { "a file, not a folder" } else { "no such folder" };
    format!("{}: {what}; expected the trials folder (the one that holds subject.json)", path.display())
}

pub fn run(model: &Path, trials: Option<&Path>, setup: Option<&Path>, linear: bool, outputs: &Outputs, json: bool) -> Result<Outcome, Failure> {
    let setup = match (setup, trials) {
        (Some(file), None) => ScaleSetup::read(file)?,
        (None, Some(folder)) if !folder.is_dir() => return Err(not_a_folder(folder).into()),
        (None, Some(folder)) if linear => trials_setup(folder)?,
        (None, Some(folder)) => {
            let problem = "expected a dynamometry subject.json (with \"trial_files\") for functional scaling, or --linear for OpenSim's linear scaling of a static trial";
            return Err(format!("{}: {problem}", folder.join("subject.json").display()).into());
        }
        (Some(_), Some(_)) => return Err("give either --setup or a trials folder, not both".into()),
        (None, None) => return Err("give --setup SETUP.xml or a trials folder with --linear".into()),
    };
    let inputs = input_files(model, &setup);
    let input_refs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    for output in outputs.files() {
        ensure_not_an_input(output, &input_refs)?;
    }
    let generic = OsimDocument::read(model)?;
    let outcome = run_scale_tool(&generic, &setup, &mut |step| eprintln!("scale: {step}"))?;
    let scaled_only = match (&outputs.scaled_only, &outcome.scaled) {
        (Some(_), None) => return Err("--scaled-only: the setup does not scale the model (ModelScaler off)".into()),
        (_, scaled) => scaled.as_ref().map(|s| s.document.xml.serialize()),
    };
    let static_pose = match (&outputs.static_pose, &outcome.placement) {
        (Some(_), None) => return Err("--static-pose: the setup does not place markers (MarkerPlacer off)".into()),
        (Some(_), Some(placement)) => {
            let multibody = Multibody::new(&ModelSpec::read(&outcome.document)?)?;
            let solution = IkSolution { markers: placement.tracked_markers.clone(), coordinates: placement.coordinates.clone(), frames: vec![placement.frame.clone()] };
            Some(solution.motion_table(&multibody)?.to_text())
        }
        (None, _) => None,
    };
    let marker_set = outputs.marker_set.as_ref().map(|_| marker_set_document(&outcome.document)).transpose()?;
    create_output_folders(outputs.files().map(PathBuf::as_path))?;
    write_atomically(&outputs.model, &outcome.document.xml.serialize(), &input_refs)?;
    if let (Some(file), Some(text)) = (&outputs.scaled_only, scaled_only) {
        write_atomically(file, &text, &input_refs)?;
    }
    if let Some(file) = &outputs.scale_set {
        write_atomically(file, outcome.scale_set.to_document_text().as_bytes(), &input_refs)?;
    }
    if let (Some(file), Some(text)) = (&outputs.static_pose, static_pose) {
        write_atomically(file, text.as_bytes(), &input_refs)?;
    }
    if let (Some(file), Some(text)) = (&outputs.marker_set, marker_set) {
        write_atomically(file, text.as_bytes(), &input_refs)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&summary_json(&outcome))?);
    } else {
        print_summary(&outcome);
    }
    Ok(Outcome::Success)
}

impl Outputs {
    fn files(&self) -> impl Iterator<Item = &PathBuf> {
        std::iter::once(&self.model).chain(self.scaled_only.iter()).chain(self.scale_set.iter()).chain(self.static_pose.iter()).chain(self.marker_set.iter())
    }
}

/// Every file the run reads (outputs must be none of them).
fn input_files(model: &Path, setup: &ScaleSetup) -> Vec<PathBuf> {
    let mut files = vec![model.to_path_buf(), setup.file.clone()];
    files.extend(setup.generic_model_maker.iter().flat_map(|m| m.marker_set_file.iter().map(|f| f.resolved.clone())));
    files.extend(setup.model_scaler.iter().flat_map(|s| s.marker_file.iter().map(|f| f.resolved.clone())));
    files.extend(setup.marker_placer.iter().flat_map(|p| p.marker_file.iter().map(|f| f.resolved.clone())));
    files
}

fn print_summary(outcome: &ScaleOutcome) {
    for measured in &outcome.measurements {
        println!("measurement {:<12} factor {:.6}", measured.measurement, measured.factor);
        for pair in &measured.pairs {
            let missing = if pair.frames_missing > 0 { format!(" ({} frames without both markers left out)", pair.frames_missing) } else { String::new() };
            println!("  {} – {}: model {:.4} m, trial {:.4} m{missing}", pair.markers[0], pair.markers[1], pair.model, pair.experimental);
        }
    }
    println!("scale factors (x y z):");
    for body in &outcome.scale_set.bodies {
        let [x, y, z] = body.factors;
        println!("  {:<12} {x:.6} {y:.6} {z:.6}", body.body);
    }
    for body in &outcome.unknown_bodies {
        println!("warning: body {body:?} is named in the setup but not in the model; ignored (as OpenSim does)");
    }
    if let Some(scaled) = &outcome.scaled {
        println!("mass: {:.4} kg after scaling, × {:.6} to the subject mass", scaled.mass_before_adjustment, scaled.mass_factor);
        let ratios = scaled.paths.iter().map(|p| p.ratio());
        let (low, high) = ratios.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| (l.min(r), h.max(r)));
        if !scaled.paths.is_empty() {
            println!("{} path forces: L_opt and L_ts × {low:.4} … {high:.4} (default-pose path length ratio)", scaled.paths.len());
        }
    }
    if let Some(placement) = &outcome.placement {
        let errors = &placement.frame.errors;
        let worst = errors.worst.map_or("-", |i| placement.tracked_markers[i].as_str());
        println!("static pose at t = {} s: marker error RMS {:.4} m, max {:.4} m ({worst}) before placement", placement.time, errors.rms, errors.max);
        println!("markers moved: {}", placement.moved.len());
        for name in &placement.deleted {
            println!("warning: marker {name} is not in the static trial; deleted from the model (as OpenSim does)");
        }
        for name in &placement.without_data {
            println!("warning: marker {name} has no data in the time range; not moved");
        }
    }
}

fn summary_json(outcome: &ScaleOutcome) -> serde_json::Value {
    let bodies: serde_json::Map<String, serde_json::Value> = outcome.scale_set.bodies.iter().map(|b| (b.body.clone(), json!(b.factors))).collect();
    let measurements: Vec<_> = outcome
        .measurements
        .iter()
        .map(|m| json!({"name": m.measurement, "factor": m.factor, "pairs": m.pairs.iter().map(|p| json!({"markers": p.markers, "model_m": p.model, "trial_m": p.experimental, "frames_missing": p.frames_missing})).collect::<Vec<_>>()}))
        .collect();
    let placement = outcome.placement.as_ref().map(|p| {
        json!({"time": p.time, "rms_m": p.frame.errors.rms, "max_m": p.frame.errors.max, "moved": p.moved, "deleted": p.deleted, "without_data": p.without_data})
    });
    let mass = outcome.scaled.as_ref().map(|s| json!({"after_scaling_kg": s.mass_before_adjustment, "factor": s.mass_factor}));
    json!({"scale_factors": bodies, "measurements": measurements, "unknown_bodies": outcome.unknown_bodies, "mass": mass, "marker_placement": placement})
}
