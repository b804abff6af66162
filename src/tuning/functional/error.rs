//! Errors of functional scaling: reading dynamometry trials and evaluating the knee-moment
//! model. Each names the file (subject file, trial file or model) and the key, line and column,
//! or the muscle and trial at fault, and says what was expected.

use std::path::PathBuf;

use crate::io::table::TableError;
use crate::mechanics::muscle::MuscleError;
use crate::mechanics::MechanicsError;
use crate::solvers::nlp::NlpError;

#[derive(Debug, thiserror::Error)]
pub enum FunctionalError {
    /// A trial file could not be read as an OpenSim storage table.
    #[error(transparent)]
    Table(#[from] TableError),
    /// The model could not be compiled for evaluation.
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    /// `subject.json` (or another input file) cannot be read at all.
    #[error("{}: cannot read: {source}", file.display())]
    Io { file: PathBuf, source: std::io::Error },
    /// `subject.json` is not the JSON expected: a missing key, a value of the wrong type.
    #[error("{}:{line}:{column}: {problem}", file.display())]
    Subject { file: PathBuf, line: usize, column: usize, problem: String },
    /// A value of `subject.json` has the right type but is not acceptable.
    #[error("{}: key {key:?} is {value}; expected {expected}", file.display())]
    SubjectValue { file: PathBuf, key: String, value: String, expected: String },
    /// A trial set was asked for that `subject.json` does not list.
    #[error("{}: no trial set {set:?} under \"trial_files\"; expected one of: {available}", file.display())]
    UnknownSet { file: PathBuf, set: String, available: String },
    /// A trial file listed in `subject.json` does not exist.
    #[error("{}: trial file {} (trial_files.{set}.{direction}) does not exist; expected it next to the subject file", subject.display(), trial.display())]
    MissingTrialFile { subject: PathBuf, trial: PathBuf, set: String, direction: String },
    /// A trial file lacks a column.
    #[error("{}: no column {column:?}; expected {expected}", file.display())]
    MissingColumn { file: PathBuf, column: String, expected: String },
    /// A trial file holds no trials.
    #[error("{}: the table has no rows; expected one row per trial", file.display())]
    NoTrials { file: PathBuf },
    /// A value of a trial file is out of range (activation outside (0, 1], a non-finite angle
    /// or moment).
    #[error("{}:{line}: column {column:?} is {value}; expected {expected}", file.display())]
    TrialValue { file: PathBuf, line: usize, column: String, value: f64, expected: String },
    /// A name of the trials (muscle, coordinate) does not fit the model.
    #[error("{}: {what} {name:?}: {problem}", model.display())]
    Model { model: PathBuf, what: &'static str, name: String, problem: String },
    /// Parameters given for evaluation do not fit the model's estimated muscles.
    #[error("parameters of muscle {muscle:?}: {problem}")]
    Parameters { muscle: String, problem: String },
    /// No point of a muscle's rest curve within the searched L_opt span (relative to `optimal`,
    /// m) reproduces its rest fiber length `reference` (m) with an equilibrium in every trial.
    #[error("parameters of muscle {muscle:?}: no L_opt in {span:?} × {optimal} m reproduces the rest fiber length {reference} m with an equilibrium in every trial")]
    NoRestCurvePoint { muscle: String, span: [f64; 2], optimal: f64, reference: f64 },
    /// Too few trials for the parameters of one direction's agonists.
    #[error("{}: the {direction} trials give {observations} observation(s) (distinct knee angles + rest fiber lengths) for {parameters} parameters; not identifiable: {unidentifiable}; add trials at more knee angles", folder.display())]
    NotIdentifiable { folder: PathBuf, direction: &'static str, observations: usize, parameters: usize, unidentifiable: String },
    /// The measured moments have the opposite sign of the model's in both directions.
    #[error("{}: column {column:?} has the opposite sign of the model's knee moments in both the extension and the flexion trials; expected positive {column} = positive generalized force of {coordinate} (OpenSim's convention; negate the column if the dynamometer reports the other sign)", folder.display())]
    SignConvention { folder: PathBuf, column: String, coordinate: String },
    /// The Phase II NLP is inconsistent (a bound range that is empty, a start point that is
    /// not finite).
    #[error("Phase II cannot be set up: {0}")]
    Nlp(#[from] NlpError),
    /// A muscle has no equilibrium in a trial (`file` the trial file) or at rest, or cannot be
    /// built from the model's properties (`file` the model).
    #[error("{}: {muscle} in {context}: {source}", file.display())]
    Muscle { file: PathBuf, muscle: String, context: String, source: Box<MuscleError> },
}

impl FunctionalError {
    /// A [`FunctionalError::Parameters`] about the estimated muscles as a whole.
    pub fn all_muscles(problem: impl Into<String>) -> FunctionalError {
        FunctionalError::Parameters { muscle: "(all)".into(), problem: problem.into() }
    }
}
