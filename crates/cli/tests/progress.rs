//! Progress on stderr: a resumed sweep always says how many rows it reused; a run whose
//! stderr is not a terminal prints no progress bar, and stdout stays the result only.

mod common;

use common::{run, temp_dir, SWEEP};
use std::path::Path;

/// Runs the sweep into `dir`: its stderr.
fn sweep_into(dir: &Path) -> String {
    let mut args = SWEEP.to_vec();
    args.extend(["--out", dir.to_str().expect("a UTF-8 path")]);
    let (ok, _, stderr) = run(&args);
    assert!(ok, "{stderr}");
    stderr
}

/// Keeps the header and the first `rows` rows of the row log of `dir`, as a run killed
/// after `rows` rows leaves it.
fn cut_row_log(dir: &Path, rows: usize) {
    let path = dir.join("rows.log");
    let text = std::fs::read_to_string(&path).expect("a row log");
    let kept: String = text.split_inclusive('\n').take(rows + 1).collect();
    std::fs::write(&path, kept).expect("the row log is writable");
}

#[test]
fn a_resumed_sweep_says_how_many_rows_it_reused() {
    let dir = temp_dir("progress-resume");
    let first = sweep_into(&dir);
    assert!(!first.contains("resumed"), "a fresh sweep: {first}");
    cut_row_log(&dir, 3);
    let again = sweep_into(&dir);
    let line = format!(
        "resumed the sweep in {}: 3 of 8 rows reused from its row log, 5 to compute",
        dir.display()
    );
    assert!(again.contains(&line), "expected {line:?} in {again:?}");
    let whole = sweep_into(&dir);
    assert!(whole.contains("8 of 8 rows reused"), "{whole}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Signs of a progress bar: carriage returns, cursor movement, the bar's own words.
fn has_progress_noise(stderr: &str) -> bool {
    stderr.contains('\r') || stderr.contains('\u{1b}') || stderr.contains("(eta ")
}

#[test]
fn runs_with_stderr_not_a_terminal_print_no_progress() {
    let shake = ["blocks", "shake", "--blocks", "2", "--periods", "1"];
    let (ok, stdout, stderr) = run(&shake);
    assert!(ok, "{stderr}");
    assert!(!has_progress_noise(&stderr), "{stderr:?}");
    assert!(!has_progress_noise(&stdout), "{stdout:?}");
    let dir = temp_dir("progress-quiet-sweep");
    let stderr = sweep_into(&dir);
    assert!(!has_progress_noise(&stderr), "{stderr:?}");
    let _ = std::fs::remove_dir_all(dir);
}

/// What `rollstack ARGS` writes to a terminal (stdout and stderr both on a pseudo
/// terminal, by util-linux's `script`); None where `script` is not installed.
fn on_a_terminal(args: &str) -> Option<String> {
    let bin = env!("CARGO_BIN_EXE_rollstack");
    let out = std::process::Command::new("script")
        .args(["-qec", &format!("'{bin}' {args}"), "/dev/null"])
        .output()
        .ok()?;
    assert!(out.status.success(), "{args}: {out:?}");
    Some(String::from_utf8_lossy(&out.stdout).into_owned())
}

#[test]
fn a_single_run_on_a_terminal_shows_its_progress_but_not_with_json() {
    let shake = "blocks shake --blocks 6 --periods 20";
    let Some(shown) = on_a_terminal(shake) else {
        eprintln!("skipped: no `script` to make a terminal");
        return;
    };
    assert!(
        shown.contains("blocks shake [") && shown.contains("% of t"),
        "{shown:?}"
    );
    let json = on_a_terminal(&format!("{shake} --json")).expect("`script` ran once");
    // The terminal turns each newline into \r\n: only the bar's own marks count here.
    assert!(
        !json.contains("(eta ") && !json.contains('\u{1b}'),
        "{json:?}"
    );
    assert!(json.trim_start().starts_with('{'), "{json:?}");
}

/// `command` (its words split at spaces) prints no progress when stderr is not a
/// terminal, shows `stage` on a terminal, and nothing of the kind with `--json`.
fn alive_on_a_terminal_only(command: &str, stage: &str) {
    let (ok, _, stderr) = run(&command.split(' ').collect::<Vec<_>>());
    assert!(ok, "{stderr}");
    assert!(!has_progress_noise(&stderr), "{stderr:?}");
    let Some(shown) = on_a_terminal(command) else {
        eprintln!("skipped: no `script` to make a terminal");
        return;
    };
    assert!(shown.contains(stage), "{shown:?}");
    let json = on_a_terminal(&format!("{command} --json")).expect("`script` ran once");
    assert!(!json.contains('\u{1b}'), "{json:?}");
}

#[test]
fn cylinder_pair_shows_it_is_alive_on_a_terminal_only() {
    alive_on_a_terminal_only(
        "cylinder pair --theta 30deg --steps 300",
        "cylinder pair: solving",
    );
}

#[test]
fn blocks_explore_shows_its_branches_on_a_terminal_only() {
    alive_on_a_terminal_only(
        "blocks explore shaking --t-end 0.5 --max-branches 4",
        "branches [",
    );
}

#[test]
fn nsga_work_precision_shows_it_is_alive_on_a_terminal_only() {
    alive_on_a_terminal_only(
        "nsga work-precision --system oscillator --dts 0.01,0.005",
        "nsga work-precision: solving",
    );
}
