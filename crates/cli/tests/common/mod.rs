//! Helpers shared by the CLI integration tests: run the binary, read its JSON.
// Each test file uses a different subset of these helpers.
#![allow(dead_code)]

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

/// A frequency sweep of eight rows, a few tens of milliseconds each.
pub const SWEEP: &[&str] = &[
    "blocks",
    "sweep",
    "frequency",
    "--omega",
    "2:9:1",
    "--periods",
    "2",
    "--blocks",
    "2",
];

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

/// Runs `rollstack` in `dir`: (success, stdout, stderr).
pub fn run_in(dir: &std::path::Path, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rollstack"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs");
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

/// A transcript on a page of docs/: a `text` block whose first line is `$ rollstack ARGS`, then
/// what the command prints (stdout, then stderr), line by line; `…` stands for any lines.
pub struct Transcript {
    /// The arguments after `rollstack`.
    pub args: Vec<String>,
    /// What it prints, as the page shows it.
    pub lines: Vec<String>,
}

/// The transcripts of a page, in order.
pub fn transcripts(text: &str) -> Vec<Transcript> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if line.trim() != "```text" {
            continue;
        }
        let block: Vec<&str> = lines.by_ref().take_while(|l| l.trim() != "```").collect();
        if let Some(command) = block.first().and_then(|l| l.strip_prefix("$ rollstack ")) {
            out.push(Transcript {
                args: command.split_whitespace().map(str::to_owned).collect(),
                lines: block[1..].iter().map(|l| (*l).to_owned()).collect(),
            });
        }
    }
    out
}

/// Whether `seen` reads as `expected`: a line `…` matches any lines, and `…` within a
/// line any text (`500 steps to t = 5.2360 (…)`).
pub fn transcript_matches(expected: &[String], seen: &[&str]) -> bool {
    match expected.split_first() {
        None => seen.is_empty(),
        Some((first, rest)) if first == "…" => {
            (0..=seen.len()).any(|k| transcript_matches(rest, &seen[k..]))
        }
        Some((first, rest)) => {
            seen.first().is_some_and(|line| line_matches(first, line))
                && transcript_matches(rest, &seen[1..])
        }
    }
}

/// Whether `line` reads as `pattern`, each `…` in it matching any text.
fn line_matches(pattern: &str, line: &str) -> bool {
    let mut parts = pattern.split('…');
    let first = parts.next().unwrap_or_default();
    let Some(mut rest) = line.strip_prefix(first) else {
        return false;
    };
    let parts: Vec<&str> = parts.collect();
    let Some((last, middle)) = parts.split_last() else {
        return rest.is_empty();
    };
    for part in middle {
        match rest.find(part) {
            Some(i) => rest = &rest[i + part.len()..],
            None => return false,
        }
    }
    rest.len() >= last.len() && rest.ends_with(last)
}

/// Runs every transcript of `page` in a directory holding only `files` (name, text) and
/// returns how each that prints otherwise differs (none when the page is right); the page
/// must hold at least `least`.
pub fn transcript_failures(
    page: &str,
    tag: &str,
    least: usize,
    files: &[(&str, &str)],
) -> Vec<String> {
    let dir = temp_dir(&format!("{tag}-transcripts"));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let found = transcripts(page);
    assert!(found.len() >= least, "the page's transcripts are read");
    let mut failures = Vec::new();
    for t in &found {
        let args: Vec<&str> = t.args.iter().map(String::as_str).collect();
        let (_, stdout, stderr) = run_in(&dir, &args);
        let printed = format!("{stdout}{stderr}");
        let seen: Vec<&str> = printed.lines().collect();
        if !transcript_matches(&t.lines, &seen) {
            failures.push(format!(
                "$ rollstack {}\n--- the page:\n{}\n--- the program:\n{printed}",
                t.args.join(" "),
                t.lines.join("\n")
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    failures
}
