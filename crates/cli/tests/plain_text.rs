//! No debug text reaches the user (docs/cli.md "Output"): every cheap command, with and
//! without `--json`, and the files it writes (CSV, JSON, the tour's page) print missing
//! values as `none` or null and choices by their command-line words, never as Rust's
//! `Debug` of an `Option` or an enum (`Some(0.43)`, `None`, `Scaled(1.0)`, `Pair9`,
//! `Nsga`).

mod common;

use std::path::Path;

/// What `Debug` of the options and enums the commands print would look like.
const DEBUG_TEXT: [&str; 7] = [
    "Some(",
    "None",
    "Scaled(",
    "Constant(",
    "Pair9",
    "Pair7",
    "Nsga",
];

/// One cheap command: its arguments, whether it takes `--json` and whether `--out`.
struct Case {
    args: Vec<String>,
    json: bool,
    out: bool,
}

fn case(args: &[&str], json: bool, out: bool) -> Case {
    Case {
        args: args.iter().map(|s| (*s).to_owned()).collect(),
        json,
        out,
    }
}

fn cases() -> Vec<Case> {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../blockstack/scenes/shaking.toml"
    );
    vec![
        case(
            &[
                "rotation",
                "--from",
                "axis-angle",
                "--values",
                "0,0,1,90deg",
            ],
            true,
            false,
        ),
        case(
            &["rotation", "--from", "euler:3-1-3", "--values", "0,0,30deg"],
            true,
            false,
        ),
        case(
            &[
                "sphere", "holonomy", "--theta", "pi/2", "--phi1", "0", "--phi2", "pi",
            ],
            true,
            true,
        ),
        // A rectangle without holonomy, (2.4.8)₂.
        case(
            &[
                "sphere", "holonomy", "--theta", "2pi", "--phi1", "0.5", "--phi2", "2",
            ],
            true,
            false,
        ),
        case(
            &[
                "sphere",
                "plan",
                "--angle",
                "3pi/2",
                "--axis",
                "0.1,0.98994949,0.1",
            ],
            true,
            true,
        ),
        case(
            &[
                "sphere",
                "euler-plan",
                "--set",
                "3-1-3",
                "--angles",
                "30deg,45deg,60deg",
            ],
            true,
            true,
        ),
        case(&["sphere", "roll", "--steps", "40"], true, true),
        case(&["cylinder", "support", "--theta", "30deg"], true, false),
        // No smooth or (−) support: the missing forces.
        case(
            &[
                "cylinder", "support", "--theta", "5deg", "--mu", "0.6", "--mass", "2",
            ],
            true,
            false,
        ),
        case(&["cylinder", "statics", "--points", "11"], false, true),
        case(
            &[
                "cylinder",
                "holonomy",
                "rectangle",
                "--theta",
                "pi/10",
                "--phi1",
                "1",
                "--phi2",
                "1",
                "--max-step",
                "0.05",
            ],
            true,
            true,
        ),
        case(
            &[
                "cylinder",
                "holonomy",
                "circle",
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
                "--cw",
            ],
            true,
            true,
        ),
        case(&["cylinder", "frobenius"], true, false),
        case(&["cylinder", "frobenius", "--system", "pair9"], true, false),
        case(
            &[
                "cylinder",
                "frobenius",
                "--system",
                "pair7",
                "--config",
                "touching",
            ],
            true,
            false,
        ),
        // Case 1 never rolls: its rolling onset does not exist.
        case(&["nsga", "ball", "--case", "1", "--dt", "0.01"], true, true),
        case(
            &[
                "nsga",
                "ball",
                "--case",
                "2",
                "--dt",
                "0.01",
                "--scheme",
                "moreau",
                "--prox-constant",
                "0.3",
            ],
            true,
            true,
        ),
        case(
            &[
                "nsga",
                "work-precision",
                "--system",
                "oscillator",
                "--dts",
                "0.01,0.005",
                "--rho-inf",
                "0.5",
                "--repeat",
                "1",
            ],
            true,
            true,
        ),
        case(
            &[
                "blocks",
                "run",
                scene,
                "--t-end",
                "0.05",
                "--max-frames",
                "0",
            ],
            true,
            true,
        ),
        case(
            &[
                "blocks",
                "run",
                "slide",
                "--t-end",
                "0.03",
                "--max-frames",
                "0",
                "--prox-constant",
                "0.3",
            ],
            true,
            true,
        ),
        case(&["blocks", "scenes"], false, false),
        case(&["blocks", "scenes", "shaking"], false, false),
        case(
            &[
                "blocks",
                "shake",
                "--blocks",
                "2",
                "--periods",
                "0.05",
                "--max-frames",
                "0",
            ],
            true,
            true,
        ),
        case(
            &[
                "blocks",
                "lire",
                "--blocks",
                "2",
                "--t-end",
                "0.05",
                "--max-frames",
                "0",
            ],
            true,
            true,
        ),
        case(
            &[
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
            true,
        ),
        case(
            &[
                "blocks", "sweep", "slide", "--v0", "0.1", "--t-end", "0.05", "--blocks", "1",
            ],
            true,
            true,
        ),
        case(
            &["blocks", "painleve", "--aspect", "0.5", "--grid", "5"],
            true,
            true,
        ),
        case(&["tour", "--only", "rotations,nsga"], false, true),
    ]
}

/// The debug text in `text`, if any, as `(pattern, the line it is on)`.
fn debug_text(text: &str) -> Option<(&'static str, String)> {
    DEBUG_TEXT.iter().find_map(|p| {
        text.lines()
            .find(|l| l.contains(p))
            .map(|l| (*p, l.chars().take(200).collect()))
    })
}

/// Every file below `dir` whose contents a user reads as text.
fn text_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
        let p = entry.path();
        if p.is_dir() {
            text_files(&p, out);
        } else if p
            .extension()
            .is_some_and(|e| e == "csv" || e == "json" || e == "html")
        {
            out.push(p);
        }
    }
}

#[test]
fn no_debug_text_in_any_output() {
    let mut failures = Vec::new();
    let mut files_read = 0;
    for (n, c) in cases().iter().enumerate() {
        for json in [false, true] {
            if json && !c.json {
                continue;
            }
            let mut args: Vec<String> = c.args.clone();
            if json {
                args.push("--json".into());
            }
            let dir = common::temp_dir(&format!("plain-text-{n}-{json}"));
            if c.out {
                args.extend(["--out".to_owned(), dir.to_string_lossy().into_owned()]);
            }
            let argv: Vec<&str> = args.iter().map(String::as_str).collect();
            let (ok, stdout, stderr) = common::run(&argv);
            assert!(ok, "{argv:?} failed: {stderr}");
            assert!(!stdout.trim().is_empty(), "{argv:?} printed nothing");
            for (what, text) in [("stdout", &stdout), ("stderr", &stderr)] {
                if let Some((p, line)) = debug_text(text) {
                    failures.push(format!("{argv:?} {what}: `{p}` in: {line}"));
                }
            }
            if c.out {
                let mut files = Vec::new();
                text_files(&dir, &mut files);
                assert!(!files.is_empty(), "{argv:?} wrote no CSV or JSON");
                for f in files {
                    files_read += 1;
                    let text = std::fs::read_to_string(&f).unwrap();
                    if let Some((p, line)) = debug_text(&text) {
                        failures.push(format!("{argv:?} {}: `{p}` in: {line}", f.display()));
                    }
                }
                let _ = std::fs::remove_dir_all(&dir);
            }
        }
    }
    assert!(files_read > 20, "only {files_read} files read");
    assert!(
        failures.is_empty(),
        "debug text in the output:\n  {}",
        failures.join("\n  ")
    );
}

#[test]
fn missing_values_read_none_and_choices_read_their_names() {
    let (ok, text, _) = common::run(&["nsga", "ball", "--case", "1", "--dt", "0.01"]);
    assert!(ok);
    assert!(text.contains(", rolling from none, "), "{text}");
    let v = common::json(&["nsga", "ball", "--case", "1", "--dt", "0.01", "--json"]);
    assert!(v["rolling_onset_time"].is_null());

    let (ok, text, _) = common::run(&["blocks", "run", "slide", "--t-end", "0.02"]);
    assert!(ok);
    assert!(text.contains(", prox scaled, alpha = 1"), "{text}");
    let v = common::json(&[
        "blocks",
        "run",
        "slide",
        "--t-end",
        "0.02",
        "--prox-constant",
        "0.3",
        "--json",
    ]);
    assert_eq!(v["prox"], "constant(r=0.3)");
    assert_eq!(v["scene"]["prox"], "constant(r=0.3)");

    let (ok, text, _) = common::run(&["cylinder", "frobenius", "--system", "pair9"]);
    assert!(ok);
    assert!(text.starts_with("Frobenius test (pair9): rank 9"), "{text}");

    let (ok, text, _) = common::run(&[
        "cylinder",
        "holonomy",
        "circle",
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
    ]);
    assert!(ok);
    assert!(text.contains("(case I, counter-clockwise)"), "{text}");
}

#[test]
fn the_tour_work_precision_file_names_its_schemes() {
    let dir = common::temp_dir("plain-text-tour");
    let d = dir.to_string_lossy().into_owned();
    let (ok, _, stderr) = common::run(&["tour", "--only", "nsga", "--out", &d]);
    assert!(ok, "{stderr}");
    let csv = std::fs::read_to_string(dir.join("nsga/work_precision/work_precision.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("scheme,rho_inf,dt,error,wall_time_s,contact_events,follows_reference,fitted")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().any(|r| r[0] == "nsga" && !r[1].is_empty()));
    let moreau: Vec<_> = rows.iter().filter(|r| r[0] == "moreau").collect();
    assert!(!moreau.is_empty() && moreau.iter().all(|r| r[1].is_empty()));
    assert!(rows.iter().all(|r| r[0] == "nsga" || r[0] == "moreau"));
    let _ = std::fs::remove_dir_all(dir);
}
