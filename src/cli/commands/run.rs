//! `osim-tune run SETUP.xml [--dry-run]`: an OpenSim tool setup run as `opensim-cmd run-tool`
//! runs it — the model, inputs and outputs the setup names (relative names from the setup's
//! folder), outputs under OpenSim's names — by the osim-tune commands that do the tool's work,
//! each printed before it runs.

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

use clap::Parser;

use crate::cli::{Arguments, Failure, Outcome};
use crate::model::ComponentReader;
use crate::setup::{read_document, required_input, AnalyzeSetup, ForwardSetup, IdSetup, IkSetup, RraSetup, ScaleSetup, TrackingSetup, CmcSetup, SetupPath};

/// The setups `run` knows, by their root element.
const TOOLS: &str = "<ScaleTool>, <InverseKinematicsTool>, <InverseDynamicsTool>, <AnalyzeTool>, <ForwardTool>, <RRATool> or <CMCTool>";
/// The AnalyzeTool analyses `run` runs.
const ANALYSES: &str = "MuscleAnalysis, Kinematics, BodyKinematics, PointKinematics, ForceReporter, Actuation, StatesReporter, ProbeReporter, InducedAccelerations, StaticOptimization, JointReaction";

/// One osim-tune command line: its words after the program name.
struct Invocation(Vec<OsString>);

impl Invocation {
    fn new(words: &[&OsStr]) -> Invocation {
        Invocation(words.iter().map(|w| w.to_os_string()).collect())
    }

    fn with(mut self, words: &[&OsStr]) -> Invocation {
        self.0.extend(words.iter().map(|w| w.to_os_string()));
        self
    }

    /// The command as a shell line, words with spaces or quotes in single quotes.
    fn shell_line(&self) -> String {
        let quoted = |word: &OsString| {
            let text = word.to_string_lossy();
            let plain = !text.is_empty() && text.chars().all(|c| c.is_alphanumeric() || "-_./=:,+@%".contains(c));
            if plain { text.into_owned() } else { format!("'{}'", text.replace('\'', r"'\''")) }
        };
        std::iter::once("osim-tune".to_string()).chain(self.0.iter().map(quoted)).collect::<Vec<_>>().join(" ")
    }
}

pub fn run(setup: &Path, dry_run: bool) -> Result<Outcome, Failure> {
    let document = read_document(setup)?;
    let tool = ComponentReader::new(&document, document.object);
    let invocations = match tool.class() {
        "ScaleTool" => vec![scale_tool(setup, &ScaleSetup::from_document(&document)?)?],
        "InverseKinematicsTool" => vec![inverse_kinematics_tool(setup, &IkSetup::from_document(&document)?)?],
        "InverseDynamicsTool" => vec![inverse_dynamics_tool(setup, &IdSetup::from_document(&document)?)?],
        "AnalyzeTool" => analyze_tool(setup, &AnalyzeSetup::from_document(&document)?)?,
        "ForwardTool" => vec![forward_tool(setup, &ForwardSetup::from_document(&document)?)?],
        "RRATool" => vec![tracking_tool("rra", setup, &RraSetup::from_document(&document)?.tracking)?],
        "CMCTool" => vec![tracking_tool("cmc", setup, &CmcSetup::from_document(&document)?.tracking)?],
        other => return Err(format!("{}:{}: <{other}> is not a tool osim-tune runs; expected {TOOLS} ({ANALYSES})", setup.display(), tool.line()).into()),
    };
    let mut outcome = Outcome::Success;
    for invocation in invocations {
        println!("{}", invocation.shell_line());
        if dry_run {
            continue;
        }
        let words = std::iter::once(OsString::from("osim-tune")).chain(invocation.0);
        let arguments = Arguments::try_parse_from(words).map_err(|e| format!("{}: the command it gives is not valid: {e}", setup.display()))?;
        if let Outcome::NotConverged = super::run(arguments.command)? {
            outcome = Outcome::NotConverged;
        }
    }
    Ok(outcome)
}

/// The file a setup's `property` names, which must exist.
fn input(setup: &Path, property: &str, path: Option<&SetupPath>) -> Result<PathBuf, Failure> {
    Ok(required_input(setup, property, path)?)
}

/// The output a setup's `property` names, which must be set.
fn output(setup: &Path, property: &str, path: Option<&SetupPath>, why: &str) -> Result<PathBuf, Failure> {
    path.map(|p| p.resolved.clone()).ok_or_else(|| format!("{}: {property} is not set; {why}", setup.display()).into())
}

/// ScaleTool: `scale GENERIC --setup SETUP -o MODEL` with the ModelScaler's and MarkerPlacer's
/// outputs; the final model is the placer's when it runs, else the scaler's.
fn scale_tool(file: &Path, setup: &ScaleSetup) -> Result<Invocation, Failure> {
    let generic = input(file, "GenericModelMaker/model_file", setup.generic_model_maker.as_ref().and_then(|m| m.model_file.as_ref()))?;
    let scaler = setup.model_scaler.as_ref().filter(|s| s.apply);
    let placer = setup.marker_placer.as_ref().filter(|p| p.apply);
    let scaled_model = scaler.and_then(|s| s.output_model_file.as_ref());
    let model = match (scaler, placer) {
        (None, None) => return Err(format!("{}: neither ModelScaler nor MarkerPlacer is applied; the tool does nothing", file.display()).into()),
        (_, Some(placer)) => output(file, "MarkerPlacer/output_model_file", placer.output_model_file.as_ref(), "osim-tune writes the model with its markers placed")?,
        (Some(_), None) => output(file, "ModelScaler/output_model_file", scaled_model, "osim-tune writes the scaled model")?,
    };
    let mut invocation = Invocation::new(&["scale".as_ref(), generic.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), model.as_ref()]);
    if let (Some(scaled), Some(_)) = (scaled_model, placer) {
        invocation = invocation.with(&["--scaled-only".as_ref(), scaled.resolved.as_ref()]);
    }
    if let Some(scale_set) = scaler.and_then(|s| s.output_scale_file.as_ref()) {
        invocation = invocation.with(&["--scale-set".as_ref(), scale_set.resolved.as_ref()]);
    }
    if let Some(pose) = placer.and_then(|p| p.output_motion_file.as_ref()) {
        invocation = invocation.with(&["--static-pose".as_ref(), pose.resolved.as_ref()]);
    }
    if let Some(markers) = placer.and_then(|p| p.output_marker_file.as_ref()) {
        invocation = invocation.with(&["--marker-set".as_ref(), markers.resolved.as_ref()]);
    }
    Ok(invocation)
}

/// InverseKinematicsTool: `ik MODEL TRIAL --setup SETUP -o MOTION`, with
/// `<results_directory>/<name>_ik_marker_errors.sto` and `…_ik_model_marker_locations.sto` when
/// it reports them.
fn inverse_kinematics_tool(file: &Path, setup: &IkSetup) -> Result<Invocation, Failure> {
    let model = input(file, "model_file", setup.model_file.as_ref())?;
    let trial = input(file, "marker_file", setup.marker_file.as_ref())?;
    let motion = output(file, "output_motion_file", setup.output_motion_file.as_ref(), "the tool writes no coordinates")?;
    let mut invocation = Invocation::new(&["ik".as_ref(), model.as_ref(), trial.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), motion.as_ref()]);
    let results = setup.results_directory.as_ref().map_or(setup.directory.clone(), |d| d.resolved.clone());
    if setup.report_errors {
        let errors = results.join(format!("{}_ik_marker_errors.sto", setup.name));
        invocation = invocation.with(&["--errors".as_ref(), errors.as_ref()]);
    }
    if setup.report_marker_locations {
        let locations = results.join(format!("{}_ik_model_marker_locations.sto", setup.name));
        invocation = invocation.with(&["--marker-locations".as_ref(), locations.as_ref()]);
    }
    Ok(invocation)
}

/// InverseDynamicsTool: `id MODEL COORDINATES --setup SETUP -o <results_directory>/<output_gen_force_file>`.
fn inverse_dynamics_tool(file: &Path, setup: &IdSetup) -> Result<Invocation, Failure> {
    let model = input(file, "model_file", setup.model_file.as_ref())?;
    let coordinates = input(file, "coordinates_file", setup.coordinates_file.as_ref())?;
    let forces = setup.results_directory.resolved.join(&setup.output_gen_force_file);
    Ok(Invocation::new(&["id".as_ref(), model.as_ref(), coordinates.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), forces.as_ref()]))
}

/// AnalyzeTool: `analyze --motion` for its MuscleAnalysis, Kinematics, BodyKinematics,
/// PointKinematics, reporters, InducedAccelerations and a JointReaction without a forces file, `so` for its
/// StaticOptimization, then `reaction` for a JointReaction with one, each `MODEL COORDINATES --setup SETUP -o <results_directory>` — given
/// the states file instead when the setup names one, which each reads as states (the commands
/// name the setup's other analyses, which they do not run).
fn analyze_tool(file: &Path, setup: &AnalyzeSetup) -> Result<Vec<Invocation>, Failure> {
    let analyses = [(setup.has_analyze_tables(), "analyze", ["--motion"].as_slice()), (setup.static_optimization.is_some(), "so", &[]), (setup.joint_reaction.is_some() && !setup.joint_reaction_from_states(), "reaction", &[])];
    if !analyses.iter().any(|(on, _, _)| *on) {
        let others = if setup.other_analyses.is_empty() { "none".to_string() } else { setup.other_analyses.join(", ") };
        return Err(format!("{}: the AnalysisSet has no analysis osim-tune runs that is on ({ANALYSES}; others on: {others})", file.display()).into());
    }
    if let Some(speeds) = &setup.speeds_file {
        return Err(format!("{}: speeds_file {:?} is not supported; the speeds are the coordinates' spline derivatives", file.display(), speeds.written).into());
    }
    let model = input(file, "model_file", setup.model_file.as_ref())?;
    // OpenSim reads the states file and ignores the coordinates file when both are set.
    let coordinates = match &setup.states_file {
        Some(states) => input(file, "states_file", Some(states))?,
        None => input(file, "coordinates_file", setup.coordinates_file.as_ref())?,
    };
    let tail: [&OsStr; 5] = [coordinates.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), setup.results_directory.resolved.as_ref()];
    let invocation = |command: &str, flags: &[&str]| {
        let flags: Vec<&OsStr> = flags.iter().map(|f| f.as_ref()).collect();
        Invocation::new(&[command.as_ref(), model.as_ref()]).with(&flags).with(&tail)
    };
    Ok(analyses.into_iter().filter(|(on, _, _)| *on).map(|(_, command, flags)| invocation(command, flags)).collect())
}

/// RRATool and CMCTool: `rra|cmc MODEL --setup SETUP -o <results_directory>`.
fn tracking_tool(command: &str, file: &Path, setup: &TrackingSetup) -> Result<Invocation, Failure> {
    let model = input(file, "model_file", setup.tool.model_file.as_ref())?;
    Ok(Invocation::new(&[command.as_ref(), model.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), setup.tool.results_directory.resolved.as_ref()]))
}

/// ForwardTool: `simulate MODEL --setup SETUP -o <results_directory>`.
fn forward_tool(file: &Path, setup: &ForwardSetup) -> Result<Invocation, Failure> {
    let model = input(file, "model_file", setup.tool.model_file.as_ref())?;
    if let Some(states) = &setup.tool.states_file {
        input(file, "states_file", Some(states))?;
    }
    Ok(Invocation::new(&["simulate".as_ref(), model.as_ref(), "--setup".as_ref(), file.as_ref(), "-o".as_ref(), setup.tool.results_directory.resolved.as_ref()]))
}
