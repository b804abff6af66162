//! What the tool goldens share (`golden/rra/`, `golden/cmc/`): a case's setup copied with its
//! inputs into a temporary folder, as the generator ran it, and the files a run wrote against
//! those OpenSim wrote (`files.txt`).

use std::path::{Path, PathBuf};

/// A temporary folder holding `golden`'s `setup.xml` and the `inputs` ((name, repository path)),
/// and the setup's path in it.
pub fn case_folder(root: &Path, golden: &Path, inputs: &[(&str, &str)]) -> Result<(tempfile::TempDir, PathBuf), String> {
    let folder = tempfile::tempdir().map_err(|e| e.to_string())?;
    for &(name, source) in inputs {
        std::fs::copy(root.join(source), folder.path().join(name)).map_err(|e| format!("{source}: {e}"))?;
    }
    let setup = folder.path().join("setup.xml");
    std::fs::copy(golden.join("setup.xml"), &setup).map_err(|e| format!("{}: {e}", golden.display()))?;
    Ok((folder, setup))
}

/// The files OpenSim wrote (`golden`'s `files.txt`) that `ours` lacks, and ours it did not write.
pub fn file_differences(golden: &Path, ours: &[String]) -> Result<(Vec<String>, Vec<String>), String> {
    let written = std::fs::read_to_string(golden.join("files.txt")).map_err(|e| e.to_string())?;
    let missing = written.lines().filter(|f| !ours.iter().any(|o| o == f)).map(String::from).collect();
    let extra = ours.iter().filter(|o| !written.lines().any(|f| f == o.as_str())).cloned().collect();
    Ok((missing, extra))
}
