//! Sweeps split into shards, killed and resumed, and merged: the result is always the
//! table one uninterrupted run on one machine writes (docs/cluster.md).

mod common;

use common::{temp_dir, SWEEP};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn command(args: &[&str], threads: &str) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rollstack"));
    c.args(args).env("RAYON_NUM_THREADS", threads);
    c
}

fn sweep(extra: &[&str], out: &Path, threads: &str) -> Output {
    let mut args = SWEEP.to_vec();
    args.extend(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    command(&args, threads).output().unwrap()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn merge(dirs: &[&PathBuf], out: &Path) -> Output {
    let mut args = vec!["merge".to_owned()];
    args.extend(dirs.iter().map(|d| d.to_string_lossy().into_owned()));
    args.extend(["--out".to_owned(), out.to_string_lossy().into_owned()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    command(&args, "2").output().unwrap()
}

/// The CSV of the frequency sweep in `dir` without its timing column.
fn table(dir: &Path) -> Vec<Vec<String>> {
    csv_table(dir, "sweep_frequency.csv")
}

/// The CSV `file` of `dir` without its timing column, which differs from run to run.
fn csv_table(dir: &Path, file: &str) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(dir.join(file)).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_owned).collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| header[i] != "wall_time_s")
        .collect();
    let mut rows = vec![keep.iter().map(|&i| header[i].clone()).collect()];
    for rec in r.records() {
        let rec = rec.unwrap();
        rows.push(keep.iter().map(|&i| rec[i].to_owned()).collect());
    }
    rows
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn shards_merged_in_any_order_equal_one_run_with_any_number_of_threads() {
    let dir = temp_dir("shards-merge");
    let single = dir.join("single");
    ok(&sweep(&[], &single, "1"));
    let two_threads = dir.join("two-threads");
    ok(&sweep(&[], &two_threads, "2"));
    assert_eq!(table(&single), table(&two_threads));
    assert_eq!(table(&single).len(), 9);

    let parts: Vec<PathBuf> = (1..=3).map(|k| dir.join(format!("part{k}"))).collect();
    for (k, p) in parts.iter().enumerate() {
        ok(&sweep(&["--shard", &format!("{}/3", k + 1)], p, "2"));
    }
    // --shard auto reads the task of a Slurm job array.
    let auto = dir.join("auto");
    let mut args = SWEEP.to_vec();
    args.extend(["--shard", "auto", "--out", auto.to_str().unwrap()]);
    let out = command(&args, "1")
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .unwrap();
    ok(&out);
    assert_eq!(table(&auto), table(&parts[2]));

    let merged = dir.join("merged");
    ok(&merge(&[&parts[2], &parts[0], &parts[1]], &merged));
    assert_eq!(table(&merged), table(&single));
    for f in ["sweep_frequency.png", "manifest.json"] {
        assert!(merged.join(f).exists(), "{f}");
    }
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(merged.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["inputs"]["shard"], "1/1");
    assert_eq!(run["failed_rows"], 0);
    // The plot is drawn from the same rows: the same picture.
    assert_eq!(
        std::fs::read(merged.join("sweep_frequency.png")).unwrap(),
        std::fs::read(single.join("sweep_frequency.png")).unwrap()
    );

    // A missing shard and a duplicated row are named.
    let out = merge(&[&parts[0], &parts[2]], &dir.join("m1"));
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("rows 2-4 in no shard"),
        "{}",
        stderr(&out)
    );
    let out = merge(&[&parts[0], &parts[1], &parts[2], &auto], &dir.join("m2"));
    assert!(
        stderr(&out).contains("rows 5-7 in both"),
        "{}",
        stderr(&out)
    );
    // A shard of another sweep, and one of another version.
    let other = dir.join("other");
    let mut args = SWEEP.to_vec();
    args[4] = "3:10:1";
    args.extend(["--shard", "3/3", "--out", other.to_str().unwrap()]);
    ok(&command(&args, "2").output().unwrap());
    let out = merge(&[&parts[0], &parts[1], &other], &dir.join("m3"));
    assert!(
        stderr(&out).contains("inputs differ: omega = \"2:9:1\" against \"3:10:1\""),
        "{}",
        stderr(&out)
    );
    let manifest = parts[1].join("manifest.json");
    let text = std::fs::read_to_string(&manifest).unwrap();
    std::fs::write(
        &manifest,
        text.replace("\"version\": \"", "\"version\": \"9"),
    )
    .unwrap();
    let out = merge(&[&parts[1], &parts[0], &parts[2]], &dir.join("m4"));
    assert!(stderr(&out).contains("rollstack 9"), "{}", stderr(&out));
    std::fs::write(&manifest, text).unwrap();
    // A damaged CSV.
    let csv = parts[0].join("sweep_frequency.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    std::fs::write(&csv, text.replacen("200", "201", 1)).unwrap();
    let out = merge(&[&parts[0], &parts[1], &parts[2]], &dir.join("m5"));
    assert!(
        stderr(&out).contains("sweep_frequency.csv: does not match the checksum"),
        "{}",
        stderr(&out)
    );
    for m in ["m1", "m2", "m3", "m4", "m5"] {
        assert!(!dir.join(m).join("sweep_frequency.csv").exists(), "{m}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Lines of the row log of `dir` (its header included).
fn log_lines(dir: &Path) -> usize {
    std::fs::read(dir.join("rows.log"))
        .map(|b| b.iter().filter(|&&c| c == b'\n').count())
        .unwrap_or(0)
}

#[test]
fn a_sweep_killed_at_any_point_resumes_to_the_same_table() {
    let dir = temp_dir("shards-resume");
    let whole = dir.join("whole");
    ok(&sweep(&[], &whole, "2"));
    // Kill points: before any row, after some rows, and at times that fall anywhere,
    // also inside a write.
    let points: [(usize, u64); 5] = [(0, 0), (1, 0), (4, 0), (0, 7), (0, 23)];
    for (n, &(rows, ms)) in points.iter().enumerate() {
        let out = dir.join(format!("killed{n}"));
        let mut args = SWEEP.to_vec();
        args.extend(["--out", out.to_str().unwrap()]);
        let mut child = command(&args, "1").spawn().unwrap();
        let start = Instant::now();
        while log_lines(&out) < rows + 1 && start.elapsed() < Duration::from_secs(60) {
            std::thread::sleep(Duration::from_millis(1));
        }
        std::thread::sleep(Duration::from_millis(ms));
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        let kept = log_lines(&out).saturating_sub(1);
        ok(&sweep(&[], &out, "2"));
        assert_eq!(table(&out), table(&whole), "kill point {n}");
        // Each row is computed once: the log holds every row once after the resume.
        assert_eq!(
            log_lines(&out),
            9,
            "kill point {n} (killed after {kept} rows)"
        );
    }
    // A temporary file of a killed run is removed by the next run into the directory.
    let stale = dir.join("whole").join(".tmp-4999999-trajectory.csv");
    std::fs::write(&stale, "half").unwrap();
    ok(&sweep(&[], &whole, "2"));
    assert!(!stale.exists());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn failed_rows_are_counted_and_end_with_status_3() {
    let dir = temp_dir("shards-failed");
    let part = dir.join("part");
    ok(&sweep(&[], &part, "2"));
    // A shard whose row 3 did not converge, with consistent checksums.
    let (id, mut rows) = shards::RowLog::read(&part).unwrap();
    rows.get_mut(&3).unwrap()["error"] = "did not converge".into();
    shards::RowLog::write_all(&part, &id, &rows).unwrap();
    let m = shards::Manifest::read(&part).unwrap();
    let shard = m.shard.parse().unwrap();
    shards::Manifest::new(&id, m.argv, shard, 8, m.rows, &m.csv, &part)
        .unwrap()
        .write(&part)
        .unwrap();
    let merged = dir.join("merged");
    let out = merge(&[&part], &merged);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("1 of 8 rows failed"),
        "{}",
        stderr(&out)
    );
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(merged.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["failed_rows"], 1);
    // Column 7 of sweep_frequency.csv is `error`.
    assert_eq!(table(&merged)[4][7], "did not converge");
    let _ = std::fs::remove_dir_all(dir);
}

/// A sweep of `my.toml` (in the working directory) over five amplitudes, two blocks,
/// about 0.1 s a row: slow enough to be killed between rows.
const SCENE_SWEEP: &[&str] = &[
    "blocks",
    "sweep",
    "scene",
    "my.toml",
    "--set",
    "base.amplitude=0.1:0.3:0.05",
    "--set",
    "blocks.count=2",
    "--set",
    "solver.periods=40",
];

/// Writes `dir/my.toml`: the built-in scene `shaking` with the friction coefficient `mu`.
fn write_scene(dir: &Path, mu: &str) {
    let out = command(&["blocks", "scenes", "shaking"], "1")
        .output()
        .unwrap();
    ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("\nmu = 0.2\n"), "{text}");
    let text = text.replace("\nmu = 0.2\n", &format!("\nmu = {mu}\n"));
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("my.toml"), text).unwrap();
}

/// The scene sweep with `extra` arguments, run in `cwd` on one thread.
fn scene_sweep(cwd: &Path, extra: &[&str]) -> Command {
    let mut args = SCENE_SWEEP.to_vec();
    args.extend(extra);
    let mut c = command(&args, "1");
    c.current_dir(cwd);
    c
}

#[test]
fn an_edited_scene_is_refused_by_the_rows_of_the_old_one() {
    let dir = temp_dir("shards-scene-edit");
    write_scene(&dir, "0.2");
    ok(&scene_sweep(&dir, &["--out", "out"]).output().unwrap());
    let out = dir.join("out");
    let before = csv_table(&out, "sweep_scene.csv");
    assert_eq!(before.len(), 6);
    assert_eq!(
        std::fs::read(out.join("scene.toml")).unwrap(),
        std::fs::read(dir.join("my.toml")).unwrap(),
        "the sweep keeps a copy of its scene"
    );
    // Edited, then run again: refused, naming the file, the change and the way out.
    write_scene(&dir, "0.5");
    let refused = scene_sweep(&dir, &["--out", "out"]).output().unwrap();
    let says = stderr(&refused);
    assert!(!refused.status.success(), "{says}");
    assert!(
        says.contains("scene my.toml differs from the one the rows in out were computed from")
            && says.contains("is `mu = 0.5`, was `mu = 0.2`")
            && says.contains("remove out or give another --out"),
        "{says}"
    );
    assert_eq!(says.lines().count(), 1, "{says}");
    assert_eq!(csv_table(&out, "sweep_scene.csv"), before);
    // Killed after some rows, edited, run again: refused too, never a table that mixes
    // the rows of two scenes.
    write_scene(&dir, "0.2");
    let killed = dir.join("killed");
    let mut child = scene_sweep(&dir, &["--out", "killed"]).spawn().unwrap();
    let start = Instant::now();
    while log_lines(&killed) < 3 && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(1));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let kept = log_lines(&killed) - 1;
    assert!((2..5).contains(&kept), "killed after {kept} of 5 rows");
    write_scene(&dir, "0.5");
    let refused = scene_sweep(&dir, &["--out", "killed"]).output().unwrap();
    assert!(
        stderr(&refused).contains("is `mu = 0.5`, was `mu = 0.2`"),
        "{}",
        stderr(&refused)
    );
    assert!(!killed.join("sweep_scene.csv").exists());
    assert_eq!(log_lines(&killed) - 1, kept, "the old rows are kept");
    // The scene as it was: the sweep resumes to the uninterrupted table.
    write_scene(&dir, "0.2");
    ok(&scene_sweep(&dir, &["--out", "killed"]).output().unwrap());
    assert_eq!(csv_table(&killed, "sweep_scene.csv"), before);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn merge_reads_the_kept_scene_from_anywhere_and_refuses_two_scenes() {
    let dir = temp_dir("shards-scene-merge");
    let (here, elsewhere) = (dir.join("here"), dir.join("elsewhere"));
    std::fs::create_dir_all(&elsewhere).unwrap();
    write_scene(&here, "0.2");
    ok(&scene_sweep(&here, &["--out", "single"]).output().unwrap());
    for k in 1..=2 {
        let (shard, out) = (format!("{k}/2"), format!("part{k}"));
        ok(&scene_sweep(&here, &["--shard", &shard, "--out", &out])
            .output()
            .unwrap());
    }
    // From a directory without my.toml, whose manifests name it by a relative path.
    let merge_in = |cwd: &Path, parts: &[&str], out: &str| {
        let mut args = vec!["merge"];
        args.extend(parts);
        args.extend(["--out", out]);
        let mut c = command(&args, "2");
        c.current_dir(cwd).output().unwrap()
    };
    ok(&merge_in(
        &elsewhere,
        &["../here/part2", "../here/part1"],
        "merged",
    ));
    let merged = elsewhere.join("merged");
    assert_eq!(
        csv_table(&merged, "sweep_scene.csv"),
        csv_table(&here.join("single"), "sweep_scene.csv")
    );
    assert_eq!(
        std::fs::read(merged.join("scene.toml")).unwrap(),
        std::fs::read(here.join("my.toml")).unwrap()
    );
    // A shard of the edited scene does not join the others.
    write_scene(&here, "0.5");
    ok(&scene_sweep(&here, &["--shard", "2/2", "--out", "edited2"])
        .output()
        .unwrap());
    let out = merge_in(&elsewhere, &["../here/part1", "../here/edited2"], "m");
    let says = stderr(&out);
    assert!(!out.status.success(), "{says}");
    assert!(
        says.contains("not shards of one sweep: they read different scene.toml")
            && says.contains("is `mu = 0.2` in ../here/part1, `mu = 0.5` in ../here/edited2"),
        "{says}"
    );
    assert!(!elsewhere.join("m").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// A stand-in for `sbatch` on PATH: it records its arguments and the words of its
/// script's `#SBATCH` lines (read with a shell's quotes, as sbatch reads them) into
/// `$SBATCH_LOG`, one `[word]` each, and prints a job id as `--parsable` does.
const FAKE_SBATCH: &str = r#"#!/bin/bash
{
    printf 'sbatch'; printf ' [%s]' "$@"; echo
    grep '^#SBATCH ' "${@: -1}" | while IFS= read -r line; do
        eval "set -- ${line#'#SBATCH '}"
        printf 'directive'; printf ' [%s]' "$@"; echo
    done
} >> "$SBATCH_LOG"
echo "4242;cluster"
"#;

/// Every path below `dir` whose file name is `name`.
fn find(dir: &Path, name: &str) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.file_name().is_some_and(|n| n == name) {
            found.push(path.clone());
        }
        if path.is_dir() {
            found.extend(find(&path, name));
        }
    }
    found
}

fn slurm_in(cwd: &Path, options: &[&str], out: &str) -> Output {
    let mut args = vec!["slurm"];
    args.extend(options);
    args.extend(SWEEP);
    args.extend(["--out", out]);
    let mut c = command(&args, "2");
    c.current_dir(cwd).output().unwrap()
}

#[test]
fn slurm_refuses_bad_requests_and_values_before_writing() {
    let dir = temp_dir("shards-slurm-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let given = ["--time", "5", "--mem", "100"];
    for (options, out, says) in [
        (
            &["--tasks", "2", "--partition", "a\nb"][..],
            "o",
            "--partition holds the control character '\\n'",
        ),
        (
            &["--tasks", "2"],
            "o\nx",
            "holds the control character '\\n'",
        ),
        (
            &["--tasks", "2", "--time", "0"],
            "o",
            "--time must be at least 1 minute",
        ),
        (
            &["--tasks", "2", "--mem", "0"],
            "o",
            "--mem must be at least 1 MiB",
        ),
        (
            &["--tasks", "1000000000"],
            "o",
            "--tasks must be between 1 and 100000",
        ),
        (
            &["--tasks", "0"],
            "o",
            "--tasks must be between 1 and 100000",
        ),
    ] {
        let out = slurm_in(&dir, options, out);
        assert!(!out.status.success(), "{options:?}");
        assert!(stderr(&out).contains(says), "{options:?}: {}", stderr(&out));
        assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
    }
    // With --time and --mem there is no calibration run; the sweep's values are checked.
    let mut args = vec!["slurm", "--tasks", "2"];
    args.extend(given);
    args.extend(&SWEEP[..3]);
    args.extend(["--omega", "2,nan", "--out", "o"]);
    let out = command(&args, "1").current_dir(&dir).output().unwrap();
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--omega"), "{}", stderr(&out));
    let mut args = vec!["slurm", "--tasks", "2"];
    args.extend(given);
    args.extend([
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "contact.mu=-1,0.2",
    ]);
    args.extend(["--out", "o"]);
    let out = command(&args, "1").current_dir(&dir).output().unwrap();
    assert!(
        stderr(&out).contains("--set contact.mu=-1"),
        "{}",
        stderr(&out)
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing is written"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn slurm_scripts_hold_hostile_values_literally_when_run() {
    let dir = temp_dir("shards-slurm-hostile");
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let sbatch = bin.join("sbatch");
    std::fs::write(&sbatch, FAKE_SBATCH).unwrap();
    let chmod = Command::new("chmod")
        .arg("+x")
        .arg(&sbatch)
        .status()
        .unwrap();
    assert!(chmod.success());
    let name = "o4 $(touch INJ1) `touch INJ2` \" ' ; touch INJ3 #";
    let options = [
        "--tasks",
        "2",
        "--time",
        "5",
        "--mem",
        "100",
        "--partition",
        "p q'\"",
    ];
    ok(&slurm_in(&dir, &options, name));
    let out = dir.join(name);
    let scripts = out.join("slurm");
    let log = dir.join("sbatch.log");
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    let submit = Command::new("bash")
        .arg(scripts.join("submit.sh"))
        .env("PATH", &path)
        .env("SBATCH_LOG", &log)
        .current_dir(&dir)
        .output()
        .unwrap();
    ok(&submit);
    let printed = String::from_utf8_lossy(&submit.stdout);
    assert!(
        printed.contains(&format!("the merged sweep will be in {}\n", out.display())),
        "{printed}"
    );
    let calls = std::fs::read_to_string(&log).unwrap();
    let logs = scripts.join("logs");
    for line in [
        "sbatch [--parsable] [shards.sbatch]".to_owned(),
        "directive [--array=0-1]".to_owned(),
        "directive [--partition=p q'\"]".to_owned(),
        format!("directive [--output={}/shard-%a.out]", logs.display()),
        "sbatch [--parsable] [--dependency=afterok:4242] [merge.sbatch]".to_owned(),
        format!("directive [--output={}/merge.out]", logs.display()),
    ] {
        assert!(calls.lines().any(|l| l == line), "{line}\nnot in\n{calls}");
    }
    // The jobs, run as Slurm would run them: each array task, then the merge.
    for task in ["0", "1"] {
        let run = Command::new("bash")
            .arg(scripts.join("shards.sbatch"))
            .env("SLURM_ARRAY_TASK_ID", task)
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env("SLURM_CPUS_PER_TASK", "1")
            .current_dir(&dir)
            .output()
            .unwrap();
        ok(&run);
    }
    ok(&Command::new("bash")
        .arg(scripts.join("merge.sbatch"))
        .current_dir(&dir)
        .output()
        .unwrap());
    let single = dir.join("single");
    ok(&sweep(&[], &single, "2"));
    assert_eq!(table(&out), table(&single));
    for injected in ["INJ1", "INJ2", "INJ3"] {
        assert_eq!(find(&dir, injected), Vec::<PathBuf>::new(), "{injected}");
    }
    let _ = std::fs::remove_dir_all(dir);
}
