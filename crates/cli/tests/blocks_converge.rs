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

/// `blocks run` and `blocks shake` with `--convergence K` print the study's two verdicts
/// right after the failure line, and give the study in their JSON.
#[test]
fn a_run_asked_for_convergence_prints_its_verdict_after_its_failure() {
    let args = [
        "blocks",
        "run",
        "lire-collapse",
        "--t-end",
        "6.7",
        "--convergence",
        "1",
        "--ensemble",
        "0",
    ];
    let (ok, stdout, stderr) = run(&args);
    assert!(ok, "{stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.starts_with("failure (loss of support) at t = 6.6000"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        lines[at + 1].starts_with("convergence over Δt/2^k, k = 0…1, 0 member(s)"),
        "{stdout}"
    );
    assert!(
        lines[at + 2].starts_with("failure time 6.5950: converged"),
        "{stdout}"
    );
    assert!(lines[at + 3].starts_with("outcome: "), "{stdout}");
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let v = json(&with_json);
    assert_eq!(v["convergence"]["failure"]["verdict"], "converged", "{v}");
    assert_eq!(v["convergence"]["failure"]["rule"], "agreement", "{v}");
    assert_eq!(v["convergence"]["dts"].as_array().unwrap().len(), 2, "{v}");
    // Without the flag: no verdict, no key.
    let v = json(&["blocks", "run", "lire-collapse", "--t-end", "6.7", "--json"]);
    assert!(v.get("convergence").is_none(), "{v}");
    // shake: the column of Figure 4.6 at ω = 4 to t = 4, K = 1 and one member per
    // magnitude.
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "shake",
        "--t-end",
        "4",
        "--convergence",
        "1",
        "--ensemble",
        "1",
    ]);
    assert!(ok, "{stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.starts_with("failure (loss of support)"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(lines[at + 2].starts_with("failure time "), "{stdout}");
    // The members perturbed by at most 1e-7 count: two of three.
    assert!(lines[at + 2].contains("over 2 member(s)"), "{stdout}");
    // Refused before any run, naming the flag.
    for bad in [
        &["--convergence", "0"][..],
        &["--convergence", "9"],
        &["--ensemble", "1"],
        &["--convergence", "1", "--ensemble", "21"],
    ] {
        let mut a = vec!["blocks", "run", "lire-collapse"];
        a.extend_from_slice(bad);
        let (ok, stdout, stderr) = run(&a);
        let flag = bad[bad.len() - 2];
        assert!(!ok && stdout.is_empty(), "{bad:?}: {stdout}");
        assert!(stderr.contains(flag), "{bad:?}: {stderr}");
    }
}

/// The CSV of `path`: its header and rows, split at commas (no cell here holds one).
fn csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect());
    (lines.next().unwrap(), lines.collect())
}

/// `--convergence K` on the sweeps: every row gains the verdict columns after its own,
/// whose cells are those of the sweep without it; without the flag the CSV has the
/// columns it had, and the rows' JSON and row log no `convergence`; a sweep with it
/// resumes from its row log.
#[test]
fn sweeps_with_convergence_add_the_verdict_columns_and_resume() {
    let dir = temp_dir("sweep-convergence");
    let (plain, judged) = (dir.join("plain"), dir.join("judged"));
    let sweep = |out: &std::path::Path, extra: &[&str]| {
        let mut a = vec![
            "blocks",
            "sweep",
            "frequency",
            "--omega",
            "4,16",
            "--t-max",
            "5",
            "--out",
            out.to_str().unwrap(),
            "--json",
        ];
        a.extend_from_slice(extra);
        json(&a)
    };
    let v = sweep(&plain, &[]);
    assert!(v["rows"][0].get("convergence").is_none(), "{v}");
    let log = std::fs::read_to_string(plain.join("rows.log")).unwrap();
    assert!(!log.contains("convergence"), "{log}");
    let (header, rows) = csv(&plain.join("sweep_frequency.csv"));
    assert_eq!(header.last().unwrap(), "failure_time_max", "{header:?}");
    let v = sweep(&judged, &["--convergence", "2"]);
    let (judged_header, judged_rows) = csv(&judged.join("sweep_frequency.csv"));
    assert_eq!(judged_header[..header.len()], header[..]);
    assert_eq!(
        judged_header[header.len()..],
        [
            "levels",
            "failure_verdict",
            "failure_tolerance",
            "failure_extrapolated",
            "level_failure_times",
            "outcome_verdict",
            "spread_min",
            "spread_max",
            "convergence_error"
        ]
    );
    let wall = header.iter().position(|c| c == "wall_time_s").unwrap();
    for (a, b) in rows.iter().zip(&judged_rows) {
        let same = |r: &[String]| {
            let mut r = r[..header.len()].to_vec();
            r.remove(wall);
            r
        };
        assert_eq!(same(a), same(b));
    }
    // ω = 4 fails at 3.958 at Δt (Figure 4.6's column), the levels at Δt/2 and Δt/4 at
    // 3.401 and 3.428: the row's failure time is its level 0's.
    let c = &v["rows"][0]["convergence"];
    let times = c["failure_times"].as_array().unwrap();
    assert_eq!(times.len(), 3, "{c}");
    assert_eq!(times[0], v["rows"][0]["failure_time"], "{c}");
    assert_eq!(
        judged_rows[0][header.len() + 1],
        c["failure_verdict"].as_str().unwrap()
    );
    assert_eq!(judged_rows[0][header.len()], "2");
    // The spread holds the finest level's failure time, and every level's.
    let lo = c["spread"][0].as_f64().unwrap();
    let hi = c["spread"][1].as_f64().unwrap();
    for t in times.iter().filter_map(serde_json::Value::as_f64) {
        assert!(lo <= t && t <= hi, "{c}");
    }
    // The sweep's solver time counts the studies' runs.
    let run_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(judged.join("run.json")).unwrap()).unwrap();
    let seconds: f64 = v["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r["wall_time_s"].as_f64().unwrap() + r["convergence"]["wall_time_s"].as_f64().unwrap()
        })
        .sum();
    let solver = run_json["timings"]["solver_s"].as_f64().unwrap();
    assert!(
        (solver - seconds).abs() <= 1e-9 * seconds,
        "{solver} {seconds}"
    );
    assert!(c["wall_time_s"].as_f64().unwrap() > 0.0, "{c}");
    // Resumed: the same command computes nothing and writes the same CSV.
    let before = std::fs::read_to_string(judged.join("sweep_frequency.csv")).unwrap();
    let again = sweep(&judged, &["--convergence", "2"]);
    assert_eq!(again["rows"], v["rows"]);
    let after = std::fs::read_to_string(judged.join("sweep_frequency.csv")).unwrap();
    assert_eq!(before, after);
    // Another K is another sweep: it does not resume K = 2's rows.
    let other = sweep(&judged, &["--convergence", "1"]);
    let times = other["rows"][0]["convergence"]["failure_times"]
        .as_array()
        .unwrap();
    assert_eq!(times.len(), 2, "{other}");
    std::fs::remove_dir_all(&dir).unwrap();
}
