//! `rollstack blocks fragility`: its files, its shards merged, its Slurm job and its
//! one-line errors, on a slender block under three tiny one-sine records written here.

mod common;

use common::{run, run_in, temp_dir, transcript_matches, transcripts};
use std::path::{Path, PathBuf};

/// A slender block (0.2 × 1.0 m, tan α = 0.2) on a base playing a record, a floor.
const SCENE: &str = r#"
[base]
width = 2.0
height = 0.2

[[blocks]]
width = 0.2
height = 1.0

[contact]
mu = 1.0
e_n = 0.0

[solver]
dt = 0.01
gravity = 9.81

[floor]
"#;

/// A one-sine acceleration pulse of `peak` g and period `period` s at 100 Hz, as CSV.
fn one_sine(peak: f64, period: f64) -> String {
    let mut text = String::from("t,a\n");
    for i in 0..=100 {
        let t = f64::from(i) * 0.01;
        let a = if t < period {
            peak * (2.0 * std::f64::consts::PI * t / period).sin()
        } else {
            0.0
        };
        text.push_str(&format!("{t},{a}\n"));
    }
    text
}

/// A directory with the scene and three records.
fn study(tag: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let records = dir.join("records-in");
    std::fs::create_dir_all(&records).unwrap();
    std::fs::write(dir.join("block.toml"), SCENE).unwrap();
    for (name, peak, period) in [
        ("a.csv", 1.5, 1.0),
        ("b.csv", 1.2, 0.8),
        ("c.csv", 0.9, 0.6),
    ] {
        std::fs::write(records.join(name), one_sine(peak, period)).unwrap();
    }
    (dir, records)
}

fn fragility<'a>(dir: &'a Path, records: &'a Path, extra: &[&'a str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "blocks",
        "fragility",
        dir.join("block.toml").to_str().unwrap(),
        "--records",
        records.to_str().unwrap(),
        "--scales",
        "0.1,0.6,1.0",
        "--t-end",
        "2.5",
    ]
    .map(str::to_owned)
    .to_vec();
    args.extend(extra.iter().map(|s| (*s).to_owned()));
    args
}

fn ok(args: &[String]) -> String {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (ok, stdout, stderr) = run(&args);
    assert!(ok, "{args:?}: {stderr}");
    stdout
}

/// runs.csv without its timing column.
fn runs(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join("runs.csv"))
        .unwrap()
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_owned())
        .collect()
}

#[test]
fn a_study_writes_its_files_and_its_merged_shards_equal_one_run() {
    let (dir, records) = study("fragility-files");
    let whole = dir.join("whole");
    ok(&fragility(
        &dir,
        &records,
        &["--out", whole.to_str().unwrap()],
    ));
    let table = runs(&whole);
    assert_eq!(table.len(), 1 + 9, "{table:?}");
    assert!(table[0].starts_with("record,level,pga_g,pgv,overturned,failed"));
    // Records in name order, levels in the order given.
    assert!(table[1].starts_with("a.csv,0.1,") && table[9].starts_with("c.csv,1.0,"));
    for file in [
        "fragility.csv",
        "fit.json",
        "fragility.png",
        "scene.toml",
        "records/b.csv",
    ] {
        assert!(whole.join(file).is_file(), "{file}");
    }
    let fit: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("fit.json")).unwrap()).unwrap();
    let curves = fit["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 4);
    for c in curves {
        assert!(c["theta"].is_f64() != c["no_fit"].is_string(), "{c}");
    }
    let header = std::fs::read_to_string(whole.join("fragility.csv")).unwrap();
    assert!(header.starts_with("outcome,intensity,kind,im,p,p_low,p_high,runs\n"));
    // Two shards, merged from another directory, equal the whole.
    let shards: Vec<PathBuf> = (1..=2).map(|k| dir.join(format!("shard{k}"))).collect();
    for (k, out) in shards.iter().enumerate() {
        let shard = format!("{}/2", k + 1);
        ok(&fragility(
            &dir,
            &records,
            &["--shard", &shard, "--out", out.to_str().unwrap()],
        ));
    }
    let merged = dir.join("merged");
    let (done, _, stderr) = run_in(
        Path::new("/"),
        &[
            "merge",
            shards[1].to_str().unwrap(),
            shards[0].to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ],
    );
    assert!(done, "{stderr}");
    assert_eq!(runs(&merged), table);
    // A study killed after 4 rows (its row log cut there) resumes from --out to the
    // same table, computing only the rows the log lacks.
    let log = std::fs::read_to_string(whole.join("rows.log")).unwrap();
    let kept: Vec<&str> = log.lines().take(1 + 4).collect();
    std::fs::write(whole.join("rows.log"), kept.join("\n") + "\n").unwrap();
    let args = fragility(&dir, &records, &["--out", whole.to_str().unwrap()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (done, _, stderr) = run(&args);
    assert!(
        done && stderr.contains("4 of 9 rows reused from its row log, 5 to compute"),
        "{stderr}"
    );
    assert_eq!(runs(&whole), table);
    // --json: the rows and the four fits on stdout.
    let json: serde_json::Value =
        serde_json::from_str(&ok(&fragility(&dir, &records, &["--json"]))).unwrap();
    assert_eq!(
        (
            json["rows"].as_array().unwrap().len(),
            json["fits"].as_array().unwrap().len()
        ),
        (9, 4)
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_records_and_levels_are_one_line_naming_the_flag_or_the_file() {
    let (dir, records) = study("fragility-errors");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let fails = |args: Vec<String>, says: &str| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (ok, _, stderr) = run(&args);
        assert!(!ok && stderr.contains(says), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    };
    fails(fragility(&dir, &empty, &[]), "--records: ");
    fails(
        fragility(&dir, &empty, &[]),
        "holds no record (*.AT2 or *.csv)",
    );
    let scaled = |scales: &str, extra: &[&str]| {
        let mut args = fragility(&dir, &records, extra);
        args[6] = scales.to_owned();
        args
    };
    fails(
        scaled("0,0.5", &["--measure", "pga"]),
        "--scales: level 0: a target PGA (g) must be finite and positive",
    );
    fails(scaled("1,x", &[]), "--scales");
    std::fs::write(records.join("d.csv"), "t,a\n0,0\n0.01,oops\n").unwrap();
    fails(fragility(&dir, &records, &[]), "d.csv line 3");
    std::fs::remove_file(records.join("d.csv")).unwrap();
    let mut harmonic = fragility(&dir, &records, &[]);
    harmonic[2] = "shaking".into();
    fails(harmonic, "give [solver] dt");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn slurm_writes_a_job_for_a_study_and_checks_its_levels_first() {
    let (dir, records) = study("fragility-slurm");
    let slurm = |scales: &str| {
        let mut args: Vec<String> = ["slurm", "--tasks", "2", "--time", "5", "--mem", "100"]
            .map(str::to_owned)
            .to_vec();
        let mut study = fragility(&dir, &records, &["--out", "job"]);
        study[6] = scales.to_owned();
        args.extend(study);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        run_in(&dir, &args)
    };
    let (done, stdout, stderr) = slurm("0.1,1.0");
    assert!(done, "{stderr}");
    assert!(stdout.contains("submit with: bash"), "{stdout}");
    for script in ["shards.sbatch", "merge.sbatch", "submit.sh"] {
        assert!(dir.join("job/slurm").join(script).is_file(), "{script}");
    }
    let batch = std::fs::read_to_string(dir.join("job/slurm/shards.sbatch")).unwrap();
    assert!(
        batch.contains("fragility") && batch.contains("--shard"),
        "{batch}"
    );
    // The jobs, run as Slurm would run them: each array task, then the merge, which
    // writes what one run writes.
    let bash = |script: &str, task: &str| {
        let out = std::process::Command::new("bash")
            .arg(dir.join("job/slurm").join(script))
            .env("SLURM_ARRAY_TASK_ID", task)
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env("SLURM_CPUS_PER_TASK", "1")
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{script}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    bash("shards.sbatch", "0");
    bash("shards.sbatch", "1");
    bash("merge.sbatch", "");
    let mut one = fragility(&dir, &records, &["--out", "one"]);
    one[6] = "0.1,1.0".to_owned();
    let one: Vec<&str> = one.iter().map(String::as_str).collect();
    let (done, _, stderr) = run_in(&dir, &one);
    assert!(done, "{stderr}");
    assert_eq!(runs(&dir.join("job")), runs(&dir.join("one")));
    let (done, _, stderr) = slurm("-1");
    assert!(!done && stderr.contains("--scales: level -1"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_page_s_example_prints_what_the_program_prints() {
    let page = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/fragility.md"
    ));
    let (dir, records) = study("fragility-doc");
    std::fs::rename(&records, dir.join("pulses")).unwrap();
    let found = transcripts(page);
    assert_eq!(found.len(), 1, "the page's transcript is read");
    for t in &found {
        let args: Vec<&str> = t.args.iter().map(String::as_str).collect();
        let (_, stdout, stderr) = run_in(&dir, &args);
        let printed = format!("{stdout}{stderr}");
        let seen: Vec<&str> = printed.lines().collect();
        assert!(
            transcript_matches(&t.lines, &seen),
            "docs/fragility.md shows\n{}\nthe program prints\n{printed}",
            t.lines.join("\n")
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The README's section "From a record to a fragility curve", run in order in a fresh
/// directory as a new user types it, shortened: fewer and shorter records, runs cut at
/// t = 0.05 (what each command writes does not depend on their length).
#[test]
fn the_readme_s_way_from_a_record_to_a_fragility_curve_runs() {
    let readme = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md"));
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let section = readme
        .split("**From a record to a fragility curve.**")
        .nth(1)
        .and_then(|s| s.split("```sh\n").nth(1))
        .and_then(|s| s.split("```").next())
        .expect("the README's section");
    let dir = temp_dir("fragility-readme");
    std::fs::create_dir_all(&dir).unwrap();
    let at_root = |w: &str| {
        if w.starts_with("examples/") || w.starts_with("scripts/") {
            root.join(w).display().to_string()
        } else {
            w.to_owned()
        }
    };
    let mut ran = 0;
    for line in section.lines() {
        let command = line.split('#').next().unwrap_or_default().trim();
        let words: Vec<String> = command.split_whitespace().map(at_root).collect();
        match words.first().map(String::as_str) {
            Some("rollstack") => {
                let mut args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
                args.extend(["--t-end", "0.05"]);
                if args[1] == "run" {
                    args.extend(["--max-frames", "2"]);
                }
                let (ok, _, stderr) = run_in(&dir, &args);
                assert!(ok, "{command}: {stderr}");
            }
            Some("python3") => {
                let mut args = words[1..].to_vec();
                for (flag, short) in [("--count", "3"), ("--duration", "1")] {
                    let at = args.iter().position(|a| a == flag).unwrap() + 1;
                    args[at] = short.to_owned();
                }
                let status = std::process::Command::new("python3")
                    .args(&args)
                    .current_dir(&dir)
                    .status()
                    .unwrap();
                assert!(status.success(), "{command}");
            }
            _ => continue,
        }
        ran += 1;
    }
    assert_eq!(ran, 3, "{section}");
    assert!(dir.join("column/animation.gif").is_file());
    for file in ["runs.csv", "fragility.csv", "fit.json", "fragility.png"] {
        assert!(dir.join("column-fragility").join(file).is_file(), "{file}");
    }
    let rows = std::fs::read_to_string(dir.join("column-fragility/runs.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 3 * 20);
    std::fs::remove_dir_all(dir).unwrap();
}
