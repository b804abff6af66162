//! `osim-tune flatten DOCUMENT`: a stable line-per-property text for `git diff`.

use std::path::Path;

use crate::cli::{Failure, Outcome};
use crate::io::osim::OsimDocument;
use crate::review::{flatten, FlatEntry};

pub fn run(document: &Path) -> Result<Outcome, Failure> {
    let document = OsimDocument::read_object(document)?;
    println!("@Version = {}", document.version.number);
    for (path, entry) in flatten(&document).entries {
        match entry {
            FlatEntry::Component { class } => println!("{path} ({class})"),
            FlatEntry::Property { value } => println!("{path} = {}", normalise(&value)),
        }
    }
    Ok(Outcome::Success)
}

/// Numbers in shortest round-trip form, other text with whitespace folded.
fn normalise(value: &str) -> String {
    value
        .split_whitespace()
        .map(|token| token.parse::<f64>().map_or(token.to_string(), |number| number.to_string()))
        .collect::<Vec<_>>()
        .join(" ")
}
