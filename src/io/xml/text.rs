//! Escaping and unescaping of character data and attribute values.

use std::borrow::Cow;

/// Replaces the predefined entities and character references of `raw`; `None` when a reference
/// is malformed or unknown.
pub fn unescape(raw: &str) -> Option<Cow<'_, str>> {
    quick_xml::escape::unescape(raw).ok()
}

/// Escapes `&`, `<` and `>` for element content.
pub fn escape_content(value: &str) -> Cow<'_, str> {
    quick_xml::escape::partial_escape(value)
}

/// Escapes `&`, `<`, `>`, `'` and `"` for an attribute value (or any text).
pub fn escape_attribute(value: &str) -> Cow<'_, str> {
    quick_xml::escape::escape(value)
}

/// Byte offset → (1-based line, 1-based column), from the sorted offsets where lines start.
pub fn line_and_column(line_starts: &[usize], offset: usize) -> (usize, usize) {
    let line_index = line_starts.partition_point(|&start| start <= offset).saturating_sub(1);
    (line_index + 1, offset - line_starts[line_index] + 1)
}

/// `bytes` as text with each byte that is not part of a UTF-8 character replaced by `?`, so
/// every offset stays where it was.
pub fn with_ascii_stand_ins(bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        text.push_str(chunk.valid());
        text.extend(std::iter::repeat_n('?', chunk.invalid().len()));
    }
    text
}

/// The first of 128 private-use characters that stand for the bytes 0x80–0xFF that are not part
/// of a UTF-8 character, so text moved around in an element tree can be written back as the
/// bytes it was read from.
const RAW_BYTE_BASE: u32 = 0x10_FF00;

/// `bytes` as text, each byte that is not part of a UTF-8 character as its private-use stand-in
/// (see [`raw_bytes`]).
pub fn with_raw_byte_stand_ins(bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        text.push_str(chunk.valid());
        text.extend(chunk.invalid().iter().filter_map(|&b| char::from_u32(RAW_BYTE_BASE + u32::from(b))));
    }
    text
}

/// `text` as bytes, each private-use stand-in of a stray byte (as `Document::tree` reads them) as
/// the byte it stands for.
pub fn raw_bytes(text: &str) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(text.len());
    for c in text.chars() {
        match u32::from(c).checked_sub(RAW_BYTE_BASE).and_then(|b| u8::try_from(b).ok()) {
            Some(byte) => bytes.push(byte),
            None => bytes.extend_from_slice(c.encode_utf8(&mut [0; 4]).as_bytes()),
        }
    }
    bytes
}

/// Offsets where each line of `source` starts (always begins with 0).
pub fn line_starts(source: &str) -> Vec<usize> {
    std::iter::once(0)
        .chain(source.match_indices('\n').map(|(index, _)| index + 1))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stray_bytes_come_back_as_they_were() {
        let bytes = b"829\x96840 \xff \xc3\xa9";
        let text = with_raw_byte_stand_ins(bytes);
        assert_eq!(text.chars().count(), 11);
        assert!(text.ends_with(" \u{e9}"));
        assert_eq!(raw_bytes(&text), bytes);
    }

    #[test]
    fn lines_and_columns_are_one_based() {
        let starts = line_starts("ab\ncd\n");
        assert_eq!(line_and_column(&starts, 0), (1, 1));
        assert_eq!(line_and_column(&starts, 4), (2, 2));
        assert_eq!(line_and_column(&starts, 6), (3, 1));
    }

    #[test]
    fn unescape_rejects_unknown_entities() {
        assert_eq!(unescape("a &amp; b").unwrap(), "a & b");
        assert!(unescape("&bogus;").is_none());
    }
}
