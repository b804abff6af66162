//! Reading the numbers of a 3.x property and writing them as OpenSim's conversion does.

use std::path::Path;

use crate::io::xml::TreeElement;
use crate::model::conversion::six_significant_digits;
use crate::model::error::{BadProperty, ModelError};

/// Where the values come from, for messages.
pub struct Values<'a> {
    pub file: &'a Path,
}

impl Values<'_> {
    /// The `N` numbers of property `property` of `element`, `default` when it is absent.
    pub fn numbers<const N: usize>(&self, element: &TreeElement, property: &str, default: [f64; N]) -> Result<[f64; N], ModelError> {
        let Some(text) = element.child_text(property) else { return Ok(default) };
        let parsed: Option<Vec<f64>> = text.split_whitespace().map(|word| word.parse().ok()).collect();
        parsed.and_then(|values| <[f64; N]>::try_from(values).ok()).ok_or_else(|| self.bad(element, property, &format!("{N} numbers"), text))
    }

    pub fn bad(&self, element: &TreeElement, property: &str, expected: &str, found: &str) -> ModelError {
        let line = element.child(property).map_or(element.line, |p| p.line);
        ModelError::BadProperty(Box::new(BadProperty {
            file: self.file.into(),
            line,
            component: component_name(element),
            property: property.into(),
            expected: expected.into(),
            found: found.into(),
        }))
    }

    /// A part of the model the conversion cannot carry into the 4.x format.
    pub fn unsupported(&self, element: &TreeElement, problem: &str) -> ModelError {
        ModelError::Unsupported { file: self.file.into(), line: element.line, component: component_name(element), problem: problem.into() }
    }
}

/// `Class 'name'`, or the class alone for an unnamed element.
fn component_name(element: &TreeElement) -> String {
    match element.name() {
        Some(name) => format!("{} '{name}'", element.tag),
        None => element.tag.clone(),
    }
}

/// Numbers as a C++ stream writes them at its default precision (six significant digits),
/// separated by spaces: how OpenSim's conversion writes the values it computes or moves.
pub fn stream(values: &[f64]) -> String {
    values.iter().map(|&v| six_significant_digits(v).to_string()).collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streamed_numbers_keep_six_digits() {
        assert_eq!(stream(&[-0.07243760, 0.0, 1234567.0, 1.0]), "-0.0724376 0 1234570 1");
        let values = Values { file: Path::new("m.osim") };
        let element = TreeElement { line: 7, ..TreeElement::leaf("Body", "") };
        assert_eq!(values.numbers(&element, "location", [0.0; 3]).unwrap(), [0.0; 3]);
        let mut body = TreeElement::named("Body", "femur");
        body.push(TreeElement::leaf("location", " 1 2"));
        let error = values.numbers(&body, "location", [0.0; 3]).unwrap_err().to_string();
        assert!(error.contains("Body 'femur': <location> must be 3 numbers"), "{error}");
    }
}
