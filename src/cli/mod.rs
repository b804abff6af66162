//! Command-line interface: parse arguments into plain structs, run the command, print. The only
//! module that prints. Exit codes: 0 success (or no differences), 1 differences found,
//! 2 error (bad input, unknown path, unwritable output).

mod args;
mod commands;

use std::path::Path;
use std::process::ExitCode;

use clap::Parser;

pub use args::{Arguments, AxisMethodArgument, Command, PoseArgument};

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
