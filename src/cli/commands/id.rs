//! `osim-tune id MODEL COORDINATES [--external-loads LOADS.xml] [--setup SETUP.xml] [--time START END] [--lowpass HZ] -o OUT.sto`

use std::path::{Path, PathBuf};

use crate::analysis::{inverse_dynamics, InverseDynamicsResult, InverseDynamicsSettings};
use crate::cli::{check_time_and_cutoff, create_output_folders, read_external_loads, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
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
    let mut inputs: Vec<PathBuf> = [model, coordinates].iter().map(|p| p.to_path_buf()).chain(request.setup.clone()).collect();
    let loads = loads_file.as_deref().map(|file| read_external_loads(file, &multibody, &mut inputs)).transpose()?;
    let input_paths: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    ensure_not_an_input(&request.output, &input_paths)?;
    let settings = settings(request, setup.as_ref())?;
    let table = StorageTable::read(coordinates)?;
    let result = inverse_dynamics(&multibody, &table, coordinates, loads.as_ref(), &settings)?;
    create_output_folders([request.output.as_path()])?;
    write_atomically(&request.output, result.forces.to_text().as_bytes(), &input_paths)?;
    report(&result, coordinates, loads_file.as_deref(), &settings, &request.output);
    Ok(Outcome::Success)
}

/// The command line's time range and cutoff, else the setup's, else all frames unfiltered.
fn settings(request: &Request, setup: Option<&IdSetup>) -> Result<InverseDynamicsSettings, Failure> {
    check_time_and_cutoff(request.time, request.lowpass)?;
    let from_setup = setup.map(|s| (s.time_range, s.lowpass_cutoff_frequency_for_coordinates));
    let time_range = request.time.or(from_setup.map(|(r, _)| [r.start, r.end])).unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
    let lowpass_cutoff = request.lowpass.or(from_setup.map(|(_, c)| c).filter(|&c| c >= 0.0));
    Ok(InverseDynamicsSettings { time_range, lowpass_cutoff })
}

/// Our inverse dynamics applies gravity and external loads only, so every model force that
/// applies (disabled ones do not) must be excluded by the setup (names, or the keywords `all`, `actuators`, `muscles`, any case), and
/// body forces at joints are not reported.
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
    if !setup.joints_to_report_body_forces.is_empty() {
        return Err(format!("{}: joints_to_report_body_forces is not supported; leave it empty", setup.file.display()).into());
    }
    Ok(())
}

fn report(result: &InverseDynamicsResult, coordinates: &Path, loads: Option<&Path>, settings: &InverseDynamicsSettings, output: &Path) {
    let times = result.forces.times();
    let (Some(first), Some(last)) = (times.first(), times.last()) else { return };
    let filter = settings.lowpass_cutoff.map_or("unfiltered".to_string(), |c| format!("low-pass {c} Hz"));
    let loads = loads.map_or("no external loads".to_string(), |l| format!("external loads {}", l.display()));
    println!("{} frames of {} ({first:.4}–{last:.4} s, {filter}), {loads} → {}", times.len(), coordinates.display(), output.display());
    if !result.defaulted.is_empty() {
        println!("held at their default value (not in the coordinates): {}", result.defaulted.join(", "));
    }
    if !result.ignored_columns.is_empty() {
        println!("columns that are no coordinate, ignored: {}", result.ignored_columns.join(", "));
    }
}
