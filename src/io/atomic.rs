//! Safe output: write to a temporary file beside the target, then rename it into place, so a
//! failure never leaves a partial file; refuse to overwrite any input.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output path names one of the inputs of the same command.
    #[error("{output}: refusing to overwrite an input file; choose another output path")]
    OverwritesInput { output: PathBuf },
    /// Creating, writing or renaming the file failed.
    #[error("{path}: cannot write: {source}")]
    Io { path: PathBuf, source: std::io::Error },
}

/// Writes `contents` to `output` atomically, after checking that `output` is none of `inputs`
/// (compared after resolving links and `..`, so `./a.osim` and `a.osim` are the same file).
/// The file gets the mode any new file gets (0666 less the umask), not the temporary file's
/// private 0600.
pub fn write_atomically(output: &Path, contents: &[u8], inputs: &[&Path]) -> Result<(), OutputError> {
    write_all_atomically(&[(output, contents)], inputs)
}

/// Writes several files as [`write_atomically`] does, all or none: every file is written to
/// its temporary file first and renamed into place only when all are written, so a failure
/// while writing leaves none of them (only a failing rename, after the writes, can leave the
/// earlier ones).
pub fn write_all_atomically(outputs: &[(&Path, &[u8])], inputs: &[&Path]) -> Result<(), OutputError> {
    for (output, _) in outputs {
        ensure_not_an_input(output, inputs)?;
    }
    let mut written = Vec::with_capacity(outputs.len());
    for &(output, contents) in outputs {
        let io_error = |source| OutputError::Io { path: output.to_path_buf(), source };
        let mut temporary = new_file_builder().tempfile_in(directory_of(output)).map_err(io_error)?;
        temporary.write_all(contents).map_err(io_error)?;
        temporary.as_file().sync_all().map_err(io_error)?;
        written.push((output, temporary));
    }
    for (output, temporary) in written {
        temporary.persist(output).map_err(|error| OutputError::Io { path: output.to_path_buf(), source: error.error })?;
    }
    Ok(())
}

/// The folder a file is written in.
fn directory_of(output: &Path) -> PathBuf {
    match output.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

#[cfg(unix)]
fn new_file_builder() -> tempfile::Builder<'static, 'static> {
    use std::os::unix::fs::PermissionsExt;
    let mut builder = tempfile::Builder::new();
    builder.permissions(fs::Permissions::from_mode(0o666));
    builder
}

#[cfg(not(unix))]
fn new_file_builder() -> tempfile::Builder<'static, 'static> {
    tempfile::Builder::new()
}

/// Fails with [`OutputError::OverwritesInput`] when `output` is the same file as an input.
pub fn ensure_not_an_input(output: &Path, inputs: &[&Path]) -> Result<(), OutputError> {
    let resolved_output = resolve(output);
    if inputs.iter().any(|input| resolve(input) == resolved_output) {
        return Err(OutputError::OverwritesInput { output: output.to_path_buf() });
    }
    Ok(())
}

/// Canonical form of a path whose file may not exist yet (its directory is resolved).
fn resolve(path: &Path) -> PathBuf {
    if let Ok(canonical) = fs::canonicalize(path) {
        return canonical;
    }
    let directory = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    match (fs::canonicalize(directory), path.file_name()) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => path.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A batch whose second file cannot be written leaves neither file.
    #[test]
    fn a_failed_batch_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let first = dir.path().join("first.sto");
        let second = dir.path().join("missing_folder").join("second.sto");
        let result = write_all_atomically(&[(&first, b"a"), (&second, b"b")], &[]);
        assert!(matches!(result, Err(OutputError::Io { ref path, .. }) if path == &second));
        assert!(!first.exists());
        let entries: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(entries.is_empty(), "temporary files left: {entries:?}");
    }

    /// The output's mode is that of a file `std::fs::write` creates (0666 less the umask).
    #[cfg(unix)]
    #[test]
    fn output_gets_the_mode_of_a_new_file() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let (output, plain) = (dir.path().join("out.osim"), dir.path().join("plain.osim"));
        write_atomically(&output, b"x", &[]).unwrap();
        fs::write(&plain, b"x").unwrap();
        let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&output), mode(&plain));
    }

    #[test]
    fn refuses_an_input_spelled_differently() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("a.osim");
        fs::write(&input, "x").unwrap();
        let same = dir.path().join(".").join("a.osim");
        let error = write_atomically(&same, b"y", &[&input]).unwrap_err();
        assert!(matches!(error, OutputError::OverwritesInput { .. }));
        assert_eq!(fs::read_to_string(&input).unwrap(), "x");
    }

    #[test]
    fn writes_whole_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let output = dir.path().join("out.sto");
        write_atomically(&output, b"hello", &[]).unwrap();
        assert_eq!(fs::read_to_string(&output).unwrap(), "hello");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn missing_directory_is_an_error_not_a_panic() {
        let error = write_atomically(Path::new("/nonexistent-dir/x.osim"), b"y", &[]).unwrap_err();
        assert!(matches!(error, OutputError::Io { .. }));
    }
}
