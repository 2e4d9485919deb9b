//! One set of run defaults: the `blocks` commands' solver flags and the Python module's
//! keywords default to `blockstack::RunOptions::default()`, and the flags that only
//! decide what a run records (branch points, and the rule that picks their candidates)
//! leave the run's motion alone.

mod common;

use blockstack::RunOptions;
use clap::CommandFactory;
use common::json;
use rollstack_cli::Cli;
use serde_json::Value;

const PYTHON_SOURCE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../python/src/blocks.rs"
));
const PYTHON_WRAPPERS: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../python/python/rollstack/blocks.py"
));

/// (flag, Python keyword, the library's default as the flag writes it).
fn library_defaults() -> Vec<(&'static str, &'static str, String)> {
    let o = RunOptions::default();
    vec![
        (
            "explore-branches",
            "explore_branches",
            o.explore_branches.to_string(),
        ),
        (
            "last-resort",
            "last_resort",
            (!o.skip_last_resort).to_string(),
        ),
        (
            "low-rank-updates",
            "low_rank_updates",
            (!o.skip_low_rank_updates).to_string(),
        ),
        (
            "branch-rule",
            "branch_rule",
            o.branch_rule.name().replace('_', "-"),
        ),
    ]
}

/// The default of `--flag` in every leaf command under `cmd` that has it: (command, value).
fn flag_defaults(cmd: &clap::Command, path: &str, flag: &str, out: &mut Vec<(String, String)>) {
    let path = format!("{path} {}", cmd.get_name());
    for sub in cmd.get_subcommands() {
        flag_defaults(sub, &path, flag, out);
    }
    for arg in cmd.get_arguments() {
        if let (Some(long), [value]) = (arg.get_long(), arg.get_default_values()) {
            if long == flag {
                out.push((path.clone(), value.to_string_lossy().into_owned()));
            }
        }
    }
}

#[test]
fn the_blocks_commands_default_to_the_library_s_run_options() {
    let cli = Cli::command();
    let blocks = cli.find_subcommand("blocks").expect("a blocks command");
    for (flag, _, expected) in library_defaults() {
        let mut seen = Vec::new();
        flag_defaults(blocks, "", flag, &mut seen);
        assert!(!seen.is_empty(), "no blocks command has --{flag}");
        for (command, value) in seen {
            assert_eq!(value, expected, "--{flag} of{command}");
        }
    }
}

/// Every default the Python module gives `keyword`: in the PyO3 signatures of
/// `src/blocks.rs` (`keyword = true`) and in the wrappers of `blocks.py`
/// (`keyword: bool = True`), lower-cased and without quotes.
fn python_defaults(keyword: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (source, marker) in [
        (PYTHON_SOURCE, format!("{keyword} = ")),
        (PYTHON_WRAPPERS, format!("{keyword}: bool = ")),
        (PYTHON_WRAPPERS, format!("{keyword}: str = ")),
    ] {
        for (at, _) in source.match_indices(&marker) {
            let rest = &source[at + marker.len()..];
            let end = rest.find([',', ')', '\n']).unwrap_or(rest.len());
            out.push(rest[..end].trim().trim_matches('"').to_lowercase());
        }
    }
    out
}

#[test]
fn the_python_module_defaults_to_the_library_s_run_options() {
    for (_, keyword, expected) in library_defaults() {
        let seen = python_defaults(keyword);
        assert!(!seen.is_empty(), "no Python function has {keyword}");
        let expected = expected.replace('-', "_");
        for value in seen {
            assert_eq!(value, expected, "the Python default of {keyword}");
        }
    }
}

/// The plain runs of a frequency sweep, without what differs from run to run or only
/// records (wall time, branch points).
fn plain_rows(extra: &[&str]) -> Vec<Value> {
    let mut args = vec![
        "blocks",
        "sweep",
        "frequency",
        "--omega",
        "5",
        "--t-max",
        "20",
    ];
    args.extend_from_slice(extra);
    args.push("--json");
    let mut out = json(&args);
    let rows = out["rows"].as_array_mut().expect("rows");
    for row in rows.iter_mut() {
        let row = row.as_object_mut().expect("a row");
        row.remove("wall_time_s");
        row.remove("branch_points");
    }
    rows.clone()
}

/// At ω = 5 the column's steps cycle, and some of their fixed-set re-solves converge
/// without being self-consistent: the run is the same whether its branch points are
/// recorded and under either rule.
#[test]
fn recording_branch_points_leaves_the_plain_run_alone() {
    let recorded = plain_rows(&[]);
    assert!(
        recorded[0]["steps"].as_u64().is_some_and(|s| s > 100),
        "{recorded:?}"
    );
    for extra in [
        &["--explore-branches", "false"][..],
        &["--branch-rule", "converged"],
        &["--explore-branches", "false", "--branch-rule", "converged"],
    ] {
        assert_eq!(plain_rows(extra), recorded, "{extra:?}");
    }
}
