//! docs/cli.md against the command line, so that the document cannot drift.
//!
//! - The clap definition (`Cli::command()`) is walked: every leaf command needs a section
//!   headed ``### `rollstack <path>` ``, every flag (and positional, by value name) a row
//!   of that section's table with the flag's exact default, `required` or `off`, and its
//!   possible values; a section or a row for a command or flag that does not exist fails.
//! - Every leaf command is run with small sizes: the keys of its `--json` object (nested
//!   objects included) and of its `run.json` must be exactly the documented lists, the
//!   header of every CSV file it writes exactly the documented columns, and every file it
//!   writes must be named in its section.
//!
//! How the page is read (docs/cli.md, "How this page is checked"): a section runs from its
//! heading to the next `##`/`###` heading. A table row starts with ``| `--flag` |``; its
//! second cell is the default. A key list starts with a line `JSON keys` or
//! ``` `run.json` keys ```, followed by bullets (`- `) up to a blank line; a bullet's keys
//! are the `` `code` `` spans before its first colon, and indented bullets are the keys of
//! the object (or of the objects in the array) above them; a key whose bullet says
//! "keyed by" is a map with data-dependent keys. A column list starts with a paragraph
//! ``CSV columns of `file.csv`:``: the columns are the code spans after that colon and the
//! keys of the bullets that follow. `{k}` in a name stands for a number (`x{k}`: `x1`, …),
//! `{key}` for a dotted scene key (`contact.mu`).

mod common;

use clap::{ArgAction, CommandFactory};
use rollstack_cli::Cli;
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const DOC: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md"));

/// CSV files a section documents that the runs below do not write, and why.
const CSV_NOT_RUN: &[(&str, &str, &str)] = &[(
    "sphere roll",
    "roll_study.csv",
    "`--study` times both integrators on two paths: seconds in a debug build",
)];

// ------------------------------------------------------------------ reading the page

/// The page: the text before the first command section, and each command section by
/// its command path (`blocks lire`).
struct Doc {
    overview: String,
    sections: BTreeMap<String, String>,
    duplicates: Vec<String>,
}

fn read_doc() -> Doc {
    let mut overview = String::new();
    let mut sections = BTreeMap::new();
    let mut duplicates = Vec::new();
    let mut current: Option<(String, String)> = None;
    let mut seen_section = false;
    for line in DOC.lines() {
        let heading = line.starts_with("# ") || line.starts_with("## ") || line.starts_with("### ");
        if heading {
            if let Some((name, body)) = current.take() {
                if sections.insert(name.clone(), body).is_some() {
                    duplicates.push(name);
                }
            }
            if let Some(name) = line
                .strip_prefix("### `rollstack ")
                .and_then(|rest| rest.strip_suffix('`'))
            {
                current = Some((name.to_owned(), String::new()));
                seen_section = true;
                continue;
            }
        }
        if let Some((_, body)) = current.as_mut() {
            body.push_str(line);
            body.push('\n');
        } else if !seen_section {
            overview.push_str(line);
            overview.push('\n');
        }
    }
    if let Some((name, body)) = current {
        if sections.insert(name.clone(), body).is_some() {
            duplicates.push(name);
        }
    }
    Doc {
        overview,
        sections,
        duplicates,
    }
}

/// The `` `code` `` spans of a text.
fn code_spans(text: &str) -> Vec<&str> {
    text.split('`').skip(1).step_by(2).collect()
}

/// A text split at its first colon outside code spans.
fn split_at_colon(text: &str) -> (&str, Option<&str>) {
    let mut in_code = false;
    for (i, c) in text.char_indices() {
        match c {
            '`' => in_code = !in_code,
            ':' if !in_code => return (&text[..i], Some(&text[i + 1..])),
            _ => {}
        }
    }
    (text, None)
}

/// Whether a documented name matches a real one: `{key}` matches a dotted scene key
/// (`contact.mu`, `blocks.0.width`), another `{…}` one or more of `0-9 . -` (block
/// numbers, snapshot times), everything else itself.
fn name_matches(pattern: &str, text: &str) -> bool {
    if let Some(after) = pattern.strip_prefix("{key}") {
        return (1..=text.len())
            .filter(|&k| text.is_char_boundary(k))
            .any(|k| is_scene_key(&text[..k]) && name_matches(after, &text[k..]));
    }
    if let Some(rest) = pattern.strip_prefix('{') {
        let Some(end) = rest.find('}') else {
            return pattern == text;
        };
        let after = &rest[end + 1..];
        let n = text
            .bytes()
            .take_while(|b| b.is_ascii_digit() || *b == b'.' || *b == b'-')
            .count();
        return (1..=n).any(|k| name_matches(after, &text[k..]));
    }
    match (pattern.chars().next(), text.chars().next()) {
        (None, None) => true,
        (Some(a), Some(b)) if a == b => {
            name_matches(&pattern[a.len_utf8()..], &text[b.len_utf8()..])
        }
        _ => false,
    }
}

/// A dotted scene key: words of `a-z 0-9 _` joined by dots, at least two of them.
fn is_scene_key(text: &str) -> bool {
    let words: Vec<&str> = text.split('.').collect();
    words.len() >= 2
        && words.iter().all(|w| {
            !w.is_empty()
                && w.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
        })
}

/// One bullet of a list: its depth (two spaces per level) and its whole text.
struct Bullet {
    depth: usize,
    text: String,
}

/// The bullets that follow line `start` up to the next blank line; other lines continue
/// the bullet above them.
fn bullets_after(lines: &[&str], start: usize) -> Vec<Bullet> {
    let mut out: Vec<Bullet> = Vec::new();
    for line in lines.iter().skip(start + 1) {
        if line.trim().is_empty() {
            break;
        }
        let body = line.trim_start();
        let indent = line.len() - body.len();
        if let Some(text) = body.strip_prefix("- ") {
            out.push(Bullet {
                depth: indent / 2,
                text: text.to_owned(),
            });
        } else if let Some(last) = out.last_mut() {
            last.text.push(' ');
            last.text.push_str(body);
        }
    }
    out
}

/// The keys a bullet names: its code spans before its first colon.
fn bullet_keys(text: &str) -> Vec<String> {
    code_spans(split_at_colon(text).0)
        .into_iter()
        .map(str::to_owned)
        .collect()
}

/// A tree of keys: documented, or observed in the program's output.
type Tree = BTreeMap<String, Entry>;

#[derive(Clone, Debug, Default)]
struct Entry {
    /// The keys of the object below (or of the objects in the array below); `None` for
    /// a value without keys (a number, a string, an array of numbers, null, or a
    /// documented key with no indented bullets).
    children: Option<Tree>,
    /// A documented map with data-dependent keys ("keyed by").
    map: bool,
}

fn build_tree(bullets: &[Bullet], i: &mut usize, depth: usize) -> Tree {
    let mut tree = Tree::new();
    while *i < bullets.len() && bullets[*i].depth == depth {
        let b = &bullets[*i];
        *i += 1;
        let children = (*i < bullets.len() && bullets[*i].depth > depth).then(|| {
            let d = bullets[*i].depth;
            build_tree(bullets, i, d)
        });
        for key in bullet_keys(&b.text) {
            tree.insert(
                key,
                Entry {
                    children: children.clone(),
                    map: b.text.contains("keyed by"),
                },
            );
        }
    }
    tree
}

/// The key list of a section that starts with a line beginning `heading`, if any.
fn key_list(section: &str, heading: &str) -> Option<Tree> {
    let lines: Vec<&str> = section.lines().collect();
    let start = lines.iter().position(|l| l.starts_with(heading))?;
    let bullets = bullets_after(&lines, start);
    let mut i = 0;
    let depth = bullets.first().map_or(0, |b| b.depth);
    Some(build_tree(&bullets, &mut i, depth))
}

/// The column lists of a section: (files, columns) per `CSV columns of` paragraph.
fn column_lists(section: &str) -> Vec<(Vec<String>, Vec<String>)> {
    let lines: Vec<&str> = section.lines().collect();
    let mut out = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        if !line.starts_with("CSV columns of") {
            continue;
        }
        let mut header = String::new();
        let mut end = start;
        for (k, l) in lines.iter().enumerate().skip(start) {
            if l.trim().is_empty() || l.trim_start().starts_with("- ") {
                break;
            }
            header.push_str(l);
            header.push(' ');
            end = k;
        }
        let (before, after) = split_at_colon(&header);
        let files = code_spans(before)
            .into_iter()
            .filter(|s| s.ends_with(".csv"))
            .map(str::to_owned)
            .collect();
        let mut columns: Vec<String> = code_spans(after.unwrap_or(""))
            .into_iter()
            .map(str::to_owned)
            .collect();
        for b in bullets_after(&lines, end) {
            columns.extend(bullet_keys(&b.text));
        }
        out.push((files, columns));
    }
    out
}

/// The rows of a section's flag table: first code span of the first cell → the cells.
fn flag_rows(section: &str) -> BTreeMap<String, Vec<String>> {
    section
        .lines()
        .filter(|l| l.starts_with("| `"))
        .filter_map(|l| {
            let cells: Vec<String> = l
                .trim()
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_owned())
                .collect();
            let name = code_spans(&cells[0]).first()?.to_string();
            Some((name, cells))
        })
        .collect()
}

// ------------------------------------------------------------------ the command line

/// Every leaf command of the CLI, by path (`blocks sweep slide`).
fn leaf_commands() -> Vec<(String, clap::Command)> {
    fn walk(cmd: &clap::Command, path: &str, out: &mut Vec<(String, clap::Command)>) {
        let subs: Vec<&clap::Command> = cmd
            .get_subcommands()
            .filter(|s| s.get_name() != "help")
            .collect();
        if subs.is_empty() {
            out.push((path.to_owned(), cmd.clone()));
        }
        for s in subs {
            let p = if path.is_empty() {
                s.get_name().to_owned()
            } else {
                format!("{path} {}", s.get_name())
            };
            walk(s, &p, out);
        }
    }
    let mut out = Vec::new();
    walk(&Cli::command(), "", &mut out);
    out
}

/// How the page names an argument: `--flag`, or the value name of a positional.
fn arg_name(arg: &clap::Arg) -> String {
    match arg.get_long() {
        Some(long) => format!("--{long}"),
        None => arg
            .get_value_names()
            .and_then(|v| v.first())
            .map_or_else(|| arg.get_id().as_str().to_uppercase(), ToString::to_string),
    }
}

fn documented_args(cmd: &clap::Command) -> Vec<&clap::Arg> {
    cmd.get_arguments()
        .filter(|a| !matches!(a.get_id().as_str(), "help" | "version"))
        .collect()
}

#[test]
fn every_command_and_flag_is_documented() {
    let doc = read_doc();
    let mut failures: Vec<String> = doc
        .duplicates
        .iter()
        .map(|d| format!("two sections for `rollstack {d}`"))
        .collect();
    let leaves = leaf_commands();
    let names: BTreeSet<&str> = leaves.iter().map(|(p, _)| p.as_str()).collect();
    for name in doc.sections.keys() {
        if !names.contains(name.as_str()) {
            failures.push(format!(
                "section `rollstack {name}`: no such command (the leaf commands: {names:?})"
            ));
        }
    }
    for (path, cmd) in &leaves {
        let Some(section) = doc.sections.get(path) else {
            failures.push(format!("no section \"### `rollstack {path}`\""));
            continue;
        };
        let rows = flag_rows(section);
        let args = documented_args(cmd);
        for arg in &args {
            let name = arg_name(arg);
            let Some(cells) = rows.get(&name) else {
                failures.push(format!("`rollstack {path}`: no table row for `{name}`"));
                continue;
            };
            let default_cell = cells.get(1).map_or("", String::as_str);
            let defaults: Vec<String> = arg
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .collect();
            let switch = matches!(arg.get_action(), ArgAction::SetTrue | ArgAction::SetFalse);
            let expected = if switch {
                Some("off".to_owned())
            } else if !defaults.is_empty() {
                Some(format!("`{}`", defaults.join(",")))
            } else if arg.is_required_set() {
                Some("required".to_owned())
            } else {
                None
            };
            match expected {
                Some(e) if default_cell != e => failures.push(format!(
                    "`rollstack {path}` `{name}`: default cell is '{default_cell}', the CLI says {e}"
                )),
                None if matches!(default_cell, "" | "required" | "off") => {
                    failures.push(format!(
                        "`rollstack {path}` `{name}`: optional without a default; its default cell \
                         '{default_cell}' should say what happens without it"
                    ));
                }
                _ => {}
            }
            if !switch {
                let row = cells.join(" | ");
                for pv in arg.get_possible_values() {
                    if pv.is_hide_set() {
                        continue;
                    }
                    let v = format!("`{}`", pv.get_name());
                    if !row.contains(&v) {
                        failures.push(format!(
                            "`rollstack {path}` `{name}`: possible value {v} not in its row"
                        ));
                    }
                }
            }
        }
        let known: BTreeSet<String> = args.iter().map(|a| arg_name(a)).collect();
        for row in rows.keys() {
            if !known.contains(row) {
                failures.push(format!(
                    "`rollstack {path}`: table row `{row}` names no argument of the command"
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "docs/cli.md disagrees with the command line:\n  {}",
        failures.join("\n  ")
    );
}

// ------------------------------------------------------------------ running the commands

/// One documented command run with small sizes; `out`: also pass `--out DIR`.
struct Run {
    section: &'static str,
    args: Vec<String>,
    out: bool,
}

fn run(section: &'static str, args: &[&str], out: bool) -> Run {
    let mut all: Vec<String> = section.split(' ').map(str::to_owned).collect();
    all.extend(args.iter().map(|s| (*s).to_owned()));
    Run {
        section,
        args: all,
        out,
    }
}

/// Every leaf command, cheap enough for a debug build (each well under a second).
fn runs() -> Vec<Run> {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../blockstack/scenes/shaking.toml"
    );
    // A base moving in y and rotating: the run report's `other_motions`.
    let moving_table = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/column-on-moving-table.toml"
    );
    let mut runs = vec![
        run(
            "rotation",
            &["--from", "axis-angle", "--values", "0,0,1,90deg", "--json"],
            false,
        ),
        run(
            "rotation",
            &["--from", "euler:3-1-3", "--values", "0.3,0.4,0.5"],
            true,
        ),
        run(
            "sphere holonomy",
            &["--theta", "pi/2", "--phi1", "0", "--phi2", "pi", "--json"],
            true,
        ),
        run(
            "sphere plan",
            &["--angle", "3pi/2", "--axis", "0.1,0.98994949,0.1", "--json"],
            true,
        ),
        run(
            "sphere euler-plan",
            &["--set", "3-1-3", "--angles", "30deg,45deg,60deg", "--json"],
            true,
        ),
        run("sphere roll", &["--steps", "40", "--json"], true),
        run("cylinder support", &["--theta", "30deg", "--json"], false),
        run(
            "cylinder support",
            &["--theta", "30deg", "--mass", "2", "--json"],
            false,
        ),
        run("cylinder statics", &["--points", "11"], true),
        run(
            "cylinder holonomy rectangle",
            &[
                "--theta",
                "pi/10",
                "--phi1",
                "1",
                "--phi2",
                "1",
                "--max-step",
                "0.05",
                "--json",
            ],
            true,
        ),
        run(
            "cylinder holonomy circle",
            &[
                "--ell",
                "0.3",
                "--theta",
                "pi/10",
                "--h",
                "1",
                "--r",
                "0.1",
                "--max-step",
                "0.05",
                "--json",
            ],
            true,
        ),
        run("cylinder frobenius", &["--json"], false),
        run(
            "cylinder frobenius",
            &["--system", "pair9", "--json"],
            false,
        ),
        run(
            "cylinder frobenius",
            &["--system", "pair7", "--config", "touching", "--json"],
            false,
        ),
        run(
            "cylinder pair",
            &["--theta", "0.5", "--steps", "20", "--ramp", "0.1", "--json"],
            true,
        ),
        run(
            "cylinder sweep pair",
            &["--theta", "0.3,0.5", "--steps", "20", "--json"],
            true,
        ),
        run(
            "cylinder sweep push",
            &[
                "--theta", "0.5", "--push", "0.2,0.25", "--steps", "40", "--json",
            ],
            true,
        ),
        run(
            "nsga ball",
            &["--case", "2", "--dt", "0.01", "--json"],
            true,
        ),
        run(
            "nsga work-precision",
            &[
                "--system",
                "oscillator",
                "--dts",
                "0.01,0.005",
                "--rho-inf",
                "0.5",
                "--repeat",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks run",
            &[scene, "--t-end", "0.05", "--max-frames", "2", "--json"],
            true,
        ),
        run(
            "blocks run",
            &["slide", "--t-end", "0.03", "--max-frames", "0", "--json"],
            true,
        ),
        run(
            "blocks run",
            &[
                moving_table,
                "--t-end",
                "0.03",
                "--max-frames",
                "0",
                "--json",
            ],
            true,
        ),
        // A scene with materials per interface: its report lists them.
        run(
            "blocks run",
            &[
                "rocking-block",
                "--t-end",
                "0.02",
                "--max-frames",
                "0",
                "--json",
            ],
            false,
        ),
        run("blocks scenes", &[], false),
        run("blocks scenes", &["shaking"], false),
        run(
            "blocks shake",
            &[
                "--blocks",
                "2",
                "--periods",
                "0.05",
                "--max-frames",
                "2",
                "--json",
            ],
            true,
        ),
        run(
            "blocks lire",
            &[
                "--blocks",
                "2",
                "--t-end",
                "0.05",
                "--max-frames",
                "2",
                "--json",
            ],
            true,
        ),
        run(
            "blocks sweep frequency",
            &[
                "--omega",
                "10",
                "--periods",
                "0.2",
                "--blocks",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks sweep slide",
            &["--v0", "0.1", "--t-end", "0.05", "--blocks", "1", "--json"],
            true,
        ),
        // With --convergence: the rows' verdict columns (the last run of a section
        // gives the header checked).
        run(
            "blocks sweep frequency",
            &[
                "--omega",
                "10",
                "--periods",
                "0.2",
                "--blocks",
                "1",
                "--convergence",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks sweep slide",
            &[
                "--v0",
                "0.1",
                "--t-end",
                "0.05",
                "--blocks",
                "1",
                "--convergence",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks sweep scene",
            &[
                "shaking",
                "--set",
                "contact.mu=0.2,0.3",
                "--set",
                "blocks.count=1",
                "--t-end",
                "0.05",
                "--json",
            ],
            true,
        ),
        run(
            "blocks sweep scene",
            &[
                "shaking",
                "--set",
                "contact.mu=0.2",
                "--set",
                "blocks.count=1",
                "--t-end",
                "0.05",
                "--convergence",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks painleve",
            &["--aspect", "0.5", "--grid", "5", "--json"],
            true,
        ),
        run(
            "blocks explore",
            &[
                "abundance-author",
                "--t-end",
                "0.05",
                "--classify",
                "--json",
            ],
            true,
        ),
        run(
            "blocks work-precision",
            &[
                "--dts",
                "1e-2,5e-3",
                "--reference-factor",
                "2",
                "--repeat",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks converge",
            &[
                "lire-collapse",
                "--t-end",
                "0.05",
                "--levels",
                "1",
                "--ensemble",
                "1",
                "--json",
            ],
            true,
        ),
        run(
            "blocks fragility",
            &[
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../../examples/scenes/drums-on-record.toml"
                ),
                "--records",
                concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data"),
                "--scales",
                "0.5,1",
                "--t-end",
                "0.05",
                "--json",
            ],
            true,
        ),
        run(
            "cylinder work-precision",
            &["--dts", "2e-2,1e-2", "--repeat", "1", "--json"],
            true,
        ),
        run("tour", &["--only", "rotations,nsga"], true),
        run(
            "slurm",
            &[
                "--tasks",
                "2",
                "--time",
                "5",
                "--mem",
                "100",
                "blocks",
                "sweep",
                "frequency",
                "--omega",
                "10",
                "--periods",
                "0.2",
                "--blocks",
                "1",
            ],
            true,
        ),
    ];
    // `merge` joins the output of the frequency sweep's run above (its directory is
    // named by its place in this list, as in `documented_outputs_match_the_program`).
    let sweep = runs
        .iter()
        .position(|r| r.section == "blocks sweep frequency" && r.out)
        .expect("a frequency sweep with --out");
    let shard = common::temp_dir(&format!("cli-doc-{sweep}"));
    runs.push(run("merge", &[shard.to_str().unwrap(), "--json"], true));
    runs
}

/// The keys of a JSON value: an object's, or those of the objects in an array.
fn observed(v: &Value) -> Option<Tree> {
    match v {
        Value::Object(m) => Some(
            m.iter()
                .map(|(k, v)| {
                    (
                        k.clone(),
                        Entry {
                            children: observed(v),
                            map: false,
                        },
                    )
                })
                .collect(),
        ),
        Value::Array(items) => items.iter().filter_map(observed).reduce(|mut a, b| {
            merge(&mut a, b);
            a
        }),
        _ => None,
    }
}

/// Adds the keys of `b` to `a` (a key that was null in one run and an object in another
/// takes the object's keys).
fn merge(a: &mut Tree, b: Tree) {
    for (k, e) in b {
        match a.get_mut(&k) {
            None => {
                a.insert(k, e);
            }
            Some(old) => match (&mut old.children, e.children) {
                (Some(x), Some(y)) => merge(x, y),
                (x @ None, Some(y)) => *x = Some(y),
                _ => {}
            },
        }
    }
}

/// Documented keys against printed keys, both ways, at every depth.
fn compare(doc: &Tree, seen: &Tree, at: &str, failures: &mut Vec<String>) {
    for key in seen.keys().filter(|k| !doc.contains_key(*k)) {
        failures.push(format!("{at}: key `{key}` is printed but not documented"));
    }
    for key in doc.keys().filter(|k| !seen.contains_key(*k)) {
        failures.push(format!(
            "{at}: documented key `{key}` is not printed by any run"
        ));
    }
    for (key, d) in doc {
        let Some(s) = seen.get(key) else { continue };
        let here = format!("{at}.{key}");
        match (&d.children, &s.children) {
            (Some(dc), Some(sc)) => compare(dc, sc, &here, failures),
            (None, Some(sc)) if !sc.is_empty() && !d.map => failures.push(format!(
                "{here}: holds the keys {:?}, which are not documented (indented bullets)",
                sc.keys().collect::<Vec<_>>()
            )),
            (Some(dc), None) if !dc.is_empty() => failures.push(format!(
                "{here}: documented keys {:?} below it, but no run printed an object there",
                dc.keys().collect::<Vec<_>>()
            )),
            _ => {}
        }
    }
}

/// Every file below `dir`, relative, with `/` separators.
fn files_below(dir: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
            let p = entry.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap();
                let parts: Vec<String> = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                out.push(parts.join("/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

/// What the runs of one section produced.
#[derive(Default)]
struct Seen {
    json: Option<Tree>,
    run_json: Option<Tree>,
    /// CSV file (relative) → header.
    csv: BTreeMap<String, Vec<String>>,
    files: BTreeSet<String>,
}

#[test]
fn documented_outputs_match_the_program() {
    let doc = read_doc();
    let mut failures = Vec::new();
    for key in ["command", "version", "inputs", "timings"] {
        if !doc.overview.contains(&format!("`{key}`")) {
            failures.push(format!(
                "the conventions do not name the run.json key `{key}`"
            ));
        }
    }
    let runs = runs();
    let mut seen: BTreeMap<&str, Seen> = BTreeMap::new();
    let mut dirs: Vec<PathBuf> = Vec::new();
    for (n, r) in runs.iter().enumerate() {
        let mut args: Vec<&str> = r.args.iter().map(String::as_str).collect();
        let dir = common::temp_dir(&format!("cli-doc-{n}"));
        let dir_text = dir.to_string_lossy().into_owned();
        if r.out {
            args.extend(["--out", &dir_text]);
        }
        let (ok, stdout, stderr) = common::run(&args);
        assert!(ok, "{args:?} failed: {stderr}");
        let s = seen.entry(r.section).or_default();
        if args.contains(&"--json") {
            let v: Value = serde_json::from_str(&stdout)
                .unwrap_or_else(|e| panic!("{args:?}: stdout is not one JSON object: {e}"));
            let keys = observed(&v).expect("a JSON object");
            merge(s.json.get_or_insert_with(Tree::new), keys);
        }
        if r.out {
            for f in files_below(&dir) {
                let path = dir.join(&f);
                // The tour's files are those of the commands it runs, documented with
                // them; its section names the directory each command writes into.
                if r.section == "tour" && f.matches('/').count() >= 2 {
                    let step: Vec<&str> = f.splitn(3, '/').take(2).collect();
                    s.files.insert(format!("{}/", step.join("/")));
                    continue;
                }
                if f == "run.json" {
                    let v: Value =
                        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
                    // `merge` writes what one run of the merged sweep writes.
                    let command = match r.section {
                        "merge" => "blocks sweep frequency",
                        section => section,
                    };
                    if v["command"] != command {
                        failures.push(format!(
                            "`rollstack {}`: run.json says command {}",
                            r.section, v["command"]
                        ));
                    }
                    let mut keys = observed(&v).expect("run.json is an object");
                    keys.remove("command");
                    keys.remove("version");
                    merge(s.run_json.get_or_insert_with(Tree::new), keys);
                }
                if f.ends_with(".csv") {
                    let text = std::fs::read_to_string(&path).unwrap();
                    let header = text.lines().next().unwrap_or("");
                    s.csv
                        .insert(f.clone(), header.split(',').map(str::to_owned).collect());
                }
                s.files.insert(f);
            }
            dirs.push(dir);
        }
    }

    for (path, cmd) in leaf_commands() {
        let has = |flag: &str| cmd.get_arguments().any(|a| a.get_long() == Some(flag));
        let used = |flag: &str, out: bool| {
            runs.iter()
                .any(|r| r.section == path && (r.args.iter().any(|a| a == flag) || (out && r.out)))
        };
        if !runs.iter().any(|r| r.section == path) {
            failures.push(format!(
                "`rollstack {path}` is not run by this test: add a cheap run to runs()"
            ));
        }
        if has("json") && !used("--json", false) {
            failures.push(format!("`rollstack {path}` is never run with --json here"));
        }
        if has("out") && !used("--out", true) {
            failures.push(format!("`rollstack {path}` is never run with --out here"));
        }
    }

    for (section_name, s) in &seen {
        let at = format!("`rollstack {section_name}`");
        let Some(section) = doc.sections.get(*section_name) else {
            failures.push(format!("{at}: no section"));
            continue;
        };
        for (list, heading, what) in [
            (&s.json, "JSON keys", "JSON"),
            (&s.run_json, "`run.json` keys", "run.json"),
        ] {
            match (list, key_list(section, heading)) {
                (Some(seen_keys), Some(doc_keys)) => {
                    compare(&doc_keys, seen_keys, &format!("{at} {what}"), &mut failures);
                }
                (Some(_), None) => {
                    failures.push(format!("{at}: writes {what} but has no \"{heading}\" list"));
                }
                (None, Some(_)) => failures.push(format!(
                    "{at}: documents \"{heading}\" but no run produced {what}"
                )),
                (None, None) => {}
            }
        }
        let lists = column_lists(section);
        for (file, header) in &s.csv {
            let Some((_, columns)) = lists
                .iter()
                .find(|(files, _)| files.iter().any(|f| name_matches(f, file)))
            else {
                failures.push(format!(
                    "{at}: writes {file} but has no \"CSV columns of `{file}`\""
                ));
                continue;
            };
            for col in header {
                if !columns.iter().any(|c| name_matches(c, col)) {
                    failures.push(format!("{at} {file}: column `{col}` is not documented"));
                }
            }
            for c in columns {
                if !header.iter().any(|col| name_matches(c, col)) {
                    failures.push(format!(
                        "{at} {file}: documented column `{c}` is not in the header {header:?}"
                    ));
                }
            }
        }
        for (files, _) in &lists {
            for f in files {
                let written = s.csv.keys().any(|w| name_matches(f, w));
                let exempt = CSV_NOT_RUN
                    .iter()
                    .any(|(sec, file, _)| sec == section_name && file == f);
                if !written && !exempt {
                    failures.push(format!(
                        "{at}: documents the columns of {f}, which no run wrote"
                    ));
                }
            }
        }
        let named = code_spans(section);
        for f in &s.files {
            if !named.iter().any(|n| name_matches(n, f)) {
                failures.push(format!(
                    "{at}: writes `{f}`, which its section does not name"
                ));
            }
        }
    }
    for d in dirs {
        let _ = std::fs::remove_dir_all(d);
    }
    assert!(
        failures.is_empty(),
        "docs/cli.md disagrees with what the commands print and write:\n  {}",
        failures.join("\n  ")
    );
}

#[test]
fn the_page_reader_reads_what_it_should() {
    assert!(name_matches("x{k}", "x12"));
    assert!(name_matches("s{i}{j}", "s13"));
    assert!(name_matches("snapshot_t{t}.png", "snapshot_t6.4.png"));
    assert!(!name_matches("x{k}", "x_x"));
    assert!(!name_matches("x{k}", "x"));
    assert!(name_matches("base_x", "base_x"));
    assert!(name_matches("{key}", "contact.mu") && name_matches("{key}", "blocks.0.width"));
    assert!(!name_matches("{key}", "failure_time") && !name_matches("{key}", "a..b"));
    assert_eq!(split_at_colon("`a:b`, `c`: d").0, "`a:b`, `c`");
    let doc = read_doc();
    let lire = &doc.sections["blocks lire"];
    let keys = key_list(lire, "JSON keys").expect("the JSON keys of blocks lire");
    assert!(keys.contains_key("steps") && keys.contains_key("files"));
    assert_eq!(keys["final"].children.as_ref().map(Tree::len), Some(3));
    let lists = column_lists(lire);
    assert!(lists
        .iter()
        .any(|(f, c)| f == &["trajectory.csv"] && c.contains(&"x{k}".to_owned())));
    assert_eq!(flag_rows(lire)["--blocks"][1], "`4`");
}

// ------------------------------------------------------------------ the overview and transcripts

#[test]
fn the_command_table_names_every_command() {
    // A row of the overview's table: ``| `rollstack a b`, `c`, `d e` | …``: the first
    // span names a command by its path, the others by their path below its group (or,
    // as `merge`, `slurm`, a command of their own).
    let doc = read_doc();
    let mut named = BTreeSet::new();
    for row in doc
        .overview
        .lines()
        .filter(|l| l.starts_with("| `rollstack "))
    {
        let first = row.split('|').nth(1).unwrap_or_default();
        let spans = code_spans(first);
        let Some(full) = spans.first().and_then(|s| s.strip_prefix("rollstack ")) else {
            continue;
        };
        let group = full.split(' ').next().unwrap_or_default();
        named.insert(full.to_owned());
        for rest in &spans[1..] {
            named.insert(format!("{group} {rest}"));
            named.insert((*rest).to_owned());
        }
    }
    let missing: Vec<String> = leaf_commands()
        .into_iter()
        .map(|(path, _)| path)
        .filter(|path| !named.contains(path))
        .collect();
    assert!(
        missing.is_empty(),
        "the command table of docs/cli.md lacks {missing:?}"
    );
}

#[test]
fn every_transcript_on_the_page_is_what_the_command_prints() {
    let failures = common::transcript_failures(DOC, "cli-doc", 2, &[]);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_transcript_reader_reads_what_it_should() {
    let page = "a\n```text\n$ rollstack x --y 1\none\n…\nthree\n```\n```text\nno command\n```\n";
    let t = common::transcripts(page);
    assert_eq!(t.len(), 1);
    assert_eq!(t[0].args, ["x", "--y", "1"]);
    let matches = common::transcript_matches;
    assert!(matches(&t[0].lines, &["one", "two", "2b", "three"]));
    assert!(matches(&t[0].lines, &["one", "three"]));
    assert!(!matches(&t[0].lines, &["one", "two"]));
    assert!(!matches(&t[0].lines, &["zero", "one", "three"]));
    let inline = ["a = 1 (…), b".to_owned()];
    assert!(matches(&inline, &["a = 1 (solver 0.3 s), b"]));
    assert!(!matches(&inline, &["a = 2 (solver 0.3 s), b"]));
    assert!(!matches(&inline, &["a = 1 (x), b, c"]));
}
