//! An owned, editable element tree for structural rewrites (moving, renaming and creating
//! elements), printed in OpenSim's layout: one element per line, tab-indented, `<tag />` when
//! empty. The lossless [`Document`] stays the form for value edits; this is for conversions
//! whose output is a new document.

use super::document::{character_data, Document, ElementId};
use super::text;

/// A child of an element: an element or a comment (whitespace between elements is not kept;
/// printing lays the tree out anew).
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    Element(TreeElement),
    Comment(String),
}

/// An element with its unescaped attribute values and either children or a text value.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeElement {
    pub tag: String,
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Node>,
    /// Unescaped character data of an element without child elements.
    pub text: String,
    /// 1-based line in the document it was read from (0 for created elements).
    pub line: usize,
}

impl TreeElement {
    /// A new empty element.
    pub fn new(tag: &str) -> Self {
        TreeElement { tag: tag.to_string(), attributes: Vec::new(), children: Vec::new(), text: String::new(), line: 0 }
    }

    /// A new element holding the value `text`.
    pub fn leaf(tag: &str, text: &str) -> Self {
        TreeElement { text: text.to_string(), ..TreeElement::new(tag) }
    }

    /// A new element with a `name` attribute.
    pub fn named(tag: &str, name: &str) -> Self {
        let mut element = TreeElement::new(tag);
        element.set_attribute("name", name);
        element
    }

    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes.iter().find(|(key, _)| key == name).map(|(_, value)| value.as_str())
    }

    pub fn name(&self) -> Option<&str> {
        self.attribute("name")
    }

    pub fn set_attribute(&mut self, name: &str, value: &str) {
        match self.attributes.iter_mut().find(|(key, _)| key == name) {
            Some((_, old)) => *old = value.to_string(),
            None => self.attributes.push((name.to_string(), value.to_string())),
        }
    }

    /// Child elements in order.
    pub fn elements(&self) -> impl Iterator<Item = &TreeElement> {
        self.children.iter().filter_map(|node| match node {
            Node::Element(element) => Some(element),
            Node::Comment(_) => None,
        })
    }

    pub fn elements_mut(&mut self) -> impl Iterator<Item = &mut TreeElement> {
        self.children.iter_mut().filter_map(|node| match node {
            Node::Element(element) => Some(element),
            Node::Comment(_) => None,
        })
    }

    /// The first child element with tag `tag`.
    pub fn child(&self, tag: &str) -> Option<&TreeElement> {
        self.elements().find(|e| e.tag == tag)
    }

    pub fn child_mut(&mut self, tag: &str) -> Option<&mut TreeElement> {
        self.elements_mut().find(|e| e.tag == tag)
    }

    /// The trimmed value of child `tag`.
    pub fn child_text(&self, tag: &str) -> Option<&str> {
        self.child(tag).map(|e| e.text.trim())
    }

    /// Removes and returns the first child element with tag `tag`.
    pub fn take(&mut self, tag: &str) -> Option<TreeElement> {
        let index = self.children.iter().position(|node| matches!(node, Node::Element(e) if e.tag == tag))?;
        match self.children.remove(index) {
            Node::Element(element) => Some(element),
            Node::Comment(_) => None,
        }
    }

    /// Removes every child element and comment, returning the elements.
    pub fn take_all(&mut self) -> Vec<TreeElement> {
        std::mem::take(&mut self.children)
            .into_iter()
            .filter_map(|node| match node {
                Node::Element(element) => Some(element),
                Node::Comment(_) => None,
            })
            .collect()
    }

    /// Appends a child element.
    pub fn push(&mut self, element: TreeElement) {
        self.children.push(Node::Element(element));
    }

    /// Inserts a child element before the first child with tag `before` (at the end without one).
    pub fn insert_before(&mut self, before: &str, element: TreeElement) {
        let index = self.children.iter().position(|node| matches!(node, Node::Element(e) if e.tag == before)).unwrap_or(self.children.len());
        self.children.insert(index, Node::Element(element));
    }

    /// Inserts a child element after the first child with tag `after` (at the end without one).
    pub fn insert_after(&mut self, after: &str, element: TreeElement) {
        let index = self.children.iter().position(|node| matches!(node, Node::Element(e) if e.tag == after)).map_or(self.children.len(), |i| i + 1);
        self.children.insert(index, Node::Element(element));
    }

    /// The element printed at `depth` tabs, with a line break after it.
    pub fn print(&self, depth: usize, out: &mut String) {
        let indent = "\t".repeat(depth);
        out.push_str(&indent);
        out.push('<');
        out.push_str(&self.tag);
        for (name, value) in &self.attributes {
            out.push_str(&format!(" {name}=\"{}\"", text::escape_attribute(value)));
        }
        if self.children.is_empty() {
            if self.text.is_empty() {
                out.push_str(" />\n");
            } else {
                out.push_str(&format!(">{}</{}>\n", text::escape_content(&self.text), self.tag));
            }
            return;
        }
        out.push_str(">\n");
        for node in &self.children {
            match node {
                Node::Element(element) => element.print(depth + 1, out),
                Node::Comment(comment) => out.push_str(&format!("{indent}\t<!--{comment}-->\n")),
            }
        }
        out.push_str(&format!("{indent}</{}>\n", self.tag));
    }
}

impl Document {
    /// The element `id` and everything in it as an owned tree (comments between child elements
    /// kept, whitespace between them dropped).
    pub fn tree(&self, id: ElementId) -> TreeElement {
        let element = self.element(id);
        let mut tree = TreeElement {
            tag: element.tag.clone(),
            attributes: element.attributes.iter().map(|a| (a.name.clone(), a.value.clone())).collect(),
            children: Vec::new(),
            text: String::new(),
            line: self.line(id),
        };
        if element.children.is_empty() {
            tree.text = match (&self.original, element.content.clone()) {
                (Some(_), Some(content)) => {
                    let raw = self.decoded(content);
                    if raw.contains('<') { character_data(&raw) } else { text::unescape(&raw).map(|t| t.into_owned()).unwrap_or(raw) }
                }
                _ => self.text(id).map(|t| t.into_owned()).unwrap_or_default(),
            };
            return tree;
        }
        let content = element.content.clone().unwrap_or_default();
        let mut position = content.start;
        for &child in &element.children {
            let start = self.element(child).start_tag.start;
            tree.children.extend(comments(&self.decoded(position..start)).map(Node::Comment));
            tree.children.push(Node::Element(self.tree(child)));
            position = self.element_end(child);
        }
        tree.children.extend(comments(&self.decoded(position..content.end)).map(Node::Comment));
        tree
    }

    /// The text of `range`, bytes that are not UTF-8 as their stand-ins.
    fn decoded(&self, range: std::ops::Range<usize>) -> String {
        match &self.original {
            Some(bytes) => text::with_raw_byte_stand_ins(&bytes[range]),
            None => self.source[range].to_string(),
        }
    }
}

/// The comments (without `<!--`/`-->`) in `between`, the text between two sibling elements.
fn comments(between: &str) -> impl Iterator<Item = String> + '_ {
    between.split("<!--").skip(1).filter_map(|piece| piece.split_once("-->").map(|(comment, _)| comment.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn a_tree_prints_in_opensims_layout() {
        let source = "<A n=\"x &amp; y\">\n  <!--doc-->\n  <b> 1 2 </b><c/>\n  <d><e>t&lt;</e></d>\n</A>";
        let document = Document::parse(source.to_string(), Path::new("t.xml")).unwrap();
        let mut tree = document.tree(document.root());
        assert_eq!(tree.name(), None);
        assert_eq!(tree.attribute("n"), Some("x & y"));
        assert_eq!(tree.child_text("b"), Some("1 2"));
        assert_eq!(tree.child("d").unwrap().line, 4);
        let c = tree.take("c").unwrap();
        tree.insert_before("b", c);
        tree.insert_after("d", TreeElement::leaf("f", "a<b"));
        let mut out = String::new();
        tree.print(0, &mut out);
        assert_eq!(out, "<A n=\"x &amp; y\">\n\t<!--doc-->\n\t<c />\n\t<b> 1 2 </b>\n\t<d>\n\t\t<e>t&lt;</e>\n\t</d>\n\t<f>a&lt;b</f>\n</A>\n");
    }
}
