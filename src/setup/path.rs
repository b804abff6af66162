//! File names in setup files: what was written and where it points.

use std::path::{Path, PathBuf};

use serde::Serialize;

/// A file or directory named in a setup file. OpenSim reads a setup and runs its tool with the
/// working directory set to the setup file's directory, so a relative name is resolved there;
/// an absolute name stays as written.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SetupPath {
    /// The name as written (trimmed), for messages.
    pub written: String,
    /// `written` joined to the setup's directory, `.` components removed (`..` kept).
    pub resolved: PathBuf,
}

impl SetupPath {
    /// `written` resolved against `directory`; a relative name written with Windows separators
    /// (`..\models\a.osim`, setups shared from Windows) resolves as the same relative path.
    pub fn resolve(written: &str, directory: &Path) -> SetupPath {
        let relative_windows = written.contains('\\') && !written.contains('/') && !written.contains(':') && !written.starts_with('\\');
        let portable = if relative_windows { written.replace('\\', "/") } else { written.to_string() };
        let resolved = directory.join(portable).components().collect();
        SetupPath { written: written.to_string(), resolved }
    }
}

/// The existing file `path` that the setup `setup`'s `property` names; an error message naming
/// the setup and the property when it is unset or no such file (a Windows drive path named as
/// such).
pub fn required_input(setup: &Path, property: &str, path: Option<&SetupPath>) -> Result<PathBuf, String> {
    let path = path.ok_or_else(|| format!("{}: {property} is not set; the tool needs it", setup.display()))?;
    if !path.resolved.is_file() {
        let drive = path.written.as_bytes().get(..3).is_some_and(|b| b[0].is_ascii_alphabetic() && b[1] == b':' && (b[2] == b'\\' || b[2] == b'/'));
        let hint = if drive { "; a Windows path: give it relative to the setup's folder" } else { "" };
        return Err(format!("{}: {property} {:?}: no such file ({}){hint}", setup.display(), path.written, path.resolved.display()));
    }
    Ok(path.resolved.clone())
}

/// OpenSim's convention for an unset string property: empty or `Unassigned`.
pub fn is_unassigned(text: &str) -> bool {
    text.is_empty() || text == "Unassigned"
}

/// The directory that relative names in `setup_file` are resolved against.
pub fn directory_of(setup_file: &Path) -> PathBuf {
    setup_file.parent().map(Path::to_path_buf).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_names_join_the_setup_directory_and_absolute_names_stay() {
        let directory = Path::new("data/subject01");
        assert_eq!(SetupPath::resolve("static.trc", directory).resolved, Path::new("data/subject01/static.trc"));
        assert_eq!(SetupPath::resolve("./", directory).resolved, Path::new("data/subject01"));
        assert_eq!(SetupPath::resolve("../models/a.osim", directory).resolved, Path::new("data/subject01/../models/a.osim"));
        assert_eq!(SetupPath::resolve("/abs/a.osim", directory).resolved, Path::new("/abs/a.osim"));
        assert_eq!(SetupPath::resolve("a.osim", &directory_of(Path::new("setup.xml"))).resolved, Path::new("a.osim"));
        assert_eq!(SetupPath::resolve("..\\models\\a.osim", directory).resolved, Path::new("data/subject01/../models/a.osim"));
        assert_eq!(SetupPath::resolve("C:\\data\\a.osim", directory).resolved, Path::new("data/subject01/C:\\data\\a.osim"));
    }

    #[test]
    fn empty_and_unassigned_are_unset() {
        assert!(is_unassigned("") && is_unassigned("Unassigned"));
        assert!(!is_unassigned("unassigned.trc"));
    }
}
