//! Edits of a model document planned while reading it, applied afterwards: new property values,
//! and functions wrapped in a `MultiplierFunction` as OpenSim does when it scales them.

use crate::io::osim::format_numbers;
use crate::io::osim::OsimDocument;
use crate::io::xml::{escape_attribute, Document, EditError, ElementId};
use crate::model::{ComponentReader, ModelError};

/// One planned edit.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// New text of a value property.
    Value { element: ElementId, text: String },
    /// New text of a whole element.
    Replace { element: ElementId, text: String },
}

/// Applies `edits` in order.
pub fn apply(document: &mut OsimDocument, edits: &[Edit]) -> Result<(), EditError> {
    for edit in edits {
        match edit {
            Edit::Value { element, text } => document.xml.set_text(*element, text)?,
            Edit::Replace { element, text } => document.xml.replace_element(*element, text)?,
        }
    }
    Ok(())
}

/// The edit setting numeric property `property` of `component` to `values`, or none when the
/// numbers do not change (so unscaled values keep their bytes).
pub fn numbers_edit(component: ComponentReader, property: &str, values: &[f64]) -> Result<Option<Edit>, ModelError> {
    let old = component.numbers(property, Some(values.len()))?;
    if old == values {
        return Ok(None);
    }
    let element = component.child(property).ok_or_else(|| component.missing(property))?;
    Ok(Some(Edit::Value { element, text: format_numbers(values) }))
}

/// The edit multiplying vector property `property` of `component` element-wise by `factors`.
pub fn scaled_vec3_edit(component: ComponentReader, property: &str, factors: [f64; 3]) -> Result<Option<Edit>, ModelError> {
    let old = component.vec3(property)?;
    numbers_edit(component, property, &[old[0] * factors[0], old[1] * factors[1], old[2] * factors[2]])
}

/// The edit multiplying number property `property` of `component` by `factor`.
pub fn scaled_number_edit(component: ComponentReader, property: &str, factor: f64) -> Result<Option<Edit>, ModelError> {
    numbers_edit(component, property, &[component.number(property)? * factor])
}

/// The edit scaling `function` by `factor` as OpenSim's scale() methods do: an existing
/// `MultiplierFunction`'s `scale` is multiplied; any other function is wrapped in a new
/// `MultiplierFunction` (which takes over the function's `name` attribute).
pub fn scaled_function_edit(document: &OsimDocument, function: ElementId, factor: f64) -> Result<Option<Edit>, ModelError> {
    let reader = ComponentReader::new(document, function);
    if reader.class() == "MultiplierFunction" {
        return scaled_number_edit(reader, "scale", factor);
    }
    Ok(Some(Edit::Replace { element: function, text: multiplier_function(&document.xml, function, factor) }))
}

/// One level of indentation in a document indented by `indentation`: a tab unless it uses
/// spaces.
pub fn indent_unit(indentation: &str) -> &'static str {
    if indentation.contains('\t') || indentation.is_empty() { "\t" } else { "  " }
}

/// `<MultiplierFunction>` text holding the element `function` (re-indented one level deeper
/// than its new parent `<function>`) and `scale`.
fn multiplier_function(xml: &Document, function: ElementId, scale: f64) -> String {
    let indentation = xml.indentation(function);
    let unit = indent_unit(indentation);
    let name = xml.attribute(function, "name").map(|n| format!(" name=\"{}\"", escape_attribute(n))).unwrap_or_default();
    let inner = xml.element_source(function).replace('\n', &format!("\n{unit}{unit}"));
    format!(
        "<MultiplierFunction{name}>\n{indentation}{unit}<function>\n{indentation}{unit}{unit}{inner}\n{indentation}{unit}</function>\n\
         {indentation}{unit}<scale>{scale}</scale>\n{indentation}</MultiplierFunction>"
    )
}
