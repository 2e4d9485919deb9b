//! Manifests: what one shard's output directory holds, so that shards can be checked
//! against each other before they are joined ([`merge`]).

use crate::inputs::first_difference;
use crate::{checksum, is_failed, RowLog, Shard, ShardError};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The name of the manifest in a sweep's output directory.
pub const MANIFEST_FILE: &str = "manifest.json";

/// The manifest format this crate writes and reads.
const FORMAT: u32 = 1;

/// What makes two runs parts of one sweep: the same command, the same inputs (the
/// values swept and everything that changes a row, not the shard or the output
/// directory), the same content of every file it reads, and the same rollstack version
/// (another version may compute other rows).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepId {
    /// The command, as `run.json` names it (`blocks sweep frequency`).
    pub command: String,
    /// The inputs that determine the rows.
    pub inputs: Value,
    /// The version of rollstack that computed the rows.
    pub version: String,
    /// The [`checksum`] of each file the sweep reads, by the name of the copy kept in
    /// its output directory (`scene.toml`): the content counts, not the path, so that
    /// an edited file is another sweep and a moved one is not. Absent when none.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub files: BTreeMap<String, String>,
}

impl SweepId {
    /// A sweep's identity, reading no file.
    #[must_use]
    pub fn new(command: impl Into<String>, inputs: Value, version: impl Into<String>) -> Self {
        Self {
            command: command.into(),
            inputs,
            version: version.into(),
            files: BTreeMap::new(),
        }
    }

    /// This sweep reading a file with the content `bytes`, kept as `copy`.
    #[must_use]
    pub fn with_file(mut self, copy: &str, bytes: &[u8]) -> Self {
        self.files.insert(copy.to_owned(), checksum(bytes));
        self
    }
}

/// The manifest of one shard, `manifest.json` beside its CSV and its row log.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The manifest format (1).
    pub format: u32,
    /// The sweep the rows belong to (its keys `command`, `inputs`, `version` are
    /// top-level keys of the file).
    #[serde(flatten)]
    pub sweep: SweepId,
    /// The command line that computed the rows, without the program name; `merge` runs
    /// it again, over all rows, to write the joined outputs.
    pub argv: Vec<String>,
    /// The shard, `K/N`.
    pub shard: String,
    /// Rows of the whole sweep.
    pub total_rows: usize,
    /// The indices of the rows this shard holds, from `start` up to `end` (excluded).
    pub rows: Range<usize>,
    /// How many of them failed (their `error` is set).
    pub failed_rows: usize,
    /// The CSV file of the rows, in the same directory.
    pub csv: String,
    /// [`checksum`] of the CSV file.
    pub csv_checksum: String,
    /// [`checksum`] of the rows' lines in the row log, in index order.
    pub rows_checksum: String,
}

impl Manifest {
    /// The manifest of the rows `rows` (of `total_rows`) of the sweep `sweep`, whose CSV
    /// `csv` and row log are in `dir`.
    ///
    /// # Errors
    /// An unreadable CSV or row log, a row log of another sweep, or one that lacks a row.
    pub fn new(
        sweep: &SweepId,
        argv: Vec<String>,
        shard: Shard,
        total_rows: usize,
        rows: Range<usize>,
        csv: &str,
        dir: &Path,
    ) -> Result<Self, ShardError> {
        let csv_path = dir.join(csv);
        let bytes = std::fs::read(&csv_path).map_err(|e| ShardError::io(&csv_path, e))?;
        let (logged, all) = RowLog::read(dir)?;
        if logged != *sweep {
            return Err(ShardError::corrupt(
                dir.join(crate::ROW_LOG_FILE),
                "holds the rows of another sweep",
            ));
        }
        let (rows_checksum, failed_rows) = rows_summary(dir, &all, &rows)?;
        Ok(Self {
            format: FORMAT,
            sweep: sweep.clone(),
            argv,
            shard: shard.to_string(),
            total_rows,
            rows,
            failed_rows,
            csv: csv.to_owned(),
            csv_checksum: checksum(&bytes),
            rows_checksum,
        })
    }

    /// Writes `manifest.json` into `dir`, atomically.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn write(&self, dir: &Path) -> Result<(), ShardError> {
        let path = dir.join(MANIFEST_FILE);
        let tmp = dir.join(format!(".tmp-{}-{MANIFEST_FILE}", std::process::id()));
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        std::fs::write(&tmp, text).map_err(|e| ShardError::io(&tmp, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| ShardError::io(&path, e))
    }

    /// Reads `manifest.json` from `dir`.
    ///
    /// # Errors
    /// A missing or unreadable manifest, or one of another format.
    pub fn read(dir: &Path) -> Result<Self, ShardError> {
        let path = dir.join(MANIFEST_FILE);
        let text = std::fs::read_to_string(&path).map_err(|e| ShardError::io(&path, e))?;
        let manifest: Self = serde_json::from_str(&text)
            .map_err(|e| ShardError::corrupt(&path, format!("not a shard manifest: {e}")))?;
        if manifest.format != FORMAT {
            return Err(ShardError::corrupt(
                &path,
                format!("manifest format {}, expected {FORMAT}", manifest.format),
            ));
        }
        Ok(manifest)
    }
}

/// The checksum of the log lines of `rows` and how many of them failed.
fn rows_summary(
    dir: &Path,
    all: &BTreeMap<usize, Value>,
    rows: &Range<usize>,
) -> Result<(String, usize), ShardError> {
    let mut text = String::new();
    let mut failed = 0;
    for i in rows.clone() {
        let row = all.get(&i).ok_or_else(|| {
            ShardError::corrupt(dir.join(crate::ROW_LOG_FILE), format!("row {i} is missing"))
        })?;
        failed += usize::from(is_failed(row));
        text.push_str(&format!("{i} {row}\n"));
    }
    Ok((checksum(text.as_bytes()), failed))
}

/// One run of a sweep: which sweep, which shard of it, and how many rows the whole
/// sweep has; it selects the shard's points, resumes their rows, and writes the manifest.
#[derive(Debug, Clone)]
pub struct Run {
    /// The sweep.
    pub id: SweepId,
    /// The shard this run computes.
    pub shard: Shard,
    /// Rows of the whole sweep.
    pub total: usize,
}

impl Run {
    /// The (global index, value) pairs of `all` this run's shard computes.
    #[must_use]
    pub fn select<T: Clone>(&self, all: &[T]) -> Vec<(usize, T)> {
        self.shard.select(all)
    }

    /// The number of failed `rows` (this shard's, in order); with an output directory,
    /// writes its manifest there, for the CSV `csv` already written. `argv` is the
    /// command line, without the program name.
    ///
    /// # Errors
    /// An unreadable CSV or row log, or an unwritable manifest.
    pub fn finish(
        &self,
        out: Option<&Path>,
        argv: Vec<String>,
        csv: &str,
        rows: &[Value],
    ) -> Result<usize, ShardError> {
        if let Some(dir) = out {
            let range = self.shard.range(self.total);
            Manifest::new(&self.id, argv, self.shard, self.total, range, csv, dir)?.write(dir)?;
        }
        Ok(rows.iter().filter(|v| is_failed(v)).count())
    }
}

/// Shards joined by [`merge`].
#[derive(Debug, Clone)]
pub struct Merged {
    /// The sweep.
    pub sweep: SweepId,
    /// The command line of the first shard given.
    pub argv: Vec<String>,
    /// Every row of the sweep, by index.
    pub rows: BTreeMap<usize, Value>,
    /// How many of them failed.
    pub failed_rows: usize,
    /// The content of each file the sweep read, from the copy kept in the shards, by
    /// the name of the copy.
    pub files: BTreeMap<String, Vec<u8>>,
}

/// Checks the shards in `dirs` (in any order) against each other and joins their rows:
/// every manifest names the same sweep (with the same content of the files it read) and
/// the version `version` (the merging program's: it rewrites the outputs with its own
/// code), every row of the sweep is in exactly one shard, and each shard's CSV, rows and
/// kept copies of the files match the checksums of its manifest.
///
/// # Errors
/// A missing or damaged manifest, CSV, row log or kept file; shards of different sweeps
/// (named by the first line of a file that differs) or of another version; rows in no
/// shard or in two (named by index and directory).
pub fn merge(dirs: &[PathBuf], version: &str) -> Result<Merged, ShardError> {
    let first_dir = dirs
        .first()
        .ok_or_else(|| ShardError::Merge("no shard directories given".into()))?;
    let manifests = dirs
        .iter()
        .map(|d| Manifest::read(d))
        .collect::<Result<Vec<_>, _>>()?;
    let first = &manifests[0];
    for (dir, m) in dirs.iter().zip(&manifests).skip(1) {
        if let Some(why) = differs((first_dir.as_path(), first), (dir.as_path(), m)) {
            return Err(ShardError::Merge(format!(
                "{} and {} are not shards of one sweep: {why}",
                first_dir.display(),
                dir.display()
            )));
        }
    }
    if first.sweep.version != version {
        return Err(ShardError::Merge(format!(
            "{} holds rows of rollstack {}; this is rollstack {version}",
            first_dir.display(),
            first.sweep.version
        )));
    }
    check_coverage(dirs, &manifests)?;
    let mut rows = BTreeMap::new();
    let mut failed_rows = 0;
    let mut files = BTreeMap::new();
    for (dir, m) in dirs.iter().zip(&manifests) {
        checked_read(&dir.join(&m.csv), &m.csv_checksum)?;
        for (name, sum) in &m.sweep.files {
            files.insert(name.clone(), checked_read(&dir.join(name), sum)?);
        }
        let (logged, all) = RowLog::read(dir)?;
        let log_path = dir.join(crate::ROW_LOG_FILE);
        if logged != m.sweep {
            return Err(ShardError::corrupt(
                &log_path,
                "holds the rows of another sweep",
            ));
        }
        let (sum, failed) = rows_summary(dir, &all, &m.rows)?;
        if sum != m.rows_checksum {
            return Err(ShardError::corrupt(
                &log_path,
                "its rows do not match the checksum of the manifest",
            ));
        }
        failed_rows += failed;
        rows.extend(all.into_iter().filter(|(i, _)| m.rows.contains(i)));
    }
    Ok(Merged {
        sweep: first.sweep.clone(),
        argv: first.argv.clone(),
        rows,
        failed_rows,
        files,
    })
}

/// The bytes of the file `path` of a shard, which must match `sum` of its manifest.
fn checked_read(path: &Path, sum: &str) -> Result<Vec<u8>, ShardError> {
    let bytes = std::fs::read(path).map_err(|e| ShardError::io(path, e))?;
    if checksum(&bytes) != sum {
        return Err(ShardError::corrupt(
            path,
            "does not match the checksum of its manifest (damaged or changed after the run)",
        ));
    }
    Ok(bytes)
}

/// Why the manifests `a` and `b` (each with its directory) are not of one sweep, or
/// `None`.
fn differs((dir_a, a): (&Path, &Manifest), (dir_b, b): (&Path, &Manifest)) -> Option<String> {
    if a.sweep.command != b.sweep.command {
        return Some(format!(
            "`{}` against `{}`",
            a.sweep.command, b.sweep.command
        ));
    }
    if a.sweep.version != b.sweep.version {
        return Some(format!(
            "rollstack {} against rollstack {}",
            a.sweep.version, b.sweep.version
        ));
    }
    if a.sweep.inputs != b.sweep.inputs {
        let keys = |v: &Value| v.as_object().cloned().unwrap_or_default();
        let (ka, kb) = (keys(&a.sweep.inputs), keys(&b.sweep.inputs));
        let names: Vec<String> = ka
            .keys()
            .chain(kb.keys())
            .filter(|k| ka.get(*k) != kb.get(*k))
            .map(|k| format!("{k} = {} against {}", show(ka.get(k)), show(kb.get(k))))
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        return Some(format!("inputs differ: {}", names.join(", ")));
    }
    if a.sweep.files != b.sweep.files {
        return Some(files_differ(dir_a, dir_b, &a.sweep.files, &b.sweep.files));
    }
    (a.total_rows != b.total_rows)
        .then(|| format!("{} rows against {} rows", a.total_rows, b.total_rows))
}

/// Which file read by the shards in `dir_a` and `dir_b` differs, with its first
/// differing line from the kept copies.
fn files_differ(
    dir_a: &Path,
    dir_b: &Path,
    a: &BTreeMap<String, String>,
    b: &BTreeMap<String, String>,
) -> String {
    let name = a
        .keys()
        .chain(b.keys())
        .find(|k| a.get(*k) != b.get(*k))
        .map_or("", String::as_str);
    let line = match (
        std::fs::read(dir_a.join(name)),
        std::fs::read(dir_b.join(name)),
    ) {
        (Ok(x), Ok(y)) => first_difference(&x, &y).map(|(n, x, y)| {
            format!(
                " (line {n} is {x} in {}, {y} in {})",
                dir_a.display(),
                dir_b.display()
            )
        }),
        _ => None,
    };
    format!("they read different {name}{}", line.unwrap_or_default())
}

fn show(v: Option<&Value>) -> String {
    v.map_or_else(|| "(none)".to_owned(), ToString::to_string)
}

/// Every row in exactly one shard, or an error naming the rows in none and in two.
fn check_coverage(dirs: &[PathBuf], manifests: &[Manifest]) -> Result<(), ShardError> {
    let total = manifests[0].total_rows;
    let mut owner: Vec<Option<usize>> = vec![None; total];
    let mut twice: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (k, m) in manifests.iter().enumerate() {
        if m.rows.end > total {
            return Err(ShardError::Merge(format!(
                "{} holds rows up to {} of a sweep of {total}",
                dirs[k].display(),
                m.rows.end - 1
            )));
        }
        for i in m.rows.clone() {
            match owner[i] {
                Some(j) => twice.entry((j, k)).or_default().push(i),
                None => owner[i] = Some(k),
            }
        }
    }
    let missing: Vec<usize> = (0..total).filter(|&i| owner[i].is_none()).collect();
    let mut problems = Vec::new();
    if !missing.is_empty() {
        problems.push(format!(
            "{} in no shard (a shard missing from the list, or one that did not finish?)",
            ranges(&missing)
        ));
    }
    for ((j, k), rows) in &twice {
        problems.push(format!(
            "{} in both {} and {}",
            ranges(rows),
            dirs[*j].display(),
            dirs[*k].display()
        ));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(ShardError::Merge(problems.join("; ")))
    }
}

/// Sorted indices as `row 4` / `rows 3-7, 9` (at most ten ranges, then a count).
fn ranges(indices: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut k = 0;
    while k < indices.len() {
        let start = indices[k];
        while k + 1 < indices.len() && indices[k + 1] == indices[k] + 1 {
            k += 1;
        }
        let end = indices[k];
        parts.push(if start == end {
            start.to_string()
        } else {
            format!("{start}-{end}")
        });
        k += 1;
    }
    let n = parts.len();
    if n > 10 {
        parts.truncate(10);
        parts.push(format!("and {} more ranges", n - 10));
    }
    let word = if indices.len() == 1 { "row" } else { "rows" };
    format!("{word} {}", parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Shards k/n of a six-row sweep with inputs `inputs`, each in its own directory.
    fn shards(root: &Path, inputs: &Value, parts: &[(usize, usize)]) -> Vec<PathBuf> {
        let id = SweepId::new("t", inputs.clone(), "1");
        parts
            .iter()
            .map(|&(index, count)| {
                let shard = Shard { index, count };
                let dir = root.join(format!("s{index}of{count}-{inputs}"));
                let log = RowLog::open(&dir, &id).unwrap();
                for i in shard.range(6) {
                    let error = if i == 4 {
                        json!("did not converge")
                    } else {
                        json!(null)
                    };
                    log.append(i, &json!({"i": i, "error": error})).unwrap();
                }
                std::fs::write(dir.join("t.csv"), format!("{shard}\n")).unwrap();
                Manifest::new(&id, vec![], shard, 6, shard.range(6), "t.csv", &dir)
                    .unwrap()
                    .write(&dir)
                    .unwrap();
                dir
            })
            .collect()
    }

    fn root(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shards-merge-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn shards_in_any_order_join_and_count_their_failures() {
        let r = root("ok");
        let d = shards(&r, &json!({"x": 1}), &[(3, 3), (1, 3), (2, 3)]);
        let m = merge(&d, "1").unwrap();
        assert_eq!(
            m.rows.keys().copied().collect::<Vec<_>>(),
            (0..6).collect::<Vec<_>>()
        );
        assert_eq!(m.failed_rows, 1);
        std::fs::remove_dir_all(&r).unwrap();
    }

    #[test]
    fn shards_of_two_contents_of_a_file_are_refused_and_kept_copies_checked() {
        let r = root("files");
        let shard = |k: usize, text: &str| {
            let id = SweepId::new("t", json!({}), "1").with_file("scene.toml", text.as_bytes());
            let shard = Shard { index: k, count: 2 };
            let dir = r.join(format!("s{k}-{}", text.len()));
            let file = crate::InputFile {
                copy: "scene.toml".into(),
                source: "scene s.toml".into(),
                bytes: text.as_bytes().to_vec(),
            };
            crate::keep_inputs(&dir, &id, &[file]).unwrap();
            let log = RowLog::open(&dir, &id).unwrap();
            for i in shard.range(4) {
                log.append(i, &json!({"i": i, "error": null})).unwrap();
            }
            std::fs::write(dir.join("t.csv"), "x\n").unwrap();
            Manifest::new(&id, vec![], shard, 4, shard.range(4), "t.csv", &dir)
                .unwrap()
                .write(&dir)
                .unwrap();
            dir
        };
        let (a, b) = (shard(1, "mu = 0.2\n"), shard(2, "mu = 0.25\n"));
        let err = merge(&[a.clone(), b], "1").unwrap_err().to_string();
        assert!(
            err.contains("they read different scene.toml (line 1 is `mu = 0.2` in"),
            "{err}"
        );
        let c = shard(2, "mu = 0.2\n");
        let m = merge(&[a.clone(), c.clone()], "1").unwrap();
        assert_eq!(m.files["scene.toml"], b"mu = 0.2\n");
        std::fs::write(c.join("scene.toml"), "mu = 0.3\n").unwrap();
        let err = merge(&[a, c], "1").unwrap_err().to_string();
        assert!(
            err.contains("scene.toml: does not match the checksum"),
            "{err}"
        );
        std::fs::remove_dir_all(&r).unwrap();
    }

    #[test]
    fn missing_duplicated_foreign_and_damaged_shards_are_named() {
        let r = root("bad");
        let inputs = json!({"x": 1});
        let d = shards(&r, &inputs, &[(1, 3), (2, 3), (3, 3), (2, 2)]);
        let err = merge(&d[..2], "1").unwrap_err().to_string();
        assert!(err.contains("rows 4-5 in no shard"), "{err}");
        let err = merge(&[d[0].clone(), d[1].clone(), d[3].clone()], "1")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("rows 3 in both") || err.contains("row 3 in both"),
            "{err}"
        );
        let other = shards(&r, &json!({"x": 2}), &[(3, 3)]);
        let err = merge(&[d[0].clone(), d[1].clone(), other[0].clone()], "1")
            .unwrap_err()
            .to_string();
        assert!(err.contains("inputs differ: x = 1 against 2"), "{err}");
        std::fs::write(d[2].join("t.csv"), "3/3 changed\n").unwrap();
        let err = merge(&d[..3], "1").unwrap_err().to_string();
        assert!(err.contains("t.csv") && err.contains("checksum"), "{err}");
        std::fs::remove_dir_all(&r).unwrap();
    }
}
