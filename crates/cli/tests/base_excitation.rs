//! Scenes whose base plays a recorded accelerogram, a pulse, a heave or a tilt:
//! `blocks run` and `blocks sweep scene --set base.scale=…`, with their errors.

mod common;

use common::{json, run, temp_dir};
use std::path::Path;

/// The repository's synthetic record (scripts/synthetic_record.py).
const RECORD: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/data/synthetic.AT2"
);
/// The example scene that plays it.
const EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../examples/scenes/drums-on-record.toml"
);

/// A block on a base whose x plays `record` (a path relative to the scene) with the
/// given extra keys of [base.x], and other tables appended.
fn scene(x_keys: &str, more: &str) -> String {
    format!(
        "[base]\nwidth = 1.0\nheight = 0.1\n[base.x]\nmotion = \"record\"\nrecord = \"quake.AT2\"\n{x_keys}\n{more}\n[[blocks]]\nwidth = 0.2\nheight = 0.4\n[contact]\nmu = 0.5\n[solver]\ndt = 0.01\nt_end = 0.3\ngravity = 9.81\n[floor]\n"
    )
}

/// Writes `text` as `name` into `dir` with a copy of the synthetic record beside it.
fn with_record(dir: &Path, name: &str, text: &str) -> String {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(RECORD, dir.join("quake.AT2")).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_scene_plays_its_record_from_the_scene_files_directory() {
    let dir = temp_dir("excite-run");
    let file = with_record(&dir, "scene.toml", &scene("scale_to_pga = 0.3", ""));
    // Run from elsewhere: the record is found beside the scene file.
    let v = json(&["blocks", "run", &file, "--json"]);
    assert_eq!(v["error"], serde_json::Value::Null, "{v}");
    assert_eq!(v["scene"]["motion"], "record");
    assert_eq!(v["steps"], 30);
    // The block follows the base: it has moved with the record.
    let x = v["final"][0]["x"].as_f64().unwrap();
    assert!(x.abs() > 1e-6, "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_example_scene_runs() {
    let v = json(&["blocks", "run", EXAMPLE, "--t-end", "0.1", "--json"]);
    assert_eq!(v["error"], serde_json::Value::Null, "{v}");
    assert_eq!(v["steps"], 50);
    assert_eq!(v["scene"]["gravity"], 9.81);
}

#[test]
fn other_components_are_reported() {
    let dir = temp_dir("excite-components");
    let more = "[base.y]\nmotion = \"pulse\"\nshape = \"ricker\"\namplitude = 1.0\nperiod = 0.2\n[base.rotation]\nmotion = \"harmonic\"\namplitude = 0.01\nomega = 2.0\n";
    let file = with_record(&dir, "scene.toml", &scene("", more));
    let (ok, stdout, stderr) = run(&["blocks", "run", &file]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("base record (rotation harmonic, y pulse)"),
        "{stdout}"
    );
    let v = json(&["blocks", "run", &file, "--json"]);
    assert_eq!(v["scene"]["other_motions"]["y"], "pulse", "{v}");
    assert_eq!(v["scene"]["other_motions"]["rotation"], "harmonic", "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The one-line error of `blocks run` on the scene `text` (written beside a record).
fn error_of(tag: &str, text: &str) -> String {
    let dir = temp_dir(tag);
    let file = with_record(&dir, "scene.toml", text);
    let (ok, _, stderr) = run(&["blocks", "run", &file]);
    assert!(!ok);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
    stderr
}

#[test]
fn bad_excitations_are_one_line_naming_the_key() {
    let e = error_of("excite-e1", &scene("scale_to_pga = -1", ""));
    assert!(
        e.contains("base.x scale_to_pga must be positive, got -1"),
        "{e}"
    );
    let e = error_of("excite-e2", &scene("omega = 2", ""));
    assert!(
        e.contains("base.x key 'omega' does not apply to motion \"record\""),
        "{e}"
    );
    let e = error_of(
        "excite-e3",
        &scene("", "").replace("quake.AT2", "missing.AT2"),
    );
    assert!(
        e.contains("cannot read record") && e.contains("missing.AT2"),
        "{e}"
    );
    let e = error_of(
        "excite-e4",
        &scene("", "").replace(
            "[base.x]",
            "motion = \"harmonic\"\namplitude = 0.1\nomega = 1\n[base.x]",
        ),
    );
    assert!(
        e.contains("given both by the keys of [base] and by [base.x]"),
        "{e}"
    );
    let e = error_of(
        "excite-e5",
        "[base]\nwidth = 1.0\nheight = 0.1\nmotion = \"pulse\"\n[[blocks]]\nwidth = 0.2\nheight = 0.4\n[contact]\nmu = 0.5\n",
    );
    assert!(e.contains("goes in a table of its own"), "{e}");
}

#[test]
fn a_malformed_record_names_its_file_and_line() {
    let dir = temp_dir("excite-malformed");
    let file = with_record(&dir, "scene.toml", &scene("", ""));
    let text = std::fs::read_to_string(RECORD).unwrap();
    let broken = text.replacen("E-03", "E-0x", 1);
    let line = broken.lines().position(|l| l.contains("E-0x")).unwrap() + 1;
    std::fs::write(dir.join("quake.AT2"), broken).unwrap();
    let (ok, _, stderr) = run(&["blocks", "run", &file]);
    assert!(!ok);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!("quake.AT2 line {line}: '")) && stderr.contains("is not a number"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sweep_scales_the_record() {
    let dir = temp_dir("excite-sweep");
    let file = with_record(&dir, "scene.toml", &scene("scale_to_pga = 0.2", ""));
    let out = dir.join("out");
    let v = json(&[
        "blocks",
        "sweep",
        "scene",
        &file,
        "--set",
        "base.scale=0.5,2",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    let rows = v["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 2, "{v}");
    let x: Vec<f64> = rows
        .iter()
        .map(|r| {
            assert_eq!(r["error"], serde_json::Value::Null, "{r}");
            r["top_x"].as_f64().unwrap()
        })
        .collect();
    // Stuck to the base (μ = 0.5 > 0.4 g), the block moves as the record: 4 times as far.
    assert!(x[0].abs() > 1e-6);
    assert!((x[1] / x[0] - 4.0).abs() < 1e-6, "{x:?}");
    let (ok, _, stderr) = run(&["blocks", "sweep", "scene", &file, "--set", "base.y.shape=1"]);
    assert!(!ok && stderr.contains("not a number"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
