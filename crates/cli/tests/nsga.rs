//! `rollstack nsga`: JSON keys of docs/cli.md and the analytic ball answers.

mod common;

use common::{json as ball_json, rollstack};

#[test]
fn ball_json_has_design_keys_and_exact_answers() {
    let v = ball_json(&["nsga", "ball", "--case", "2", "--json"]);
    for key in [
        "first_impact_time",
        "rolling_onset_time",
        "final_velocity",
        "min_gap",
        "steps",
        "newton_iterations_mean",
        "wall_time_s",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    let fv = v["final_velocity"].as_array().unwrap();
    assert!((fv[0].as_f64().unwrap() + 1.428_571_428_571_4).abs() < 1e-9);
    assert!((fv[1].as_f64().unwrap() - 14.285_714_285_714).abs() < 1e-8);
    assert!((v["rolling_onset_time"].as_f64().unwrap() - 0.728).abs() < 4e-3);
    assert!(v["min_gap"].as_f64().unwrap() >= -1e-8);
    assert_eq!(v["steps"].as_u64(), Some(750));
}

#[test]
fn ball_case_1_never_slips_so_onset_is_at_rest_and_moreau_penetrates() {
    let v = ball_json(&["nsga", "ball", "--case", "1", "--json"]);
    assert!(v["rolling_onset_time"].is_null());
    assert!((v["first_impact_time"].as_f64().unwrap() - 0.4284).abs() < 2e-3);
    assert!(v["min_gap"].as_f64().unwrap() >= -1e-8);
    assert!(v["newton_iterations_mean"].as_f64().unwrap() <= 3.0);
    let m = ball_json(&[
        "nsga", "ball", "--case", "1", "--scheme", "moreau", "--json",
    ]);
    assert!(m["min_gap"].as_f64().unwrap() < -1e-4);
}

#[test]
fn ball_rejects_bad_input() {
    for args in [
        &["nsga", "ball", "--case", "7", "--json"][..],
        &["nsga", "ball", "--case", "1", "--dt", "-1", "--json"][..],
        &["nsga", "ball", "--case", "1", "--rho-inf", "2", "--json"][..],
        &["nsga", "ball", "--case", "1", "--dt", "NaN", "--json"][..],
    ] {
        let out = rollstack(args);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn work_precision_writes_csv_png_and_run_json() {
    let dir = common::temp_dir("nsga-wp");
    let out = rollstack(&[
        "nsga",
        "work-precision",
        "--system",
        "oscillator",
        "--dts",
        "0.01,0.005",
        "--rho-inf",
        "0.5",
        "--repeat",
        "1",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    // Second order: halving Δt divides the NSGA error by about 4.
    let e0 = rows[0]["error"].as_f64().unwrap();
    let e1 = rows[1]["error"].as_f64().unwrap();
    assert!((e0 / e1 - 4.0).abs() < 0.5, "{e0} / {e1}");
    // No contacts: both runs follow the reference, and the order is their slope.
    let order = &v["orders"][0]["order"];
    assert_eq!(order["status"], "fitted", "{order}");
    let slope = (e0 / e1).ln() / 2f64.ln();
    assert!(
        (order["order"].as_f64().unwrap() - slope).abs() < 1e-9,
        "{order}"
    );
    let csv = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    assert!(csv.starts_with("scheme,rho_inf,dt,error,wall_time_s"));
    assert!(dir.join("work_precision.png").exists() && dir.join("run.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn zero_repetitions_are_refused_not_silently_raised() {
    let (ok, _, stderr) = common::run(&["nsga", "work-precision", "--repeat", "0"]);
    assert!(!ok && stderr.contains("--repeat"), "{stderr}");
}
