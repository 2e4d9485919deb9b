//! Sweeps that outgrow one machine: a sweep's rows split into shards, each shard run
//! anywhere (a workstation, a Slurm job array), killed and resumed, and the shards
//! joined into what one machine would have written.
//!
//! - [`Shard`] and [`ShardChoice`]: which contiguous block of a sweep's rows a run
//!   computes, from `--shard K/N` or from a Slurm job array's environment.
//! - [`RowLog`]: an append-only log of finished rows in the output directory, whose
//!   half-written last record (a run killed mid-write) is dropped, never read back; a
//!   resumed run computes only the rows the log lacks.
//! - [`Manifest`]: what a shard holds (the sweep's command and inputs, the version, the
//!   checksums of the files it read, the shard, its row indices, checksums of its CSV and
//!   of its rows), and [`merge`], which checks a set of shards against each other before
//!   joining their rows.
//! - [`InputFile`] and [`keep_inputs`]: a file a sweep reads (a scene) is part of its
//!   identity by its content, and a copy of it is kept in the output directory; rows of
//!   another content are never resumed or merged with its rows.
//! - [`slurm`]: the resources a shard needs, from a calibration run, and the batch
//!   scripts for a job array with a merge job that depends on it.
//!
//! The crate knows nothing of what a row is: rows are JSON values, and a row failed when
//! its `error` key is set. The command line turns them back into its typed rows.
//!
//! ```
//! use shards::{merge, Manifest, RowLog, Shard, SweepId};
//! use serde_json::json;
//!
//! let root = std::env::temp_dir().join(format!("shards-doc-{}", std::process::id()));
//! let id = SweepId::new("square", json!({"x": "0:5:1"}), "1.0.0");
//! let values: Vec<f64> = (0..6).map(f64::from).collect();
//! let mut dirs = Vec::new();
//! for k in 1..=2 {
//!     let shard: Shard = format!("{k}/2").parse()?;
//!     let dir = root.join(format!("part{k}"));
//!     let log = RowLog::open(&dir, &id)?;
//!     for (i, x) in shard.select(&values) {
//!         log.append(i, &json!({"x": x, "square": x * x, "error": null}))?;
//!     }
//!     std::fs::write(dir.join("rows.csv"), format!("part {k}\n"))?;
//!     let rows = shard.range(values.len());
//!     Manifest::new(&id, vec![], shard, values.len(), rows, "rows.csv", &dir)?.write(&dir)?;
//!     dirs.push(dir);
//! }
//! let joined = merge(&dirs, "1.0.0")?;
//! assert_eq!(joined.rows.len(), 6);
//! assert_eq!(joined.rows[&4]["square"], json!(16.0));
//! # std::fs::remove_dir_all(&root)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

mod checksum;
mod inputs;
mod manifest;
mod rowlog;
mod shard;
pub mod slurm;
mod temps;

pub use checksum::checksum;
pub use inputs::{keep_inputs, InputFile};
pub use manifest::{merge, Manifest, Merged, Run, SweepId, MANIFEST_FILE};
pub use rowlog::{is_failed, resume_rows, Record, RowLog, ROW_LOG_FILE};
pub use shard::{Shard, ShardChoice};
pub use temps::remove_stale_temps;

use std::path::PathBuf;

/// Some rows of a sweep failed (their `error` is set). A sweep writes its files first
/// and then ends with this error, which the command line turns into a distinct exit
/// status, so that a job array can tell a shard with failed rows from a good one.
#[derive(Debug, thiserror::Error)]
#[error("{failed} of {rows} rows failed (their error column says why)")]
pub struct RowsFailed {
    /// Rows whose `error` is set.
    pub failed: usize,
    /// Rows of this run.
    pub rows: usize,
}

/// Why a shard, a row log or a merge was refused. Each message names the file or the
/// rows at fault, so that a user can tell which shard to rerun.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// `--shard` text that is neither `K/N` nor `auto`, or `auto` outside a job array.
    #[error("{0}")]
    Shard(String),
    /// A file that could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A row log or manifest that is damaged or not ours.
    #[error("{path}: {message}")]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// Shards that do not join into one sweep.
    #[error("cannot merge: {0}")]
    Merge(String),
    /// A file the sweep reads differs from the one the rows of its output directory
    /// were computed from.
    #[error("{0}")]
    InputChanged(String),
}

impl ShardError {
    fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    fn corrupt(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Corrupt {
            path: path.into(),
            message: message.into(),
        }
    }
}
