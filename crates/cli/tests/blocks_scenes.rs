//! `rollstack blocks scenes`, `blocks run NAME`, `blocks shake`, and what a run says
//! about its scene (defaults taken, warnings) and about its failures (a run that cannot
//! start still writes run.json with its error; no `inf` in the text).

mod common;

use common::{json, rollstack, run, temp_dir};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;

/// Two blocks at rest on a fixed base, no floor, no [solver]: every default taken.
const NO_FLOOR: &str =
    "[base]\nwidth = 1.0\nheight = 0.1\n\n[[blocks]]\nwidth = 0.2\nheight = 0.4\ncount = 2\n\n[contact]\nmu = 0.2\n";

fn write(dir: &Path, name: &str, text: &str) -> String {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn scenes_lists_the_builtin_scenes_and_prints_one_as_its_file() {
    let (ok, stdout, _) = run(&["blocks", "scenes"]);
    assert!(ok);
    for s in blockstack::scenes::builtin() {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(s.name))
            .unwrap_or_else(|| panic!("{} not listed: {stdout}", s.name));
        assert!(line.ends_with(s.description), "{line}");
    }
    let (ok, stdout, _) = run(&["blocks", "scenes", "shaking"]);
    assert!(ok);
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../blockstack/scenes/shaking.toml"
    );
    assert_eq!(stdout, std::fs::read_to_string(file).unwrap());
    let (ok, stdout, stderr) = run(&["blocks", "scenes", "tower"]);
    assert!(!ok && stdout.is_empty());
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("no built-in scene 'tower'")
            && stderr.contains(
                "lire, lire-collapse, rocking-block, shaking, side-by-side, slide, trilith"
            ),
        "{stderr}"
    );
}

#[test]
fn run_takes_a_builtin_name_and_a_file_wins_over_it() {
    let dir = temp_dir("scenes-by-name");
    let out = dir.join("out");
    let v = json(&[
        "blocks",
        "run",
        "slide",
        "--t-end",
        "0.05",
        "--max-frames",
        "0",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(v["steps"].as_u64(), Some(5));
    assert_eq!(v["scene"]["motion"], "constant-velocity");
    assert!(
        v["warnings"].as_array().unwrap().is_empty(),
        "slide has a floor"
    );
    let run_json = read_json(&out.join("run.json"));
    assert_eq!(run_json["inputs"]["scene"], "slide");
    assert!(run_json["error"].is_null());
    // A file called `slide` in the working directory is read instead.
    write(&dir, "slide", NO_FLOOR);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rollstack"))
        .args(["blocks", "run", "slide", "--t-end", "0.02", "--json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["scene"]["motion"], "fixed");
    assert_eq!(v["final"].as_array().unwrap().len(), 2);
    // Neither a file nor a built-in name: one line naming the built-in scenes.
    let (ok, stdout, stderr) = run(&["blocks", "run", "tower", "--json"]);
    assert!(!ok && stdout.is_empty());
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(
            "built-in scenes: abundance, abundance-author, drop, drum-column, lire, lire-collapse, rocking-block, shaking, side-by-side, slide, trilith"
        ),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn defaults_and_warnings_are_printed_and_recorded() {
    let dir = temp_dir("scenes-defaults");
    let scene = write(&dir, "two.toml", NO_FLOOR);
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "run",
        &scene,
        "--t-end",
        "0.05",
        "--max-frames",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.starts_with("warning: no floor:"), "{stderr}");
    assert!(
        stdout.starts_with("scene: 2 blocks, base fixed, no floor"),
        "{stdout}"
    );
    assert!(
        stdout.contains("\ndefaults taken: solver.dt = 0.01, solver.rho_inf = 0.5,"),
        "{stdout}"
    );
    // --t-end replaced the default end time: it is not listed.
    assert!(!stdout.contains("solver.t_end"), "{stdout}");
    let r = read_json(&out.join("run.json"));
    assert_eq!(r["scene"]["defaults"]["solver.dt"], 0.01);
    assert_eq!(r["scene"]["defaults"]["solver.gravity"], 1.0);
    assert_eq!(r["scene"]["t_end"], 0.05);
    assert!(r["scene"]["steps_per_period"].is_null());
    let warnings = r["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].as_str().unwrap().starts_with("no floor"));
    // With a floor: no warning.
    let floored = write(&dir, "floor.toml", &format!("{NO_FLOOR}[floor]\n"));
    let (ok, _, stderr) = run(&["blocks", "run", &floored, "--t-end", "0.02"]);
    assert!(ok && !stderr.contains("warning"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn period_keys_are_checked_against_the_base_motion() {
    let dir = temp_dir("scenes-periods");
    let fixed = write(
        &dir,
        "fixed.toml",
        &format!("{NO_FLOOR}[solver]\nsteps_per_period = 100\n"),
    );
    let (ok, stdout, stderr) = run(&["blocks", "run", &fixed, "--json"]);
    assert!(!ok && stdout.is_empty());
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("steps_per_period needs a periodic base (motion = \"harmonic\")"),
        "{stderr}"
    );
    let harmonic = NO_FLOOR.replace(
        "height = 0.1\n",
        "height = 0.1\nmotion = \"harmonic\"\namplitude = 0.1\nomega = 6.0\n",
    );
    let both = write(
        &dir,
        "both.toml",
        &format!("{harmonic}[solver]\ndt = 0.01\nsteps_per_period = 100\n"),
    );
    let (ok, _, stderr) = run(&["blocks", "run", &both]);
    assert!(
        !ok && stderr.contains("both dt and steps_per_period"),
        "{stderr}"
    );
    let good = write(
        &dir,
        "good.toml",
        &format!("{harmonic}[solver]\nsteps_per_period = 50\nperiods = 0.1\n[floor]\n"),
    );
    let v = json(&["blocks", "run", &good, "--json", "--max-frames", "0"]);
    assert_eq!(v["steps"].as_u64(), Some(5));
    assert_eq!(v["scene"]["steps_per_period"], 50.0);
    assert!((v["scene"]["dt"].as_f64().unwrap() - 2.0 * PI / 300.0).abs() < 1e-15);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn shake_runs_a_column_with_the_outputs_of_run() {
    let dir = temp_dir("scenes-shake");
    let v = json(&[
        "blocks",
        "shake",
        "--blocks",
        "6",
        "--omega",
        "6",
        "--amplitude",
        "0.1",
        "--periods",
        "0.1",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // 100 steps per period (default), 0.1 periods: 10 steps of 2π/600.
    assert_eq!(v["steps"].as_u64(), Some(10));
    assert_eq!(v["final"].as_array().unwrap().len(), 6);
    assert!(v["error"].is_null() && v["warnings"].as_array().unwrap().is_empty());
    let s = &v["scene"];
    assert_eq!(
        (s["blocks"].as_u64(), s["motion"].as_str()),
        (Some(6), Some("harmonic"))
    );
    assert!((s["dt"].as_f64().unwrap() - 2.0 * PI / 600.0).abs() < 1e-15);
    assert_eq!(s["steps_per_period"], 100.0);
    assert_eq!(s["floor"], -0.05);
    let files: Vec<&str> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    for f in [
        "trajectory.csv",
        "animation.gif",
        "top_block.png",
        "run.json",
    ] {
        assert!(files.contains(&f) && dir.join(f).exists(), "{f}: {files:?}");
    }
    let r = read_json(&dir.join("run.json"));
    assert_eq!(r["command"], "blocks shake");
    assert_eq!(r["inputs"]["omega"], 6.0);
    assert_eq!(r["inputs"]["blocks"], 6);
    // --t-end instead of --periods; both at once is a usage error.
    let v = json(&["blocks", "shake", "--t-end", "0.05", "--json"]);
    assert_eq!(v["scene"]["t_end"], 0.05);
    let out = rollstack(&["blocks", "shake", "--t-end", "1", "--periods", "2"]);
    assert_eq!(out.status.code(), Some(2));
    let (ok, _, stderr) = run(&["blocks", "shake", "--omega", "0"]);
    assert!(
        !ok && stderr.contains("--omega must be positive"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--start-with-base`: a 30-block column on x = 0.001 sin 2t that starts moving with
/// its base is one rigid body below its tipping acceleration (method.md §8.2): one
/// Newton update per step on the factors of one linear solve. From rest, friction kicks
/// it at t = 0 and its interfaces rock: more updates than steps.
#[test]
fn shake_start_with_base_keeps_a_tall_column_in_one_piece() {
    let column = |with_base: bool| {
        let mut args = vec![
            "blocks",
            "shake",
            "--blocks",
            "30",
            "--omega",
            "2",
            "--amplitude",
            "0.001",
            "--steps-per-period",
            "314",
            "--t-end",
            "0.1",
            "--json",
        ];
        if with_base {
            args.push("--start-with-base");
        }
        json(&args)
    };
    let moving = column(true);
    assert!(moving["error"].is_null(), "{}", moving["error"]);
    assert_eq!(moving["steps"].as_u64(), Some(10));
    assert!(moving["newton_iterations_mean"].as_f64().unwrap() <= 1.0);
    assert_eq!(moving["linear_solves"].as_u64(), Some(1));
    let at_rest = column(false);
    assert!(at_rest["newton_iterations_mean"].as_f64().unwrap() > 1.0);
}

/// Valid numbers that make the consistent start fail: a constant prox parameter of
/// 1e300 leaves the start's Newton matrix singular (and every later step's).
fn start_fails(dir: &Path) -> String {
    write(
        dir,
        "start.toml",
        &format!("{NO_FLOOR}[solver]\nt_end = 0.05\nr = 1e300\n"),
    )
}

/// `blocks run` of a scene whose start fails, with `extra` flags and the last resort off
/// (it would take the first step instead: the test after these).
fn run_unstarted(scene: &str, extra: &[&str]) -> (bool, String, String) {
    let mut args = vec!["blocks", "run", scene, "--last-resort", "false"];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn a_run_that_cannot_start_still_writes_run_json_with_its_error() {
    let dir = temp_dir("scenes-start-fails");
    let scene = start_fails(&dir);
    let out = dir.join("out");
    let (ok, stdout, stderr) = run_unstarted(&scene, &["--json", "--out", out.to_str().unwrap()]);
    assert!(!ok, "a failed run exits non-zero");
    assert!(!stderr.contains("no frame to animate"), "{stderr}");
    let last = stderr.trim().lines().last().unwrap();
    assert!(
        last.starts_with("error: the simulation could not start: consistent start"),
        "{stderr}"
    );
    let v: Value = serde_json::from_str(&stdout).expect("the JSON is printed");
    assert!(v["error"].as_str().unwrap().contains("consistent start"));
    assert_eq!(v["steps"].as_u64(), Some(0));
    assert!(v["min_gap"].is_null());
    let notes: Vec<&str> = v["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert!(
        notes.iter().any(|n| n.starts_with("no animation.gif")),
        "{notes:?}"
    );
    assert!(!out.join("animation.gif").exists());
    let r = read_json(&out.join("run.json"));
    assert_eq!(r["error"], v["error"]);
    assert_eq!(r["notes"].as_array().unwrap().len(), notes.len());
    assert_eq!(r["command"], "blocks run");
    assert!(out.join("trajectory.csv").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_run_that_stops_on_its_first_step_keeps_its_start() {
    let dir = temp_dir("scenes-first-step");
    // g = 1e100 passes validation, starts, and no Newton attempt resolves a step (the
    // last resort, left out here, would take them: the blocks fall 1e98 per step).
    // (g = 1e300 started only while a friction force's norm overflowed to ∞, which
    // dropped it; with the norm of one component its magnitude, docs/method.md §3, the
    // start's friction overflows and the start fails.)
    let scene = write(
        &dir,
        "heavy.toml",
        &format!("{NO_FLOOR}[solver]\nt_end = 0.05\ngravity = 1e100\n"),
    );
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "run",
        &scene,
        "--last-resort",
        "false",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("the simulation stopped at t = 0.000000 after 0 steps"),
        "{stderr}"
    );
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert!(v["error"].is_string());
    // The state at t = 0 was computed: it is drawn.
    assert!(out.join("snapshot_t0.png").exists() && out.join("animation.gif").exists());
    assert_eq!(read_json(&out.join("run.json"))["error"], v["error"]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_run_without_steps_prints_none_not_inf() {
    let dir = temp_dir("scenes-no-inf");
    let scene = start_fails(&dir);
    let (ok, stdout, stderr) = run_unstarted(&scene, &["--max-frames", "0"]);
    assert!(!ok);
    assert!(stdout.contains("min gap none"), "{stdout}");
    // No number prints as `inf` (`rho_inf` is a name).
    let words = stdout.split(|c: char| !c.is_alphanumeric() && c != '_');
    assert!(!words.into_iter().any(|w| w == "inf"), "{stdout}");
    assert!(!stderr.contains("no frame"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_run_whose_consistent_start_fails_goes_on_by_the_last_resort_and_says_so() {
    let dir = temp_dir("scenes-start-fails-last-resort");
    let scene = start_fails(&dir);
    let (ok, stdout, stderr) = run(&["blocks", "run", &scene, "--json"]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).expect("the JSON is printed");
    assert!(v["error"].is_null(), "{v}");
    assert_eq!(v["steps"].as_u64(), Some(5));
    let why = v["start_failure"]
        .as_str()
        .expect("the start's failure is reported");
    assert!(why.starts_with("consistent start at t = 0 failed"), "{why}");
    // Every step's Newton matrix is singular too: each is a last-resort step.
    assert_eq!(v["fallback_steps"].as_u64(), Some(5));
    assert!(v["fallback_residual"].as_f64().unwrap() < 1e-8);
    assert!(
        v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("taken by the last resort")),
        "{v}"
    );
    assert!(
        stderr.contains("the first step was taken by the last resort"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The blocks a shaken column leaves on the floor are held out of the solve while the
/// base shakes on (docs/method.md §8.2, "Islands at rest"), and the run says in how many
/// steps, in its text and as the JSON keys `held_island_steps` and `island_wakes`.
#[test]
fn a_run_counts_the_steps_with_islands_held_at_rest() {
    let dir = temp_dir("islands");
    let out = dir.to_str().unwrap();
    let args = [
        "blocks",
        "shake",
        "--blocks",
        "3",
        "--omega",
        "8",
        "--mu",
        "0.5",
        "--amplitude",
        "0.2",
        "--steps-per-period",
        "200",
        "--t-end",
        "20",
        "--max-frames",
        "0",
        "--force",
        "--out",
        out,
    ];
    let (ok, text, stderr) = run(&args);
    assert!(ok, "{stderr}");
    let j = json(&[&args[..], &["--json"]].concat());
    let held = j["held_island_steps"].as_u64().expect("held_island_steps");
    let wakes = j["island_wakes"].as_u64().expect("island_wakes");
    assert!(held * 2 > j["steps"].as_u64().unwrap(), "{held} steps held");
    assert_eq!(j["resting_steps"].as_u64(), Some(0), "the base shakes on");
    assert!(
        text.contains(&format!(
            "steps with blocks at rest held out of the solve: {held} (woken by a force {wakes} times)"
        )),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Piles at rest beside a fixed base are held without solving, and the run says how many
/// steps were held, in its text and as the JSON key `resting_steps`.
#[test]
fn a_run_held_at_rest_counts_the_steps_held() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/pile-at-rest.toml"
    );
    let dir = temp_dir("resting");
    let out = dir.to_str().unwrap();
    let (ok, text, stderr) = run(&["blocks", "run", scene, "--force", "--out", out]);
    assert!(ok, "{stderr}");
    let j = json(&["blocks", "run", scene, "--json", "--force", "--out", out]);
    let held = j["resting_steps"].as_u64().expect("resting_steps");
    assert!(
        held + 10 >= j["steps"].as_u64().unwrap(),
        "{held} steps held"
    );
    assert!(
        text.contains(&format!(
            "steps held at rest without solving (the base standing still): {held}"
        )),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}
