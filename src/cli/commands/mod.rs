//! One file per command.

mod analyze;
mod diff;
mod flatten;
mod info;
mod set;

use super::{Command, Failure, Outcome};

pub fn run(command: Command) -> Result<Outcome, Failure> {
    match command {
        Command::Analyze { model, motion, output, skip_unknown_columns } => analyze::run(&model, &motion, &output, skip_unknown_columns),
        Command::Info { model, json } => info::run(&model, json),
        Command::Set { input, output, assignments } => set::run(&input, &output, &assignments),
        Command::Diff { a, b, json, rtol } => diff::run(&a, &b, json, rtol),
        Command::Flatten { document } => flatten::run(&document),
    }
}
