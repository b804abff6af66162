//! OpenSim "Storage" tables (`.sto`, `.mot`): a time column followed by named data columns.

mod parse;

use std::borrow::Cow;
use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use super::text::{format_number, read_text};
use super::TableError;

/// Header keys that describe the layout; they are regenerated on write, never kept as
/// metadata (`datarows`/`datacolumns` are their legacy SIMM spellings).
const LAYOUT_KEYS: [&str; 4] = ["version", "nRows", "nColumns", "inDegrees"];

/// An OpenSim `.sto`/`.mot` table, lossless in values and header text.
///
/// - `labels` start with the time column (normally `time`); `n_columns` counts it, as the
///   file's `nColumns` does. Time is in seconds.
/// - Values are row-major: the value of row `r`, column `c` is `values[r * n_columns + c]`.
/// - Angle units: `in_degrees` is `Some(true)` when rotational columns are in degrees,
///   `Some(false)` when in radians, and `None` when the file does not say (see
///   [`StorageTable::parse`] for what says; OpenSim then reads radians, and
///   [`StorageTable::with_in_degrees`] declares it). Other columns are in the units the file uses
///   (OpenSim: SI — metres, newtons, newton-metres).
/// - Labels read from a file may repeat (OpenSim's legacy IK output repeats the ground-force
///   labels of both feet); label lookups then refuse to guess, see
///   [`StorageTable::column_index`]. Tables built with [`StorageTable::new`] need unique labels.
/// - `metadata` holds the header's `key=value` lines in order, except `version`, `nRows`,
///   `nColumns`, `inDegrees` (and legacy `datarows`/`datacolumns`), which are regenerated on
///   write. `comments` holds the header's other lines (blank ones included) in order.
#[derive(Debug, Clone, PartialEq)]
pub struct StorageTable {
    name: String,
    in_degrees: Option<bool>,
    metadata: Vec<(String, String)>,
    comments: Vec<String>,
    labels: Vec<String>,
    values: Vec<f64>,
}

impl StorageTable {
    /// A table named `name` with column `labels` (time first) and row-major `values`, whose
    /// length must be a multiple of the number of labels. The angle unit is unknown.
    pub fn new(name: &str, labels: Vec<String>, values: Vec<f64>) -> Result<Self, TableError> {
        check_single_line("table name", name)?;
        check_labels(&labels)?;
        if !values.len().is_multiple_of(labels.len()) {
            return Err(shape(format!(
                "{} values do not fill whole rows of {} columns",
                values.len(),
                labels.len()
            )));
        }
        let name = name.trim().to_owned();
        Ok(StorageTable {
            name,
            in_degrees: None,
            metadata: Vec::new(),
            comments: Vec::new(),
            labels,
            values,
        })
    }

    /// Reads a `.sto`/`.mot` file.
    pub fn read(path: &Path) -> Result<Self, TableError> {
        Self::parse(&read_text(path)?, path)
    }

    /// This table with its angle unit declared (degrees when `in_degrees`), without
    /// converting any value: for files that do not say, the caller decides.
    pub fn with_in_degrees(mut self, in_degrees: bool) -> Self {
        self.in_degrees = Some(in_degrees);
        self
    }

    /// This table with a `key=value` header line appended. The key must be a word without
    /// `=` and not a layout key (`version`, `nRows`, `nColumns`, `inDegrees`).
    pub fn with_metadata(mut self, key: &str, value: &str) -> Result<Self, TableError> {
        let bad_key = key.is_empty() || key.contains(|c: char| c == '=' || c.is_whitespace());
        if bad_key || LAYOUT_KEYS.contains(&key) || parse::is_legacy_layout_key(key) {
            return Err(shape(format!("`{key}` cannot be a metadata key")));
        }
        check_single_line("metadata value", value)?;
        self.metadata.push((key.to_owned(), value.trim().to_owned()));
        Ok(self)
    }

    /// This table with a free-text header line appended; it must not read as a header field
    /// (`key=value`, `endheader`, `datarows N`, `datacolumns N`).
    pub fn with_comment(mut self, line: &str) -> Result<Self, TableError> {
        check_single_line("comment", line)?;
        if !parse::is_comment(line) {
            return Err(shape(format!("`{line}` would be read back as a header field, not a comment")));
        }
        self.comments.push(line.trim_end().to_owned());
        Ok(self)
    }

    /// The table's name (first header line).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// `Some(true)` if rotational columns are in degrees, `Some(false)` if in radians, `None`
    /// if the file did not say.
    pub fn in_degrees(&self) -> Option<bool> {
        self.in_degrees
    }

    /// The header's `key=value` lines in file order (layout keys excluded).
    pub fn metadata(&self) -> &[(String, String)] {
        &self.metadata
    }

    /// The value of the first metadata line with `key`.
    pub fn metadata_value(&self, key: &str) -> Option<&str> {
        self.metadata.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// The header's free-text lines in file order.
    pub fn comments(&self) -> &[String] {
        &self.comments
    }

    /// Column labels, time first.
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// All values, row-major.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Number of data rows.
    pub fn n_rows(&self) -> usize {
        self.values.len() / self.labels.len()
    }

    /// Number of columns, the time column included.
    pub fn n_columns(&self) -> usize {
        self.labels.len()
    }

    /// Index of the one column labelled `label` (time is 0); `None` if no column, or several
    /// columns, have that label (see [`StorageTable::column_indices`]).
    pub fn column_index(&self, label: &str) -> Option<usize> {
        match self.column_indices(label)[..] {
            [index] => Some(index),
            _ => None,
        }
    }

    /// Indices of every column labelled `label`, in order.
    pub fn column_indices(&self, label: &str) -> Vec<usize> {
        self.labels.iter().enumerate().filter(|(_, l)| *l == label).map(|(index, _)| index).collect()
    }

    /// Labels shared by several columns, each once, in order of first appearance.
    pub fn duplicate_labels(&self) -> Vec<&str> {
        let mut seen = HashSet::new();
        let mut duplicates = Vec::new();
        for label in &self.labels {
            if !seen.insert(label.as_str()) && !duplicates.contains(&label.as_str()) {
                duplicates.push(label.as_str());
            }
        }
        duplicates
    }

    /// The values of the one column labelled `label` (see [`StorageTable::column_index`]),
    /// top to bottom.
    pub fn column(&self, label: &str) -> Option<Vec<f64>> {
        self.column_index(label).map(|index| self.column_at(index))
    }

    /// The table as OpenSim's `Storage` holds a file it reads: a row at the time of the row
    /// before it replaces that row (`Storage::append`), so a repeated last row — OpenSim's own
    /// tools write some — counts once, with the later values. Borrowed when no time repeats.
    pub fn with_repeated_times_replaced(&self) -> Cow<'_, StorageTable> {
        let rows: Vec<&[f64]> = self.rows().collect();
        if rows.windows(2).all(|pair| pair[0][0] != pair[1][0]) {
            return Cow::Borrowed(self);
        }
        let kept = (0..rows.len()).filter(|&i| i + 1 == rows.len() || rows[i + 1][0] != rows[i][0]);
        Cow::Owned(StorageTable { values: kept.flat_map(|i| rows[i].iter().copied()).collect(), ..self.clone() })
    }

    /// The times of the rows, in seconds (column 0).
    pub fn times(&self) -> Vec<f64> {
        self.column_at(0)
    }

    /// Row `index`, time first.
    pub fn row(&self, index: usize) -> Option<&[f64]> {
        self.rows().nth(index)
    }

    /// The rows, top to bottom, each time first.
    pub fn rows(&self) -> impl Iterator<Item = &[f64]> {
        self.values.chunks_exact(self.n_columns())
    }

    /// The value at `row`, `column`.
    pub fn value(&self, row: usize, column: usize) -> Option<f64> {
        self.row(row)?.get(column).copied()
    }

    /// The file text in OpenSim 4 layout: name, `version=1`, `nRows`, `nColumns`,
    /// `inDegrees` (when known), metadata, comments, `endheader`, tab-separated labels and
    /// rows. Numbers are written so they read back bit-exactly (NaN as `NaN`).
    pub fn to_text(&self) -> String {
        let mut text = String::new();
        let _ = writeln!(text, "{}\nversion=1", self.name);
        let _ = writeln!(text, "nRows={}\nnColumns={}", self.n_rows(), self.n_columns());
        if let Some(in_degrees) = self.in_degrees {
            let _ = writeln!(text, "inDegrees={}", if in_degrees { "yes" } else { "no" });
        }
        for (key, value) in &self.metadata {
            let _ = writeln!(text, "{key}={value}");
        }
        for comment in &self.comments {
            let _ = writeln!(text, "{comment}");
        }
        text.push_str("endheader\n");
        text.push_str(&self.labels.join("\t"));
        text.push('\n');
        for row in self.rows() {
            let fields: Vec<String> = row.iter().map(|&value| format_number(value)).collect();
            text.push_str(&fields.join("\t"));
            text.push('\n');
        }
        text
    }

    /// A copy with the columns selected by `is_rotational` (given each label; time is never
    /// selected) converted from degrees to radians, and `in_degrees` set to `Some(false)`.
    /// Fails unless the table is declared in degrees.
    pub fn to_radians(&self, is_rotational: impl Fn(&str) -> bool) -> Result<StorageTable, TableError> {
        self.require_in_degrees(true)?;
        Ok(self.map_rotational(is_rotational, f64::to_radians, false))
    }

    /// A copy with the columns selected by `is_rotational` (time never) converted from radians
    /// to degrees, and `in_degrees` set to `Some(true)`. Fails unless the table is declared in
    /// radians.
    pub fn to_degrees(&self, is_rotational: impl Fn(&str) -> bool) -> Result<StorageTable, TableError> {
        self.require_in_degrees(false)?;
        Ok(self.map_rotational(is_rotational, f64::to_degrees, true))
    }

    /// Fails unless `in_degrees` is declared and equals `expected`.
    fn require_in_degrees(&self, expected: bool) -> Result<(), TableError> {
        let unit = |degrees: bool| if degrees { "degrees" } else { "radians" };
        match self.in_degrees {
            None => Err(TableError::UnknownAngleUnit { table: self.name.clone() }),
            Some(actual) if actual != expected => Err(TableError::WrongAngleUnit {
                table: self.name.clone(),
                expected: unit(expected),
                actual: unit(actual),
            }),
            Some(_) => Ok(()),
        }
    }

    /// A copy with `convert` applied to the selected non-time columns.
    fn map_rotational(
        &self,
        is_rotational: impl Fn(&str) -> bool,
        convert: fn(f64) -> f64,
        in_degrees: bool,
    ) -> Self {
        let selected: Vec<bool> =
            self.labels.iter().enumerate().map(|(index, label)| index > 0 && is_rotational(label)).collect();
        let mut converted = self.clone();
        for (index, value) in converted.values.iter_mut().enumerate() {
            if selected[index % selected.len()] {
                *value = convert(*value);
            }
        }
        converted.in_degrees = Some(in_degrees);
        converted
    }

    /// The values of column `index`, top to bottom.
    fn column_at(&self, index: usize) -> Vec<f64> {
        self.rows().filter_map(|row| row.get(index).copied()).collect()
    }
}

/// An error about a table built in memory.
fn shape(problem: String) -> TableError {
    TableError::Shape { problem }
}

/// Fails if `text` spans several lines.
fn check_single_line(what: &str, text: &str) -> Result<(), TableError> {
    if text.contains(['\n', '\r']) {
        return Err(shape(format!("{what} `{}` contains a line break", text.escape_debug())));
    }
    Ok(())
}

/// Checks that `labels` can be written as a label line and read back unchanged: at least the
/// time column, each non-empty, unique, without tabs or line breaks or surrounding whitespace
/// (and without any whitespace when it is the only label).
fn check_labels(labels: &[String]) -> Result<(), TableError> {
    if labels.is_empty() {
        return Err(shape("a table needs at least the time column".to_owned()));
    }
    let mut seen = HashSet::new();
    for label in labels {
        let lone_with_space = labels.len() == 1 && label.contains(char::is_whitespace);
        if label.is_empty() || label.trim() != label || label.contains(['\t', '\n', '\r']) || lone_with_space
        {
            return Err(shape(format!(
                "column label `{}` cannot be written to a label line",
                label.escape_debug()
            )));
        }
        if !seen.insert(label.as_str()) {
            return Err(shape(format!("duplicate column label `{label}`")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(names: &[&str]) -> Vec<String> {
        names.iter().map(|name| name.to_string()).collect()
    }

    fn knee_table() -> StorageTable {
        let values = vec![0.0, 90.0, 0.5, 0.01, -45.0, 0.6];
        StorageTable::new("Coordinates", labels(&["time", "knee_angle_r", "pelvis_tx"]), values).unwrap()
    }

    #[test]
    fn a_repeated_time_keeps_its_later_row_as_opensims_storage_reads_it() {
        // opensim-core's gait10dof18musc RRA kinematics end with their last row twice.
        let values = vec![0.0, 1.0, 0.1, 2.0, 0.1, 3.0, 0.1, 4.0, 0.2, 5.0, 0.2, 6.0];
        let table = StorageTable::new("q", labels(&["time", "a"]), values).unwrap();
        let read = table.with_repeated_times_replaced();
        assert_eq!((read.times(), read.column("a")), (vec![0.0, 0.1, 0.2], Some(vec![1.0, 4.0, 6.0])));
        assert!(matches!(knee_table().with_repeated_times_replaced(), Cow::Borrowed(table) if *table == knee_table()));
    }

    #[test]
    fn shape_and_column_access() {
        let table = knee_table();
        assert_eq!((table.n_rows(), table.n_columns()), (2, 3));
        assert_eq!(table.times(), vec![0.0, 0.01]);
        assert_eq!(table.column("pelvis_tx"), Some(vec![0.5, 0.6]));
        assert_eq!(table.column_index("knee_angle_r"), Some(1));
        assert_eq!(table.column("missing"), None);
        assert_eq!(table.row(1), Some(&[0.01, -45.0, 0.6][..]));
        assert_eq!(table.row(2), None);
        assert_eq!(table.value(1, 1), Some(-45.0));
        assert_eq!(table.value(0, 3), None);
        assert_eq!(table.value(usize::MAX, 1), None);
    }

    #[test]
    fn new_rejects_bad_shapes_and_labels() {
        let partial_row = StorageTable::new("t", labels(&["time", "a"]), vec![0.0, 1.0, 2.0]);
        assert!(partial_row.unwrap_err().to_string().contains("whole rows of 2 columns"));
        assert!(StorageTable::new("t", Vec::new(), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["time", "a", "a"]), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["time", "a\tb"]), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["time", " a"]), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["my time"]), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["time", ""]), Vec::new()).is_err());
        assert!(StorageTable::new("two\nlines", labels(&["time"]), Vec::new()).is_err());
        assert!(StorageTable::new("t", labels(&["time", "a b"]), Vec::new()).is_ok());
    }

    #[test]
    fn metadata_and_comments_are_checked() {
        let table = knee_table();
        assert!(table.clone().with_metadata("nRows", "3").is_err());
        assert!(table.clone().with_metadata("datarows", "3").is_err());
        assert!(table.clone().with_metadata("two words", "3").is_err());
        assert!(table.clone().with_metadata("k", "a\nb").is_err());
        assert!(table.clone().with_comment("a=b").is_err());
        assert!(table.clone().with_comment("endheader").is_err());
        let table = table.with_metadata("DataType", "double").unwrap().with_comment("Units are SI").unwrap();
        assert_eq!(table.metadata_value("DataType"), Some("double"));
        assert_eq!(table.comments(), ["Units are SI"]);
    }

    #[test]
    fn writes_opensim4_layout() {
        let table = knee_table().with_in_degrees(true).with_metadata("DataType", "double").unwrap();
        let expected = "Coordinates\nversion=1\nnRows=2\nnColumns=3\ninDegrees=yes\nDataType=double\n\
                        endheader\ntime\tknee_angle_r\tpelvis_tx\n0\t90\t0.5\n0.01\t-45\t0.6\n";
        assert_eq!(table.to_text(), expected);
        assert!(!knee_table().to_text().contains("inDegrees"));
    }

    #[test]
    fn converts_only_rotational_columns() {
        let table = knee_table().with_in_degrees(true);
        let radians = table.to_radians(|label| label.contains("angle")).unwrap();
        assert_eq!(radians.in_degrees(), Some(false));
        assert_eq!(radians.column("knee_angle_r"), Some(vec![90f64.to_radians(), (-45f64).to_radians()]));
        assert_eq!(radians.column("pelvis_tx"), table.column("pelvis_tx"));
        assert_eq!(radians.times(), table.times());
        let degrees = radians.to_degrees(|label| label.contains("angle")).unwrap();
        assert_eq!(degrees.in_degrees(), Some(true));
        assert!((degrees.value(0, 1).unwrap() - 90.0).abs() < 1e-12);
    }

    #[test]
    fn time_is_never_converted() {
        let table = knee_table().with_in_degrees(true);
        let radians = table.to_radians(|_| true).unwrap();
        assert_eq!(radians.times(), table.times());
        assert_eq!(radians.column("pelvis_tx"), Some(vec![0.5f64.to_radians(), 0.6f64.to_radians()]));
    }

    #[test]
    fn conversion_needs_a_declared_matching_unit() {
        let unknown = knee_table().to_radians(|_| true).unwrap_err();
        assert!(matches!(unknown, TableError::UnknownAngleUnit { .. }), "{unknown}");
        assert!(unknown.to_string().contains("with_in_degrees"));
        let wrong = knee_table().with_in_degrees(false).to_radians(|_| true).unwrap_err();
        assert_eq!(
            wrong.to_string(),
            "table `Coordinates` is in radians; expected degrees for this conversion"
        );
        assert!(knee_table().with_in_degrees(true).to_degrees(|_| true).is_err());
    }
}
