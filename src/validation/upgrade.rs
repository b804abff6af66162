//! A converted 2.x/3.x model against OpenSim's own conversion of it: every component and value
//! the conversion writes must be one OpenSim writes.

use crate::io::osim::OsimDocument;
use crate::review::{flatten, flatten_for_comparison, FlatEntry};

/// Each component or property of `ours` (our conversion) that OpenSim's printed conversion
/// `opensim` lacks or writes differently, as `path: ours vs OpenSim's`; numbers compare as
/// doubles, socket paths in their absolute form (OpenSim writes a freshly converted offset
/// frame's `../../../bodyset/…` until it builds the model), and a 4.0 document's unnamed
/// `GeometryPath` as the `path` OpenSim ≥ 4.5 names it.
pub fn conversion_mismatches(opensim: &OsimDocument, ours: &OsimDocument) -> Vec<String> {
    let expected = flatten(opensim);
    let (ours, _) = flatten_for_comparison(ours, opensim.version.number);
    let mut mismatches = Vec::new();
    for (path, entry) in &ours.entries {
        let same = match (entry, expected.get(path)) {
            (FlatEntry::Component { class }, Some(FlatEntry::Component { class: theirs })) => class == theirs,
            (FlatEntry::Property { value }, Some(FlatEntry::Property { value: theirs })) => same_value(value, theirs),
            _ => false,
        };
        if !same {
            mismatches.push(format!("{path}: {entry:?} vs {:?}", expected.get(path)));
        }
    }
    mismatches
}

/// Equal text up to whitespace, numbers equal as doubles, relative socket paths as absolute.
fn same_value(ours: &str, theirs: &str) -> bool {
    let theirs = theirs.trim().replace("../../../", "/");
    let (a, b): (Vec<&str>, Vec<&str>) = (ours.split_whitespace().collect(), theirs.split_whitespace().collect());
    a.len() == b.len() && a.iter().zip(&b).all(|(x, y)| x == y || matches!((x.parse::<f64>(), y.parse::<f64>()), (Ok(p), Ok(q)) if p == q))
}
