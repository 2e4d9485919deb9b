//! Numbers the docs quote from rollstack's runs, checked against the (debug) binary, so
//! that they cannot drift: the cheap counts that `scripts/doc_numbers.py` writes between
//! markers, and what the tour's text says its runs print. The matrix of method.md and
//! tuning.md takes minutes: `scripts/doc_numbers.py BIN --check` checks it.

mod common;

use serde_json::Value;

const METHOD: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/method.md"));
const EXPLORATION: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../docs/exploration.md"
));
const CLI: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md"));

/// The text between `<!-- NAME: begin -->` and `<!-- NAME: end -->` of `page`.
fn marked<'a>(page: &'a str, name: &str) -> &'a str {
    let begin = format!("<!-- {name}: begin -->");
    let end = format!("<!-- {name}: end -->");
    let start = page.find(&begin).unwrap_or_else(|| panic!("no {begin}")) + begin.len();
    let len = page[start..]
        .find(&end)
        .unwrap_or_else(|| panic!("no {end}"));
    &page[start..start + len]
}

/// The number written after `label` in `text`, its digit groups joined ("369 344").
fn count_after(text: &str, label: &str) -> u64 {
    let text = text.replace('\n', " ");
    let at = text
        .find(label)
        .unwrap_or_else(|| panic!("no '{label}' in {text:?}"));
    let digits: String = text[at + label.len()..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == ' ')
        .filter(char::is_ascii_digit)
        .collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("no count after '{label}'"))
}

/// A workload of `scripts/reference_workload.py`: its `--json` report.
fn workload(args: &[&str]) -> Value {
    let out = common::rollstack(args);
    serde_json::from_slice(&out.stdout).unwrap_or_else(|_| panic!("{args:?}: no JSON report"))
}

#[test]
fn method_md_quotes_the_reference_workloads_linear_solves() {
    let quoted = marked(METHOD, "reference_counts");
    let lire = ["blocks", "lire", "--perturb", "bottom", "--json"];
    let floor = ["blocks", "lire", "--perturb", "bottom", "--floor", "--json"];
    let kicked = [
        "blocks",
        "shake",
        "--blocks",
        "30",
        "--omega",
        "2",
        "--amplitude",
        "0.001",
        "--mu",
        "0.2",
        "--steps-per-period",
        "314",
        "--t-end",
        "1",
        "--json",
        "--force",
    ];
    for (label, args) in [
        ("Lire collapse", &lire[..]),
        ("on a floor", &floor[..]),
        ("kicked 30-block column", &kicked[..]),
    ] {
        let report = workload(args);
        assert_eq!(
            report["linear_solves"].as_u64(),
            Some(count_after(quoted, label)),
            "{label}: docs/method.md §8.3 differs from `rollstack {}` (scripts/doc_numbers.py rewrites it)",
            args.join(" ")
        );
        if quoted.contains("no unresolved or last-resort step") {
            assert_eq!(report["fallback_steps"].as_u64(), Some(0), "{label}");
        }
    }
}

#[test]
fn exploration_md_quotes_the_lire_collapses_failure_times() {
    let quoted = marked(EXPLORATION, "lire_convergence").replace('\n', " ");
    let report = common::json(&[
        "blocks",
        "converge",
        "lire-collapse",
        "--levels",
        "2",
        "--ensemble",
        "0",
        "--t-end",
        "7",
        "--json",
    ]);
    let times: Vec<String> = report["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| format!("{:.3}", r["failure_time"].as_f64().unwrap()))
        .collect();
    let verdict = report["failure"]["verdict"].as_str().unwrap();
    let expected = format!(
        "fails at {}, {} and {} at Δt = 0.01, Δt/2 and Δt/4 ({verdict}",
        times[0], times[1], times[2]
    );
    assert_eq!(quoted, expected, "scripts/doc_numbers.py rewrites it");
}

/// The decimal numbers a text quotes as times: after "t = ", "t ≈ " and, in "between
/// t ≈ A and B", B.
fn quoted_times(text: &str) -> Vec<String> {
    let text = text.replace('\n', " ");
    let number = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect::<String>()
            .trim_end_matches('.')
            .to_owned()
    };
    let mut out = Vec::new();
    for prefix in ["t = ", "t ≈ "] {
        for (i, _) in text.match_indices(prefix) {
            let first = number(&text[i + prefix.len()..]);
            let rest = &text[i + prefix.len() + first.len()..];
            if !first.is_empty() {
                out.push(first);
            }
            if let Some(second) = rest.strip_prefix(" and ") {
                out.push(number(second));
            }
        }
    }
    out.retain(|n| !n.is_empty());
    out
}

/// Whether `quoted` is some number of `shown` rounded to `quoted`'s decimals.
fn rounds_from(quoted: &str, shown: &str) -> bool {
    let decimals = quoted.split_once('.').map_or(0, |(_, d)| d.len());
    let Ok(q) = quoted.parse::<f64>() else {
        return false;
    };
    shown
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|w| w.trim_end_matches('.').parse::<f64>().ok())
        .any(|v| format!("{v:.decimals$}") == format!("{q:.decimals$}"))
}

#[test]
fn the_tour_quotes_only_times_its_checked_transcripts_print() {
    // A step marked `checked` says what its run prints; docs/cli.md shows that run as a
    // transcript, which cli_doc runs. Each time its text quotes is one of the transcript's
    // numbers (or of its command line, the horizon), rounded as quoted.
    let shown = common::transcripts(CLI);
    let mut quotes = 0;
    for section in rollstack_cli::tour::sections().unwrap() {
        for step in section.steps.iter().filter(|s| s.checked) {
            let transcript = shown
                .iter()
                .find(|t| t.args.join(" ") == step.args)
                .unwrap_or_else(|| panic!("no transcript of `rollstack {}`", step.args));
            let printed = format!("{} {}", step.args, transcript.lines.join("\n"));
            for t in quoted_times(&step.text) {
                quotes += 1;
                assert!(
                    rounds_from(&t, &printed),
                    "the tour's `rollstack {}` says t = {t}, which its transcript in docs/cli.md does not print",
                    step.args
                );
            }
        }
    }
    assert!(quotes >= 4, "the sweeps' quoted failure times are read");
}

#[test]
fn the_times_a_text_quotes_are_read() {
    let text = "fail, the last at t ≈ 31.9, and from ω = 20 on they stand at t = 40.\nAt ω = 8 between t ≈ 15.05 and 17.42; the plain run at t = 15.06.";
    assert_eq!(
        quoted_times(text),
        ["40", "15.06", "31.9", "15.05", "17.42"]
    );
    assert!(rounds_from("31.9", "failure at t = 31.8872, 8120 steps"));
    assert!(!rounds_from("31.8", "failure at t = 31.8872, 8120 steps"));
    assert!(rounds_from("40", "none by t = 40.0000"));
}

#[test]
fn the_tour_says_how_many_motions_figure_4_5s_setting_has() {
    let plans = rollstack_cli::tour::sections().unwrap();
    let step = plans
        .iter()
        .flat_map(|s| &s.steps)
        .find(|s| s.args.starts_with("blocks explore abundance"))
        .expect("the tour explores Figure 4.5's setting");
    let report = common::json(&["blocks", "explore", "abundance", "--json"]);
    let outcomes = report["distinct_outcomes"].as_u64().unwrap();
    let said = match outcomes {
        1 => "there is one.".to_owned(),
        n => format!("there are {n}."),
    };
    assert!(
        step.text.ends_with(&said),
        "the tour's text on `rollstack {}` should end with '{said}' (the run finds {outcomes} distinct outcomes)",
        step.args
    );
}

#[test]
fn cli_md_states_the_limits_and_the_guards_constants() {
    use blockstack::scene::MAX_BLOCKS;
    use blockstack::scene_file::MAX_SCENE_BYTES;
    use blockstack::time_guard::{
        CALIBRATION_STEPS, CALIBRATION_TIMEOUT_S, CALIBRATION_WALL_S, SECONDS_PER_BLOCK_STEP,
    };
    use input::watchdog::{TIME_BOUND_S, WATCHDOG_GRACE_S};
    let start = CLI
        .find("*Limits and the time guard.*")
        .expect("the paragraph");
    let words: Vec<&str> = CLI[start..].split_whitespace().take(400).collect();
    let text = words.join(" ");
    let minutes = TIME_BOUND_S / 60.0;
    let minutes = if minutes == 10.0 {
        "ten".to_owned()
    } else {
        minutes.to_string()
    };
    for stated in [
        format!("at most {MAX_BLOCKS} blocks"),
        format!("up to {} MiB", MAX_SCENE_BYTES >> 20),
        format!("at {} µs per block and step", SECONDS_PER_BLOCK_STEP * 1e6),
        format!("at most {CALIBRATION_STEPS} steps or {CALIBRATION_WALL_S} s"),
        format!("at most {CALIBRATION_TIMEOUT_S} s waited for the first step"),
        format!("over {minutes} minutes refuses to start"),
        format!("after the first {WATCHDOG_GRACE_S} s"),
    ] {
        assert!(
            text.contains(&stated),
            "docs/cli.md, \"Limits and the time guard\", should say \"{stated}\""
        );
    }
}
