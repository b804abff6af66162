//! Isometric dynamometry trials from a subject folder: `subject.json` (estimated muscles, the
//! agonists of each direction, trial files, optional rest fiber lengths and noise level) and one
//! `.mot` table per trial set and direction (`setN_extension.mot`, `setN_flexion.mot`) whose rows
//! are trials: knee, hip and ankle angles, the measured knee moment and the agonists'
//! activations. Angles are converted to radians here; everything after works in SI units. The
//! estimated muscles may be replaced ([`TrialOptions::estimated_muscles`]); rest lengths and
//! abbreviations may name any muscle the file names, and the estimated muscles' are kept.
//!
//! `ground_truth.json`, when present, is never read: it exists only to score estimates.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::error::FunctionalError;
use crate::io::table::StorageTable;

/// The subject file of a dynamometry folder.
pub const SUBJECT_FILE: &str = "subject.json";

/// Suffix of an activation column: `<muscle>.activation`.
pub const ACTIVATION_SUFFIX: &str = ".activation";

/// Which way the subject pushes against the dynamometer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub enum Direction {
    /// Knee extension: the extensors are the agonists (positive moment for `knee_angle_r`).
    Extension,
    /// Knee flexion: the flexors are the agonists.
    Flexion,
}

impl Direction {
    pub const BOTH: [Direction; 2] = [Direction::Extension, Direction::Flexion];

    /// The key of the direction in `subject.json`'s `trial_files`.
    pub fn key(self) -> &'static str {
        match self {
            Direction::Extension => "extension",
            Direction::Flexion => "flexion",
        }
    }
}

/// The side of the measured leg, which names the coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Right,
    Left,
}

/// Column labels of a trial file. The three angle columns are also the names of the model
/// coordinates they set (OpenSim's gait2392 names by default).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrialColumns {
    /// The knee coordinate, e.g. `knee_angle_r` (negative in flexion).
    pub knee_angle: String,
    /// e.g. `hip_flexion_r`.
    pub hip_flexion: String,
    /// e.g. `ankle_angle_r`.
    pub ankle_angle: String,
    /// The measured knee moment, N·m, positive = generalized force of the knee coordinate.
    pub moment: String,
}

impl TrialColumns {
    /// gait2392 coordinate names for `side` and the moment column `knee_moment`.
    pub fn for_side(side: Side) -> TrialColumns {
        let suffix = match side {
            Side::Right => "r",
            Side::Left => "l",
        };
        TrialColumns {
            knee_angle: format!("knee_angle_{suffix}"),
            hip_flexion: format!("hip_flexion_{suffix}"),
            ankle_angle: format!("ankle_angle_{suffix}"),
            moment: "knee_moment".into(),
        }
    }

    /// The three angle columns, knee first.
    pub fn angles(&self) -> [&str; 3] {
        [&self.knee_angle, &self.hip_flexion, &self.ankle_angle]
    }
}

impl Default for TrialColumns {
    fn default() -> TrialColumns {
        TrialColumns::for_side(Side::Right)
    }
}

/// Which trial sets of `subject.json` to read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum SetSelection {
    /// Every set listed under `trial_files`.
    #[default]
    All,
    /// Only these sets (e.g. `["set5"]`), in this order.
    Only(Vec<String>),
}

/// How to read a dynamometry folder.
#[derive(Debug, Clone, Default)]
pub struct TrialOptions {
    pub sets: SetSelection,
    pub columns: TrialColumns,
    /// The muscles to estimate instead of the subject file's `estimated_muscles`.
    pub estimated_muscles: Option<Vec<String>>,
}

/// One isometric trial: a fixed posture, the agonists' activations and the measured moment.
#[derive(Debug, Clone, PartialEq)]
pub struct IsometricTrial {
    /// The trial file it comes from.
    pub file: PathBuf,
    /// Its 1-based line in that file.
    pub line: usize,
    /// The trial set, e.g. `set5`.
    pub set: String,
    pub direction: Direction,
    /// 1-based position in its file (the `time` column of the public data holds the same).
    pub number: usize,
    /// rad.
    pub knee_angle: f64,
    /// rad.
    pub hip_flexion: f64,
    /// rad.
    pub ankle_angle: f64,
    /// Measured knee moment, N·m, OpenSim's sign: + = generalized force of the knee coordinate
    /// (knee extension for `knee_angle_r`).
    pub moment: f64,
    /// `(muscle, activation)` for every activation column of the file, in column order, each in
    /// (0, 1].
    pub activations: Vec<(String, f64)>,
}

impl IsometricTrial {
    /// The activation the file gives `muscle`, if any.
    pub fn activation(&self, muscle: &str) -> Option<f64> {
        self.activations.iter().find(|(name, _)| name == muscle).map(|(_, a)| *a)
    }

    /// `set5 extension #3` style label for messages and tables.
    pub fn label(&self) -> String {
        format!("{} {} #{}", self.set, self.direction.key(), self.number)
    }
}

/// A dynamometry subject: what `subject.json` says and the selected trials.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamometryData {
    pub folder: PathBuf,
    /// Muscles whose L_opt and L_ts are estimated, in the subject file's order.
    pub estimated_muscles: Vec<String>,
    pub extension_agonists: Vec<String>,
    pub flexion_agonists: Vec<String>,
    /// `(muscle, abbreviation)` in estimated-muscle order (e.g. `("rect_fem_r", "RF")`).
    pub abbreviations: Vec<(String, String)>,
    /// The agonists' activation level the protocol asked for, in (0, 1].
    pub agonist_activation: f64,
    /// `(muscle, fiber length in m)`: fiber length along the fibre at rest (all coordinates 0,
    /// every muscle at minimum activation), in estimated-muscle order; empty when not measured.
    pub reference_rest_fiber_lengths: Vec<(String, f64)>,
    /// Standard deviation of the moment noise, N·m, when the subject file states it.
    pub noise_sd: Option<f64>,
    /// Column labels the trials were read with (and the model coordinates they set).
    pub columns: TrialColumns,
    /// Set by set (in the selection's order, or natural order of the set names), extension
    /// before flexion, trials in file order.
    pub trials: Vec<IsometricTrial>,
}

/// `subject.json` as far as the trials need it; other keys are descriptions and are ignored.
#[derive(Debug, Deserialize)]
struct SubjectFile {
    estimated_muscles: Vec<String>,
    extension_agonists: Vec<String>,
    flexion_agonists: Vec<String>,
    #[serde(default)]
    muscle_abbreviations: BTreeMap<String, String>,
    agonist_activation: f64,
    #[serde(default, rename = "reference_rest_fiber_length_m")]
    reference_rest_fiber_lengths: BTreeMap<String, f64>,
    #[serde(default, rename = "knee_moment_noise_sd_Nm")]
    noise_sd: Option<f64>,
    trial_files: BTreeMap<String, TrialFiles>,
}

#[derive(Debug, Deserialize)]
struct TrialFiles {
    extension: String,
    flexion: String,
}

impl DynamometryData {
    /// Reads the subject folder `folder` (see the module documentation).
    pub fn read(folder: &Path, options: &TrialOptions) -> Result<DynamometryData, FunctionalError> {
        let file = folder.join(SUBJECT_FILE);
        let text = std::fs::read_to_string(&file).map_err(|source| FunctionalError::Io { file: file.clone(), source })?;
        let mut subject: SubjectFile = serde_json::from_str(&text).map_err(|e| {
            let message = e.to_string();
            let place = format!(" at line {} column {}", e.line(), e.column());
            let problem = message.strip_suffix(&place).unwrap_or(&message).to_string();
            FunctionalError::Subject { file: file.clone(), line: e.line(), column: e.column(), problem }
        })?;
        let declared: Vec<String> = subject.estimated_muscles.iter().chain(&subject.extension_agonists).chain(&subject.flexion_agonists).cloned().collect();
        if let Some(muscles) = &options.estimated_muscles {
            subject.estimated_muscles = muscles.clone();
        }
        let checked = subject.check(&file, &declared)?;
        let mut trials = Vec::new();
        for set in selected_sets(&subject.trial_files, &options.sets, &file)? {
            let files = &subject.trial_files[&set];
            for direction in Direction::BOTH {
                let name = match direction {
                    Direction::Extension => &files.extension,
                    Direction::Flexion => &files.flexion,
                };
                let trial_file = folder.join(name);
                if !trial_file.is_file() {
                    return Err(FunctionalError::MissingTrialFile {
                        subject: file.clone(),
                        trial: trial_file,
                        set: set.clone(),
                        direction: direction.key().into(),
                    });
                }
                let agonists = match direction {
                    Direction::Extension => &subject.extension_agonists,
                    Direction::Flexion => &subject.flexion_agonists,
                };
                trials.extend(read_trial_file(&trial_file, &set, direction, agonists, &options.columns)?);
            }
        }
        Ok(DynamometryData {
            folder: folder.to_path_buf(),
            abbreviations: checked.abbreviations,
            reference_rest_fiber_lengths: checked.reference_rest_fiber_lengths,
            estimated_muscles: subject.estimated_muscles,
            extension_agonists: subject.extension_agonists,
            flexion_agonists: subject.flexion_agonists,
            agonist_activation: subject.agonist_activation,
            noise_sd: subject.noise_sd,
            columns: options.columns.clone(),
            trials,
        })
    }

    /// The agonists of `direction`.
    pub fn agonists(&self, direction: Direction) -> &[String] {
        match direction {
            Direction::Extension => &self.extension_agonists,
            Direction::Flexion => &self.flexion_agonists,
        }
    }

    /// The measured moments (N·m) in trial order.
    pub fn measured_moments(&self) -> Vec<f64> {
        self.trials.iter().map(|t| t.moment).collect()
    }

    /// The reference rest fiber length (m) of `muscle`, if measured.
    pub fn reference_rest_fiber_length(&self, muscle: &str) -> Option<f64> {
        self.reference_rest_fiber_lengths.iter().find(|(name, _)| name == muscle).map(|(_, l)| *l)
    }
}

/// The parts of `subject.json` that are checked and reordered.
struct CheckedSubject {
    abbreviations: Vec<(String, String)>,
    reference_rest_fiber_lengths: Vec<(String, f64)>,
}

impl SubjectFile {
    /// Checks the values of the subject file `file` (its estimated muscles possibly replaced);
    /// abbreviations and rest lengths may name any of the `declared` muscles (those the file
    /// names), and only the estimated ones' are kept.
    fn check(&self, file: &Path, declared: &[String]) -> Result<CheckedSubject, FunctionalError> {
        let bad = |key: &str, value: String, expected: &str| FunctionalError::SubjectValue {
            file: file.into(),
            key: key.into(),
            value,
            expected: expected.into(),
        };
        if self.estimated_muscles.is_empty() {
            return Err(bad("estimated_muscles", "empty".into(), "at least one muscle name"));
        }
        for (key, names) in [
            ("estimated_muscles", &self.estimated_muscles),
            ("extension_agonists", &self.extension_agonists),
            ("flexion_agonists", &self.flexion_agonists),
        ] {
            if let Some(repeated) = names.iter().enumerate().find(|(i, n)| names[..*i].contains(n)).map(|(_, n)| n) {
                return Err(bad(key, format!("a list naming {repeated:?} twice"), "each muscle once"));
            }
        }
        let activation = self.agonist_activation;
        if !(activation > 0.0 && activation <= 1.0) {
            return Err(bad("agonist_activation", activation.to_string(), "an activation in (0, 1]"));
        }
        if let Some(sd) = self.noise_sd {
            if !(sd >= 0.0 && sd.is_finite()) {
                return Err(bad("knee_moment_noise_sd_Nm", sd.to_string(), "a standard deviation ≥ 0 in N·m"));
            }
        }
        if self.trial_files.is_empty() {
            return Err(bad("trial_files", "empty".into(), "at least one trial set"));
        }
        let estimated = |key: &str, name: &String| {
            if declared.contains(name) {
                Ok(self.estimated_muscles.contains(name))
            } else {
                Err(bad(key, format!("a key {name:?}"), "only muscles the file names in estimated_muscles, extension_agonists or flexion_agonists as keys"))
            }
        };
        let mut abbreviations = Vec::new();
        for (name, abbreviation) in &self.muscle_abbreviations {
            if estimated("muscle_abbreviations", name)? {
                abbreviations.push((name.clone(), abbreviation.clone()));
            }
        }
        let mut lengths = Vec::new();
        for (name, &length) in &self.reference_rest_fiber_lengths {
            if !estimated("reference_rest_fiber_length_m", name)? {
                continue;
            }
            if !(length > 0.0 && length.is_finite()) {
                return Err(bad(&format!("reference_rest_fiber_length_m.{name}"), length.to_string(), "a positive length in m"));
            }
            lengths.push((name.clone(), length));
        }
        let order = |name: &String| self.estimated_muscles.iter().position(|m| m == name);
        abbreviations.sort_by_key(|(name, _)| order(name));
        lengths.sort_by_key(|(name, _)| order(name));
        Ok(CheckedSubject { abbreviations, reference_rest_fiber_lengths: lengths })
    }
}

/// The sets to read: the selection's, or all in natural order (`set5` before `set10`).
fn selected_sets(files: &BTreeMap<String, TrialFiles>, selection: &SetSelection, file: &Path) -> Result<Vec<String>, FunctionalError> {
    match selection {
        SetSelection::All => {
            let mut sets: Vec<String> = files.keys().cloned().collect();
            sets.sort_by(|a, b| natural_key(a).cmp(&natural_key(b)));
            Ok(sets)
        }
        SetSelection::Only(sets) => {
            for set in sets {
                if !files.contains_key(set) {
                    let available = files.keys().cloned().collect::<Vec<_>>().join(", ");
                    return Err(FunctionalError::UnknownSet { file: file.into(), set: set.clone(), available });
                }
            }
            Ok(sets.clone())
        }
    }
}

/// Sorts `set5` before `set10`: the name without its trailing digits, then their value.
fn natural_key(name: &str) -> (&str, u64, &str) {
    let stem = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let number = name[stem.len()..].parse().unwrap_or(0);
    (stem, number, name)
}

/// The trials of one file.
fn read_trial_file(
    file: &Path,
    set: &str,
    direction: Direction,
    agonists: &[String],
    columns: &TrialColumns,
) -> Result<Vec<IsometricTrial>, FunctionalError> {
    let table = StorageTable::read(file)?;
    if table.n_rows() == 0 {
        return Err(FunctionalError::NoTrials { file: file.into() });
    }
    // The unit as OpenSim reads it (see `StorageTable::parse`); undeclared is radians.
    let in_degrees = table.in_degrees().unwrap_or(false);
    let column = |label: &str, expected: &str| {
        table.column_index(label).ok_or_else(|| FunctionalError::MissingColumn {
            file: file.into(),
            column: label.into(),
            expected: expected.into(),
        })
    };
    let angle_expected = "the angle of the model coordinate of that name (degrees when inDegrees=yes)";
    let angles = [
        column(&columns.knee_angle, angle_expected)?,
        column(&columns.hip_flexion, angle_expected)?,
        column(&columns.ankle_angle, angle_expected)?,
    ];
    let moment = column(&columns.moment, "the measured knee moment in N·m")?;
    for agonist in agonists {
        column(&format!("{agonist}{ACTIVATION_SUFFIX}"), &format!("the activation of the {} agonist {agonist}", direction.key()))?;
    }
    let activations: Vec<(usize, String)> = table
        .labels()
        .iter()
        .enumerate()
        .skip(1)
        .filter_map(|(i, label)| label.strip_suffix(ACTIVATION_SUFFIX).map(|muscle| (i, muscle.to_string())))
        .collect();
    let lines = data_lines(file)?;
    let mut trials = Vec::with_capacity(table.n_rows());
    for (row_index, row) in table.rows().enumerate() {
        let line = lines.get(row_index).copied().unwrap_or(0);
        let bad = |c: usize, expected: &str| FunctionalError::TrialValue {
            file: file.into(),
            line,
            column: table.labels()[c].clone(),
            value: row[c],
            expected: expected.into(),
        };
        let mut radians = [0.0; 3];
        for (value, &c) in radians.iter_mut().zip(&angles) {
            if !row[c].is_finite() {
                return Err(bad(c, "a finite angle"));
            }
            *value = if in_degrees { row[c].to_radians() } else { row[c] };
        }
        if !row[moment].is_finite() {
            return Err(bad(moment, "a finite moment in N·m"));
        }
        let mut trial_activations = Vec::with_capacity(activations.len());
        for (c, muscle) in &activations {
            let a = row[*c];
            if !(a > 0.0 && a <= 1.0) {
                return Err(bad(*c, "an activation in (0, 1]"));
            }
            trial_activations.push((muscle.clone(), a));
        }
        trials.push(IsometricTrial {
            file: file.into(),
            line,
            set: set.into(),
            direction,
            number: row_index + 1,
            knee_angle: radians[0],
            hip_flexion: radians[1],
            ankle_angle: radians[2],
            moment: row[moment],
            activations: trial_activations,
        });
    }
    Ok(trials)
}

/// The 1-based line numbers of a storage file's data rows: the non-blank lines after the label
/// line that follows `endheader` (as the table reader takes them).
fn data_lines(file: &Path) -> Result<Vec<usize>, FunctionalError> {
    let text = std::fs::read_to_string(file).map_err(|source| FunctionalError::Io { file: file.into(), source })?;
    let mut lines = text.lines().enumerate().map(|(i, line)| (i + 1, line));
    lines.by_ref().find(|(_, line)| line.trim() == "endheader");
    lines.by_ref().find(|(_, line)| !line.trim().is_empty());
    Ok(lines.filter(|(_, line)| !line.trim().is_empty()).map(|(number, _)| number).collect())
}

/// √(Σ v²/n) of `values` (0 for none), in their unit: e.g. of moment residuals, N·m.
pub(crate) fn root_mean_square(values: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, n) = values.into_iter().fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n.max(1) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_sort_naturally() {
        let mut sets = vec!["set20", "set5", "set10", "extra"];
        sets.sort_by(|a, b| natural_key(a).cmp(&natural_key(b)));
        assert_eq!(sets, ["extra", "set5", "set10", "set20"]);
    }

    #[test]
    fn left_side_columns() {
        let columns = TrialColumns::for_side(Side::Left);
        assert_eq!(columns.angles(), ["knee_angle_l", "hip_flexion_l", "ankle_angle_l"]);
    }
}
