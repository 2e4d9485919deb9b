//! Files written atomically: a temporary sibling first, then a rename, so that an
//! interrupted run never leaves half a PNG (or half a CSV) under the final name.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// A temporary sibling of `path` that keeps its extension (image encoders read it).
#[must_use]
pub fn temp_sibling(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".tmp-{}-{name}", std::process::id()))
}

/// Finishes a file produced at [`temp_sibling`]`(path)` by renaming it into place.
///
/// # Errors
/// When the rename fails.
pub fn commit_temp(path: &Path) -> io::Result<()> {
    fs::rename(temp_sibling(path), path)
}
