//! Marker trajectories (`.trc`): 3-D positions of named markers, frame by frame.

mod parse;

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use super::text::{format_number, read_text};
use super::{LengthUnit, TableError};

/// The `.trc` header fields, except `NumFrames` and `NumMarkers`, which the table derives
/// from its data.
#[derive(Debug, Clone, PartialEq)]
pub struct TrcHeader {
    /// The file name on the `PathFileType` line (may be empty).
    pub file_name: String,
    /// `DataRate`, frames per second (Hz).
    pub data_rate: f64,
    /// `CameraRate`, frames per second (Hz).
    pub camera_rate: f64,
    /// `Units` of every coordinate.
    pub units: LengthUnit,
    /// `OrigDataRate` (Hz), if the file has it.
    pub orig_data_rate: Option<f64>,
    /// `OrigDataStartFrame`, if the file has it.
    pub orig_data_start_frame: Option<u64>,
    /// `OrigNumFrames`, if the file has it.
    pub orig_num_frames: Option<u64>,
    /// Other header fields in file order, written back after the standard ones. Names and
    /// values must be single words.
    pub extra: Vec<(String, String)>,
    /// `NumFrames` as read when it differs from the frames the file holds: OpenSim reads the
    /// frames that are there, and so does osim-tune (writing writes the true count).
    pub declared_frames: Option<usize>,
}

impl TrcHeader {
    /// A header for data sampled at `data_rate` Hz (camera rate too) in `units`, without the
    /// optional `Orig*` fields.
    pub fn new(data_rate: f64, units: LengthUnit) -> Self {
        TrcHeader {
            file_name: String::new(),
            data_rate,
            camera_rate: data_rate,
            units,
            orig_data_rate: None,
            orig_data_start_frame: None,
            orig_num_frames: None,
            extra: Vec::new(),
            declared_frames: None,
        }
    }
}

/// A `.trc` marker table, lossless in values.
///
/// Positions are frame-major: the position of marker `m` in frame `f` is
/// `positions[f * n_markers + m]`, in the header's units; `None` marks a marker missing in
/// that frame (empty fields in the file). A `NaN` written in the file stays a `NaN` value.
/// Frame numbers are the file's `Frame#` column; times (`Time`) are in seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct MarkerTable {
    header: TrcHeader,
    marker_names: Vec<String>,
    frame_numbers: Vec<u64>,
    times: Vec<f64>,
    positions: Vec<Option<[f64; 3]>>,
}

impl MarkerTable {
    /// A table of `marker_names` with one frame per time (numbered from 1) and frame-major
    /// `positions` (`times.len() * marker_names.len()` of them).
    pub fn new(
        header: TrcHeader,
        marker_names: Vec<String>,
        times: Vec<f64>,
        positions: Vec<Option<[f64; 3]>>,
    ) -> Result<Self, TableError> {
        check_marker_names(&marker_names)?;
        if times.len().checked_mul(marker_names.len()) != Some(positions.len()) {
            let problem = format!(
                "{} positions for {} frames of {} markers; expected one per marker and frame",
                positions.len(),
                times.len(),
                marker_names.len()
            );
            return Err(TableError::Shape { problem });
        }
        let frame_numbers = (1..).take(times.len()).collect();
        Ok(MarkerTable { header, marker_names, frame_numbers, times, positions })
    }

    /// Reads a `.trc` file.
    pub fn read(path: &Path) -> Result<Self, TableError> {
        Self::parse(&read_text(path)?, path)
    }

    /// The header fields.
    pub fn header(&self) -> &TrcHeader {
        &self.header
    }

    /// The unit of every coordinate.
    pub fn units(&self) -> LengthUnit {
        self.header.units
    }

    /// The data rate in frames per second (Hz).
    pub fn rate(&self) -> f64 {
        self.header.data_rate
    }

    /// Marker names in column order.
    pub fn marker_names(&self) -> &[String] {
        &self.marker_names
    }

    /// Index of the marker called `name`.
    pub fn marker_index(&self, name: &str) -> Option<usize> {
        self.marker_names.iter().position(|marker| marker == name)
    }

    /// Number of frames (data rows).
    pub fn n_frames(&self) -> usize {
        self.times.len()
    }

    /// Number of markers.
    pub fn n_markers(&self) -> usize {
        self.marker_names.len()
    }

    /// The `Frame#` of each frame.
    pub fn frame_numbers(&self) -> &[u64] {
        &self.frame_numbers
    }

    /// The time of each frame, in seconds.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// All positions, frame-major, in [`MarkerTable::units`]; `None` where a marker is missing.
    pub fn positions(&self) -> &[Option<[f64; 3]>] {
        &self.positions
    }

    /// Position of marker index `marker` in frame index `frame` (both from 0), in
    /// [`MarkerTable::units`]; `None` if missing there or out of range.
    pub fn position(&self, frame: usize, marker: usize) -> Option<[f64; 3]> {
        if marker >= self.n_markers() {
            return None;
        }
        self.positions.chunks_exact(self.n_markers()).nth(frame)?[marker]
    }

    /// A copy with every coordinate converted to metres and `Units` set to `m`.
    pub fn in_meters(&self) -> MarkerTable {
        let per_meter = self.units().per_meter();
        let mut converted = self.clone();
        for xyz in converted.positions.iter_mut().flatten() {
            *xyz = xyz.map(|coordinate| coordinate / per_meter);
        }
        converted.header.units = LengthUnit::Meters;
        converted
    }

    /// The file text: the standard five header lines, a blank line, then one tab-separated
    /// row per frame. Numbers read back bit-exactly; missing markers are empty fields.
    pub fn to_text(&self) -> String {
        let mut text = String::new();
        let _ = writeln!(text, "PathFileType\t4\t(X/Y/Z)\t{}", self.header.file_name);
        let (keys, values): (Vec<String>, Vec<String>) = self.header_fields().into_iter().unzip();
        let _ = writeln!(text, "{}\n{}", keys.join("\t"), values.join("\t"));
        text.push_str("Frame#\tTime\t");
        for name in &self.marker_names {
            let _ = write!(text, "{name}\t\t\t");
        }
        text.push_str("\n\t\t");
        for number in 1..=self.n_markers() {
            let _ = write!(text, "X{number}\tY{number}\tZ{number}\t");
        }
        text.push_str("\n\n");
        for frame in 0..self.n_frames() {
            self.write_row(&mut text, frame);
        }
        text
    }

    /// The header field names and values, in file order.
    fn header_fields(&self) -> Vec<(String, String)> {
        let header = &self.header;
        let mut fields = vec![
            ("DataRate".to_owned(), format_number(header.data_rate)),
            ("CameraRate".to_owned(), format_number(header.camera_rate)),
            ("NumFrames".to_owned(), self.n_frames().to_string()),
            ("NumMarkers".to_owned(), self.n_markers().to_string()),
            ("Units".to_owned(), header.units.symbol().to_owned()),
        ];
        if let Some(rate) = header.orig_data_rate {
            fields.push(("OrigDataRate".to_owned(), format_number(rate)));
        }
        if let Some(start) = header.orig_data_start_frame {
            fields.push(("OrigDataStartFrame".to_owned(), start.to_string()));
        }
        if let Some(count) = header.orig_num_frames {
            fields.push(("OrigNumFrames".to_owned(), count.to_string()));
        }
        fields.extend(header.extra.iter().cloned());
        fields
    }

    /// Appends the data row of frame index `frame`.
    fn write_row(&self, text: &mut String, frame: usize) {
        let _ = write!(text, "{}\t{}\t", self.frame_numbers[frame], format_number(self.times[frame]));
        let start = frame * self.n_markers();
        for position in &self.positions[start..start + self.n_markers()] {
            match position {
                Some(xyz) => {
                    for coordinate in xyz {
                        let _ = write!(text, "{}\t", format_number(*coordinate));
                    }
                }
                None => text.push_str("\t\t\t"),
            }
        }
        text.push('\n');
    }
}

/// Checks that marker names can be written to the name line and read back unchanged:
/// non-empty, unique, without tabs, line breaks or surrounding whitespace.
fn check_marker_names(names: &[String]) -> Result<(), TableError> {
    let mut seen = HashSet::new();
    for name in names {
        if name.is_empty() || name.trim() != name || name.contains(['\t', '\n', '\r']) {
            let problem = format!("marker name `{}` cannot be written to a name line", name.escape_debug());
            return Err(TableError::Shape { problem });
        }
        if !seen.insert(name.as_str()) {
            return Err(TableError::Shape { problem: format!("duplicate marker name `{name}`") });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_markers() -> MarkerTable {
        let names = vec!["R.ASIS".to_owned(), "L.ASIS".to_owned()];
        let positions = vec![
            Some([608.66431, 1072.71313, 157.44215]),
            None,
            Some([1.0, 2.0, 3.0]),
            Some([-4.0, 5.5, 0.0]),
        ];
        MarkerTable::new(
            TrcHeader::new(60.0, LengthUnit::Millimeters),
            names,
            vec![0.0, 1.0 / 60.0],
            positions,
        )
        .unwrap()
    }

    #[test]
    fn accessors() {
        let table = two_markers();
        assert_eq!((table.n_frames(), table.n_markers()), (2, 2));
        assert_eq!(table.marker_index("L.ASIS"), Some(1));
        assert_eq!(table.marker_index("nope"), None);
        assert_eq!(table.position(0, 0), Some([608.66431, 1072.71313, 157.44215]));
        assert_eq!(table.position(0, 1), None);
        assert_eq!(table.position(1, 1), Some([-4.0, 5.5, 0.0]));
        assert_eq!(table.position(0, 2), None);
        assert_eq!(table.position(2, 0), None);
        assert_eq!(table.position(usize::MAX, 1), None);
        assert_eq!(table.frame_numbers(), [1, 2]);
        assert_eq!(table.rate(), 60.0);
    }

    #[test]
    fn converts_to_meters() {
        let meters = two_markers().in_meters();
        assert_eq!(meters.units(), LengthUnit::Meters);
        let expected = [0.60866431, 1.07271313, 0.15744215];
        for (got, want) in meters.position(0, 0).unwrap().into_iter().zip(expected) {
            assert!((got - want).abs() <= 1e-15 * want, "{got} != {want}");
        }
        assert_eq!(meters.position(0, 1), None);
        assert_eq!(meters.position(1, 1), Some([-0.004, 0.0055, 0.0]));
        assert_eq!(meters.in_meters(), meters);
    }

    #[test]
    fn writes_trc_layout() {
        let expected = "PathFileType\t4\t(X/Y/Z)\t\n\
                        DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n60\t60\t2\t2\tmm\n\
                        Frame#\tTime\tR.ASIS\t\t\tL.ASIS\t\t\t\n\t\tX1\tY1\tZ1\tX2\tY2\tZ2\t\n\n\
                        1\t0\t608.66431\t1072.71313\t157.44215\t\t\t\t\n\
                        2\t0.016666666666666666\t1\t2\t3\t-4\t5.5\t0\t\n";
        assert_eq!(two_markers().to_text(), expected);
    }

    #[test]
    fn new_checks_shape_and_names() {
        let header = TrcHeader::new(60.0, LengthUnit::Meters);
        let names = vec!["A".to_owned()];
        assert!(MarkerTable::new(header.clone(), names.clone(), vec![0.0], Vec::new()).is_err());
        assert!(
            MarkerTable::new(header.clone(), vec!["A".into(), "A".into()], Vec::new(), Vec::new()).is_err()
        );
        assert!(MarkerTable::new(header.clone(), vec!["A\tB".into()], Vec::new(), Vec::new()).is_err());
        assert!(MarkerTable::new(header.clone(), vec![String::new()], Vec::new(), Vec::new()).is_err());
        assert!(MarkerTable::new(header, names, vec![0.0], vec![None]).is_ok());
    }
}
