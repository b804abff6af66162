//! Building the element tree with byte spans from quick-xml's event stream.

use std::ops::Range;
use std::path::Path;

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

use super::document::{Attribute, Document, Element, ElementId};
use super::error::XmlError;
use super::text;

impl Document {
    /// Parses `source`; `file` is only used in error messages.
    pub fn parse(source: String, file: &Path) -> Result<Self, XmlError> {
        let elements = TreeBuilder::new(&source, file).build()?;
        Ok(Document::from_parts(file.to_path_buf(), source, elements))
    }
}

/// Turns reader events into [`Element`]s, keeping the stack of open elements.
struct TreeBuilder<'a> {
    source: &'a str,
    file: &'a Path,
    elements: Vec<Element>,
    open: Vec<ElementId>,
    root_closed: bool,
}

impl<'a> TreeBuilder<'a> {
    fn new(source: &'a str, file: &'a Path) -> Self {
        TreeBuilder { source, file, elements: Vec::new(), open: Vec::new(), root_closed: false }
    }

    fn build(mut self) -> Result<Vec<Element>, XmlError> {
        let mut reader = Reader::from_str(self.source);
        let config = reader.config_mut();
        config.trim_text(false);
        config.check_end_names = true;
        config.check_comments = true;
        loop {
            let start = reader.buffer_position() as usize;
            let event = reader.read_event().map_err(|error| {
                self.error(reader.error_position() as usize, error.to_string())
            })?;
            let end = reader.buffer_position() as usize;
            match event {
                Event::Start(tag) => self.open_element(&tag, start..end, false)?,
                Event::Empty(tag) => self.open_element(&tag, start..end, true)?,
                Event::End(_) => self.close_element(start),
                Event::Text(text) if self.open.is_empty() => {
                    let stray = String::from_utf8_lossy(text.as_ref()).trim().to_string();
                    if !stray.is_empty() && stray != "\u{feff}" {
                        return Err(self.error(start, format!("text outside the root element: {stray:.40}")));
                    }
                }
                Event::CData(_) | Event::GeneralRef(_) if self.open.is_empty() => {
                    return Err(self.error(start, "content outside the root element"));
                }
                Event::GeneralRef(_) if text::unescape(&self.source[start..end]).is_none() => {
                    return Err(self.error(start, format!("unknown entity {}", &self.source[start..end])));
                }
                Event::Eof => break,
                _ => {}
            }
        }
        if let Some(&unclosed) = self.open.last() {
            let element = &self.elements[unclosed.0 as usize];
            let message = format!("<{}> is never closed", element.tag);
            return Err(self.error(element.start_tag.start, message));
        }
        if self.elements.is_empty() {
            return Err(self.error(self.source.len(), "no root element"));
        }
        Ok(self.elements)
    }

    fn open_element(&mut self, start: &BytesStart, start_tag: Range<usize>, empty: bool) -> Result<(), XmlError> {
        if self.open.is_empty() && self.root_closed {
            return Err(self.error(start_tag.start, "a second root element"));
        }
        let tag = String::from_utf8_lossy(start.name().as_ref()).into_owned();
        let attributes = self.attributes(start, start_tag.start)?;
        let id = ElementId(self.elements.len() as u32);
        let parent = self.open.last().copied();
        if let Some(parent) = parent {
            self.elements[parent.0 as usize].children.push(id);
        }
        let content = if empty { None } else { Some(start_tag.end..start_tag.end) };
        self.elements.push(Element { tag, attributes, parent, children: Vec::new(), start_tag, content });
        if empty {
            self.root_closed |= parent.is_none();
        } else {
            self.open.push(id);
        }
        Ok(())
    }

    fn close_element(&mut self, end_tag_start: usize) {
        if let Some(id) = self.open.pop() {
            let element = &mut self.elements[id.0 as usize];
            element.content = Some(element.start_tag.end..end_tag_start);
            self.root_closed |= self.open.is_empty();
        }
    }

    /// Attributes of a start tag, checked for well-formedness (quotes, `=`, duplicates).
    fn attributes(&self, start: &BytesStart, offset: usize) -> Result<Vec<Attribute>, XmlError> {
        let mut attributes = Vec::new();
        for item in start.attributes().with_checks(true) {
            let attribute = item.map_err(|error| self.error(offset, format!("bad attribute: {error}")))?;
            let name = String::from_utf8_lossy(attribute.key.as_ref()).into_owned();
            let raw_value = String::from_utf8_lossy(&attribute.value).into_owned();
            let value = text::unescape(&raw_value)
                .ok_or_else(|| self.error(offset, format!("bad entity in attribute {name}")))?
                .into_owned();
            attributes.push(Attribute { name, value });
        }
        Ok(attributes)
    }

    fn error(&self, offset: usize, message: impl Into<String>) -> XmlError {
        let starts = text::line_starts(self.source);
        let (line, column) = text::line_and_column(&starts, offset.min(self.source.len()));
        XmlError { file: self.file.to_path_buf(), line, column, message: message.into() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const SNIPPET: &str = "<OpenSimDocument Version=\"40000\"><Model name=\"m\"><objects/><x a='1'>1 &amp; 2</x></Model></OpenSimDocument>";

    #[test]
    fn spans_cover_tags_and_values() {
        let document = Document::parse(SNIPPET.to_string(), Path::new("t.xml")).unwrap();
        let x = document.ids().find(|&id| document.tag(id) == "x").unwrap();
        assert_eq!(document.text(x).unwrap(), "1 & 2");
        assert_eq!(document.attribute(x, "a"), Some("1"));
        assert_eq!(&SNIPPET[document.element(x).start_tag.clone()], "<x a='1'>");
    }

    proptest! {
        /// Regression: the fuzzer found start tags whose attribute text was sliced out of range.
        #[test]
        fn mutated_documents_never_panic(cut in 0..SNIPPET.len(), insert in "[<>/=\"' a-z&;#0-9]{0,6}") {
            if SNIPPET.is_char_boundary(cut) {
                let text = format!("{}{}{}", &SNIPPET[..cut], insert, &SNIPPET[cut..]);
                let _ = Document::parse(text, Path::new("fuzz.xml"));
            }
        }

        #[test]
        fn unchanged_documents_serialise_to_their_input(text in "[<>/=\"' a-z]{0,40}") {
            if let Ok(document) = Document::parse(text.clone(), Path::new("p.xml")) {
                prop_assert_eq!(document.serialize(), text.as_bytes());
            }
        }
    }
}
