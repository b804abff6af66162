//! `time_range`: the interval a tool works on.

use serde::Serialize;

use super::error::SetupError;
use crate::model::ComponentReader;

/// A time interval in seconds with `start ≤ end` (either may be infinite).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TimeRange {
    /// s
    pub start: f64,
    /// s
    pub end: f64,
}

impl TimeRange {
    /// The `time_range` property of `reader` (two numbers), `default` when absent.
    pub(super) fn read_or(reader: ComponentReader, default: TimeRange) -> Result<TimeRange, SetupError> {
        if reader.child("time_range").is_none() {
            return Ok(default);
        }
        let values = reader.numbers("time_range", Some(2))?;
        let (start, end) = (values[0], values[1]);
        if start <= end {
            Ok(TimeRange { start, end })
        } else {
            let text = reader.optional_text("time_range").unwrap_or_default();
            Err(reader.bad("time_range", "two times in s with start ≤ end", &text).into())
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::io::osim::OsimDocument;

    fn read(object: &str) -> Result<TimeRange, SetupError> {
        let source = format!("<OpenSimDocument Version=\"40600\">{object}</OpenSimDocument>");
        let document = OsimDocument::parse(source, Path::new("t.xml")).unwrap();
        TimeRange::read_or(ComponentReader::new(&document, document.object), TimeRange { start: -1.0, end: -1.0 })
    }

    #[test]
    fn reads_infinite_and_old_style_exponents_and_keeps_the_default_when_absent() {
        assert_eq!(read("<T><time_range>-Inf Infinity</time_range></T>").unwrap(), TimeRange { start: f64::NEG_INFINITY, end: f64::INFINITY });
        assert_eq!(read("<T><time_range> 1e-005 2 </time_range></T>").unwrap(), TimeRange { start: 1e-5, end: 2.0 });
        assert_eq!(read("<T/>").unwrap(), TimeRange { start: -1.0, end: -1.0 });
        assert_eq!(read("<T><time_range>2 2</time_range></T>").unwrap(), TimeRange { start: 2.0, end: 2.0 });
    }

    #[test]
    fn refuses_reversed_missing_and_nan_times() {
        for text in ["2 1", "1", "", "NaN 1", "1 two"] {
            let error = read(&format!("<T><time_range>{text}</time_range></T>")).unwrap_err();
            assert!(error.to_string().starts_with("t.xml:1: /: <time_range> must be"), "{error}");
        }
    }
}
