//! Files a sweep reads (a scene): their content is part of the sweep's identity
//! ([`SweepId::with_file`]), and a copy of each is kept in the output directory. Rows
//! computed from one content of a file are then never resumed, nor merged, with rows of
//! another, and `merge` reads the copy, wherever it runs, instead of a path relative to
//! the directory the sweep ran in.

use crate::{checksum, rowlog::logged_sweep, ShardError, SweepId};
use std::path::Path;

/// A file a sweep reads, as it read it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputFile {
    /// The name of its copy in the output directory (`scene.toml`), or its path there
    /// (`records/quake.AT2`: the folder is made).
    pub copy: String,
    /// The file as the user named it, for messages (`scene my.toml`).
    pub source: String,
    /// Its content.
    pub bytes: Vec<u8>,
}

/// Keeps a copy of each of `files` in `dir`, for the sweep `id`, after checking that the
/// rows `dir` already holds of the same command were computed from the same content of
/// each file. Call it before the row log is opened: an edited file would otherwise make
/// another sweep, and its rows would replace the old ones without a word.
///
/// # Errors
/// A file whose content differs from the one the rows of `dir` were computed from (the
/// message names the file, the first line that differs, and how to start afresh); an
/// unreadable row log; an unwritable directory.
pub fn keep_inputs(dir: &Path, id: &SweepId, files: &[InputFile]) -> Result<(), ShardError> {
    if let Some(logged) = logged_sweep(dir)? {
        let changed = files.iter().find(|f| {
            logged.command == id.command
                && logged
                    .files
                    .get(&f.copy)
                    .is_some_and(|then| *then != checksum(&f.bytes))
        });
        if let Some(file) = changed {
            return Err(changed_since_the_rows(dir, file));
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| ShardError::io(dir, e))?;
    for f in files {
        let path = dir.join(&f.copy);
        // A copy may sit in a folder of its own (`records/quake.AT2`).
        let folder = path.parent().unwrap_or(dir);
        std::fs::create_dir_all(folder).map_err(|e| ShardError::io(folder, e))?;
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let tmp = folder.join(format!(".tmp-{}-{name}", std::process::id()));
        std::fs::write(&tmp, &f.bytes).map_err(|e| ShardError::io(&tmp, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| ShardError::io(&path, e))?;
    }
    Ok(())
}

fn changed_since_the_rows(dir: &Path, file: &InputFile) -> ShardError {
    let kept = dir.join(&file.copy);
    let what = std::fs::read(&kept).map_or_else(
        |_| "its content differs".to_owned(),
        |old| {
            first_difference(&old, &file.bytes).map_or_else(
                || "its line ends or spaces differ".to_owned(),
                |(line, old, new)| format!("line {line} is {new}, was {old}"),
            )
        },
    );
    ShardError::InputChanged(format!(
        "{} differs from the one the rows in {} were computed from ({}): {what}; to start \
         afresh, remove {} or give another --out",
        file.source,
        dir.display(),
        kept.display(),
        dir.display()
    ))
}

/// The first line where `a` and `b` differ (counted from 1) and that line of each, quoted,
/// or `(none)` past the end; `None` when their lines agree (the bytes may still differ in
/// line ends).
pub(crate) fn first_difference(a: &[u8], b: &[u8]) -> Option<(usize, String, String)> {
    let (a, b) = (String::from_utf8_lossy(a), String::from_utf8_lossy(b));
    let (mut la, mut lb) = (a.lines(), b.lines());
    let show = |l: Option<&str>| {
        l.map_or_else(
            || "(none)".to_owned(),
            |l| format!("`{}`", l.chars().take(80).collect::<String>()),
        )
    };
    (1..).find_map(|n| match (la.next(), lb.next()) {
        (None, None) => Some(None),
        (x, y) if x != y => Some(Some((n, show(x), show(y)))),
        _ => None,
    })?
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RowLog;
    use serde_json::json;

    fn scene(text: &str) -> InputFile {
        InputFile {
            copy: "scene.toml".into(),
            source: "scene my.toml".into(),
            bytes: text.as_bytes().to_vec(),
        }
    }

    #[test]
    fn rows_of_another_content_are_refused_and_a_copy_is_kept() {
        let dir = std::env::temp_dir().join(format!("shards-inputs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let old = scene("[contact]\nmu = 0.2\n");
        let id = |f: &InputFile| SweepId::new("t", json!({}), "1").with_file(&f.copy, &f.bytes);
        keep_inputs(&dir, &id(&old), std::slice::from_ref(&old)).unwrap();
        RowLog::open(&dir, &id(&old)).unwrap();
        assert_eq!(std::fs::read(dir.join("scene.toml")).unwrap(), old.bytes);
        let new = scene("[contact]\nmu = 0.5\n");
        let err = keep_inputs(&dir, &id(&new), std::slice::from_ref(&new))
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("scene my.toml differs from the one the rows in")
                && err.contains("line 2 is `mu = 0.5`, was `mu = 0.2`")
                && err.contains("remove"),
            "{err}"
        );
        assert_eq!(std::fs::read(dir.join("scene.toml")).unwrap(), old.bytes);
        // Another command in the directory is another sweep: it starts over.
        let other = SweepId::new("u", json!({}), "1").with_file("scene.toml", &new.bytes);
        keep_inputs(&dir, &other, std::slice::from_ref(&new)).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_first_differing_line_is_named() {
        let d = |a: &str, b: &str| first_difference(a.as_bytes(), b.as_bytes());
        assert_eq!(d("a\nb\n", "a\nb\n"), None);
        assert_eq!(d("a\nb", "a\nb\n"), None);
        assert_eq!(d("a\nb\n", "a\nc\n"), Some((2, "`b`".into(), "`c`".into())));
        assert_eq!(d("a\n", "a\nc\n"), Some((2, "(none)".into(), "`c`".into())));
    }
}
