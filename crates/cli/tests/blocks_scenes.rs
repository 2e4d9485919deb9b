//! What a run says about its scene (defaults taken, warnings, the period keys) and about
//! its failures (a run that cannot start still writes run.json with its error; no `inf`
//! in the text).

mod common;

use common::{json, run, temp_dir};
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

/// Valid numbers that make the consistent start fail: a constant prox parameter of
/// 1e300 leaves the start's Newton matrix singular.
fn start_fails(dir: &Path) -> String {
    write(
        dir,
        "start.toml",
        &format!("{NO_FLOOR}[solver]\nt_end = 0.05\nr = 1e300\n"),
    )
}

#[test]
fn a_run_that_cannot_start_still_writes_run_json_with_its_error() {
    let dir = temp_dir("scenes-start-fails");
    let scene = start_fails(&dir);
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "run",
        &scene,
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
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
    // g = 1e300 passes validation, starts, and no step can be resolved.
    let scene = write(
        &dir,
        "heavy.toml",
        &format!("{NO_FLOOR}[solver]\nt_end = 0.05\ngravity = 1e300\n"),
    );
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "run",
        &scene,
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
    let (ok, stdout, stderr) = run(&["blocks", "run", &scene, "--max-frames", "0"]);
    assert!(!ok);
    assert!(stdout.contains("min gap none"), "{stdout}");
    // No number prints as `inf` (`rho_inf` is a name).
    let words = stdout.split(|c: char| !c.is_alphanumeric() && c != '_');
    assert!(!words.into_iter().any(|w| w == "inf"), "{stdout}");
    assert!(!stderr.contains("no frame"), "{stderr}");
    std::fs::remove_dir_all(dir).unwrap();
}
