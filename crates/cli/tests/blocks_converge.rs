//! `rollstack blocks converge`: its files and JSON, and its refusals.

mod common;

use common::{json, run, temp_dir};

#[test]
fn converge_writes_a_csv_per_run_the_table_and_the_plot() {
    // The Lire collapse to t = 6.7 at Δt and Δt/2, one member per magnitude: the
    // failure (6.600 and 6.595) is converged, within 2 steps of Δt.
    let dir = temp_dir("converge-files");
    let d = dir.to_str().unwrap();
    let v = json(&[
        "blocks",
        "converge",
        "lire-collapse",
        "--t-end",
        "6.7",
        "--levels",
        "1",
        "--ensemble",
        "1",
        "--out",
        d,
        "--json",
    ]);
    assert_eq!(v["failure"]["verdict"], "converged", "{v}");
    assert_eq!(v["dts"].as_array().unwrap().len(), 2);
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2 + 3, "two levels, three members");
    let t: Vec<f64> = runs[..2]
        .iter()
        .map(|r| r["failure_time"].as_f64().unwrap())
        .collect();
    assert!(
        (t[0] - 6.6).abs() < 1e-9 && (t[1] - 6.595).abs() < 1e-9,
        "{t:?}"
    );
    let files: Vec<&str> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for f in [
        "level0.csv",
        "level1.csv",
        "member01.csv",
        "member03.csv",
        "runs.csv",
        "separation.csv",
        "converge.png",
        "run.json",
    ] {
        assert!(files.contains(&f), "{f} not in {files:?}");
        assert!(dir.join(f).exists(), "{f} not written");
    }
    // A trajectory row per state: the initial one and one per step.
    let level1 = std::fs::read_to_string(dir.join("level1.csv")).unwrap();
    let steps = runs[1]["steps"].as_u64().unwrap();
    assert_eq!(level1.lines().count() as u64, 1 + 1 + steps);
    let table = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    assert_eq!(table.lines().count(), 1 + 5);
    assert!(table.lines().nth(1).unwrap().starts_with("level0,level,0,"));
    let json_file = std::fs::read_to_string(dir.join("run.json")).unwrap();
    assert!(json_file.contains("\"blocks converge\""));
    // The text table names every run and both verdicts.
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "converge",
        "lire-collapse",
        "--t-end",
        "6.7",
        "--levels",
        "1",
        "--ensemble",
        "0",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("level1") && !stdout.contains("member01"),
        "{stdout}"
    );
    assert!(
        stdout.contains("failure time 6.5950: converged"),
        "{stdout}"
    );
    assert!(stdout.contains("\noutcome: "), "{stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_levels_and_ensembles_are_refused_naming_the_flag_and_writing_nothing() {
    let dir = temp_dir("converge-refused");
    let d = dir.to_str().unwrap();
    for (flag, value) in [
        ("--levels", "0"),
        ("--levels", "9"),
        ("--levels", "-1"),
        ("--levels", "two"),
        ("--ensemble", "21"),
        ("--t-end", "-1"),
    ] {
        let (ok, stdout, stderr) = run(&["blocks", "converge", "lire", flag, value, "--out", d]);
        assert!(!ok && stdout.is_empty(), "{flag} {value}: {stdout}");
        assert!(stderr.contains(flag), "{flag} {value}: {stderr}");
        assert!(!dir.exists(), "{flag} {value} left {}", dir.display());
    }
    // Endless runs: refused before any run by the time guard, naming --force.
    let (ok, stdout, stderr) = run(&[
        "blocks", "converge", "shaking", "--t-end", "1e300", "--out", d,
    ]);
    assert!(!ok && stdout.is_empty(), "{stdout}");
    assert!(
        stderr.contains("more than 600 s") && stderr.contains("--force"),
        "{stderr}"
    );
    assert!(!dir.exists());
    let (ok, _, stderr) = run(&["blocks", "converge", "no-such-scene"]);
    assert!(!ok && stderr.contains("lire-collapse"), "{stderr}");
}
