//! Setup objects where OpenSim finds them: the document's object, an object property held inline
//! (`<MeasurementSet>…</MeasurementSet>`) or in the file its `file` attribute names
//! (`<MeasurementSet file="gait2354_Scale_MeasurementSet.xml"/>`), and the members of sets.

use std::path::Path;

use super::error::SetupError;
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// Reads a setup document: `<OpenSimDocument Version="…">` around the object, or the object as
/// the root element (OpenSim reads both).
pub fn read_document(path: &Path) -> Result<OsimDocument, SetupError> {
    Ok(OsimDocument::read_object(path)?)
}

/// Checks that `reader` is an object of class (tag) `class`.
pub fn expect_class(reader: ComponentReader, class: &str) -> Result<(), SetupError> {
    expect_one_of(reader, &[class])
}

/// Checks that `reader` is of one of `classes`.
pub fn expect_one_of(reader: ComponentReader, classes: &[&str]) -> Result<(), SetupError> {
    if classes.contains(&reader.class()) {
        return Ok(());
    }
    Err(SetupError::UnexpectedObject {
        file: reader.document.xml.file().into(),
        line: reader.line(),
        expected: classes.join("> or <"),
        found: reader.class().into(),
    })
}

/// Reads the object property of class `class` held by `parent` with `read`; `None` when absent.
/// A `file` attribute is followed relative to `directory`, the top-level setup's directory: OpenSim
/// reads referenced files with the working directory set there, also for references inside a
/// referenced file. A referenced file's own root is not followed again, so references end.
pub fn read_object<T>(
    parent: ComponentReader,
    class: &str,
    directory: &Path,
    read: impl FnOnce(ComponentReader) -> Result<T, SetupError>,
) -> Result<Option<T>, SetupError> {
    let Some(object) = parent.child_of_class(class) else { return Ok(None) };
    let reference = parent.document.xml.attribute(object.element, "file").map(str::trim).filter(|f| !f.is_empty());
    let Some(reference) = reference else { return read(object).map(Some) };
    let from_file = || -> Result<T, SetupError> {
        let document = read_document(&directory.join(reference))?;
        let referenced = ComponentReader::new(&document, document.object);
        expect_class(referenced, class)?;
        read(referenced)
    };
    from_file().map(Some).map_err(|source| SetupError::Reference {
        file: parent.document.xml.file().into(),
        line: object.line(),
        element: class.into(),
        reference: reference.into(),
        source: Box::new(source),
    })
}

/// The members of a set (`<objects>` inside it), each checked to be one of `classes`.
pub fn set_members<'a>(set: ComponentReader<'a>, classes: &[&str]) -> Result<Vec<ComponentReader<'a>>, SetupError> {
    let Some(objects) = set.child("objects") else { return Ok(Vec::new()) };
    let members: Vec<_> = set.document.xml.children(objects).iter().map(|&member| set.at(member)).collect();
    for &member in &members {
        expect_one_of(member, classes)?;
    }
    Ok(members)
}
