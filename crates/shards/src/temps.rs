//! Temporary files a killed run left behind. Outputs are written to a temporary sibling
//! `.tmp-PID-NAME` and renamed into place; a run killed before the rename leaves the
//! sibling, which for a long trajectory is hundreds of megabytes.

use crate::ShardError;
use std::path::{Path, PathBuf};

/// Removes the temporary files `.tmp-PID-NAME` in `dir` whose process is gone (another
/// PID than ours, and, where `/proc` exists, no such process), and returns them. Call it
/// when a run starts writing into `dir`.
///
/// # Errors
/// When `dir` cannot be listed or a file cannot be removed; a missing `dir` has none.
pub fn remove_stale_temps(dir: &Path) -> Result<Vec<PathBuf>, ShardError> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(Vec::new());
    };
    let ours = std::process::id();
    let proc_fs = Path::new("/proc/self").exists();
    let mut removed = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| ShardError::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(".tmp-")
            .and_then(|rest| rest.split_once('-'))
            .and_then(|(pid, _)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let alive = pid == ours || (proc_fs && Path::new(&format!("/proc/{pid}")).exists());
        if !alive && entry.file_type().is_ok_and(|t| t.is_file()) {
            let path = entry.path();
            std::fs::remove_file(&path).map_err(|e| ShardError::io(&path, e))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_only_the_files_of_dead_processes() {
        let dir = std::env::temp_dir().join(format!("shards-temps-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // PIDs above the kernel's limit (2^22) belong to no process.
        let dead = dir.join(".tmp-4999999-trajectory.csv");
        let ours = dir.join(format!(".tmp-{}-trajectory.csv", std::process::id()));
        let kept = dir.join("trajectory.csv");
        for f in [&dead, &ours, &kept] {
            std::fs::write(f, "x").unwrap();
        }
        assert_eq!(remove_stale_temps(&dir).unwrap(), vec![dead.clone()]);
        assert!(!dead.exists() && ours.exists() && kept.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
