//! Helpers shared by the CLI integration tests: run the binary, read its JSON.
// Each test file uses a different subset of these helpers.
#![allow(dead_code)]

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs `rollstack` with `args`.
pub fn rollstack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rollstack"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Runs `rollstack`: (success, stdout, stderr).
pub fn run(args: &[&str]) -> (bool, String, String) {
    let out = rollstack(args);
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `rollstack` and parses its stdout as one JSON object; fails the test on error.
pub fn json(args: &[&str]) -> Value {
    let (ok, stdout, stderr) = run(args);
    assert!(ok, "{args:?} failed: {stderr}");
    serde_json::from_str(&stdout).expect("one JSON object on stdout")
}

/// A fresh, empty temporary directory name for one test.
pub fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rollstack-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}
