//! Reading `.trc` text.

use std::collections::HashSet;
use std::path::Path;

use super::{MarkerTable, TrcHeader};
use crate::io::table::text::{decode, header_fields, is_blank, numbered_lines, parse_number, strip_bom};
use crate::io::table::{LengthUnit, TableError};

/// The header fields this reader knows; others are kept as [`TrcHeader::extra`].
const KNOWN_FIELDS: [&str; 8] = [
    "DataRate",
    "CameraRate",
    "NumFrames",
    "NumMarkers",
    "Units",
    "OrigDataRate",
    "OrigDataStartFrame",
    "OrigNumFrames",
];

/// The header as read from the field-name and value lines.
struct Fields {
    header: TrcHeader,
    num_frames: usize,
    num_markers: usize,
}

/// The field-name line (`names_line`) and the value line paired up, with the value line's number.
struct FieldLines<'a> {
    pairs: Vec<(&'a str, &'a str)>,
    names_line: usize,
    line: usize,
}

impl MarkerTable {
    /// Parses `.trc` bytes, reporting non-UTF-8 input as an error naming `file`.
    pub fn from_bytes(bytes: &[u8], file: &Path) -> Result<Self, TableError> {
        Self::parse(&decode(bytes, file)?, file)
    }

    /// Parses `.trc` text; `file` is only used in error messages.
    ///
    /// Expects the `PathFileType` line, the field names and values (DataRate, CameraRate,
    /// NumFrames, NumMarkers, Units required), the `Frame#`/`Time`/marker-name line and the
    /// `X1 Y1 Z1 ...` line, then tab-separated rows; a blank line before the rows, blank lines
    /// at the end and rows cut short after their last present marker are accepted.
    pub fn parse(text: &str, file: &Path) -> Result<Self, TableError> {
        let text = strip_bom(text);
        if is_blank(text) {
            return Err(TableError::Empty { file: file.to_path_buf() });
        }
        let mut lines = numbered_lines(text);
        let mut next = |previous: usize, expected: &'static str| {
            lines.next().ok_or(TableError::MissingHeaderLine {
                file: file.to_path_buf(),
                line: previous + 1,
                expected,
            })
        };
        let file_name = read_path_line(next(0, "the PathFileType line")?, file)?;
        let names =
            next(1, "the header field names (DataRate, CameraRate, NumFrames, NumMarkers, Units, ...)")?;
        let values = next(2, "the header field values")?;
        let fields = read_fields(pair_fields(names, values, file)?, file)?;
        let marker_line = next(3, "the name line (Frame#, Time, marker names)")?;
        let marker_names = read_marker_names(marker_line, fields.num_markers, file)?;
        check_axis_line(next(4, "the axis line (X1, Y1, Z1, ...)")?, marker_names.len(), file)?;
        let mut table = MarkerTable {
            header: TrcHeader { file_name, ..fields.header },
            marker_names,
            frame_numbers: Vec::new(),
            times: Vec::new(),
            positions: Vec::new(),
        };
        for (number, line) in lines.filter(|(_, line)| !is_blank(line)) {
            table.read_row(number, line, file)?;
        }
        if table.n_frames() != fields.num_frames {
            table.header.declared_frames = Some(fields.num_frames);
        }
        Ok(table)
    }

    /// Appends the frame on line `number`: frame number, time, then X/Y/Z per marker.
    fn read_row(&mut self, number: usize, line: &str, file: &Path) -> Result<(), TableError> {
        let fields: Vec<&str> = line.trim_end().split('\t').map(str::trim).collect();
        let width = 2 + 3 * self.n_markers();
        if fields.len() < 2 {
            return Err(TableError::ShortRow { file: file.to_path_buf(), line: number, found: fields.len() });
        }
        if fields.len() > width {
            return Err(TableError::TooManyFields {
                file: file.to_path_buf(),
                line: number,
                expected: width,
                found: fields.len(),
            });
        }
        let bad = |token: &str, expected| TableError::BadNumber {
            file: file.to_path_buf(),
            line: number,
            token: token.to_owned(),
            expected,
        };
        let frame = fields[0].parse().map_err(|_| bad(fields[0], "a frame number (a whole number)"))?;
        let time = parse_number(fields[1]).ok_or_else(|| bad(fields[1], "a time in seconds"))?;
        for (marker, name) in self.marker_names.iter().enumerate() {
            let xyz: [&str; 3] =
                std::array::from_fn(|axis| fields.get(2 + 3 * marker + axis).copied().unwrap_or(""));
            let position = match xyz.iter().filter(|field| field.is_empty()).count() {
                3 => None,
                0 => Some(parse_xyz(xyz).map_err(|token| bad(token, "a coordinate (a number)"))?),
                _ => {
                    return Err(TableError::PartialMarker {
                        file: file.to_path_buf(),
                        line: number,
                        marker: name.clone(),
                    })
                }
            };
            self.positions.push(position);
        }
        self.frame_numbers.push(frame);
        self.times.push(time);
        Ok(())
    }
}

/// Parses three coordinates, or returns the first token that is not a number.
fn parse_xyz(xyz: [&str; 3]) -> Result<[f64; 3], &str> {
    let mut position = [0.0; 3];
    for (value, token) in position.iter_mut().zip(xyz) {
        *value = parse_number(token).ok_or(token)?;
    }
    Ok(position)
}

/// Checks the `PathFileType` line and returns its file name field (empty if absent). Its first
/// word is what counts: OpenSim reads files whose `PathFileType  4` is spaced, not tabbed.
fn read_path_line((number, line): (usize, &str), file: &Path) -> Result<String, TableError> {
    let fields = header_fields(line);
    if line.split_whitespace().next() != Some("PathFileType") {
        let expected = "`PathFileType` first (PathFileType, 4, (X/Y/Z), file name)";
        return Err(TableError::MissingHeaderLine { file: file.to_path_buf(), line: number, expected });
    }
    Ok(fields.get(3).map_or(String::new(), |name| name.to_string()))
}

/// Pairs the header field names with their values, which must be as many.
fn pair_fields<'a>(
    (names_line, names): (usize, &'a str),
    (line, values): (usize, &'a str),
    file: &Path,
) -> Result<FieldLines<'a>, TableError> {
    let (names, values) = (header_fields(names), header_fields(values));
    if names.len() != values.len() {
        return Err(TableError::RaggedRow {
            file: file.to_path_buf(),
            line,
            expected: names.len(),
            found: values.len(),
        });
    }
    Ok(FieldLines { pairs: names.into_iter().zip(values).collect(), names_line, line })
}

/// Reads the known header fields; unknown or repeated ones are kept as extra fields.
fn read_fields(lines: FieldLines<'_>, file: &Path) -> Result<Fields, TableError> {
    let mut known: Vec<Option<&str>> = vec![None; KNOWN_FIELDS.len()];
    let mut extra = Vec::new();
    for (name, value) in lines.pairs {
        match KNOWN_FIELDS.iter().position(|known| *known == name) {
            Some(index) if known[index].is_none() => known[index] = Some(value),
            _ => extra.push((name.to_owned(), value.to_owned())),
        }
    }
    let line = lines.line;
    let required = |index: usize| {
        let key = KNOWN_FIELDS[index];
        known[index].ok_or(TableError::MissingField { file: file.to_path_buf(), line: lines.names_line, key })
    };
    let bad = |index: usize, value: &str, expected| TableError::BadHeaderValue {
        file: file.to_path_buf(),
        line,
        key: KNOWN_FIELDS[index].to_owned(),
        value: value.to_owned(),
        expected,
    };
    let rate =
        |index: usize, value: &str| parse_number(value).ok_or_else(|| bad(index, value, "a rate in Hz"));
    let count =
        |index: usize, value: &str| value.parse::<u64>().map_err(|_| bad(index, value, "a whole number"));
    let size =
        |index: usize, value: &str| value.parse::<usize>().map_err(|_| bad(index, value, "a whole number"));
    let optional = |index: usize| known[index];

    let data_rate = rate(0, required(0)?)?;
    let camera_rate = rate(1, required(1)?)?;
    let num_frames = size(2, required(2)?)?;
    let num_markers = size(3, required(3)?)?;
    let units_text = required(4)?;
    let units = LengthUnit::from_symbol(units_text).ok_or_else(|| TableError::UnknownUnits {
        file: file.to_path_buf(),
        line,
        units: units_text.to_owned(),
    })?;
    let header = TrcHeader {
        file_name: String::new(),
        data_rate,
        camera_rate,
        units,
        orig_data_rate: optional(5).map(|value| rate(5, value)).transpose()?,
        orig_data_start_frame: optional(6).map(|value| count(6, value)).transpose()?,
        orig_num_frames: optional(7).map(|value| count(7, value)).transpose()?,
        extra,
        declared_frames: None,
    };
    Ok(Fields { header, num_frames, num_markers })
}

/// Reads the marker names from the `Frame#`/`Time` line and checks them against NumMarkers.
fn read_marker_names(
    (number, line): (usize, &str),
    declared: usize,
    file: &Path,
) -> Result<Vec<String>, TableError> {
    let fields = header_fields(line);
    let is =
        |index: usize, word: &str| fields.get(index).is_some_and(|field| field.eq_ignore_ascii_case(word));
    if !(is(0, "Frame#") && is(1, "Time")) {
        let expected = "the name line: Frame#, Time, then the marker names";
        return Err(TableError::MissingHeaderLine { file: file.to_path_buf(), line: number, expected });
    }
    let names: Vec<String> =
        fields[2..].iter().filter(|name| !name.is_empty()).map(|name| name.to_string()).collect();
    let mut seen = HashSet::new();
    if let Some(duplicate) = names.iter().find(|name| !seen.insert(name.as_str())) {
        return Err(TableError::DuplicateMarker {
            file: file.to_path_buf(),
            line: number,
            name: duplicate.clone(),
        });
    }
    if names.len() != declared {
        return Err(TableError::MarkerCountMismatch {
            file: file.to_path_buf(),
            line: number,
            declared,
            found: names.len(),
        });
    }
    Ok(names)
}

/// Checks that the axis line has `X`, `Y`, `Z` labels (`X1 Y1 Z1 ...`) for each marker.
fn check_axis_line((number, line): (usize, &str), markers: usize, file: &Path) -> Result<(), TableError> {
    let labels: Vec<&str> = line.split_whitespace().collect();
    let axis_matches = |(index, label): (usize, &&str)| {
        label.chars().next().map(|c| c.to_ascii_uppercase()) == Some(['X', 'Y', 'Z'][index % 3])
    };
    if labels.len() == 3 * markers && labels.iter().enumerate().all(axis_matches) {
        return Ok(());
    }
    let mut found: String = labels.join(" ").chars().take(60).collect();
    if found.len() < labels.join(" ").len() {
        found.push_str(" ...");
    }
    Err(TableError::AxisLabels { file: file.to_path_buf(), line: number, markers, found })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRC: &str = "PathFileType\t4\t(X/Y/Z)\tstatic.trc\n\
        DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n\
        60.00\t60.00\t       2\t2\tmm\t60.00\t1\t       2\n\
        Frame#\tTime\tR.ASIS\t\t\tL.ASIS\t\t\t\n\
        \t\tX1\tY1\tZ1\tX2\tY2\tZ2\t\n\
        \n\
        1\t0.000000\t608.664310\t1072.713130\t157.442150\t610.637270\t1060.495000\t-103.888650\t\n\
        2\t0.016667\t\t\t\t1\t2\t3\n";

    fn parse(text: &str) -> Result<MarkerTable, TableError> {
        MarkerTable::parse(text, Path::new("walk.trc"))
    }

    fn error(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_header_names_and_rows() {
        let table = parse(TRC).unwrap();
        let header = table.header();
        assert_eq!(header.file_name, "static.trc");
        assert_eq!(
            (header.data_rate, header.camera_rate, header.units),
            (60.0, 60.0, LengthUnit::Millimeters)
        );
        assert_eq!(
            (header.orig_data_rate, header.orig_data_start_frame, header.orig_num_frames),
            (Some(60.0), Some(1), Some(2))
        );
        assert_eq!(table.marker_names(), ["R.ASIS", "L.ASIS"]);
        assert_eq!(table.frame_numbers(), [1, 2]);
        assert_eq!(table.times(), [0.0, 0.016667]);
        assert_eq!(table.position(0, 0), Some([608.66431, 1072.71313, 157.44215]));
        assert_eq!(table.position(1, 0), None);
        assert_eq!(table.position(1, 1), Some([1.0, 2.0, 3.0]));
    }

    #[test]
    fn accepts_crlf_short_rows_no_blank_line_and_extra_fields() {
        let text = TRC
            .replace("\n\n1\t", "\n1\t")
            .replace("\t1\t2\t3\n", "\n")
            .replace("OrigNumFrames\n", "OrigNumFrames\tExtra\n")
            .replace("       2\n", "       2\tx\n")
            .replace('\n', "\r\n");
        let table = parse(&text).unwrap();
        assert_eq!(table.position(1, 1), None);
        assert_eq!(table.header().extra, [("Extra".to_owned(), "x".to_owned())]);
    }

    #[test]
    fn accepts_other_units_and_no_orig_fields() {
        let text = "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n\
                    100\t100\t1\t1\tcm\nFrame#\tTime\tA\n\t\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n";
        let table = parse(text).unwrap();
        assert_eq!(table.units(), LengthUnit::Centimeters);
        assert_eq!(table.header().orig_data_rate, None);
        assert_eq!(table.in_meters().position(0, 0), Some([0.01, 0.02, 0.03]));
    }

    #[test]
    fn empty_file() {
        assert_eq!(error("\n \n"), "walk.trc:1: empty file; expected a table header");
    }

    #[test]
    fn missing_header_lines() {
        assert_eq!(
            error("Frame#\tTime\n"),
            "walk.trc:1: expected `PathFileType` first (PathFileType, 4, (X/Y/Z), file name)"
        );
        let three_lines: String = TRC.lines().take(3).map(|line| format!("{line}\n")).collect();
        assert_eq!(error(&three_lines), "walk.trc:4: expected the name line (Frame#, Time, marker names)");
        let text = TRC.replace("Frame#\tTime", "Frame\tTime");
        assert_eq!(error(&text), "walk.trc:4: expected the name line: Frame#, Time, then the marker names");
    }

    #[test]
    fn missing_and_bad_fields() {
        let text = TRC.replace("\tUnits\t", "\tUnitz\t");
        assert_eq!(error(&text), "walk.trc:2: no value for Units; expected it among the header fields");
        let text = TRC.replace("\tmm\t", "\tinch\t");
        assert_eq!(error(&text), "walk.trc:3: unknown Units `inch`; expected mm, cm or m");
        let text = TRC.replace("60.00\t60.00", "60.00\tfast");
        assert_eq!(error(&text), "walk.trc:3: CameraRate is `fast`; expected a rate in Hz");
        let text = TRC.replace("\t2\tmm", "\tmm");
        assert_eq!(error(&text), "walk.trc:3: row has 7 fields; expected 8, one per column label");
    }

    #[test]
    fn num_markers_disagrees_with_names() {
        let text = TRC.replace("\t2\tmm", "\t3\tmm");
        assert_eq!(
            error(&text),
            "walk.trc:4: NumMarkers is 3 but the name line lists 2 markers; expected them to agree"
        );
    }

    #[test]
    fn duplicate_marker_names() {
        let text = TRC.replace("L.ASIS", "R.ASIS");
        assert_eq!(error(&text), "walk.trc:4: duplicate marker name `R.ASIS`; expected unique names");
    }

    #[test]
    fn axis_line_must_have_three_per_marker() {
        let text = TRC.replace("\tX2\tY2\tZ2", "\tX2\tY2");
        let expected =
            "walk.trc:5: found axis labels `X1 Y1 Z1 X2 Y2`; expected X, Y, Z for each of 2 markers";
        assert_eq!(error(&text), expected);
        let text = TRC.replace("X2\tY2", "Y2\tX2");
        assert!(error(&text).starts_with("walk.trc:5: found axis labels"));
    }

    #[test]
    fn a_spaced_path_line_is_read() {
        let text = TRC.replace("PathFileType\t4\t", "PathFileType  4\t");
        assert_eq!(MarkerTable::parse(&text, Path::new("walk.trc")).unwrap().n_frames(), 2);
    }

    #[test]
    fn num_frames_that_disagree_with_the_rows_are_kept_aside() {
        let text = TRC.replace("       2\t2", "       3\t2");
        let table = MarkerTable::parse(&text, Path::new("walk.trc")).unwrap();
        assert_eq!((table.n_frames(), table.header.declared_frames), (2, Some(3)));
        assert_eq!(MarkerTable::parse(TRC, Path::new("walk.trc")).unwrap().header.declared_frames, None);
    }

    #[test]
    fn too_many_fields() {
        let text = TRC.replace("\t1\t2\t3\n", "\t1\t2\t3\t4\n");
        assert_eq!(
            error(&text),
            "walk.trc:8: row has 9 fields; expected at most 8 (frame, time, X/Y/Z per marker)"
        );
    }

    #[test]
    fn short_row() {
        let text = TRC.replace("2\t0.016667\t\t\t\t1\t2\t3\n", "2\n");
        assert_eq!(
            error(&text),
            "walk.trc:8: row has 1 fields; expected at least the frame number and the time"
        );
    }

    #[test]
    fn partial_marker() {
        let text = TRC.replace("\t1\t2\t3\n", "\t1\t\t3\n");
        assert_eq!(
            error(&text),
            "walk.trc:8: marker `L.ASIS` has only some of X, Y, Z; expected all three or none"
        );
        let text = TRC.replace("\t1\t2\t3\n", "\t1\t2\n");
        assert_eq!(
            error(&text),
            "walk.trc:8: marker `L.ASIS` has only some of X, Y, Z; expected all three or none"
        );
    }

    #[test]
    fn unparsable_numbers_are_quoted() {
        let text = TRC.replace("1060.495000", "1060,495");
        assert_eq!(error(&text), "walk.trc:7: `1060,495` is not a coordinate (a number)");
        let text = TRC.replace("2\t0.016667", "2.5\t0.016667");
        assert_eq!(error(&text), "walk.trc:8: `2.5` is not a frame number (a whole number)");
        let text = TRC.replace("2\t0.016667", "2\tlater");
        assert_eq!(error(&text), "walk.trc:8: `later` is not a time in seconds");
    }

    #[test]
    fn stray_bytes_read_as_replacement_characters_and_nul_is_binary() {
        let bytes = TRC.replace("R.ASIS", "R.AS\u{1}IS").into_bytes();
        let stray: Vec<u8> = bytes.iter().map(|&byte| if byte == 1 { 0xff } else { byte }).collect();
        let table = MarkerTable::from_bytes(&stray, Path::new("walk.trc")).unwrap();
        assert_eq!(table.marker_names[0], "R.AS\u{fffd}IS");
        let nul: Vec<u8> = bytes.iter().map(|&byte| if byte == 1 { 0 } else { byte }).collect();
        let message = MarkerTable::from_bytes(&nul, Path::new("walk.trc")).unwrap_err().to_string();
        assert_eq!(message, "walk.trc:4: binary data (a NUL byte); expected a text table");
    }
}
