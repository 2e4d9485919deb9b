//! Physical units of `blocks shake`: `--width`, `--height` and `--gravity` reach the
//! scene exactly as the keys `blocks.width`, `blocks.height` and `solver.gravity` of a
//! scene file do, and `--hz f` is `--omega 2πf`.

mod common;

use common::{json, run, run_in, temp_dir};
use serde_json::Value;

/// The physics of a run's JSON: everything but timings and the scene's defaults list.
fn physics(v: &Value) -> Vec<(&'static str, Value)> {
    [
        "steps",
        "failure_time",
        "failure",
        "final",
        "min_gap",
        "events",
        "t_final",
        "max_penetration",
    ]
    .into_iter()
    .map(|k| (k, v[k].clone()))
    .chain(["gravity", "dt", "t_end"].map(|k| (k, v["scene"][k].clone())))
    .collect()
}

#[test]
fn shake_units_reach_the_scene_as_its_keys_do() {
    let flags = [
        "blocks",
        "shake",
        "--periods",
        "2",
        "--width",
        "0.3",
        "--height",
        "0.5",
        "--gravity",
        "9.81",
        "--json",
    ];
    let shaken = json(&flags);
    let dir = temp_dir("units-scene");
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, scene, err) = run(&["blocks", "scenes", "shaking"]);
    assert!(ok, "{err}");
    let edits = [
        ("width = 0.2\nheight = 0.4", "width = 0.3\nheight = 0.5"),
        ("gravity = 1.0", "gravity = 9.81"),
        ("periods = 10", "periods = 2"),
    ];
    let mut scene = scene;
    for (from, to) in edits {
        assert_eq!(scene.matches(from).count(), 1, "{from:?} in {scene}");
        scene = scene.replace(from, to);
    }
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let (ok, out, err) = run_in(&dir, &["blocks", "run", "scene.toml", "--json"]);
    assert!(ok, "{err}");
    let from_file: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(physics(&shaken), physics(&from_file));
    assert_eq!(shaken["scene"]["gravity"], 9.81);
    // The defaults are the thesis's, unchanged.
    let thesis = json(&["blocks", "shake", "--periods", "2", "--json"]);
    assert_ne!(physics(&thesis), physics(&shaken));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn hz_is_omega_over_two_pi() {
    let by_omega = json(&[
        "blocks",
        "shake",
        "--omega",
        "pi",
        "--periods",
        "2",
        "--json",
    ]);
    let by_hz = json(&["blocks", "shake", "--hz", "0.5", "--periods", "2", "--json"]);
    assert_eq!(physics(&by_omega), physics(&by_hz));
}

#[test]
fn bad_unit_flags_are_refused_by_name() {
    for (args, names) in [
        (&["--hz", "1", "--omega", "2"][..], &["--hz", "--omega"][..]),
        (&["--hz", "0"], &["--hz"]),
        (&["--hz", "-1"], &["--hz"]),
        (&["--width", "0"], &["--width"]),
        (&["--height", "-0.4"], &["--height"]),
        (&["--gravity", "-9.81"], &["--gravity"]),
    ] {
        let mut all = vec!["blocks", "shake", "--periods", "1"];
        all.extend(args);
        let (ok, stdout, stderr) = run(&all);
        assert!(!ok, "{all:?} succeeded: {stdout}");
        for name in names {
            assert!(stderr.contains(name), "{all:?}: {stderr}");
        }
        assert!(!stderr.contains("panicked"), "{all:?}: {stderr}");
    }
}

/// The first row of a `blocks sweep frequency` JSON, without its solver time.
fn first_row(args: &[&str]) -> Value {
    let mut all = vec!["blocks", "sweep", "frequency", "--json"];
    all.extend(args);
    let mut row = json(&all)["rows"][0].clone();
    row["wall_time_s"] = Value::Null;
    row
}

#[test]
fn the_frequency_sweep_takes_the_units_of_shake() {
    let column = ["--omega", "4", "--blocks", "3", "--periods", "6"];
    let units = ["--width", "0.3", "--height", "0.5", "--gravity", "9.81"];
    let row = first_row(&[&column[..], &units[..]].concat());
    let shaken = json(&[&["blocks", "shake", "--json"][..], &column, &units].concat());
    assert!(row["failure_time"].is_f64(), "{row}");
    assert_eq!(row["failure_time"], shaken["failure_time"]);
    assert_eq!(row["opening_time"], shaken["opening_time"]);
    // The thesis's column survives these six periods: the units made the difference.
    assert!(first_row(&column)["failure_time"].is_null());
}

#[test]
fn the_frequency_sweep_takes_hz() {
    let rest = ["--blocks", "2", "--periods", "2"];
    let by_hz = first_row(&[&["--hz", "0.5"][..], &rest].concat());
    let by_omega = first_row(&[&["--omega", "pi"][..], &rest].concat());
    assert_eq!(by_hz, by_omega);
    for (args, names) in [
        (&["--hz", "1", "--omega", "2"][..], &["--hz", "--omega"][..]),
        (&[][..], &["--hz", "--omega"][..]),
        (
            &["--hz", "1,-1"][..],
            &["--hz must be positive, got -1"][..],
        ),
        (&["--omega", "4", "--width", "0"][..], &["--width"][..]),
    ] {
        let all = [&["blocks", "sweep", "frequency"][..], &rest, args].concat();
        let (ok, _, stderr) = run(&all);
        assert!(!ok, "{all:?} succeeded");
        for name in names {
            assert!(stderr.contains(name), "{all:?}: {stderr}");
        }
    }
}

#[test]
fn the_slide_sweep_takes_block_size_and_gravity() {
    let sweep = [
        "blocks", "sweep", "slide", "--v0", "1", "--t-end", "1", "--blocks", "2",
    ];
    let units = ["--width", "0.3", "--height", "0.5", "--gravity", "9.81"];
    let dir = temp_dir("units-slide");
    std::fs::create_dir_all(&dir).unwrap();
    let d = dir.to_str().unwrap();
    let (ok, _, err) = run(&[&sweep[..], &units, &["--out", d]].concat());
    assert!(ok, "{err}");
    let run_json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    for (key, value) in [("width", 0.3), ("height", 0.5), ("gravity", 9.81)] {
        assert_eq!(run_json["inputs"][key], value, "{key}");
    }
    // The units reach the run: at v0 = 1 the thesis's column has tilted by 0.26 rad at
    // t = 1, the one in these units has toppled.
    let thesis = json(&[&sweep[..], &["--json"]].concat())["rows"][0]["top_angle"].clone();
    let sized = json(&[&sweep[..], &units, &["--json"]].concat())["rows"][0]["top_angle"].clone();
    assert_ne!(thesis, sized);
    let (ok, _, stderr) = run(&[&sweep[..], &["--gravity", "-1"]].concat());
    assert!(
        !ok && stderr.contains("--gravity must not be negative"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(dir);
}
