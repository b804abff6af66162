//! Semantic diff: added and removed components, changed property values (numbers compared as
//! numbers, text with whitespace folded), with the relative change of numbers.

use serde::Serialize;

use super::flatten::{flatten_for_comparison, FlatDocument, FlatEntry};
use crate::io::osim::OsimDocument;

/// What happened at one path.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Change {
    /// A component present only in the second document (its contents are not listed).
    Added { class: String },
    /// A component present only in the first document.
    Removed { class: String },
    /// A property present only in the second document.
    PropertyAdded { value: String },
    /// A property present only in the first document.
    PropertyRemoved { value: String },
    /// A property whose value differs; `relative_change` is the largest |new − old| / |old| over
    /// the numbers of the value, when both values are lists of the same count of numbers.
    Changed { old: String, new: String, relative_change: Option<f64> },
}

/// One difference, at a canonical component path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Difference {
    pub path: String,
    #[serde(flatten)]
    pub change: Change,
}

/// All differences between two documents, in document order (removals first).
#[derive(Debug, Clone, Serialize)]
pub struct DocumentDiff {
    pub version_change: Option<(u32, u32)>,
    /// Forces' `GeometryPath`s of the older document compared under the name OpenSim ≥ 4.5 gives
    /// them, `path` (0 when the versions do not straddle 40500).
    pub paths_renamed: usize,
    pub differences: Vec<Difference>,
}

impl DocumentDiff {
    pub fn is_empty(&self) -> bool {
        self.version_change.is_none() && self.differences.is_empty()
    }
}

/// When two numbers count as equal: |a − b| ≤ max(`relative`·max(|a|, |b|), `absolute`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    pub relative: f64,
    pub absolute: f64,
}

/// Compares `a` with `b`, each read as OpenSim reads it for the other's version (forces' paths
/// renamed across 4.5). Numbers are equal when |a − b| ≤ `relative_tolerance`·max(|a|, |b|)
/// (0 compares values exactly, so `0.1` equals `1.0e-01`); NaN equals NaN.
pub fn diff(a: &OsimDocument, b: &OsimDocument, relative_tolerance: f64) -> DocumentDiff {
    diff_within(a, b, Tolerance { relative: relative_tolerance, absolute: 0.0 })
}

/// [`diff`] with an absolute floor under the relative tolerance (for values near zero).
pub fn diff_within(a: &OsimDocument, b: &OsimDocument, tolerance: Tolerance) -> DocumentDiff {
    let ((flat_a, renamed_a), (flat_b, renamed_b)) = (flatten_for_comparison(a, b.version.number), flatten_for_comparison(b, a.version.number));
    let differences = diff_flat(&flat_a, &flat_b, tolerance);
    let version_change = (a.version.number != b.version.number).then_some((a.version.number, b.version.number));
    DocumentDiff { version_change, paths_renamed: renamed_a + renamed_b, differences }
}

/// The differences between two flattened documents.
pub fn diff_flat(flat_a: &FlatDocument, flat_b: &FlatDocument, tolerance: Tolerance) -> Vec<Difference> {
    let mut differences = removed_entries(flat_a, flat_b);
    for (path, entry_b) in &flat_b.entries {
        let change = match (flat_a.get(path), entry_b) {
            (None, _) if has_ancestor_in(path, flat_b, flat_a) => continue,
            (None, FlatEntry::Component { class }) => Change::Added { class: class.clone() },
            (None, FlatEntry::Property { value }) => Change::PropertyAdded { value: value.clone() },
            (Some(entry_a), _) => match compare(entry_a, entry_b, tolerance) {
                Some(change) => change,
                None => continue,
            },
        };
        differences.push(Difference { path: path.clone(), change });
    }
    differences
}

/// Entries of `a` missing from `b`, topmost only.
fn removed_entries(a: &FlatDocument, b: &FlatDocument) -> Vec<Difference> {
    a.entries
        .iter()
        .filter(|(path, _)| b.get(path).is_none() && !has_ancestor_in(path, a, b))
        .map(|(path, entry)| {
            let change = match entry {
                FlatEntry::Component { class } => Change::Removed { class: class.clone() },
                FlatEntry::Property { value } => Change::PropertyRemoved { value: value.clone() },
            };
            Difference { path: path.clone(), change }
        })
        .collect()
}

/// Whether some proper ancestor of `path` (present in `own`) is missing from `other`.
fn has_ancestor_in(path: &str, own: &FlatDocument, other: &FlatDocument) -> bool {
    let mut prefix = path;
    while let Some(cut) = prefix.rfind(['/', '@']) {
        prefix = &prefix[..cut];
        if prefix.is_empty() {
            return false;
        }
        if own.get(prefix).is_some() && other.get(prefix).is_none() {
            return true;
        }
    }
    false
}

fn compare(a: &FlatEntry, b: &FlatEntry, tolerance: Tolerance) -> Option<Change> {
    match (a, b) {
        (FlatEntry::Property { value: old }, FlatEntry::Property { value: new }) => {
            compare_values(old, new, tolerance)
        }
        (FlatEntry::Component { class: old }, FlatEntry::Component { class: new }) if old == new => None,
        _ => Some(Change::Changed { old: describe(a), new: describe(b), relative_change: None }),
    }
}

fn describe(entry: &FlatEntry) -> String {
    match entry {
        FlatEntry::Component { class } => format!("<{class}>"),
        FlatEntry::Property { value } => value.clone(),
    }
}

fn compare_values(old: &str, new: &str, tolerance: Tolerance) -> Option<Change> {
    let changed = |relative_change| Some(Change::Changed { old: old.trim().into(), new: new.trim().into(), relative_change });
    match (numbers(old), numbers(new)) {
        (Some(a), Some(b)) if a.len() == b.len() => {
            let equal = a.iter().zip(&b).all(|(&x, &y)| numbers_equal(x, y, tolerance));
            if equal {
                None
            } else {
                changed(largest_relative_change(&a, &b))
            }
        }
        _ if old.split_whitespace().eq(new.split_whitespace()) => None,
        _ => changed(None),
    }
}

fn numbers(value: &str) -> Option<Vec<f64>> {
    let tokens: Vec<&str> = value.split_whitespace().collect();
    if tokens.is_empty() {
        return None;
    }
    tokens.iter().map(|t| t.parse().ok()).collect()
}

fn numbers_equal(a: f64, b: f64, tolerance: Tolerance) -> bool {
    a == b || (a.is_nan() && b.is_nan()) || (a - b).abs() <= (tolerance.relative * a.abs().max(b.abs())).max(tolerance.absolute)
}

/// max |b − a| / |a| over components with a ≠ 0; `None` when every changed component had a = 0.
fn largest_relative_change(a: &[f64], b: &[f64]) -> Option<f64> {
    a.iter()
        .zip(b)
        .filter(|(&x, &y)| x != 0.0 && x != y)
        .map(|(&x, &y)| (y - x) / x.abs())
        .max_by(|p, q| p.abs().total_cmp(&q.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXACT: Tolerance = Tolerance { relative: 0.0, absolute: 0.0 };

    fn relative(relative: f64) -> Tolerance {
        Tolerance { relative, absolute: 0.0 }
    }

    #[test]
    fn number_spelling_and_whitespace_do_not_count() {
        assert_eq!(compare_values("0.1", " 1.0e-01 ", EXACT), None);
        assert_eq!(compare_values("1 2  3", "1.0 2.0 3.0", EXACT), None);
        assert_eq!(compare_values("a  b", "a b", EXACT), None);
    }

    #[test]
    fn relative_change_is_signed_and_largest() {
        let change = compare_values("0.16 1", "0.17 1", EXACT).unwrap();
        let Change::Changed { relative_change: Some(r), .. } = change else { panic!("{change:?}") };
        assert!((r - 0.0625).abs() < 1e-12);
        let shrink = largest_relative_change(&[2.0, 1.0], &[1.0, 1.1]).unwrap();
        assert!((shrink + 0.5).abs() < 1e-12);
    }

    #[test]
    fn tolerance_hides_small_changes() {
        assert!(compare_values("1.0", "1.0000001", relative(1e-6)).is_none());
        assert!(compare_values("1.0", "1.0000001", relative(1e-9)).is_some());
    }
}
