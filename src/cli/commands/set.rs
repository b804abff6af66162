//! `osim-tune set IN -o OUT PATH=VALUE…`

use std::path::Path;

use crate::cli::{Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;

pub fn run(input: &Path, output: &Path, assignments: &[String]) -> Result<Outcome, Failure> {
    ensure_not_an_input(output, &[input])?;
    let mut document = OsimDocument::read_object(input)?;
    for assignment in assignments {
        let (path, value) = assignment
            .split_once('=')
            .ok_or_else(|| format!("assignment {assignment:?} is not PATH=VALUE"))?;
        document.set_property(path.trim(), value)?;
    }
    write_atomically(output, &document.xml.serialize(), &[input])?;
    Ok(Outcome::Success)
}
