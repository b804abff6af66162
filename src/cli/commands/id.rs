//! `osim-tune id MODEL COORDINATES [--external-loads LOADS.xml] [--setup SETUP.xml] [--time START END] [--lowpass HZ | --rates RATES.sto] [--body-force-joints J,…|ALL] [--body-forces FILE.sto] -o OUT.sto`

use std::path::{Path, PathBuf};

use crate::analysis::{inverse_dynamics, named_joints, InverseDynamicsResult, InverseDynamicsSettings, SampledMotion};
use crate::cli::{check_time_and_cutoff, create_output_folders, read_external_loads, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::Multibody;
use crate::model::{ForceSpec, ModelSpec};
use crate::setup::IdSetup;

/// What the command line asks for besides the model and the coordinates.
pub struct Request {
    pub external_loads: Option<PathBuf>,
    pub setup: Option<PathBuf>,
    pub time: Option<[f64; 2]>,
    pub lowpass: Option<f64>,
    /// The coordinates' speeds and accelerations per frame, used instead of splines.
    pub rates: Option<PathBuf>,
    pub body_force_joints: Vec<String>,
    pub body_forces: Option<PathBuf>,
    pub output: PathBuf,
}

pub fn run(model: &Path, coordinates: &Path, request: &Request) -> Result<Outcome, Failure> {
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let multibody = Multibody::new(&spec)?;
    let setup = request.setup.as_deref().map(IdSetup::read).transpose()?;
    if let Some(setup) = &setup {
        check_excluded_forces(&spec, setup)?;
    }
    let loads_file = request.external_loads.clone().or_else(|| setup.as_ref().and_then(|s| s.external_loads_file.as_ref()).map(|p| p.resolved.clone()));
    let mut inputs: Vec<PathBuf> = [model, coordinates].iter().map(|p| p.to_path_buf()).chain(request.setup.clone()).chain(request.rates.clone()).collect();
    let loads = loads_file.as_deref().map(|file| read_external_loads(file, &multibody, &mut inputs)).transpose()?;
    let input_paths: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    ensure_not_an_input(&request.output, &input_paths)?;
    let settings = settings(request, setup.as_ref())?;
    let (joints, body_forces_file) = body_forces(request, setup.as_ref(), &spec, &multibody)?;
    if let Some(file) = &body_forces_file {
        ensure_not_an_input(file, &input_paths)?;
    }
    let table = StorageTable::read(coordinates)?;
    let motion = match &request.rates {
        Some(rates) => SampledMotion::with_rates(&multibody, &table, coordinates, &StorageTable::read(rates)?, rates)?.within(settings.time_range)?,
        None => settings.motion(&multibody, &table, coordinates)?,
    };
    let result = inverse_dynamics(&multibody, &motion, loads.as_ref(), &joints)?;
    let texts = [Some(result.forces.to_text()), result.body_forces.as_ref().map(StorageTable::to_text)];
    let outputs: Vec<(&Path, &[u8])> = [Some(request.output.as_path()), body_forces_file.as_deref()].into_iter().zip(&texts).filter_map(|(file, text)| Some((file?, text.as_ref()?.as_bytes()))).collect();
    create_output_folders(outputs.iter().map(|(file, _)| *file))?;
    write_all_atomically(&outputs, &input_paths)?;
    report(&result, coordinates, loads_file.as_deref(), &differentiation(request, &settings), &request.output);
    if let Some(file) = &body_forces_file {
        println!("body forces of {} joint(s) → {}", joints.len(), file.display());
    }
    Ok(Outcome::Success)
}

/// The joints whose equivalent body forces to report (`--body-force-joints`, else the setup's;
/// none when neither names any) and where they go.
fn body_forces(request: &Request, setup: Option<&IdSetup>, spec: &ModelSpec, multibody: &Multibody) -> Result<(Vec<usize>, Option<PathBuf>), Failure> {
    let (names, source) = match setup {
        Some(setup) if request.body_force_joints.is_empty() => (setup.joints_to_report_body_forces.clone(), format!("{}: joints_to_report_body_forces", setup.file.display())),
        _ => (request.body_force_joints.clone(), "--body-force-joints".to_string()),
    };
    if names.is_empty() {
        return Ok((Vec::new(), None));
    }
    let joints = named_joints(spec, multibody, &names).map_err(|problem| format!("{source}: {problem}"))?;
    let default_name = setup.map_or("body_forces_at_joints.sto", |s| s.output_body_forces_file.as_str());
    let file = request.body_forces.clone().unwrap_or_else(|| request.output.with_file_name(default_name));
    Ok((joints, Some(file)))
}

/// The command line's time range and cutoff, else the setup's (its cutoff not with rates given),
/// else all frames unfiltered.
fn settings(request: &Request, setup: Option<&IdSetup>) -> Result<InverseDynamicsSettings, Failure> {
    check_time_and_cutoff(request.time, request.lowpass)?;
    let from_setup = setup.map(|s| (s.time_range, s.lowpass_cutoff_frequency_for_coordinates));
    let time_range = request.time.or(from_setup.map(|(r, _)| [r.start, r.end])).unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
    let setup_cutoff = from_setup.map(|(_, c)| c).filter(|&c| c >= 0.0 && request.rates.is_none());
    let lowpass_cutoff = request.lowpass.or(setup_cutoff);
    Ok(InverseDynamicsSettings { time_range, lowpass_cutoff })
}

/// Our inverse dynamics applies gravity and external loads only, so every model force that
/// applies (disabled ones do not) must be excluded by the setup (names, or the keywords `all`,
/// `actuators`, `muscles`, any case).
fn check_excluded_forces(spec: &ModelSpec, setup: &IdSetup) -> Result<(), Failure> {
    let keyword = |k: &str| setup.forces_to_exclude.iter().any(|f| f.eq_ignore_ascii_case(k));
    let excluded = |force: &ForceSpec| {
        let actuator = force.is_muscle() || force.class.ends_with("Actuator");
        keyword("all") || (keyword("muscles") && force.is_muscle()) || (keyword("actuators") && actuator) || setup.forces_to_exclude.contains(&force.name)
    };
    let left: Vec<String> = spec.forces.iter().filter(|f| f.applies_force && !excluded(f)).map(|f| format!("{} ({})", f.name, f.class)).collect();
    if !left.is_empty() {
        let more = if left.len() > 5 { format!(" and {} more", left.len() - 5) } else { String::new() };
        return Err(format!(
            "{}: forces_to_exclude leaves {} force(s) of the model in: {}{more}; osim-tune's inverse dynamics applies only gravity and the external loads, so exclude them (`muscles`, `actuators`, names, or `all`)",
            setup.file.display(),
            left.len(),
            left[..left.len().min(5)].join(", ")
        )
        .into());
    }
    Ok(())
}

/// How the speeds and accelerations came about, for the report.
fn differentiation(request: &Request, settings: &InverseDynamicsSettings) -> String {
    match (&request.rates, settings.lowpass_cutoff) {
        (Some(rates), _) => format!("not filtered, rates from {}", rates.display()),
        (None, Some(cutoff)) => format!("low-pass {cutoff} Hz"),
        (None, None) => "unfiltered".to_string(),
    }
}

fn report(result: &InverseDynamicsResult, coordinates: &Path, loads: Option<&Path>, filter: &str, output: &Path) {
    let times = result.forces.times();
    let (Some(first), Some(last)) = (times.first(), times.last()) else { return };
    let loads = loads.map_or("no external loads".to_string(), |l| format!("external loads {}", l.display()));
    println!("{} frames of {} ({first:.4}–{last:.4} s, {filter}), {loads} → {}", times.len(), coordinates.display(), output.display());
    if !result.defaulted.is_empty() {
        println!("held at their default value (not in the coordinates): {}", result.defaulted.join(", "));
    }
    if !result.ignored_columns.is_empty() {
        println!("columns that are no coordinate, ignored: {}", result.ignored_columns.join(", "));
    }
}
