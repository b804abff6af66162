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

/// `bytes` as text with each byte that is not part of a UTF-8 character read as Windows-1252
/// (the code page such bytes in OpenSim files come from, e.g. an en dash 0x96 in a citation).
pub fn with_windows_1252(bytes: &[u8]) -> String {
    /// Windows-1252's characters for 0x80–0x9F (the rest of 0x80–0xFF is Latin-1).
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8d}', 'Ž', '\u{8f}', '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ',
        '\u{9d}', 'ž', 'Ÿ',
    ];
    let mut text = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        text.push_str(chunk.valid());
        text.extend(chunk.invalid().iter().map(|&b| if (0x80..0xa0).contains(&b) { HIGH[usize::from(b - 0x80)] } else { char::from(b) }));
    }
    text
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
    fn stray_bytes_read_as_windows_1252() {
        assert_eq!(with_windows_1252(b"829\x96840 \xe9 \xc3\xa9"), "829–840 é é");
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
