//! Output files: atomic writes, CSV with a header row, JSON on stdout, and `run.json`.
//!
//! docs/architecture.md (Conventions): files are written atomically (temp file, then rename) so an
//! interrupted run never leaves a partial file; `--json` prints one object on stdout.

use anyhow::{Context, Result};
use serde::Serialize;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Creates `dir` (and parents) if needed, and removes the temporary files a killed
/// earlier run left there ([`shards::remove_stale_temps`]: a trajectory can be 500 MB).
/// The directory is remembered so that a command that fails removes its own
/// temporaries there ([`remove_own_temps`]).
///
/// # Errors
/// When the directory cannot be created or cleaned.
pub fn ensure_dir(dir: &Path) -> Result<()> {
    fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    if let Ok(mut dirs) = OUTPUT_DIRS.lock() {
        if !dirs.iter().any(|d| d == dir) {
            dirs.push(dir.to_owned());
        }
    }
    Ok(shards::remove_stale_temps(dir).map(drop)?)
}

/// The output directories of this process ([`ensure_dir`]).
static OUTPUT_DIRS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes this process's temporary files (`.tmp-PID-NAME`, [`temp_sibling`]) from every
/// output directory it used: a command that fails (a full disk, an error midway) leaves
/// none behind, whichever library was writing. Call it only once the command has
/// ended. Best effort: a file that cannot be removed is left.
pub fn remove_own_temps() {
    let dirs = OUTPUT_DIRS.lock().map(|d| d.clone()).unwrap_or_default();
    remove_own_temps_in(&dirs);
}

/// [`remove_own_temps`] in `dirs` only.
fn remove_own_temps_in(dirs: &[PathBuf]) {
    let prefix = format!(".tmp-{}-", std::process::id());
    for dir in dirs {
        let Ok(entries) = fs::read_dir(dir) else {
            continue;
        };
        for entry in entries.flatten() {
            if entry.file_name().to_string_lossy().starts_with(&prefix) {
                let _ = fs::remove_file(entry.path());
            }
        }
    }
}

pub use figures::file::temp_sibling;

/// Writes `bytes` to `path` atomically: a temporary sibling first, then a rename.
///
/// # Errors
/// When the file cannot be written or renamed (the error names `path`; the temporary
/// is removed).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_through(path, |tmp| fs::File::create(tmp), bytes)
}

/// [`write_atomic`] through the writer `create` opens on the temporary sibling (a file;
/// in tests, one that fails midway): on any failure the temporary is removed and the
/// error names `path`, never the temporary.
fn write_atomic_through<W: Write>(
    path: &Path,
    create: impl FnOnce(&Path) -> std::io::Result<W>,
    bytes: &[u8],
) -> Result<()> {
    let tmp = temp_sibling(path);
    let written = create(&tmp).and_then(|mut w| {
        w.write_all(bytes)?;
        w.flush()
    });
    if let Err(e) = written {
        discard_temp(path);
        return Err(anyhow::Error::new(e).context(format!("cannot write {}", path.display())));
    }
    commit_temp(path)
}

/// Finishes a file produced at [`temp_sibling`]`(path)` by renaming it into place.
///
/// # Errors
/// When the rename fails (the temporary is removed).
pub fn commit_temp(path: &Path) -> Result<()> {
    figures::file::commit_temp(path).map_err(|e| {
        discard_temp(path);
        anyhow::Error::new(e).context(format!("cannot write {}", path.display()))
    })
}

/// Removes the temporary sibling of `path` after a failed write (best effort: it may
/// not have been created).
pub fn discard_temp(path: &Path) {
    let _ = fs::remove_file(temp_sibling(path));
}

/// Writes a CSV file with a header row, atomically. Rows are cells a library formatted
/// (the `csv_cells` of its reports, numbers in shortest round-trip form); a non-finite
/// number (`NaN`, `inf`, `-inf`) is refused, so that none reaches a file.
///
/// # Errors
/// When a cell is not finite, a row has the wrong length or the file cannot be written.
pub fn write_csv<I, R>(path: &Path, header: &[&str], rows: I) -> Result<()>
where
    I: IntoIterator<Item = R>,
    R: IntoIterator,
    R::Item: AsRef<str>,
{
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header)?;
    for row in rows {
        let row: Vec<String> = row.into_iter().map(|c| c.as_ref().to_owned()).collect();
        anyhow::ensure!(
            row.len() == header.len(),
            "internal: CSV row of {} cells for {} columns in {}",
            row.len(),
            header.len(),
            path.display()
        );
        if let Some(v) = row
            .iter()
            .find(|c| matches!(c.as_str(), "NaN" | "inf" | "-inf"))
        {
            anyhow::bail!(
                "refusing to write non-finite value {v} to {}",
                path.display()
            );
        }
        w.write_record(&row)?;
    }
    let bytes = w.into_inner().context("cannot flush CSV")?;
    write_atomic(path, &bytes)
}

/// Serialises `value` as pretty JSON into `path`, atomically.
///
/// # Errors
/// When serialisation or writing fails.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    write_atomic(path, text.as_bytes())
}

/// Prints one JSON object on stdout (the `--json` contract).
///
/// # Errors
/// When serialisation fails, or stdout cannot be written (a full disk).
pub fn print_json(value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string(value)?;
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .map_err(stdout_error)
}

/// The error of a failed write to stdout, in one line.
#[must_use]
pub fn stdout_error(e: std::io::Error) -> anyhow::Error {
    anyhow::Error::new(e).context("cannot write to stdout")
}

/// Writes `run.json` into `dir`: the command, its inputs, the rollstack version and timings.
///
/// # Errors
/// When the file cannot be written.
pub fn write_run_json(
    dir: &Path,
    command: &str,
    inputs: &impl Serialize,
    timings: &impl Serialize,
) -> Result<()> {
    write_run_json_with(dir, command, inputs, timings, &serde_json::Map::new())
}

/// Writes `run.json` as [`write_run_json`] with the keys of `extra` after `timings`
/// (the block simulations' `scene`, `warnings`, `notes` and `error`).
///
/// # Errors
/// When the file cannot be written.
pub fn write_run_json_with(
    dir: &Path,
    command: &str,
    inputs: &impl Serialize,
    timings: &impl Serialize,
    extra: &serde_json::Map<String, serde_json::Value>,
) -> Result<()> {
    let mut record = serde_json::Map::new();
    record.insert("command".into(), command.into());
    record.insert("version".into(), env!("CARGO_PKG_VERSION").into());
    record.insert("inputs".into(), serde_json::to_value(inputs)?);
    record.insert("timings".into(), serde_json::to_value(timings)?);
    for (k, v) in extra {
        record.insert(k.clone(), v.clone());
    }
    write_json(&dir.join("run.json"), &record)
}

/// Rejects a non-finite number with a message naming it.
///
/// # Errors
/// When `value` is NaN or infinite.
pub fn require_finite(name: &str, value: f64) -> Result<f64> {
    anyhow::ensure!(
        value.is_finite(),
        "{name} must be a finite number, got {value}"
    );
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer whose disk is full after `room` bytes.
    struct FullAfter {
        file: fs::File,
        room: usize,
    }

    impl Write for FullAfter {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.room == 0 {
                return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
            }
            let n = buf.len().min(self.room);
            self.room -= n;
            self.file.write(&buf[..n])
        }

        fn flush(&mut self) -> std::io::Result<()> {
            self.file.flush()
        }
    }

    #[test]
    fn a_full_disk_leaves_no_temporary_and_names_the_destination() {
        let dir = std::env::temp_dir().join(format!("rollstack-full-{}", std::process::id()));
        ensure_dir(&dir).unwrap();
        let p = dir.join("a.csv");
        let full = |tmp: &Path| fs::File::create(tmp).map(|file| FullAfter { file, room: 5 });
        let e = write_atomic_through(&p, full, b"x,y\n1,2\n").unwrap_err();
        let message = format!("{e:#}");
        assert!(message.contains(&p.display().to_string()), "{message}");
        assert!(!message.contains(".tmp-"), "{message}");
        assert!(message.contains("No space left on device"), "{message}");
        let left: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert!(left.is_empty(), "{left:?}");
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_failed_command_removes_its_own_temporaries() {
        let dir = std::env::temp_dir().join(format!("rollstack-temps-{}", std::process::id()));
        ensure_dir(&dir).unwrap();
        let ours = temp_sibling(&dir.join("plot.png"));
        let other = dir.join(".tmp-1-plot.png");
        let kept = dir.join("plot.png");
        for f in [&ours, &other, &kept] {
            fs::write(f, "x").unwrap();
        }
        // The directory is one of this process's output directories; only its own
        // temporaries go. (Not `remove_own_temps` itself: tests run in one process, and
        // it would remove the temporaries that other tests are writing.)
        assert!(OUTPUT_DIRS.lock().unwrap().contains(&dir));
        remove_own_temps_in(std::slice::from_ref(&dir));
        assert!(!ours.exists() && other.exists() && kept.exists());
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn atomic_csv_roundtrip() {
        let dir = std::env::temp_dir().join(format!("rollstack-out-{}", std::process::id()));
        ensure_dir(&dir).unwrap();
        let p = dir.join("a.csv");
        let cells = |r: &[f64]| r.iter().map(f64::to_string).collect::<Vec<_>>();
        write_csv(&p, &["x", "y"], [cells(&[1.0, 2.5]), cells(&[-0.1, 3.0])]).unwrap();
        let text = fs::read_to_string(&p).unwrap();
        assert_eq!(text, "x,y\n1,2.5\n-0.1,3\n");
        assert!(write_csv(&p, &["x", "y"], [["1"]]).is_err());
        assert!(write_csv(&p, &["x"], [cells(&[1.0]), cells(&[f64::NAN])]).is_err());
        assert!(write_csv(&p, &["x"], [cells(&[f64::INFINITY])]).is_err());
        assert!(write_csv(&p, &["x"], [cells(&[f64::NEG_INFINITY])]).is_err());
        // the failed writes left the good file in place
        assert_eq!(fs::read_to_string(&p).unwrap(), text);
        fs::remove_dir_all(dir).unwrap();
    }
}
