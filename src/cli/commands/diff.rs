//! `osim-tune diff A B [--json] [--rtol X]`

use std::path::Path;

use crate::cli::{Failure, Outcome};
use crate::io::osim::OsimDocument;
use crate::review::{diff, Change, DocumentDiff};

pub fn run(a: &Path, b: &Path, json: bool, relative_tolerance: f64) -> Result<Outcome, Failure> {
    if relative_tolerance.is_nan() || relative_tolerance < 0.0 {
        return Err(format!("--rtol must be ≥ 0, got {relative_tolerance}").into());
    }
    let (document_a, document_b) = (OsimDocument::read_object(a)?, OsimDocument::read_object(b)?);
    let differences = diff(&document_a, &document_b, relative_tolerance);
    if json {
        println!("{}", serde_json::to_string_pretty(&differences)?);
    } else {
        print!("{}", render(&differences, a, b));
    }
    Ok(if differences.is_empty() { Outcome::Success } else { Outcome::Differences })
}

fn render(differences: &DocumentDiff, a: &Path, b: &Path) -> String {
    if differences.is_empty() {
        return String::new();
    }
    let mut text = format!("--- {}\n+++ {}\n", a.display(), b.display());
    if let Some((old, new)) = differences.version_change {
        text += &format!("~ document Version: {old} → {new}\n");
    }
    if differences.paths_renamed > 0 {
        text += &format!("# {} forces' GeometryPath compared as `path`, the name OpenSim ≥ 4.5 reads them under\n", differences.paths_renamed);
    }
    for difference in &differences.differences {
        let line = match &difference.change {
            Change::Added { class } => format!("+ {} ({class})", difference.path),
            Change::Removed { class } => format!("- {} ({class})", difference.path),
            Change::PropertyAdded { value } => format!("+ {} = {value}", difference.path),
            Change::PropertyRemoved { value } => format!("- {} = {value}", difference.path),
            Change::Changed { old, new, relative_change } => {
                let relative = relative_change.map(|r| format!(" ({:+.4}%)", 100.0 * r)).unwrap_or_default();
                format!("~ {}: {old} → {new}{relative}", difference.path)
            }
        };
        text += &line;
        text.push('\n');
    }
    text
}
