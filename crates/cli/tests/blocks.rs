//! `rollstack blocks …` end to end: JSON keys of DESIGN.md, the thesis's numbers
//! (corrected by ERRATA 18), output files, and clean errors on bad input.

mod common;

use common::{json, rollstack};

#[test]
fn painleve_json_has_the_design_keys_and_the_thesis_numbers() {
    let v = json(&["blocks", "painleve", "--aspect", "0.5", "--json"]);
    for key in ["mu_min", "theta_min", "theta_max"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    // ERRATA 18: μ_d = 4/3, ϑ_min = −63.435°, ϑ_max = 26.565° for w/h = 0.5.
    assert!((v["mu_min"].as_f64().unwrap() - 4.0 / 3.0).abs() < 1e-12);
    assert!((v["theta_min"].as_f64().unwrap().to_degrees() + 63.435).abs() < 1e-3);
    assert!((v["theta_max"].as_f64().unwrap().to_degrees() - 26.565).abs() < 1e-3);
    assert!((v["theta_at_mu_min"].as_f64().unwrap().tan().abs() - 0.5).abs() < 1e-12);
    // (I.2.10) with μ_d = 0.2 and h/w = 2: n_R = (1 + 0.4)/2 when sliding right.
    let right = &v["line_contact"]["sliding_right"][0];
    assert!((right["n_right"].as_f64().unwrap() - 0.7).abs() < 1e-12);
    assert!((right["n_left"].as_f64().unwrap() - 0.3).abs() < 1e-12);
}

#[test]
fn painleve_least_friction_is_four_thirds_for_any_aspect() {
    for aspect in ["0.1", "1", "7"] {
        let v = json(&["blocks", "painleve", "--aspect", aspect, "--json"]);
        assert!(
            (v["mu_min"].as_f64().unwrap() - 4.0 / 3.0).abs() < 1e-12,
            "aspect {aspect}"
        );
    }
}

#[test]
fn painleve_out_writes_csv_png_and_run_json() {
    let dir = common::temp_dir("blocks-painleve");
    let d = dir.to_str().unwrap();
    let out = rollstack(&[
        "blocks", "painleve", "--aspect", "0.5", "--grid", "31", "--out", d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("painleve_b_grid.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "theta_rad,theta_deg,mu_d,b_slip_positive,b_slip_negative,admissible"
    );
    assert_eq!(lines.count(), 31 * 31);
    assert!(std::fs::metadata(dir.join("painleve.png")).unwrap().len() > 1000);
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["command"], "blocks painleve");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn painleve_rejects_bad_input_with_one_line() {
    for bad in [
        ["--aspect", "-1"],
        ["--aspect", "0"],
        ["--mu", "-0.5"],
        ["--grid", "1"],
    ] {
        let mut args = vec!["blocks", "painleve", "--json", "--out"];
        let dir = common::temp_dir("blocks-bad");
        args.push(dir.to_str().unwrap());
        if bad[0] != "--aspect" {
            args.extend(["--aspect", "1"]);
        }
        args.extend(bad);
        let out = rollstack(&args);
        assert!(!out.status.success(), "{bad:?}");
        assert!(out.stdout.is_empty());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.starts_with("error: "), "{err}");
        let _ = std::fs::remove_dir_all(dir);
    }
    // NaN is refused by the argument parser.
    let out = rollstack(&["blocks", "painleve", "--aspect", "nan", "--json"]);
    assert!(!out.status.success());
    assert!(out.stdout.is_empty());
}
