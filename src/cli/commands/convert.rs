//! `osim-tune convert IN -o OUT`: a 2.x/3.x model in OpenSim 4's format.

use std::path::Path;

use crate::cli::{Failure, Outcome};
use crate::io::atomic::{ensure_not_an_input, write_atomically};
use crate::io::osim::OsimDocument;
use crate::model::{upgrade, ModelSpec};

pub fn run(input: &Path, output: &Path) -> Result<Outcome, Failure> {
    ensure_not_an_input(output, &[input])?;
    let document = OsimDocument::read(input)?;
    let converted = upgrade(&document)?;
    ModelSpec::read(&converted)?;
    write_atomically(output, &converted.xml.serialize(), &[input])?;
    if converted.version.number == document.version.number {
        println!("{} is already in OpenSim 4's format (version {}); copied unchanged", input.display(), document.version.number);
    } else {
        println!("converted {} from version {} to {}", input.display(), document.version.number, converted.version.number);
    }
    Ok(Outcome::Success)
}
