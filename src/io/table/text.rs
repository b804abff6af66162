//! Text helpers shared by the table formats: reading, decoding, numbered lines, fields and
//! numbers written so that they read back bit-exactly.

use std::borrow::Cow;
use std::path::Path;

use super::TableError;

/// Reads `file` as text without a byte-order mark (see [`decode`]).
pub(super) fn read_text(file: &Path) -> Result<String, TableError> {
    let bytes = std::fs::read(file).map_err(|source| TableError::Io { file: file.to_path_buf(), source })?;
    decode(&bytes, file).map(Cow::into_owned)
}

/// Decodes `bytes` as UTF-8, dropping a leading byte-order mark. Bytes that are no UTF-8 — a
/// Windows-1252 `é` in a `.trc`'s path line, which OpenSim reads — become U+FFFD; a NUL byte
/// (a binary file, say a `.c3d`) is an error naming its 1-based line.
pub(super) fn decode<'a>(bytes: &'a [u8], file: &Path) -> Result<Cow<'a, str>, TableError> {
    if let Some(nul) = bytes.iter().position(|&byte| byte == 0) {
        let line = 1 + bytes[..nul].iter().filter(|&&byte| byte == b'\n').count();
        return Err(TableError::Binary { file: file.to_path_buf(), line });
    }
    Ok(match String::from_utf8_lossy(bytes) {
        Cow::Borrowed(text) => Cow::Borrowed(strip_bom(text)),
        Cow::Owned(text) => Cow::Owned(strip_bom(&text).to_owned()),
    })
}

/// `text` without a leading byte-order mark.
pub(super) fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The lines of `text` with their 1-based numbers (`\n` or `\r\n` ends).
pub(super) fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    (1..).zip(text.lines())
}

/// Whether a line holds nothing but whitespace.
pub(super) fn is_blank(line: &str) -> bool {
    line.trim().is_empty()
}

/// Header fields of a line: split on tabs (each field trimmed) when it has a tab, else on
/// runs of whitespace. Trailing whitespace (and so trailing empty fields) is ignored.
pub(super) fn header_fields(line: &str) -> Vec<&str> {
    let line = line.trim();
    if line.is_empty() {
        Vec::new()
    } else if line.contains('\t') {
        line.split('\t').map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

/// Parses a decimal number as Rust does (`1e-05`, `nan`, `NaN`, `inf`, `-inf` included).
pub(super) fn parse_number(token: &str) -> Option<f64> {
    token.parse().ok()
}

/// Writes `value` in the shortest form that reads back to the same bits: plain decimal for
/// magnitudes in [1e-5, 1e16) and zero, exponent form (`1e-7`) otherwise; `NaN`, `inf`,
/// `-inf` for non-finite values (a NaN's sign and payload are not kept).
pub(super) fn format_number(value: f64) -> String {
    let magnitude = value.abs();
    if value.is_finite() && magnitude != 0.0 && !(1e-5..1e16).contains(&magnitude) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_bit_exactly() {
        let values = [
            0.0,
            -0.0,
            1.0,
            0.1,
            -608.66431,
            1e-5,
            9.999e-6,
            1e16,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -1.2345678901234567e-300,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for value in values {
            let text = format_number(value);
            let back = parse_number(&text).unwrap();
            assert_eq!(back.to_bits(), value.to_bits(), "{value} written as {text}");
        }
    }

    #[test]
    fn numbers_are_written_compactly() {
        assert_eq!(format_number(1.0), "1");
        assert_eq!(format_number(-0.0), "-0");
        assert_eq!(format_number(0.0017), "0.0017");
        assert_eq!(format_number(1e-7), "1e-7");
        assert_eq!(format_number(1e300), "1e300");
        assert_eq!(format_number(f64::NAN), "NaN");
        assert_eq!(format_number(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn special_tokens_parse() {
        assert!(parse_number("nan").unwrap().is_nan());
        assert!(parse_number("NaN").unwrap().is_nan());
        assert_eq!(parse_number("-inf"), Some(f64::NEG_INFINITY));
        assert_eq!(parse_number("1e-05"), Some(1e-5));
        assert_eq!(parse_number("1,5"), None);
    }

    #[test]
    fn header_fields_split_on_tabs_or_spaces() {
        assert_eq!(header_fields("a b\tc\t\t"), vec!["a b", "c"]);
        assert_eq!(header_fields("  a   b "), vec!["a", "b"]);
        assert_eq!(header_fields("a\t\tb"), vec!["a", "", "b"]);
        assert!(header_fields(" \t ").is_empty());
    }

    #[test]
    fn binary_data_names_its_line_and_stray_bytes_are_replaced() {
        let error = decode(b"ok\nok\n\x00\n", Path::new("bad.sto")).unwrap_err();
        assert_eq!(error.to_string(), "bad.sto:3: binary data (a NUL byte); expected a text table");
        assert_eq!(decode(b"Jos\xe9\t1", Path::new("latin1.trc")).unwrap(), "Jos\u{fffd}\t1");
    }

    #[test]
    fn byte_order_mark_is_dropped() {
        assert_eq!(decode("\u{feff}name".as_bytes(), Path::new("x")).unwrap(), "name");
    }
}
