//! Command-line interface: parse arguments into plain structs, run the command, print. The only
//! module that prints. Exit codes: 0 success (or no differences), 1 differences found,
//! 2 error (bad input, unknown path, unwritable output).

mod args;
mod commands;

use std::path::Path;
use std::process::ExitCode;

use clap::Parser;

pub use args::{AnalyzeArgs, Arguments, AxisMethodArgument, Command, PoseArgument};

/// A command's failure; printed as `error: …` with exit code 2.
pub type Failure = Box<dyn std::error::Error>;

/// What a successful command reports through the exit code.
pub enum Outcome {
    Success,
    /// `diff` found differences.
    Differences,
    /// `ik`: some frame did not converge (results are written).
    NotConverged,
}

/// Parses the process arguments, runs the command and maps the outcome to an exit code.
pub fn run() -> ExitCode {
    let arguments = Arguments::parse();
    match commands::run(arguments.command) {
        Ok(Outcome::Success) => ExitCode::SUCCESS,
        Ok(Outcome::Differences | Outcome::NotConverged) => ExitCode::from(1),
        Err(failure) => {
            eprintln!("error: {failure}");
            ExitCode::from(2)
        }
    }
}

/// Creates the missing parent folders of the output `files`, so `-o out/new/q.mot` works; called
/// after a command's checks, just before it writes, so a refused request creates nothing.
pub(crate) fn create_output_folders<'a>(files: impl IntoIterator<Item = &'a Path>) -> Result<(), Failure> {
    for folder in files.into_iter().filter_map(Path::parent).filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder).map_err(|e| format!("{}: cannot create the output folder: {e}", folder.display()))?;
    }
    Ok(())
}

/// Writes `files` (path, text) together, each atomically, after checking that none is one of the
/// files `read` and creating their folders; nothing is written when a check fails.
pub(crate) fn write_files(files: &[(std::path::PathBuf, String)], read: &[std::path::PathBuf]) -> Result<(), Failure> {
    let inputs: Vec<&Path> = read.iter().map(std::path::PathBuf::as_path).collect();
    for (path, _) in files {
        crate::io::atomic::ensure_not_an_input(path, &inputs)?;
    }
    create_output_folders(files.iter().map(|(path, _)| path.as_path()))?;
    let contents: Vec<(&Path, &[u8])> = files.iter().map(|(path, text)| (path.as_path(), text.as_bytes())).collect();
    crate::io::atomic::write_all_atomically(&contents, &inputs)?;
    Ok(())
}

/// Checks the outputs `(flag, file)` a command was given (unset ones `None`): none may be an input
/// or name the same file as another.
pub(crate) fn check_outputs(outputs: &[(&str, Option<&Path>)], inputs: &[&Path]) -> Result<(), Failure> {
    let named: Vec<(&str, &Path)> = outputs.iter().filter_map(|&(flag, file)| Some((flag, file?))).collect();
    for (k, &(flag, file)) in named.iter().enumerate() {
        crate::io::atomic::ensure_not_an_input(file, inputs)?;
        for &(other, earlier) in &named[..k] {
            crate::io::atomic::ensure_not_an_input(file, &[earlier]).map_err(|_| format!("{}: {flag} and {other} name the same file", file.display()))?;
        }
    }
    Ok(())
}

/// Checks `--time START END` (START ≤ END) and `--lowpass HZ` (> 0), shared by the commands that
/// read a motion.
pub(crate) fn check_time_and_cutoff(time: Option<[f64; 2]>, lowpass: Option<f64>) -> Result<(), Failure> {
    if let Some(cutoff) = lowpass.filter(|c| !(c.is_finite() && *c > 0.0)) {
        return Err(format!("--lowpass {cutoff}: expected a cutoff frequency > 0 Hz").into());
    }
    if let Some([start, end]) = time.filter(|[s, e]| !matches!(s.partial_cmp(e), Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal))) {
        return Err(format!("--time {start} {end}: expected START ≤ END").into());
    }
    Ok(())
}

/// A `.trc` marker trial, with a note when its `NumFrames` disagrees with the frames it holds.
pub(crate) fn read_marker_trial(file: &Path) -> Result<crate::io::table::MarkerTable, Failure> {
    let trial = crate::io::table::MarkerTable::read(file)?;
    if let Some(declared) = trial.header().declared_frames {
        eprintln!("note: {}: NumFrames says {declared}, the file holds {} frames; those are used, as OpenSim does", file.display(), trial.n_frames());
    }
    Ok(trial)
}

/// Prints `warnings`, one `warning:` line each.
pub(crate) fn warn_about(warnings: &[String]) {
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
}

/// An `ExternalLoads` file and its datafile on `multibody`; both files join `inputs` (its
/// warnings are printed).
pub(crate) fn read_external_loads(file: &Path, multibody: &crate::mechanics::Multibody, inputs: &mut Vec<std::path::PathBuf>) -> Result<crate::analysis::ExternalLoads, Failure> {
    let (loads, data_file) = crate::analysis::ExternalLoads::read(file, multibody)?;
    inputs.extend([file.to_path_buf(), data_file]);
    warn_about(&loads.warnings);
    Ok(loads)
}
