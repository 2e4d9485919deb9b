//! Materials per interface on the command line: a scene's `[contact.base]`, `[contact.blocks]`,
//! `[contact.floor]` and `[[contact.pair]]` reach `blocks run` (its scene report) and
//! `blocks sweep scene --set contact.base.mu=…`; a bad name is one line naming the key. And
//! the built-in `rocking-block` runs.

mod common;

use common::{json, run, temp_dir};

/// A block named "plinth" on a base, a block named "statue" on it, with a slippery base.
const PLINTH: &str =
    "[base]\nwidth = 1.0\nheight = 0.1\nmotion = \"harmonic\"\namplitude = 0.05\nomega = 3.0\n\
    [[blocks]]\nwidth = 0.4\nheight = 0.2\nname = \"plinth\"\n\
    [[blocks]]\nwidth = 0.2\nheight = 0.6\nname = \"statue\"\n\
    [contact]\nmu = 0.5\n[contact.base]\nmu = 0.1\n\
    [[contact.pair]]\nbodies = [\"plinth\", \"statue\"]\nmu = 5.0\n";

fn write(tag: &str, text: &str) -> (std::path::PathBuf, String) {
    let dir = temp_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let name = path.to_string_lossy().into_owned();
    (dir, name)
}

#[test]
fn a_run_reports_the_materials_it_was_given() {
    let (dir, file) = write("materials-run", PLINTH);
    let v = json(&["blocks", "run", &file, "--t-end", "0.05", "--json"]);
    assert_eq!(
        v["scene"]["materials"],
        serde_json::json!(["base: mu = 0.1", "plinth/statue: mu = 5"])
    );
    let (ok, stdout, stderr) = run(&["blocks", "run", &file, "--t-end", "0.05"]);
    assert!(ok, "{stderr}");
    let all = stdout + &stderr;
    assert!(
        all.contains("materials: base: mu = 0.1; plinth/statue: mu = 5"),
        "{all}"
    );
    // Without overrides the report has no materials.
    let plain = json(&["blocks", "run", "shaking", "--t-end", "0.02", "--json"]);
    assert!(plain["scene"].get("materials").is_none(), "{plain}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_sweep_sets_the_materials_of_a_kind_and_of_a_pair() {
    let (dir, file) = write("materials-sweep", PLINTH);
    let out = dir.join("out");
    let v = json(&[
        "blocks",
        "sweep",
        "scene",
        &file,
        "--set",
        "contact.base.mu=0.05,0.8",
        "--set",
        "contact.pair.0.e_n=0.2",
        "--t-end",
        "0.05",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[1]["set"][0]["key"], "contact.base.mu");
    assert_eq!(rows[1]["set"][1]["key"], "contact.pair.0.e_n");
    assert!(rows.iter().all(|r| r["error"].is_null()), "{v}");
    let (ok, _, stderr) = run(&[
        "blocks",
        "sweep",
        "scene",
        &file,
        "--set",
        "contact.pair.1.mu=0.1",
        "--t-end",
        "0.05",
    ]);
    assert!(!ok && stderr.trim().lines().count() == 1, "{stderr}");
    assert!(
        stderr.contains("contact.pair.1.mu") && stderr.contains("the scene has 1"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn an_unknown_body_is_one_line_naming_the_key() {
    let (dir, file) = write(
        "materials-name",
        &PLINTH.replace("\"statue\"]", "\"capital\"]"),
    );
    let (ok, _, stderr) = run(&["blocks", "run", &file, "--t-end", "0.05"]);
    assert!(!ok && stderr.trim().lines().count() == 1, "{stderr}");
    assert!(
        stderr.contains("contact.pair.0 bodies: no body named \"capital\"")
            && stderr.contains("base, floor, plinth, statue"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_rocking_block_runs() {
    let v = json(&[
        "blocks",
        "run",
        "rocking-block",
        "--t-end",
        "0.05",
        "--json",
    ]);
    assert_eq!(v["steps"].as_u64(), Some(50));
    assert_eq!(v["scene"]["materials"], serde_json::json!(["base: mu = 1"]));
    assert!(v["error"].is_null(), "{v}");
    // Released tilted on its right corner, it starts to fall back.
    let theta = v["final"][0]["theta"].as_f64().unwrap();
    assert!(theta > -0.1 && theta < 0.0, "{theta}");
}
