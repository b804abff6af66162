//! Typed reading of one component's properties with errors that name the file, line and
//! component.

use crate::io::osim::OsimDocument;
use crate::io::xml::ElementId;

use super::error::{BadProperty, ModelError};

/// A component element and the document it lives in.
#[derive(Clone, Copy)]
pub struct ComponentReader<'a> {
    pub document: &'a OsimDocument,
    pub element: ElementId,
}

impl<'a> ComponentReader<'a> {
    pub fn new(document: &'a OsimDocument, element: ElementId) -> Self {
        ComponentReader { document, element }
    }

    /// The component's `name` attribute, or its tag when unnamed.
    pub fn name(&self) -> String {
        let xml = &self.document.xml;
        xml.name(self.element).unwrap_or_else(|| xml.tag(self.element)).to_string()
    }

    pub fn class(&self) -> &'a str {
        self.document.xml.tag(self.element)
    }

    /// The component's canonical path, for messages.
    pub fn path(&self) -> String {
        self.document.path_of(self.element)
    }

    pub fn line(&self) -> usize {
        self.document.xml.line(self.element)
    }

    /// The child element holding `property`, if present.
    pub fn child(&self, property: &str) -> Option<ElementId> {
        self.document.xml.child(self.element, property)
    }

    /// Reader for another element of the same document.
    pub fn at(&self, element: ElementId) -> ComponentReader<'a> {
        ComponentReader::new(self.document, element)
    }

    /// Text of an optional value property, trimmed.
    pub fn optional_text(&self, property: &str) -> Option<String> {
        let id = self.child(property)?;
        self.document.xml.text(id).map(|t| t.trim().to_string())
    }

    /// The whitespace-separated words of a string-array property; empty when absent.
    pub fn words(&self, property: &str) -> Vec<String> {
        self.optional_text(property).unwrap_or_default().split_whitespace().map(String::from).collect()
    }

    /// Text of a required value property, trimmed.
    pub fn text(&self, property: &str) -> Result<String, ModelError> {
        self.optional_text(property).ok_or_else(|| self.missing(property))
    }

    /// Numbers of a required property, exactly `count` of them when `count` is given.
    pub fn numbers(&self, property: &str, count: Option<usize>) -> Result<Vec<f64>, ModelError> {
        let text = self.text(property)?;
        let expected = match count {
            Some(1) => "a number".to_string(),
            Some(n) => format!("{n} numbers"),
            None => "a list of numbers".to_string(),
        };
        let values: Option<Vec<f64>> = text.split_whitespace().map(|t| t.parse().ok()).collect();
        match values {
            Some(values) if count.is_none_or(|n| values.len() == n) => Ok(values),
            _ => Err(self.bad(property, &expected, &text)),
        }
    }

    pub fn number(&self, property: &str) -> Result<f64, ModelError> {
        Ok(self.numbers(property, Some(1))?[0])
    }

    pub fn vec3(&self, property: &str) -> Result<[f64; 3], ModelError> {
        let values = self.numbers(property, Some(3))?;
        Ok([values[0], values[1], values[2]])
    }

    /// Three numbers with OpenSim's default for when the property is absent (OpenSim writes an
    /// object whose properties all have their defaults as an empty element).
    pub fn vec3_or(&self, property: &str, default: [f64; 3]) -> Result<[f64; 3], ModelError> {
        if self.child(property).is_some() { self.vec3(property) } else { Ok(default) }
    }

    /// As many numbers as `default` has, which stands in when the property is absent.
    pub fn numbers_or(&self, property: &str, default: &[f64]) -> Result<Vec<f64>, ModelError> {
        if self.child(property).is_some() { self.numbers(property, Some(default.len())) } else { Ok(default.to_vec()) }
    }

    /// A number with a default for when the property is absent.
    pub fn number_or(&self, property: &str, default: f64) -> Result<f64, ModelError> {
        if self.child(property).is_some() { self.number(property) } else { Ok(default) }
    }

    /// `true`/`false` with a default for when the property is absent.
    pub fn boolean_or(&self, property: &str, default: bool) -> Result<bool, ModelError> {
        match self.optional_text(property).as_deref() {
            None => Ok(default),
            Some("true") => Ok(true),
            Some("false") => Ok(false),
            Some(other) => Err(self.bad(property, "true or false", other)),
        }
    }

    pub fn missing(&self, property: &str) -> ModelError {
        ModelError::MissingProperty {
            file: self.document.xml.file().into(),
            line: self.line(),
            component: self.path(),
            property: property.into(),
        }
    }

    pub fn bad(&self, property: &str, expected: &str, found: &str) -> ModelError {
        let line = self.child(property).map_or(self.line(), |id| self.document.xml.line(id));
        ModelError::BadProperty(Box::new(BadProperty {
            file: self.document.xml.file().into(),
            line,
            component: self.path(),
            property: property.into(),
            expected: expected.into(),
            found: found.into(),
        }))
    }

    pub fn unknown(&self, what: &str, target: &str) -> ModelError {
        ModelError::UnknownReference {
            file: self.document.xml.file().into(),
            line: self.line(),
            component: self.path(),
            what: what.into(),
            target: target.into(),
        }
    }

    /// The object held by property `property`: either `<property><Class …/></property>` (3.x and
    /// unnamed objects) or `<Class name="property">` (4.x).
    pub fn object_property(&self, property: &str) -> Option<ComponentReader<'a>> {
        let xml = &self.document.xml;
        let children = xml.children(self.element);
        if let Some(&wrapper) = children.iter().find(|&&c| xml.tag(c) == property) {
            return xml.children(wrapper).first().map(|&object| self.at(object));
        }
        children.iter().find(|&&c| xml.name(c) == Some(property)).map(|&object| self.at(object))
    }

    /// The first child element of class (tag) `class`, e.g. a Millard muscle's curve objects.
    pub fn child_of_class(&self, class: &str) -> Option<ComponentReader<'a>> {
        let xml = &self.document.xml;
        xml.children(self.element).iter().find(|&&c| xml.tag(c) == class).map(|&c| self.at(c))
    }

    /// The member elements of a set (`<Set><objects>…`) or of a list property (`<coordinates>…`).
    pub fn listed_objects(&self, container: ElementId) -> Vec<ElementId> {
        let xml = &self.document.xml;
        let list = xml.child(container, "objects").unwrap_or(container);
        xml.children(list).to_vec()
    }
}

/// Where an object's properties are read: the object, else the `<defaults>` object of its class
/// in the document's object (a `<Model>`, `<ForceSet>`, `<ControlSet>` or `<CMC_TaskSet>`),
/// which OpenSim registers as the class default while reading the document.
pub struct PropertySources<'a> {
    pub member: ComponentReader<'a>,
    defaults: Option<ComponentReader<'a>>,
}

impl<'a> PropertySources<'a> {
    pub fn new(member: ComponentReader<'a>) -> Self {
        let document = member.document;
        let defaults = document.xml.child(document.object, "defaults").and_then(|d| member.at(d).child_of_class(member.class()));
        PropertySources { member, defaults }
    }

    /// The member, then the defaults object.
    pub fn sources(&self) -> impl Iterator<Item = ComponentReader<'a>> {
        std::iter::once(self.member).chain(self.defaults)
    }

    /// The first source stating `property`; the member when none does.
    pub fn of(&self, property: &str) -> ComponentReader<'a> {
        self.sources().find(|source| source.child(property).is_some()).unwrap_or(self.member)
    }

    pub fn number(&self, property: &str, default: f64) -> Result<f64, ModelError> {
        self.of(property).number_or(property, default)
    }

    pub fn boolean(&self, property: &str, default: bool) -> Result<bool, ModelError> {
        self.of(property).boolean_or(property, default)
    }

    pub fn vec3(&self, property: &str, default: [f64; 3]) -> Result<[f64; 3], ModelError> {
        let source = self.of(property);
        if source.child(property).is_some() { source.vec3(property) } else { Ok(default) }
    }

    /// A required name (of a coordinate or body): OpenSim refuses an empty one.
    pub fn reference(&self, property: &str) -> Result<String, ModelError> {
        let text = self.of(property).optional_text(property).filter(|text| !text.is_empty());
        text.ok_or_else(|| self.member.missing(property))
    }
}
