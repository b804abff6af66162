//! Reading `.sto`/`.mot` text: OpenSim 4 headers and legacy SIMM motion headers.

use std::path::Path;

use super::StorageTable;
use crate::io::table::text::{decode, header_fields, is_blank, numbered_lines, parse_number, strip_bom};
use crate::io::table::TableError;

/// What one header line (after the name line) is.
#[derive(Debug, PartialEq)]
enum HeaderLine<'a> {
    /// `endheader`.
    End,
    /// `key=value` (key: a word without whitespace), both trimmed.
    Pair(&'a str, &'a str),
    /// Legacy `datarows N` / `datacolumns N`.
    Legacy(&'a str, &'a str),
    /// Anything else: free text.
    Comment,
}

/// A row or column count declared in the header, to be checked against the data.
struct Declared {
    key: String,
    count: usize,
    line: usize,
}

/// The header as read, up to and including `endheader`.
struct Header {
    name: String,
    in_degrees: Option<bool>,
    /// The `version` line's number (0 without one, or when it is not a number, as `atoi`).
    version: i64,
    metadata: Vec<(String, String)>,
    comments: Vec<String>,
    rows: Vec<Declared>,
    columns: Vec<Declared>,
    last_line: usize,
}

impl StorageTable {
    /// Parses `.sto`/`.mot` bytes, reporting non-UTF-8 input as an error naming `file`.
    pub fn from_bytes(bytes: &[u8], file: &Path) -> Result<Self, TableError> {
        Self::parse(&decode(bytes, file)?, file)
    }

    /// Parses `.sto`/`.mot` text; `file` names errors and, as in OpenSim, its extension bears on
    /// the angle unit.
    ///
    /// Accepts OpenSim 4 headers and legacy SIMM ones, tab- or space-separated values,
    /// `\r\n` line ends and blank lines between rows. `nRows`/`nColumns` (time counted) and
    /// their legacy forms are optional but must match the data when present. The angle unit is
    /// read as OpenSim's `Storage` reads it: `inDegrees`; in a file without a `version` line (or
    /// version 0), a SIMM header's `Angles are in degrees.` / `Angles are in radians.` line;
    /// else degrees for such a file named `.mot` (OpenSim: "Motion files from SIMM are in
    /// degrees", even over `inDegrees=no` — here a declaration is believed); else unknown.
    pub fn parse(text: &str, file: &Path) -> Result<Self, TableError> {
        let text = strip_bom(text);
        if is_blank(text) {
            return Err(TableError::Empty { file: file.to_path_buf() });
        }
        let mut lines = numbered_lines(text);
        let header = read_header(&mut lines, file)?;
        let labels = read_labels(&mut lines, header.last_line, file)?;
        check_declared(&header.columns, labels.len(), |declared| TableError::ColumnCountMismatch {
            file: file.to_path_buf(),
            line: declared.line,
            key: declared.key.clone(),
            declared: declared.count,
            found: labels.len(),
        })?;
        let values = read_rows(&mut lines, labels.len(), file)?;
        let n_rows = values.len() / labels.len();
        check_declared(&header.rows, n_rows, |declared| TableError::RowCountMismatch {
            file: file.to_path_buf(),
            line: declared.line,
            key: declared.key.clone(),
            declared: declared.count,
            found: n_rows,
        })?;
        let simm_motion = header.version < 1 && file.extension().is_some_and(|e| e.eq_ignore_ascii_case("mot"));
        Ok(StorageTable {
            name: header.name,
            in_degrees: header.in_degrees.or(simm_motion.then_some(true)),
            metadata: header.metadata,
            comments: header.comments,
            labels,
            values,
        })
    }
}

/// Whether `line` would be read as a free-text header line.
pub(super) fn is_comment(line: &str) -> bool {
    classify(line) == HeaderLine::Comment
}

/// Whether `key` is a legacy SIMM layout word (`datarows`, `datacolumns`).
pub(super) fn is_legacy_layout_key(key: &str) -> bool {
    matches!(key, "datarows" | "datacolumns")
}

/// Classifies a header line after the name line.
fn classify(line: &str) -> HeaderLine<'_> {
    let trimmed = line.trim();
    if trimmed == "endheader" {
        return HeaderLine::End;
    }
    if let Some((key, value)) = trimmed.split_once('=') {
        let key = key.trim();
        if !key.is_empty() && !key.contains(char::is_whitespace) {
            return HeaderLine::Pair(key, value.trim());
        }
    }
    let mut words = trimmed.split_whitespace();
    match (words.next(), words.next(), words.next()) {
        (Some(key), Some(value), None) if is_legacy_layout_key(key) => HeaderLine::Legacy(key, value),
        _ => HeaderLine::Comment,
    }
}

/// Reads the name line and the header through `endheader`.
fn read_header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    file: &Path,
) -> Result<Header, TableError> {
    let (first, name) = lines.next().map_or((1, ""), |(number, line)| (number, line.trim()));
    let mut header = Header {
        name: name.to_owned(),
        in_degrees: None,
        version: 0,
        metadata: Vec::new(),
        comments: Vec::new(),
        rows: Vec::new(),
        columns: Vec::new(),
        last_line: first,
    };
    for (number, line) in lines {
        header.last_line = number;
        match classify(line) {
            HeaderLine::End => return Ok(header),
            HeaderLine::Pair(key, value) => header.add_pair(key, value, number, file)?,
            HeaderLine::Legacy(key, value) => header.add_count(key, value, number, file)?,
            HeaderLine::Comment => header.add_comment(line),
        }
    }
    Err(TableError::MissingEndheader { file: file.to_path_buf(), line: header.last_line })
}

impl Header {
    /// Records a `key=value` line: layout keys are checked, others kept as metadata.
    fn add_pair(&mut self, key: &str, value: &str, line: usize, file: &Path) -> Result<(), TableError> {
        match key {
            "nRows" | "nColumns" => self.add_count(key, value, line, file)?,
            "inDegrees" => {
                self.in_degrees =
                    Some(parse_yes_no(value).ok_or_else(|| bad_value(key, value, "yes or no", line, file))?)
            }
            "version" => self.version = leading_integer(value),
            _ => self.metadata.push((key.to_owned(), value.to_owned())),
        }
        Ok(())
    }

    /// Keeps a free-text line; before any `version` line, SIMM's angle-unit sentence also
    /// declares the unit.
    fn add_comment(&mut self, line: &str) {
        if self.version == 0 {
            match line.trim() {
                "Angles are in degrees." => self.in_degrees = Some(true),
                "Angles are in radians." => self.in_degrees = Some(false),
                _ => {}
            }
        }
        self.comments.push(line.trim_end().to_owned());
    }

    /// Records a declared row (`nRows`, `datarows`) or column (`nColumns`, `datacolumns`) count.
    fn add_count(&mut self, key: &str, value: &str, line: usize, file: &Path) -> Result<(), TableError> {
        let count = value.parse().map_err(|_| bad_value(key, value, "a whole number", line, file))?;
        let declared = Declared { key: key.to_owned(), count, line };
        match key {
            "nRows" | "datarows" => self.rows.push(declared),
            _ => self.columns.push(declared),
        }
        Ok(())
    }
}

/// The integer `value` starts with, 0 if none (C's `atoi`, as OpenSim reads `version`).
fn leading_integer(value: &str) -> i64 {
    let value = value.trim_start();
    let sign_len = usize::from(value.starts_with(['-', '+']));
    let digits = value[sign_len..].find(|c: char| !c.is_ascii_digit()).map_or(value.len(), |end| sign_len + end);
    value[..digits].parse().unwrap_or(0)
}

/// `yes`/`no` (also `true`/`false`), any case.
fn parse_yes_no(value: &str) -> Option<bool> {
    match value.to_ascii_lowercase().as_str() {
        "yes" | "true" => Some(true),
        "no" | "false" => Some(false),
        _ => None,
    }
}

/// An error about a header value.
fn bad_value(key: &str, value: &str, expected: &'static str, line: usize, file: &Path) -> TableError {
    TableError::BadHeaderValue {
        file: file.to_path_buf(),
        line,
        key: key.to_owned(),
        value: value.to_owned(),
        expected,
    }
}

/// Reads the column label line, the first non-blank line after `endheader` (on `last_line`).
fn read_labels<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    last_line: usize,
    file: &Path,
) -> Result<Vec<String>, TableError> {
    let Some((number, line)) = lines.find(|(_, line)| !is_blank(line)) else {
        let expected = "a line of column labels (time first) after endheader";
        return Err(TableError::MissingHeaderLine { file: file.to_path_buf(), line: last_line, expected });
    };
    let labels: Vec<String> = header_fields(line).into_iter().map(str::to_owned).collect();
    if let Some(index) = labels.iter().position(String::is_empty) {
        return Err(TableError::EmptyLabel { file: file.to_path_buf(), line: number, position: index + 1 });
    }
    Ok(labels)
}

/// Reads the data rows (whitespace-separated, `width` fields each) into row-major values.
fn read_rows<'a>(
    lines: impl Iterator<Item = (usize, &'a str)>,
    width: usize,
    file: &Path,
) -> Result<Vec<f64>, TableError> {
    let mut values = Vec::new();
    for (number, line) in lines.filter(|(_, line)| !is_blank(line)) {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        if tokens.len() != width {
            return Err(TableError::RaggedRow {
                file: file.to_path_buf(),
                line: number,
                expected: width,
                found: tokens.len(),
            });
        }
        for token in tokens {
            let value = parse_number(token).ok_or_else(|| TableError::BadNumber {
                file: file.to_path_buf(),
                line: number,
                token: token.to_owned(),
                expected: "a number",
            })?;
            values.push(value);
        }
    }
    Ok(values)
}

/// Fails with `mismatch` for the first declaration whose count is not `actual`.
fn check_declared(
    declared: &[Declared],
    actual: usize,
    mismatch: impl Fn(&Declared) -> TableError,
) -> Result<(), TableError> {
    match declared.iter().find(|declared| declared.count != actual) {
        Some(wrong) => Err(mismatch(wrong)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OPENSIM4: &str = "Coordinates\nversion=1\nnRows=2\nnColumns=3\ninDegrees=yes\nDataType=double\n\n\
                            Units are S.I. units (second, meters, Newtons, ...)\nendheader\n\
                            time\tknee_angle_r\tpelvis_tx\n0\t90\t0.5\n0.01\t-45\t0.6\n";

    fn parse(text: &str) -> Result<StorageTable, TableError> {
        StorageTable::parse(text, Path::new("trial.sto"))
    }

    fn error(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_opensim4_header() {
        let table = parse(OPENSIM4).unwrap();
        assert_eq!(table.name(), "Coordinates");
        assert_eq!(table.in_degrees(), Some(true));
        assert_eq!(table.metadata(), [("DataType".to_owned(), "double".to_owned())]);
        assert_eq!(table.comments(), ["", "Units are S.I. units (second, meters, Newtons, ...)"]);
        assert_eq!(table.labels(), ["time", "knee_angle_r", "pelvis_tx"]);
        assert_eq!(table.values(), [0.0, 90.0, 0.5, 0.01, -45.0, 0.6]);
    }

    #[test]
    fn reads_legacy_simm_header() {
        let text = "first trial\nnRows=1\nnColumns=2\n\n# SIMM Motion File Header:\nname first trial\n\
                    datacolumns 2\ndatarows 1\notherdata 1\nrange 0.500000 0.500000\nendheader\n\
                    time\tknee\n      0.50000000000000000000\t      1.5\n";
        let table = parse(text).unwrap();
        assert_eq!(table.name(), "first trial");
        assert_eq!(table.in_degrees(), None);
        assert!(table.metadata().is_empty());
        assert_eq!(
            table.comments(),
            ["", "# SIMM Motion File Header:", "name first trial", "otherdata 1", "range 0.500000 0.500000"]
        );
        assert_eq!(table.values(), [0.5, 1.5]);
        let wrong = text.replace("datarows 1", "datarows 2");
        assert_eq!(
            error(&wrong),
            "trial.sto:8: datarows is 2 but the file has 1 data rows; expected them to agree"
        );
    }

    /// OpenSim's `Storage::parseHeaders` and its constructor decide the unit (opensim-core's
    /// runningModel kinematics is a `.sto` saying "Angles are in degrees." and nothing else).
    #[test]
    fn reads_the_angle_unit_as_opensim_storage() {
        let body = "endheader\ntime\tknee\n0\t1.5\n";
        let unit = |header: &str, name: &str| StorageTable::parse(&format!("q\n{header}{body}"), Path::new(name)).unwrap().in_degrees();
        assert_eq!(unit("Angles are in degrees.\n", "q.sto"), Some(true));
        assert_eq!(unit("  Angles are in radians.  \n", "q.mot"), Some(false));
        assert_eq!(unit("version=1\nAngles are in degrees.\n", "q.sto"), None, "after a version line it is a comment");
        assert_eq!(unit("version=0\nAngles are in degrees.\n", "q.sto"), Some(true));
        assert_eq!(unit("Angles are in degrees\n", "q.sto"), None, "only the exact sentence");
        assert_eq!(unit("", "q.sto"), None);
        assert_eq!(unit("", "q.MOT"), Some(true), "SIMM motions are in degrees");
        assert_eq!(unit("version=1\n", "q.mot"), None);
        assert_eq!(unit("version=x\n", "q.mot"), Some(true), "atoi reads 0");
        assert_eq!(unit("inDegrees=no\n", "q.mot"), Some(false), "a declaration is believed");
        assert_eq!(unit("inDegrees=no\nAngles are in degrees.\n", "q.sto"), Some(true), "the later line wins");
        let table = StorageTable::parse(&format!("q\nAngles are in degrees.\n{body}"), Path::new("q.sto")).unwrap();
        assert_eq!(table.comments(), ["Angles are in degrees."]);
    }

    #[test]
    fn leading_integers_read_as_atoi() {
        for (text, value) in [("1", 1), (" 20302", 20302), ("-3x", -3), ("+4", 4), ("x", 0), ("-", 0), ("", 0)] {
            assert_eq!(leading_integer(text), value, "{text:?}");
        }
    }

    #[test]
    fn accepts_crlf_padding_trailing_tabs_specials_and_optional_counts() {
        let text = "grf\t\t\r\nversion=1\t\t\r\nendheader\r\ntime\ta\t b \r\n  0  nan\t-inf\r\n1e-05 NaN 1E3\r\n\r\n\r\n";
        let table = parse(text).unwrap();
        assert_eq!(table.name(), "grf");
        assert_eq!(table.labels(), ["time", "a", "b"]);
        assert_eq!(table.n_rows(), 2);
        assert!(table.value(0, 1).unwrap().is_nan());
        assert_eq!(table.value(0, 2), Some(f64::NEG_INFINITY));
        assert_eq!(table.row(1).map(|row| [row[0], row[2]]), Some([1e-5, 1000.0]));
    }

    #[test]
    fn labels_split_on_tabs_keep_spaces() {
        let table = parse("t\nendheader\ntime\tknee angle\n0 1\n").unwrap();
        assert_eq!(table.labels(), ["time", "knee angle"]);
        let table = parse("t\nendheader\ntime knee\n0 1\n").unwrap();
        assert_eq!(table.labels(), ["time", "knee"]);
    }

    #[test]
    fn header_only_table_has_no_rows() {
        let table = parse("t\nnRows=0\nendheader\ntime\ta\n").unwrap();
        assert_eq!((table.n_rows(), table.n_columns()), (0, 2));
    }

    #[test]
    fn empty_file() {
        assert_eq!(error(""), "trial.sto:1: empty file; expected a table header");
        assert_eq!(error(" \n\t\r\n"), "trial.sto:1: empty file; expected a table header");
    }

    #[test]
    fn missing_endheader() {
        let message = error("Coordinates\nversion=1\nnRows=2\n");
        assert_eq!(message, "trial.sto:3: end of file inside the header; expected a line `endheader`");
    }

    #[test]
    fn missing_labels() {
        let message = error("Coordinates\nendheader\n\n");
        assert_eq!(message, "trial.sto:2: expected a line of column labels (time first) after endheader");
    }

    #[test]
    fn ragged_row() {
        let text = OPENSIM4.replace("0.01\t-45\t0.6", "0.01\t-45");
        assert_eq!(error(&text), "trial.sto:12: row has 2 fields; expected 3, one per column label");
        let text = OPENSIM4.replace("0\t90\t0.5", "0\t90\t0.5\t7");
        assert_eq!(error(&text), "trial.sto:11: row has 4 fields; expected 3, one per column label");
    }

    #[test]
    fn n_columns_disagrees_with_labels() {
        let text = OPENSIM4.replace("nColumns=3", "nColumns=2");
        let expected = "trial.sto:4: nColumns is 2 but the label line has 3 labels; expected them to agree (the time column counts)";
        assert_eq!(error(&text), expected);
    }

    #[test]
    fn n_rows_disagrees_with_data() {
        let text = OPENSIM4.replace("nRows=2", "nRows=3");
        assert_eq!(
            error(&text),
            "trial.sto:3: nRows is 3 but the file has 2 data rows; expected them to agree"
        );
    }

    #[test]
    fn unparsable_number_is_quoted() {
        let text = OPENSIM4.replace("-45", "-4,5");
        assert_eq!(error(&text), "trial.sto:12: `-4,5` is not a number");
    }

    #[test]
    fn empty_labels() {
        let text = OPENSIM4.replace("knee_angle_r\t", "\t\t");
        assert_eq!(error(&text), "trial.sto:10: column label 2 is empty; expected a name");
    }

    #[test]
    fn duplicate_labels_are_read_but_not_looked_up() {
        let table = parse(&OPENSIM4.replace("pelvis_tx", "knee_angle_r")).unwrap();
        assert_eq!(table.duplicate_labels(), ["knee_angle_r"]);
        assert_eq!(table.column_indices("knee_angle_r"), [1, 2]);
        assert_eq!(table.column_index("knee_angle_r"), None);
        assert_eq!(table.column("knee_angle_r"), None);
        assert_eq!(table.column_index("time"), Some(0));
    }

    #[test]
    fn bad_header_values() {
        let text = OPENSIM4.replace("nRows=2", "nRows=two");
        assert_eq!(error(&text), "trial.sto:3: nRows is `two`; expected a whole number");
        let text = OPENSIM4.replace("inDegrees=yes", "inDegrees=maybe");
        assert_eq!(error(&text), "trial.sto:5: inDegrees is `maybe`; expected yes or no");
    }

    #[test]
    fn stray_bytes_read_as_replacement_characters_and_nul_is_binary() {
        let mut bytes = OPENSIM4.as_bytes().to_vec();
        bytes.extend_from_slice(b"\xc3\x28 1 2\n");
        let message = StorageTable::from_bytes(&bytes, Path::new("trial.sto")).unwrap_err().to_string();
        assert_eq!(message, "trial.sto:13: `\u{fffd}(` is not a number");
        let bytes = OPENSIM4.replace("nRows=2", "nRows=\u{0}").into_bytes();
        let message = StorageTable::from_bytes(&bytes, Path::new("trial.sto")).unwrap_err().to_string();
        assert_eq!(message, "trial.sto:3: binary data (a NUL byte); expected a text table");
    }

    #[test]
    fn classifies_header_lines() {
        assert_eq!(classify("  endheader \r"), HeaderLine::End);
        assert_eq!(classify("nRows = 5\t\t"), HeaderLine::Pair("nRows", "5"));
        assert_eq!(classify("datarows 211"), HeaderLine::Legacy("datarows", "211"));
        assert_eq!(classify("a sentence with = sign"), HeaderLine::Comment);
        assert_eq!(classify("datarows 2 3"), HeaderLine::Comment);
    }
}
