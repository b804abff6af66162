//! `osim-tune trials MODEL SESSION.json -o TRIALS/ [--plateau-fraction F] [--max-crank-motion DEG]`:
//! isometric dynamometer contractions (thesis ch. 5) as the trial folder functional scaling reads
//! (ch. 6). Per contraction M3D along its motion with its load cell, the plateau around the peak
//! averaged; one row per contraction in `<set>_<direction>.mot`, and `subject.json`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_json::{Map, Value};

use crate::analysis::{isometric_contraction, DynamometerModel, ExternalLoads, IsometricContraction, SplinedMotion};
use crate::cli::{create_output_folders, Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_all_atomically};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::{Function, Multibody};
use crate::model::{FunctionSpec, MotionType};
use crate::tuning::functional::{Direction, ACTIVATION_SUFFIX, SUBJECT_FILE};

/// What the command line asks for besides the model and the session.
pub struct Request {
    /// The plateau: |M3D| at least this fraction of its peak, in (0, 1).
    pub plateau_fraction: f64,
    /// The largest turn of the crank over a plateau, degrees.
    pub max_crank_motion: f64,
    pub output: PathBuf,
}

/// The session file: the subject file's fields, the set-up's names and the contractions.
#[derive(Debug, Deserialize)]
struct Session {
    /// Copied into `subject.json` (with `trial_files` added).
    subject: Map<String, Value>,
    #[serde(default = "default_crank")]
    crank: String,
    #[serde(default = "default_knee")]
    knee: String,
    #[serde(default = "default_hip")]
    hip: String,
    #[serde(default = "default_ankle")]
    ankle: String,
    contractions: Vec<Contraction>,
}

fn default_crank() -> String {
    "crank".into()
}
fn default_knee() -> String {
    "knee_angle_r".into()
}
fn default_hip() -> String {
    "hip_flexion_r".into()
}
fn default_ankle() -> String {
    "ankle_angle_r".into()
}

/// One isometric contraction: its set and direction, the motion (e.g. IK of the leg's and the
/// crank's markers), the load cell (`ExternalLoads` on the crank) and optionally the agonists'
/// activations over time (columns `<muscle>` or `<muscle>.activation`).
#[derive(Debug, Deserialize)]
struct Contraction {
    set: String,
    direction: String,
    coordinates: PathBuf,
    load_cell: PathBuf,
    #[serde(default)]
    activations: Option<PathBuf>,
}

/// The subject fields the rows need.
#[derive(Debug, Deserialize)]
struct Agonists {
    extension_agonists: Vec<String>,
    flexion_agonists: Vec<String>,
    agonist_activation: f64,
}

impl Agonists {
    fn of(&self, direction: Direction) -> &[String] {
        match direction {
            Direction::Extension => &self.extension_agonists,
            Direction::Flexion => &self.flexion_agonists,
        }
    }
}

/// One trial row: the contraction's plateau and its agonists' activations.
struct Row {
    set: String,
    direction: Direction,
    contraction: IsometricContraction,
    activations: Vec<f64>,
}

pub fn run(model: &Path, session_file: &Path, request: &Request) -> Result<Outcome, Failure> {
    if !(request.plateau_fraction > 0.0 && request.plateau_fraction < 1.0) {
        return Err(format!("--plateau-fraction {}: expected a fraction in (0, 1)", request.plateau_fraction).into());
    }
    if !(request.max_crank_motion.is_finite() && request.max_crank_motion >= 0.0) {
        return Err(format!("--max-crank-motion {}: expected an angle ≥ 0 degrees", request.max_crank_motion).into());
    }
    let session = read_session(session_file)?;
    let agonists: Agonists = serde_json::from_value(Value::Object(session.subject.clone())).map_err(|e| format!("{}: subject: {e}", session_file.display()))?;
    let multibody = Multibody::new(&crate::model::ModelSpec::read(&OsimDocument::read(model)?)?)?;
    let dynamometer = DynamometerModel::new(&multibody, &session.crank, &session.knee)?;
    let angles = angle_coordinates(&multibody, &session, session_file)?;
    let base = session_file.parent().unwrap_or(Path::new("."));
    let mut inputs: Vec<PathBuf> = vec![model.into(), session_file.into()];
    let setup = SessionSetUp { multibody: &multibody, dynamometer: &dynamometer, base, agonists: &agonists, request };
    let mut rows = Vec::with_capacity(session.contractions.len());
    for (k, contraction) in session.contractions.iter().enumerate() {
        let context = format!("{}: contraction {} ({} {})", session_file.display(), k + 1, contraction.set, contraction.direction);
        if !is_file_stem(&contraction.set) {
            return Err(format!("{context}: set {:?}; expected a name of letters, digits, '_' or '-' (it names the trial files)", contraction.set).into());
        }
        let Some(direction) = Direction::BOTH.into_iter().find(|d| d.key() == contraction.direction) else {
            return Err(format!("{context}: direction {:?}; expected \"extension\" or \"flexion\"", contraction.direction).into());
        };
        let row = contraction_row(&setup, contraction, direction, &mut inputs).map_err(|e| format!("{context}: {e}"))?;
        rows.push(row);
    }
    check_signs(&rows, session_file)?;
    let files = trial_files(&rows, session_file)?;
    let subject = subject_json(&session, &files)?;
    let mut texts = vec![(request.output.join(SUBJECT_FILE), subject)];
    for (set, names) in &files {
        for (direction, name) in Direction::BOTH.into_iter().zip(names) {
            texts.push((request.output.join(name), trial_table(&rows, set, direction, &angles, &multibody, &agonists)?.to_text()));
        }
    }
    let input_paths: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    for (file, _) in &texts {
        ensure_not_an_input(file, &input_paths)?;
    }
    let outputs: Vec<(&Path, &[u8])> = texts.iter().map(|(file, text)| (file.as_path(), text.as_bytes())).collect();
    create_output_folders(outputs.iter().map(|(file, _)| *file))?;
    write_all_atomically(&outputs, &input_paths)?;
    report(&rows, &multibody, &dynamometer, &request.output);
    Ok(Outcome::Success)
}

/// Whether `name` can name a file in the trial folder as it is.
fn is_file_stem(name: &str) -> bool {
    !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

fn read_session(file: &Path) -> Result<Session, Failure> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let session: Session = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    if session.contractions.is_empty() {
        return Err(format!("{}: contractions: empty; expected at least one contraction per set and direction", file.display()).into());
    }
    Ok(session)
}

/// The knee's, hip's and ankle's coordinates ([`Multibody::coordinates`] indices), rotational.
fn angle_coordinates(multibody: &Multibody, session: &Session, file: &Path) -> Result<[usize; 3], Failure> {
    let mut found = [0; 3];
    for (slot, (key, name)) in found.iter_mut().zip([("knee", &session.knee), ("hip", &session.hip), ("ankle", &session.ankle)]) {
        let c = multibody.coordinate_index(name).ok_or_else(|| format!("{}: {key} {name:?} is not a coordinate of the model", file.display()))?;
        if multibody.coordinates[c].motion_type != MotionType::Rotational {
            return Err(format!("{}: {key} {name:?} is not a rotational coordinate", file.display()).into());
        }
        *slot = c;
    }
    Ok(found)
}

/// What every contraction of a session is read against.
struct SessionSetUp<'a> {
    multibody: &'a Multibody,
    dynamometer: &'a DynamometerModel,
    /// The session file's folder (contraction paths are relative to it).
    base: &'a Path,
    agonists: &'a Agonists,
    request: &'a Request,
}

/// The contraction's plateau and its agonists' activations; its files join `inputs`.
fn contraction_row(setup: &SessionSetUp, contraction: &Contraction, direction: Direction, inputs: &mut Vec<PathBuf>) -> Result<Row, Failure> {
    let SessionSetUp { multibody, dynamometer, base, agonists, request } = *setup;
    let (coordinates, load_cell) = (base.join(&contraction.coordinates), base.join(&contraction.load_cell));
    let (loads, data_file) = ExternalLoads::read(&load_cell, multibody)?;
    crate::cli::warn_about(&loads.warnings);
    dynamometer.check_load_cell(multibody, &loads, &load_cell)?;
    let motion = SplinedMotion::new(multibody, &StorageTable::read(&coordinates)?, &coordinates, None)?;
    let plateau = isometric_contraction(multibody, dynamometer, &motion, &loads, request.plateau_fraction)?;
    if plateau.crank_motion.to_degrees() > request.max_crank_motion {
        return Err(format!(
            "the crank turned {:.2}° over the plateau ({:.3}–{:.3} s); an isometric contraction holds it within --max-crank-motion {}°",
            plateau.crank_motion.to_degrees(),
            plateau.time_range()[0],
            plateau.time_range()[1],
            request.max_crank_motion
        )
        .into());
    }
    let muscles = agonists.of(direction);
    let activations = match &contraction.activations {
        Some(file) => {
            let file = base.join(file);
            let levels = plateau_activations(&file, muscles, &plateau.times)?;
            inputs.push(file);
            levels
        }
        None => vec![agonists.agonist_activation; muscles.len()],
    };
    inputs.extend([coordinates, load_cell, data_file]);
    Ok(Row { set: contraction.set.clone(), direction, contraction: plateau, activations })
}

/// Each agonist's mean activation over the plateau's frame `times` (s), `file`'s column
/// interpolated linearly, in (0, 1].
fn plateau_activations(file: &Path, muscles: &[String], times: &[f64]) -> Result<Vec<f64>, Failure> {
    let table = StorageTable::read(file)?;
    let rows = table.times();
    if rows.len() < 2 || rows.windows(2).any(|w| w[1] <= w[0]) {
        return Err(format!("{}: expected at least two rows at increasing times", file.display()).into());
    }
    let (first, last) = (times[0], times[times.len() - 1]);
    if first < rows[0] || last > rows[rows.len() - 1] {
        return Err(format!("{}: its rows span {}–{} s, the plateau {first:.3}–{last:.3} s; expected activations over the whole plateau", file.display(), rows[0], rows[rows.len() - 1]).into());
    }
    let mut levels = Vec::with_capacity(muscles.len());
    for muscle in muscles {
        let column = table.column(muscle).or_else(|| table.column(&format!("{muscle}{ACTIVATION_SUFFIX}"))).ok_or_else(|| format!("{}: no column {muscle:?} (or {muscle}{ACTIVATION_SUFFIX}) for the agonist", file.display()))?;
        let activation = Function::new(&FunctionSpec::PiecewiseLinearFunction { x: rows.clone(), y: column });
        let mean = times.iter().map(|&t| activation.value(t)).sum::<f64>() / times.len() as f64;
        if !(mean > 0.0 && mean <= 1.0) {
            return Err(format!("{}: {muscle}'s mean activation over the plateau is {mean}; expected an activation in (0, 1]", file.display()).into());
        }
        levels.push(mean);
    }
    Ok(levels)
}

/// Every contraction of a direction pushes the same way: M3D of one sign.
fn check_signs(rows: &[Row], file: &Path) -> Result<(), Failure> {
    for direction in Direction::BOTH {
        let signs: Vec<(usize, f64)> = rows.iter().enumerate().filter(|(_, r)| r.direction == direction).map(|(k, r)| (k + 1, r.contraction.knee_moment.signum())).collect();
        if let Some((k, _)) = signs.iter().find(|(_, s)| *s != signs[0].1) {
            return Err(format!("{}: contraction {k} ({}) has M3D of the other sign than contraction {}: a load cell's sign or the direction is wrong", file.display(), direction.key(), signs[0].0).into());
        }
    }
    Ok(())
}

/// Per set (in the contractions' order) its two trial files, extension first; a set lacking a
/// direction is refused.
fn trial_files(rows: &[Row], file: &Path) -> Result<Vec<(String, [String; 2])>, Failure> {
    let mut sets: Vec<String> = Vec::new();
    for row in rows {
        if !sets.contains(&row.set) {
            sets.push(row.set.clone());
        }
    }
    sets.into_iter()
        .map(|set| {
            if let Some(missing) = Direction::BOTH.iter().find(|&&d| !rows.iter().any(|r| r.set == set && r.direction == d)) {
                return Err(format!("{}: set {set:?} has no {} contraction; functional scaling needs both directions of every set", file.display(), missing.key()).into());
            }
            let names = Direction::BOTH.map(|d| format!("{set}_{}.mot", d.key()));
            Ok((set, names))
        })
        .collect()
}

/// `subject.json`: the session's subject fields and the trial files.
fn subject_json(session: &Session, files: &[(String, [String; 2])]) -> Result<String, Failure> {
    let mut subject = session.subject.clone();
    let trial_files: BTreeMap<&str, Value> = files.iter().map(|(set, [extension, flexion])| (set.as_str(), serde_json::json!({ "extension": extension, "flexion": flexion }))).collect();
    subject.insert("trial_files".into(), serde_json::to_value(trial_files)?);
    Ok(serde_json::to_string_pretty(&Value::Object(subject))? + "\n")
}

/// The set's trial file of `direction`: per contraction the plateau's knee, hip and ankle angles
/// (degrees), `knee_moment` (N·m) and `<agonist>.activation`; `time` numbers the rows from 1.
fn trial_table(rows: &[Row], set: &str, direction: Direction, angles: &[usize; 3], multibody: &Multibody, agonists: &Agonists) -> Result<StorageTable, Failure> {
    let muscles = agonists.of(direction);
    let mut labels = vec!["time".to_string()];
    labels.extend(angles.iter().map(|&c| multibody.coordinates[c].name.clone()));
    labels.push("knee_moment".into());
    labels.extend(muscles.iter().map(|m| format!("{m}{ACTIVATION_SUFFIX}")));
    let mut values = Vec::new();
    for (number, row) in rows.iter().filter(|r| r.set == set && r.direction == direction).enumerate() {
        values.push((number + 1) as f64);
        values.extend(angles.iter().map(|&c| row.contraction.coordinates[c].to_degrees()));
        values.push(row.contraction.knee_moment);
        values.extend(&row.activations);
    }
    Ok(StorageTable::new(&format!("{set}_{}", direction.key()), labels, values)?.with_in_degrees(true))
}

fn report(rows: &[Row], multibody: &Multibody, dynamometer: &DynamometerModel, output: &Path) {
    let knee = &multibody.coordinates[dynamometer.knee_coordinate].name;
    println!("{:<8} {:<10} {:>17} {:>7} {:>10} {:>12} {:>10}", "set", "direction", "plateau (s)", "frames", knee, "M3D (N·m)", "peak");
    for row in rows {
        let c = &row.contraction;
        let [first, last] = c.time_range();
        println!(
            "{:<8} {:<10} {:>8.3}–{:<8.3} {:>7} {:>9.2}° {:>12.3} {:>10.3}",
            row.set,
            row.direction.key(),
            first,
            last,
            c.times.len(),
            c.coordinates[dynamometer.knee_coordinate].to_degrees(),
            c.knee_moment,
            c.peak
        );
    }
    println!("{} contractions → {}", rows.len(), output.display());
}
