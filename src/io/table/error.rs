//! Why a table could not be read, built or converted.
//!
//! Errors about a file name the file and its 1-based line number (`file:line: ...`) and say
//! what was expected there.

use std::path::PathBuf;

/// Everything that can go wrong with a table.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// The file could not be read at all.
    #[error("{}: cannot read: {source}", file.display())]
    Io { file: PathBuf, source: std::io::Error },
    /// The file holds binary data (a NUL byte).
    #[error("{}:{line}: binary data (a NUL byte); expected a text table", file.display())]
    Binary { file: PathBuf, line: usize },
    /// The file holds nothing but whitespace.
    #[error("{}:1: empty file; expected a table header", file.display())]
    Empty { file: PathBuf },
    /// A `.sto`/`.mot` header never reaches its `endheader` line.
    #[error("{}:{line}: end of file inside the header; expected a line `endheader`", file.display())]
    MissingEndheader { file: PathBuf, line: usize },
    /// A required header line is absent or does not start as it should.
    #[error("{}:{line}: expected {expected}", file.display())]
    MissingHeaderLine { file: PathBuf, line: usize, expected: &'static str },
    /// A header field has a value of the wrong kind.
    #[error("{}:{line}: {key} is `{value}`; expected {expected}", file.display())]
    BadHeaderValue { file: PathBuf, line: usize, key: String, value: String, expected: &'static str },
    /// A required `.trc` header field is absent.
    #[error("{}:{line}: no value for {key}; expected it among the header fields", file.display())]
    MissingField { file: PathBuf, line: usize, key: &'static str },
    /// The `.trc` Units field is not `mm`, `cm` or `m`.
    #[error("{}:{line}: unknown Units `{units}`; expected mm, cm or m", file.display())]
    UnknownUnits { file: PathBuf, line: usize, units: String },
    /// The declared number of columns (`nColumns`/`datacolumns`, time included) disagrees
    /// with the label line.
    #[error(
        "{}:{line}: {key} is {declared} but the label line has {found} labels; expected them to agree (the time column counts)",
        file.display()
    )]
    ColumnCountMismatch { file: PathBuf, line: usize, key: String, declared: usize, found: usize },
    /// The declared number of rows (`nRows`/`datarows`/`NumFrames`) disagrees with the data.
    #[error(
        "{}:{line}: {key} is {declared} but the file has {found} data rows; expected them to agree",
        file.display()
    )]
    RowCountMismatch { file: PathBuf, line: usize, key: String, declared: usize, found: usize },
    /// `NumMarkers` disagrees with the marker names on the name line.
    #[error(
        "{}:{line}: NumMarkers is {declared} but the name line lists {found} markers; expected them to agree",
        file.display()
    )]
    MarkerCountMismatch { file: PathBuf, line: usize, declared: usize, found: usize },
    /// The `X1 Y1 Z1 ...` line does not have three axis labels per marker.
    #[error("{}:{line}: found axis labels `{found}`; expected X, Y, Z for each of {markers} markers", file.display())]
    AxisLabels { file: PathBuf, line: usize, markers: usize, found: String },
    /// A column label is empty.
    #[error("{}:{line}: column label {position} is empty; expected a name", file.display())]
    EmptyLabel { file: PathBuf, line: usize, position: usize },
    /// Two markers share a name.
    #[error("{}:{line}: duplicate marker name `{name}`; expected unique names", file.display())]
    DuplicateMarker { file: PathBuf, line: usize, name: String },
    /// A data row has a different number of fields than there are labels.
    #[error("{}:{line}: row has {found} fields; expected {expected}, one per column label", file.display())]
    RaggedRow { file: PathBuf, line: usize, expected: usize, found: usize },
    /// A `.trc` data row has more fields than frame, time and three per marker.
    #[error("{}:{line}: row has {found} fields; expected at most {expected} (frame, time, X/Y/Z per marker)", file.display())]
    TooManyFields { file: PathBuf, line: usize, expected: usize, found: usize },
    /// A `.trc` data row has fewer than its frame number and time.
    #[error("{}:{line}: row has {found} fields; expected at least the frame number and the time", file.display())]
    ShortRow { file: PathBuf, line: usize, found: usize },
    /// A marker has only one or two of its X/Y/Z coordinates in a frame.
    #[error("{}:{line}: marker `{marker}` has only some of X, Y, Z; expected all three or none", file.display())]
    PartialMarker { file: PathBuf, line: usize, marker: String },
    /// A field that should be a number is not.
    #[error("{}:{line}: `{token}` is not {expected}", file.display())]
    BadNumber { file: PathBuf, line: usize, token: String, expected: &'static str },
    /// A table built in memory has inconsistent parts.
    #[error("invalid table: {problem}")]
    Shape { problem: String },
    /// Angle conversion was asked of a table whose angle unit is not declared.
    #[error("table `{table}` does not declare inDegrees; state the angle unit (with_in_degrees) before converting")]
    UnknownAngleUnit { table: String },
    /// Angle conversion was asked of a table in the other unit.
    #[error("table `{table}` is in {actual}; expected {expected} for this conversion")]
    WrongAngleUnit { table: String, expected: &'static str, actual: &'static str },
}
