//! `rollstack sphere ...` end to end: the JSON keys of docs/cli.md and the thesis's numbers.

mod common;

use common::{json, run};

fn temp_dir(name: &str) -> std::path::PathBuf {
    common::temp_dir(&format!("sphere-{name}"))
}

#[test]
fn holonomy_json_keys_and_values() {
    let theta = format!("{}", 4.0 * std::f64::consts::PI / 3.0 - 0.5);
    let phi1 = format!("{}", std::f64::consts::FRAC_PI_2 - 0.4);
    let v = json(&[
        "sphere", "holonomy", "--theta", &theta, "--phi1", &phi1, "--phi2", "3pi", "--json",
    ]);
    for key in ["angle", "axis", "quaternion", "matrix", "e3_final"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert!((v["angle"].as_f64().unwrap().to_degrees() - 62.7042).abs() < 5e-5);
    assert!((v["axis"][0].as_f64().unwrap() + 0.389_418).abs() < 1e-6);
    assert!((v["axis"][2].as_f64().unwrap() + 0.921_061).abs() < 1e-6);
    let e3: Vec<f64> = v["e3_final"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        (e3[0] - 0.194_194).abs() < 1e-6
            && (e3[1] - 0.346_057).abs() < 1e-6
            && (e3[2] - 0.917_896).abs() < 1e-6
    );
    assert_eq!(v["matrix"].as_array().unwrap().len(), 3);
    assert_eq!(v["quaternion"].as_array().unwrap().len(), 4);
    // Clockwise: the same angle, the opposite axis (2.4.5).
    let w = json(&[
        "sphere", "holonomy", "--theta", &theta, "--phi1", &phi1, "--phi2", "3pi", "--cw", "--json",
    ]);
    assert!((w["axis"][0].as_f64().unwrap() - 0.389_418).abs() < 1e-6);
}

#[test]
fn plan_finds_the_rectangles_of_2_4_12() {
    let axis = format!("0.1,{},0.1", 0.98_f64.sqrt());
    let v = json(&[
        "sphere", "plan", "--angle", "3pi/2", "--axis", &axis, "--json",
    ]);
    let rects = v["rectangles"].as_array().unwrap();
    for r in rects {
        for key in ["theta", "phi1", "phi2", "direction", "error", "waypoints"] {
            assert!(r.get(key).is_some(), "missing {key}");
        }
        assert!(r["error"].as_f64().unwrap() < 1e-12);
    }
    for (t, p1, p2) in [
        (3.0333, 3.5379, 8.6465),
        (3.2499, 0.39626, 2.3633),
        (3.2499, 6.6794, 8.6465),
    ] {
        assert!(
            rects.iter().any(|r| r["direction"] == "ccw"
                && (r["theta"].as_f64().unwrap() - t).abs() < 6e-5
                && (r["phi1"].as_f64().unwrap() - p1).abs() < 6e-5
                && (r["phi2"].as_f64().unwrap() - p2).abs() < 6e-5),
            "({t}, {p1}, {p2}) missing"
        );
    }
}

#[test]
fn euler_plan_json() {
    let v = json(&[
        "sphere",
        "euler-plan",
        "--set",
        "3-2-1",
        "--angles",
        "0.3,-90deg,2",
        "--json",
    ]);
    assert_eq!(v["rectangles"].as_array().unwrap().len(), 3);
    assert!(v["error"].as_f64().unwrap() < 1e-12);
    for r in v["rectangles"].as_array().unwrap() {
        assert!(r["error"].as_f64().unwrap() < 1e-12);
        assert_eq!(r["waypoints"].as_array().unwrap().len(), 6);
    }
    let (ok, _, stderr) = run(&[
        "sphere",
        "euler-plan",
        "--set",
        "1-2-3",
        "--angles",
        "0.3,0.2,2",
        "--json",
    ]);
    assert!(!ok && stderr.contains("1-2-3"), "{stderr}");
}

#[test]
fn roll_writes_files_and_matches_closed_form() {
    let dir = temp_dir("roll");
    let d = dir.to_str().unwrap();
    let v = json(&[
        "sphere", "roll", "--theta", "1.2", "--phi1", "0.3", "--phi2", "2", "--steps", "200",
        "--out", d, "--json",
    ]);
    for key in ["angle", "axis", "error_vs_closed_form"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert!(v["error_vs_closed_form"].as_f64().unwrap() < 1e-12);
    for f in ["roll.csv", "roll_traces.png", "run.json"] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let rk = json(&[
        "sphere",
        "roll",
        "--circle",
        "2",
        "--integrator",
        "rk4",
        "--steps",
        "400",
        "--json",
    ]);
    assert!(rk["error_vs_closed_form"].as_f64().unwrap() < 1e-8);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn figures_are_written() {
    let dir = temp_dir("figs");
    let d = dir.to_str().unwrap();
    let (ok, _, e) = run(&[
        "sphere", "holonomy", "--theta", "1", "--phi1", "0.2", "--phi2", "2", "--out", d,
    ]);
    assert!(ok, "{e}");
    let (ok, _, e) = run(&[
        "sphere", "plan", "--angle", "2", "--axis", "1,1,0", "--out", d,
    ]);
    assert!(ok, "{e}");
    let (ok, _, e) = run(&[
        "sphere",
        "euler-plan",
        "--set",
        "3-1-3",
        "--angles",
        "1,2,3",
        "--out",
        d,
    ]);
    assert!(ok, "{e}");
    for f in [
        "psi_level_sets.png",
        "rectangle.png",
        "holonomy.csv",
        "plan.png",
        "plan.csv",
        "euler_plan.png",
        "euler_plan.csv",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_input_is_a_clear_error() {
    for args in [
        vec![
            "sphere", "plan", "--angle", "1", "--axis", "0,0,0", "--json",
        ],
        vec![
            "sphere", "plan", "--angle", "1", "--axis", "nan,0,1", "--json",
        ],
        vec![
            "sphere", "plan", "--angle", "0", "--axis", "1,0,0", "--json",
        ],
        vec![
            "sphere", "holonomy", "--theta", "-1", "--phi1", "0", "--phi2", "1", "--json",
        ],
        vec![
            "sphere", "holonomy", "--theta", "1", "--phi1", "2", "--phi2", "1", "--json",
        ],
        vec!["sphere", "roll", "--circle", "-1", "--json"],
        vec!["sphere", "roll", "--steps", "2", "--json"],
    ] {
        let (ok, stdout, stderr) = run(&args);
        assert!(!ok, "{args:?} should fail");
        assert!(stdout.is_empty(), "{args:?} printed {stdout}");
        assert!(
            stderr.starts_with("error:") && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
    }
}
