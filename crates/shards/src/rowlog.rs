//! The row log: the finished rows of a sweep, appended one line each as they finish, in
//! `rows.log` of the output directory. A run killed at any moment leaves at most its
//! last line half-written, without its newline; that line is dropped when the log is
//! opened again, and its row is computed again. A complete line that does not match its
//! checksum is damage (a disk, an edit), and an error rather than a row.
//!
//! Format: a header line `rollstack-rows 1 CHECKSUM SWEEP-JSON`, then one line per row,
//! `INDEX CHECKSUM ROW-JSON`, where CHECKSUM is FNV-1a over 64 bits
//! ([`checksum`](crate::checksum)) of the text after it (header) or of `INDEX ROW-JSON`
//! (row), in 16 hex digits.

use crate::checksum::fnv1a64;
use crate::{ShardError, SweepId};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The name of the row log in a sweep's output directory.
pub const ROW_LOG_FILE: &str = "rows.log";

const MAGIC: &str = "rollstack-rows 1 ";

/// Whether a row failed: its `error` key is set (a run the solver stopped, or one that
/// could not start).
#[must_use]
pub fn is_failed(row: &Value) -> bool {
    row.get("error").is_some_and(|e| !e.is_null())
}

/// An open row log: the rows an earlier run of the same sweep finished, and the file
/// the rows of this run are appended to.
#[derive(Debug)]
pub struct RowLog {
    path: PathBuf,
    file: Mutex<File>,
    rows: BTreeMap<usize, Value>,
    started_over: bool,
}

/// What a log file holds: its sweep, its complete rows, and the length of its complete
/// lines (a half-written tail follows them).
struct Parsed {
    id: SweepId,
    rows: BTreeMap<usize, Value>,
    good_len: usize,
}

impl RowLog {
    /// Opens the row log of `dir` (created with its parents if missing) for the sweep
    /// `id`. The rows of a log of another sweep (other command, inputs or version) are
    /// discarded, so that a directory can be reused for a new sweep; a half-written last
    /// line is cut off.
    ///
    /// # Errors
    /// An unreadable or unwritable file, or a damaged line before the last one.
    pub fn open(dir: &Path, id: &SweepId) -> Result<Self, ShardError> {
        std::fs::create_dir_all(dir).map_err(|e| ShardError::io(dir, e))?;
        let path = dir.join(ROW_LOG_FILE);
        let parsed = match std::fs::read(&path) {
            Ok(bytes) => parse(&path, &bytes)?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(ShardError::io(&path, e)),
        };
        let (rows, good_len, started_over) = match parsed {
            Some(p) if p.id == *id => (p.rows, p.good_len, false),
            Some(_) => (BTreeMap::new(), 0, true),
            None => (BTreeMap::new(), 0, false),
        };
        // Append mode: every line goes to the end, whatever the threads do.
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(|e| ShardError::io(&path, e))?;
        file.set_len(good_len as u64)
            .map_err(|e| ShardError::io(&path, e))?;
        let log = Self {
            path,
            file: Mutex::new(file),
            rows,
            started_over,
        };
        if good_len == 0 {
            log.write_line(&header(id))?;
        }
        Ok(log)
    }

    /// The rows an earlier run finished, by index.
    #[must_use]
    pub fn rows(&self) -> &BTreeMap<usize, Value> {
        &self.rows
    }

    /// Whether the file held the rows of another sweep, now discarded.
    #[must_use]
    pub fn started_over(&self) -> bool {
        self.started_over
    }

    /// The log's file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends row `index`, as one line written by one call, so that rows finished on
    /// several threads never interleave.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn append(&self, index: usize, row: &Value) -> Result<(), ShardError> {
        self.write_line(&record(index, row))
    }

    fn write_line(&self, line: &str) -> Result<(), ShardError> {
        let mut file = self
            .file
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        file.write_all(line.as_bytes())
            .map_err(|e| ShardError::io(&self.path, e))
    }

    /// Reads the row log of `dir` without changing it: its sweep and its complete rows.
    ///
    /// # Errors
    /// A missing, unreadable or damaged log.
    pub fn read(dir: &Path) -> Result<(SweepId, BTreeMap<usize, Value>), ShardError> {
        let path = dir.join(ROW_LOG_FILE);
        let bytes = std::fs::read(&path).map_err(|e| ShardError::io(&path, e))?;
        let parsed = parse(&path, &bytes)?
            .ok_or_else(|| ShardError::corrupt(&path, "no complete header line"))?;
        Ok((parsed.id, parsed.rows))
    }

    /// Writes a complete log of `rows` for the sweep `id` into `dir`, replacing any
    /// there, atomically (a temporary file, then a rename).
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn write_all(
        dir: &Path,
        id: &SweepId,
        rows: &BTreeMap<usize, Value>,
    ) -> Result<(), ShardError> {
        std::fs::create_dir_all(dir).map_err(|e| ShardError::io(dir, e))?;
        let mut text = header(id);
        for (&i, row) in rows {
            text.push_str(&record(i, row));
        }
        let path = dir.join(ROW_LOG_FILE);
        let tmp = dir.join(format!(".tmp-{}-{ROW_LOG_FILE}", std::process::id()));
        std::fs::write(&tmp, text).map_err(|e| ShardError::io(&tmp, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| ShardError::io(&path, e))
    }
}

/// The sweep whose rows the log of `dir` holds, or `None` when there is no log (or not
/// even its header line is complete).
///
/// # Errors
/// An unreadable or damaged log.
pub(crate) fn logged_sweep(dir: &Path) -> Result<Option<SweepId>, ShardError> {
    let path = dir.join(ROW_LOG_FILE);
    match std::fs::read(&path) {
        Ok(bytes) => Ok(parse(&path, &bytes)?.map(|p| p.id)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(ShardError::io(&path, e)),
    }
}

/// Records a finished row in the log: given to the computation by [`resume_rows`].
pub type Record<'a, R> = dyn Fn(usize, &R) -> Result<(), ShardError> + Sync + 'a;

/// The rows of `points` (global index, point) in order, resumed: with an output
/// directory `out`, the rows its log already holds (from a killed run of the same sweep)
/// are read back, and `compute` is given only the lacking points and a [`Record`] to
/// call as each row finishes, so that a run killed later loses only its unfinished rows.
/// `compute` returns the rows of the points it was given, in their order. `complete`
/// says every row must be in the log (a merge): a lacking row is then an error, never a
/// silent recomputation.
///
/// # Errors
/// An unusable log, a row that does not read back, or a lacking row when `complete`.
pub fn resume_rows<P, R, C>(
    out: Option<&Path>,
    id: &SweepId,
    complete: bool,
    points: &[(usize, P)],
    compute: C,
) -> Result<Vec<R>, ShardError>
where
    R: Serialize + DeserializeOwned,
    C: FnOnce(&[&(usize, P)], &Record<'_, R>) -> Vec<Result<R, ShardError>>,
{
    let log = out.map(|dir| RowLog::open(dir, id)).transpose()?;
    let done = |i: &usize| log.as_ref().and_then(|l| l.rows().get(i));
    let lacking: Vec<&(usize, P)> = points.iter().filter(|(i, _)| done(i).is_none()).collect();
    if complete && !lacking.is_empty() {
        return Err(ShardError::Merge(format!(
            "the command line of the manifests does not reproduce the merged sweep \
             ({} rows lacking)",
            lacking.len()
        )));
    }
    let record = |i: usize, row: &R| match &log {
        Some(log) => {
            let value = serde_json::to_value(row)
                .map_err(|e| ShardError::corrupt(log.path(), e.to_string()))?;
            log.append(i, &value)
        }
        None => Ok(()),
    };
    let mut computed = compute(&lacking, &record).into_iter();
    points
        .iter()
        .map(|(i, _)| match (done(i), &log) {
            (Some(v), Some(log)) => serde_json::from_value(v.clone())
                .map_err(|e| ShardError::corrupt(log.path(), format!("row {i}: {e}"))),
            _ => computed
                .next()
                .unwrap_or_else(|| Err(ShardError::Merge(format!("row {i} was not computed")))),
        })
        .collect()
}

fn header(id: &SweepId) -> String {
    let json = serde_json::to_string(id).unwrap_or_default();
    format!("{MAGIC}{:016x} {json}\n", fnv1a64(json.as_bytes()))
}

fn record(index: usize, row: &Value) -> String {
    let body = format!("{index} {row}");
    format!("{index} {:016x} {row}\n", fnv1a64(body.as_bytes()))
}

/// Parses a log; `None` when not even the header line is complete (a run killed at its
/// very start).
fn parse(path: &Path, bytes: &[u8]) -> Result<Option<Parsed>, ShardError> {
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |k| k + 1);
    let text = std::str::from_utf8(&bytes[..complete])
        .map_err(|_| ShardError::corrupt(path, "not UTF-8 text"))?;
    let mut lines = text.lines();
    let Some(first) = lines.next() else {
        return Ok(None);
    };
    let damaged = |n: usize| ShardError::corrupt(path, format!("line {n} is damaged"));
    let (sum, json) = first
        .strip_prefix(MAGIC)
        .and_then(|rest| rest.split_once(' '))
        .ok_or_else(|| ShardError::corrupt(path, "not a rollstack row log"))?;
    if format!("{:016x}", fnv1a64(json.as_bytes())) != sum {
        return Err(damaged(1));
    }
    let id: SweepId = serde_json::from_str(json).map_err(|_| damaged(1))?;
    let mut rows = BTreeMap::new();
    for (k, line) in lines.enumerate() {
        let n = k + 2;
        let mut parts = line.splitn(3, ' ');
        let (Some(index), Some(sum), Some(json)) = (parts.next(), parts.next(), parts.next())
        else {
            return Err(damaged(n));
        };
        let body = format!("{index} {json}");
        if format!("{:016x}", fnv1a64(body.as_bytes())) != sum {
            return Err(damaged(n));
        }
        let index: usize = index.parse().map_err(|_| damaged(n))?;
        let row: Value = serde_json::from_str(json).map_err(|_| damaged(n))?;
        rows.entry(index).or_insert(row);
    }
    Ok(Some(Parsed {
        id,
        rows,
        good_len: complete,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shards-log-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_half_written_line_is_dropped_and_the_log_goes_on() {
        let d = dir("tail");
        let id = SweepId::new("t", json!({"a": 1}), "0");
        let log = RowLog::open(&d, &id).unwrap();
        log.append(0, &json!({"x": 0.1, "error": null})).unwrap();
        log.append(2, &json!({"x": 0.30000000000000004, "error": "boom"}))
            .unwrap();
        drop(log);
        let path = d.join(ROW_LOG_FILE);
        let mut bytes = std::fs::read(&path).unwrap();
        let whole = bytes.len();
        bytes.extend_from_slice(b"5 0123456789abcdef {\"x\":");
        std::fs::write(&path, &bytes).unwrap();
        let log = RowLog::open(&d, &id).unwrap();
        assert_eq!(log.rows().keys().copied().collect::<Vec<_>>(), vec![0, 2]);
        assert_eq!(log.rows()[&2]["x"], json!(0.30000000000000004));
        assert!(is_failed(&log.rows()[&2]) && !is_failed(&log.rows()[&0]));
        log.append(5, &json!({"x": 5})).unwrap();
        drop(log);
        assert!(std::fs::metadata(&path).unwrap().len() > whole as u64);
        let (read_id, rows) = RowLog::read(&d).unwrap();
        assert_eq!((read_id, rows.len()), (id, 3));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn another_sweep_starts_over_and_damage_is_an_error() {
        let d = dir("other");
        let a = SweepId::new("t", json!({"a": 1}), "0");
        let b = SweepId::new("t", json!({"a": 2}), "0");
        RowLog::open(&d, &a).unwrap().append(0, &json!(1)).unwrap();
        let log = RowLog::open(&d, &b).unwrap();
        assert!(log.started_over() && log.rows().is_empty());
        log.append(1, &json!(2)).unwrap();
        drop(log);
        let path = d.join(ROW_LOG_FILE);
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("\n1 ", "\n7 ");
        std::fs::write(&path, text).unwrap();
        let err = RowLog::open(&d, &b).unwrap_err().to_string();
        assert!(err.contains("line 2 is damaged"), "{err}");
        std::fs::remove_dir_all(&d).unwrap();
    }
}
