//! Component paths such as `/forceset/vas_lat_r/tendon_slack_length`.
//!
//! A segment names a child by its `name` attribute, or an unnamed child by its tag (the property
//! name, e.g. `optimal_fiber_length`, or the class of an unnamed object, e.g. `SpatialTransform`).
//! `<objects>` and `<groups>` list wrappers are transparent. As in OpenSim, a named component held
//! in an unnamed property may be addressed directly (`/jointset/knee_r/knee_angle_r` finds the
//! coordinate inside `<coordinates>`). When several siblings share a segment, `[k]` (0-based)
//! picks one; the canonical path of an element adds `[k]` only where needed.

use crate::io::xml::{Document, ElementId};

/// A parsed path: segments with an optional sibling index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ComponentPath {
    pub segments: Vec<(String, Option<usize>)>,
}

impl ComponentPath {
    /// Parses `/a/b[1]/c`; the leading `/` is optional.
    pub fn parse(text: &str) -> ComponentPath {
        let segments = text
            .split('/')
            .filter(|segment| !segment.is_empty())
            .map(split_index)
            .collect();
        ComponentPath { segments }
    }
}

fn split_index(segment: &str) -> (String, Option<usize>) {
    if let Some(open) = segment.strip_suffix(']').and_then(|s| s.rfind('[')) {
        if let Ok(index) = segment[open + 1..segment.len() - 1].parse() {
            return (segment[..open].to_string(), Some(index));
        }
    }
    (segment.to_string(), None)
}

/// Whether an element is a transparent list wrapper.
fn is_list_wrapper(document: &Document, id: ElementId) -> bool {
    document.name(id).is_none() && matches!(document.tag(id), "objects" | "groups")
}

/// The children that path segments address: list wrappers replaced by their contents.
pub fn visible_children(document: &Document, id: ElementId) -> Vec<ElementId> {
    let mut visible = Vec::new();
    for &child in document.children(id) {
        if is_list_wrapper(document, child) {
            visible.extend(visible_children(document, child));
        } else {
            visible.push(child);
        }
    }
    visible
}

/// The segment an element contributes to paths: its name, else its tag.
pub fn segment(document: &Document, id: ElementId) -> &str {
    document.name(id).unwrap_or_else(|| document.tag(id))
}

/// Segments of the visible children of `parent`, with `[k]` added where siblings share one.
pub fn child_segments(document: &Document, parent: ElementId) -> Vec<(ElementId, String)> {
    let children = visible_children(document, parent);
    let names: Vec<&str> = children.iter().map(|&c| segment(document, c)).collect();
    children
        .iter()
        .enumerate()
        .map(|(i, &child)| {
            let same = names.iter().filter(|&&n| n == names[i]).count();
            let label = if same > 1 {
                let k = names[..i].iter().filter(|&&n| n == names[i]).count();
                format!("{}[{k}]", names[i])
            } else {
                names[i].to_string()
            };
            (child, label)
        })
        .collect()
}

/// The canonical path of `id` below `top` (e.g. the `<Model>` element).
pub fn canonical_path(document: &Document, top: ElementId, id: ElementId) -> String {
    let mut chain = Vec::new();
    let mut current = id;
    while current != top {
        let Some(parent) = document.parent(current) else { break };
        if !is_list_wrapper(document, current) {
            chain.push(current);
        }
        current = parent;
    }
    let mut path = String::new();
    let mut parent = top;
    for &element in chain.iter().rev() {
        let label = child_segments(document, parent)
            .into_iter()
            .find(|(child, _)| *child == element)
            .map(|(_, label)| label)
            .unwrap_or_default();
        path.push('/');
        path.push_str(&label);
        parent = element;
    }
    if path.is_empty() {
        path.push('/');
    }
    path
}

/// Outcome of resolving one segment.
pub enum SegmentMatch {
    One(ElementId),
    None,
    Many(Vec<ElementId>),
}

/// Finds the child of `current` named by `segment`, trying in turn: visible children by name or
/// tag, unnamed children by tag ignoring case (3.x `BodySet` for `bodyset`), and named components
/// inside unnamed properties.
pub fn resolve_segment(document: &Document, current: ElementId, segment: &(String, Option<usize>)) -> SegmentMatch {
    let (text, index) = segment;
    let visible = visible_children(document, current);
    let mut found: Vec<ElementId> = visible
        .iter()
        .copied()
        .filter(|&c| document.name(c) == Some(text) || (document.name(c).is_none() && document.tag(c) == text))
        .collect();
    if found.is_empty() {
        found = visible
            .iter()
            .copied()
            .filter(|&c| document.name(c).is_none() && document.tag(c).eq_ignore_ascii_case(text))
            .collect();
    }
    if found.is_empty() {
        found = named_inside_properties(document, current, text);
    }
    match (index, found.len()) {
        (Some(k), _) => found.get(*k).map_or(SegmentMatch::None, |&id| SegmentMatch::One(id)),
        (None, 0) => SegmentMatch::None,
        (None, 1) => SegmentMatch::One(found[0]),
        (None, _) => SegmentMatch::Many(found),
    }
}

/// Named descendants reachable from `id` through unnamed elements only.
fn named_inside_properties(document: &Document, id: ElementId, name: &str) -> Vec<ElementId> {
    let mut found = Vec::new();
    for &child in document.children(id) {
        match document.name(child) {
            Some(child_name) if child_name == name => found.push(child),
            Some(_) => {}
            None => found.extend(named_inside_properties(document, child, name)),
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_indices_and_ignores_empty_segments() {
        let path = ComponentPath::parse("/a//b[2]/c[x]");
        assert_eq!(
            path.segments,
            vec![("a".into(), None), ("b".into(), Some(2)), ("c[x]".into(), None)]
        );
    }
}
