//! The document: original text, an element tree with byte spans into it, and pending edits.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::error::{EditError, XmlError};
use super::text;

/// Index of an element in its [`Document`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ElementId(pub(super) u32);

/// An attribute as written in the start tag.
#[derive(Debug, Clone)]
pub struct Attribute {
    pub name: String,
    /// Unescaped value.
    pub value: String,
}

/// One element: its tag, attributes, children and where it sits in the source text.
#[derive(Debug, Clone)]
pub struct Element {
    pub tag: String,
    pub attributes: Vec<Attribute>,
    pub parent: Option<ElementId>,
    pub children: Vec<ElementId>,
    /// Bytes of the start tag (`<tag …>` or the whole `<tag … />`).
    pub start_tag: Range<usize>,
    /// Bytes between the start and the end tag; `None` for a self-closing element.
    pub content: Option<Range<usize>>,
}

/// A parsed XML document that remembers its exact text.
#[derive(Debug, Clone)]
pub struct Document {
    pub(super) file: PathBuf,
    pub(super) source: String,
    /// The file's bytes when they are not all UTF-8: `source` reads each stray byte as `?` at the
    /// same offset, and output writes these bytes back as they were.
    pub(super) original: Option<Vec<u8>>,
    pub(super) elements: Vec<Element>,
    pub(super) line_starts: Vec<usize>,
    /// Replacements keyed by the start of the replaced byte range: (end, new text).
    edits: BTreeMap<usize, (usize, String)>,
    /// Current values of edited elements.
    edited_values: BTreeMap<ElementId, String>,
}

impl Document {
    pub(super) fn from_parts(file: PathBuf, source: String, elements: Vec<Element>) -> Self {
        let line_starts = text::line_starts(&source);
        Document { file, source, original: None, elements, line_starts, edits: BTreeMap::new(), edited_values: BTreeMap::new() }
    }

    /// Reads and parses `path`.
    pub fn read(path: &Path) -> Result<Self, XmlError> {
        let bytes = std::fs::read(path).map_err(|error| XmlError {
            file: path.to_path_buf(),
            line: 0,
            column: 0,
            message: format!("cannot read file: {error}"),
        })?;
        Self::from_bytes(bytes, path)
    }

    /// Parses a file's bytes; `file` names it in messages. Bytes that are not UTF-8 — say a
    /// Windows-1252 dash in a model's publication note, which OpenSim reads — read as `?` and are
    /// written back unchanged.
    pub fn from_bytes(bytes: Vec<u8>, file: &Path) -> Result<Self, XmlError> {
        match String::from_utf8(bytes) {
            Ok(source) => Self::parse(source, file),
            Err(error) => {
                let bytes = error.into_bytes();
                let mut document = Self::parse(text::with_ascii_stand_ins(&bytes), file)?;
                document.original = Some(bytes);
                Ok(document)
            }
        }
    }

    /// The file this document was read from (used in messages).
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The root element.
    pub fn root(&self) -> ElementId {
        ElementId(0)
    }

    pub fn element(&self, id: ElementId) -> &Element {
        &self.elements[id.0 as usize]
    }

    /// All elements in document order.
    pub fn ids(&self) -> impl Iterator<Item = ElementId> {
        (0..self.elements.len() as u32).map(ElementId)
    }

    pub fn tag(&self, id: ElementId) -> &str {
        &self.element(id).tag
    }

    pub fn attribute(&self, id: ElementId, name: &str) -> Option<&str> {
        self.element(id).attributes.iter().find(|a| a.name == name).map(|a| a.value.as_str())
    }

    /// The `name` attribute, when present and not empty.
    pub fn name(&self, id: ElementId) -> Option<&str> {
        self.attribute(id, "name").filter(|name| !name.is_empty())
    }

    pub fn children(&self, id: ElementId) -> &[ElementId] {
        &self.element(id).children
    }

    /// The first child element with this tag.
    pub fn child(&self, id: ElementId, tag: &str) -> Option<ElementId> {
        self.children(id).iter().copied().find(|&c| self.tag(c) == tag)
    }

    pub fn parent(&self, id: ElementId) -> Option<ElementId> {
        self.element(id).parent
    }

    /// 1-based line of the element's start tag.
    pub fn line(&self, id: ElementId) -> usize {
        text::line_and_column(&self.line_starts, self.element(id).start_tag.start).0
    }

    /// The element's value: its unescaped character data with comments removed, or `None` when it
    /// holds child elements. A self-closing element has the empty value.
    pub fn text(&self, id: ElementId) -> Option<Cow<'_, str>> {
        if let Some(value) = self.edited_values.get(&id) {
            return Some(Cow::Borrowed(value));
        }
        let element = self.element(id);
        if !element.children.is_empty() {
            return None;
        }
        let Some(content) = element.content.clone() else { return Some(Cow::Borrowed("")) };
        let raw = &self.source[content];
        if !raw.contains('<') {
            return text::unescape(raw);
        }
        Some(Cow::Owned(character_data(raw)))
    }

    /// Replaces the value of an element that holds no child elements or comments, keeping the
    /// whitespace around the old value so the line changes only where the value does.
    pub fn set_text(&mut self, id: ElementId, value: &str) -> Result<(), EditError> {
        let element = self.element(id);
        let not_a_value =
            || EditError::NotAValue { file: self.file.clone(), line: self.line(id), tag: element.tag.clone() };
        let escaped = text::escape_content(value).into_owned();
        let (range, replacement) = match element.content.clone() {
            Some(content) => {
                let raw = &self.source[content.clone()];
                if !element.children.is_empty() || raw.contains('<') {
                    return Err(not_a_value());
                }
                let leading = raw.len() - raw.trim_start().len();
                let trailing = raw.len() - raw.trim_end().len();
                if raw.trim().is_empty() {
                    (content.start..content.end, escaped)
                } else {
                    (content.start + leading..content.end - trailing, escaped)
                }
            }
            None => {
                let tag_text = &self.source[element.start_tag.clone()];
                let open = tag_text.trim_end_matches('>').trim_end_matches('/').trim_end();
                (element.start_tag.clone(), format!("{open}>{escaped}</{}>", element.tag))
            }
        };
        self.insert_edit(id, range, replacement)?;
        self.edited_values.insert(id, value.to_string());
        Ok(())
    }

    /// The element as written: from its start tag through its end tag.
    pub fn element_source(&self, id: ElementId) -> &str {
        &self.source[self.element_range(id)]
    }

    /// The whitespace that starts the line of the element's start tag (its indentation).
    pub fn indentation(&self, id: ElementId) -> &str {
        let start = self.element(id).start_tag.start;
        let line_start = self.source[..start].rfind('\n').map_or(0, |i| i + 1);
        let prefix = &self.source[line_start..start];
        if prefix.trim().is_empty() { prefix } else { "" }
    }

    /// Replaces the whole element (start tag through end tag) by `text`, a structural edit such
    /// as wrapping a function in a `MultiplierFunction`. Refused where it would overlap another
    /// edit. An empty `text` removes the element together with the indentation and line break
    /// before it.
    pub fn replace_element(&mut self, id: ElementId, text: &str) -> Result<(), EditError> {
        let mut range = self.element_range(id);
        if text.is_empty() {
            let indentation = self.indentation(id).len();
            let line_break = usize::from(self.source[..range.start - indentation].ends_with('\n'));
            range.start -= indentation + line_break;
        }
        self.insert_edit(id, range, text.to_string())
    }

    /// Removes the element with its indentation and line break and, when the line before it
    /// holds only a comment (OpenSim's property documentation), that comment line too.
    pub fn remove_element(&mut self, id: ElementId) -> Result<(), EditError> {
        let mut range = self.element_range(id);
        range.start -= self.indentation(id).len();
        let before = &self.source[..range.start];
        let line_start = before.trim_end_matches('\n').rfind('\n').map_or(0, |i| i + 1);
        let previous_line = before[line_start..].trim();
        let documented = previous_line.starts_with("<!--") && previous_line.ends_with("-->") && previous_line[4..].find("-->") == Some(previous_line.len() - 7);
        range.start = if documented { line_start.saturating_sub(1) } else { range.start - usize::from(before.ends_with('\n')) };
        self.insert_edit(id, range, String::new())
    }

    /// Renames the element's tag in its start and end tags, keeping attributes and content.
    pub fn rename_element(&mut self, id: ElementId, tag: &str) -> Result<(), EditError> {
        let element = self.element(id);
        let old = element.tag.len();
        let start = element.start_tag.start + 1;
        let end_tag = element.content.as_ref().map(|content| content.end + 2);
        self.insert_edit(id, start..start + old, tag.to_string())?;
        if let Some(end) = end_tag {
            self.insert_edit(id, end..end + old, tag.to_string())?;
        }
        Ok(())
    }

    /// The byte just past the element's end tag.
    pub(super) fn element_end(&self, id: ElementId) -> usize {
        self.element_range(id).end
    }

    /// Bytes of the whole element.
    fn element_range(&self, id: ElementId) -> Range<usize> {
        let element = self.element(id);
        match &element.content {
            None => element.start_tag.clone(),
            Some(content) => {
                let close = self.source[content.end..].find('>').map_or(self.source.len(), |i| content.end + i + 1);
                element.start_tag.start..close
            }
        }
    }

    /// Records one replacement, refusing overlap with an earlier one (edits must stay disjoint
    /// for [`Document::serialize`] to splice them).
    fn insert_edit(&mut self, id: ElementId, range: Range<usize>, replacement: String) -> Result<(), EditError> {
        let same = |start: usize, end: usize| start == range.start && end == range.end;
        let before = self.edits.range(..=range.start).next_back().is_some_and(|(&start, &(end, _))| !same(start, end) && (start == range.start || end > range.start));
        let after = self.edits.range(range.start + 1..).next().is_some_and(|(&start, _)| start < range.end);
        if before || after {
            return Err(EditError::Overlapping { file: self.file.clone(), line: self.line(id), tag: self.element(id).tag.clone() });
        }
        self.edits.insert(range.start, (range.end, replacement));
        Ok(())
    }

    /// Whether any edit was made.
    pub fn is_modified(&self) -> bool {
        !self.edits.is_empty()
    }

    /// The document's bytes with all edits applied; the original bytes when there are none.
    pub fn serialize(&self) -> Vec<u8> {
        let source = self.original.as_deref().unwrap_or(self.source.as_bytes());
        let mut output = Vec::with_capacity(source.len());
        let mut position = 0;
        for (&start, (end, replacement)) in &self.edits {
            output.extend_from_slice(&source[position..start]);
            output.extend_from_slice(replacement.as_bytes());
            position = *end;
        }
        output.extend_from_slice(&source[position..]);
        output
    }
}

/// Character data of mixed raw content: comments dropped, CDATA kept verbatim, text unescaped.
pub(super) fn character_data(raw: &str) -> String {
    let mut value = String::new();
    let mut rest = raw;
    while let Some(open) = rest.find('<') {
        value.push_str(&text::unescape(&rest[..open]).unwrap_or(Cow::Borrowed(&rest[..open])));
        rest = &rest[open..];
        if let Some(cdata) = rest.strip_prefix("<![CDATA[") {
            let close = cdata.find("]]>").unwrap_or(cdata.len());
            value.push_str(&cdata[..close]);
            rest = cdata.get(close + 3..).unwrap_or("");
        } else {
            let close = rest.find('>').map_or(rest.len(), |i| i + 1);
            rest = &rest[close..];
        }
    }
    value.push_str(&text::unescape(rest).unwrap_or(Cow::Borrowed(rest)));
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "<r>\n\t<f name=\"function\">\n\t\t<v>1</v>\n\t</f>\n\t<g/>\n</r>";

    fn document() -> (Document, ElementId, ElementId, ElementId) {
        let document = Document::parse(TEXT.to_string(), Path::new("t.xml")).unwrap();
        let find = |tag: &str| document.ids().find(|&id| document.tag(id) == tag).unwrap();
        let (f, v, g) = (find("f"), find("v"), find("g"));
        (document, f, v, g)
    }

    #[test]
    fn an_element_is_replaced_from_start_tag_to_end_tag() {
        let (mut document, f, _, g) = document();
        assert_eq!(document.element_source(f), "<f name=\"function\">\n\t\t<v>1</v>\n\t</f>");
        assert_eq!(document.indentation(f), "\t");
        document.replace_element(f, "<m>x</m>").unwrap();
        document.replace_element(g, "").unwrap();
        assert_eq!(document.serialize(), "<r>\n\t<m>x</m>\n</r>".as_bytes());
    }

    #[test]
    fn an_element_is_renamed_and_a_documented_one_removed_with_its_comment() {
        let text = "<r>\n\t<f name=\"a\">\n\t\t<v>1</v>\n\t</f>\n\t<!--Doc of g.-->\n\t<g>\n\t</g>\n\t<h/>\n</r>";
        let mut document = Document::parse(text.to_string(), Path::new("t.xml")).unwrap();
        let find = |tag: &str| document.ids().find(|&id| document.tag(id) == tag).unwrap();
        let (f, g, h) = (find("f"), find("g"), find("h"));
        document.rename_element(f, "Pin").unwrap();
        document.remove_element(g).unwrap();
        document.rename_element(h, "k").unwrap();
        assert_eq!(document.serialize(), "<r>\n\t<Pin name=\"a\">\n\t\t<v>1</v>\n\t</Pin>\n\t<k/>\n</r>".as_bytes());
        let mut document = Document::parse(text.to_string(), Path::new("t.xml")).unwrap();
        document.remove_element(h).unwrap();
        assert_eq!(document.serialize(), "<r>\n\t<f name=\"a\">\n\t\t<v>1</v>\n\t</f>\n\t<!--Doc of g.-->\n\t<g>\n\t</g>\n</r>".as_bytes());
    }

    #[test]
    fn overlapping_edits_are_refused_in_either_order() {
        let (mut document, f, v, _) = document();
        document.set_text(v, "2").unwrap();
        document.set_text(v, "3").unwrap();
        assert!(matches!(document.replace_element(f, "<m/>"), Err(EditError::Overlapping { .. })));
        let (mut document, f, v, _) = self::document();
        document.replace_element(f, "<m/>").unwrap();
        assert!(matches!(document.set_text(v, "2"), Err(EditError::Overlapping { .. })));
    }
}
