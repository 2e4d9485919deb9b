//! `rollstack cylinder ...` end to end: JSON keys of docs/cli.md and the thesis's numbers
//! (corrected per ERRATA 8–15).

mod common;

use common::{json, run};
use serde_json::Value;

fn f(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

#[test]
fn support_json() {
    let v = json(&[
        "cylinder",
        "support",
        "--theta",
        "30deg",
        "--r-over-h",
        "0.1",
        "--mu",
        "0.2",
        "--json",
    ]);
    for key in [
        "n_over_mg_plus",
        "n_over_mg_minus",
        "n_over_mg_smooth",
        "theta_range",
        "min_force",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    for key in ["f3_over_mg", "f_over_mg", "norm_over_mg", "case"] {
        assert!(v["min_force"].get(key).is_some(), "missing min_force.{key}");
    }
    // (3.3.8) corrected (ERRATA 9) at ϑ = 30°: ½ sin ϑ / (sin ϑ − ρ cos ϑ ± μ(ρ sin ϑ + cos ϑ)).
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let expect = |sign: f64| 0.5 * s / (s - 0.1 * c + sign * 0.2 * (0.1 * s + c));
    assert!((f(&v["n_over_mg_plus"]) - expect(1.0)).abs() < 1e-14);
    assert!((f(&v["n_over_mg_minus"]) - expect(-1.0)).abs() < 1e-14);
    assert!((f(&v["n_over_mg_smooth"]) - expect(0.0)).abs() < 1e-14);
    assert!(f(&v["balance_law_error"]) < 1e-12);
    // (3.3.11) for μ = 0.2: (arctan 5, 1/2.08).
    assert!((f(&v["common_point"][1]) - 1.0 / 2.08).abs() < 1e-15);
    // Point D: arctan(2r/h).
    assert!((f(&v["self_balancing_theta"]) - 0.2f64.atan()).abs() < 1e-15);
    // (3.3.16) at the unconstrained minimum.
    assert_eq!(v["min_force"]["case"], "unconstrained");
    let norm = (0.1 * c - 0.5 * s).abs() / (1.01f64).sqrt();
    assert!((f(&v["min_force"]["norm_over_mg"]) - norm).abs() < 1e-14);
    // ERRATA 10: the (+) range starts at max(0, …) = 0 here.
    assert_eq!(f(&v["theta_range"][0]), 0.0);
}

#[test]
fn support_rejects_bad_input() {
    for args in [
        ["cylinder", "support", "--theta", "0", "--json"].as_slice(),
        &["cylinder", "support", "--theta", "90deg", "--json"],
        &[
            "cylinder", "support", "--theta", "30deg", "--mu", "-0.1", "--json",
        ],
        &[
            "cylinder",
            "support",
            "--theta",
            "30deg",
            "--r-over-h",
            "nan",
            "--json",
        ],
        &[
            "cylinder", "holonomy", "circle", "--ell", "0.5", "--theta", "pi/10", "--h", "13.3333",
            "--r", "1", "--json",
        ],
        &[
            "cylinder",
            "holonomy",
            "rectangle",
            "--theta",
            "pi/10",
            "--phi1",
            "1",
            "--phi2",
            "1",
            "--s",
            "2",
            "--json",
        ],
    ] {
        let (ok, stdout, stderr) = run(args);
        assert!(!ok, "{args:?} should fail");
        assert!(
            stdout.is_empty() && !stderr.is_empty() && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
    }
}

#[test]
fn rectangle_figure_3_10() {
    let base = [
        "cylinder",
        "holonomy",
        "rectangle",
        "--theta",
        "pi/10",
        "--phi1",
        "13pi/3",
        "--phi2",
        "29pi/4",
        "--s",
        "0",
    ];
    let one = json(&[&base[..], &["--json"]].concat());
    for key in ["delta_phi", "product_error"] {
        assert!(one.get(key).is_some(), "missing {key}");
    }
    // ERRATA 8: 139π/12 = 36.3901 rad (printed as degrees).
    assert!((f(&one["delta_phi"]) - 139.0 * std::f64::consts::PI / 12.0).abs() < 1e-13);
    assert!(f(&one["product_error"]) < 1e-12);
    assert!((f(&one["rolling_delta_phi"]) - f(&one["delta_phi"])).abs() < 1e-9);
    let two = json(&[&base[..], &["--case", "II", "--json"]].concat());
    assert!((f(&two["delta_phi"]) + 36.3901).abs() < 5e-5);
    let cw = json(&[&base[..], &["--cw", "--json"]].concat());
    assert!((f(&cw["delta_phi"]) + 36.3901).abs() < 5e-5);
    assert!(f(&cw["product_error"]) < 1e-12);
}

#[test]
fn circle_figure_3_12() {
    // ℓ = 9.44239 r (ERRATA 8), h = 13.3333 r, ϑ = π/10: Δφ = ±59.3283 rad, k = 8.33 r
    // (Case I) and 10.5515 r (Case II, ERRATA 15).
    let base = [
        "cylinder", "holonomy", "circle", "--ell", "9.44239", "--theta", "pi/10", "--h", "13.3333",
        "--r", "1",
    ];
    let one = json(&[&base[..], &["--json"]].concat());
    assert!((f(&one["delta_phi"]) - 59.3283).abs() < 5e-5);
    assert!((f(&one["k"]) - 8.3333).abs() < 5e-4);
    assert!((f(&one["rolling_delta_phi"]) - f(&one["delta_phi"])).abs() < 1e-8);
    let two = json(&[&base[..], &["--case", "II", "--json"]].concat());
    assert!((f(&two["delta_phi"]) + 59.3283).abs() < 5e-5);
    assert!((f(&two["k"]) - 10.5515).abs() < 1e-4);
}

#[test]
fn frobenius_ranks() {
    let single = json(&["cylinder", "frobenius", "--system", "single", "--json"]);
    for key in ["rank", "nullity", "max_abs_asb", "integrable"] {
        assert!(single.get(key).is_some(), "missing {key}");
    }
    assert_eq!(
        (single["rank"].as_u64(), single["nullity"].as_u64()),
        (Some(3), Some(3))
    );
    assert_eq!(
        single["integrable"],
        serde_json::json!([false, false, true])
    );
    // (D.2.4): y1ᵀS¹y3 = r sin ψ, y1ᵀS²y3 = −r cos ψ.
    for k in 0..2 {
        assert!((f(&single["d24"][0][k]) - f(&single["d24"][1][k])).abs() < 1e-15);
    }
    // ERRATA 13: rank 9, not 8.
    for config in ["generic", "touching"] {
        let nine = json(&[
            "cylinder",
            "frobenius",
            "--system",
            "pair9",
            "--config",
            config,
            "--json",
        ]);
        assert_eq!(
            (nine["rank"].as_u64(), nine["nullity"].as_u64()),
            (Some(9), Some(3)),
            "{config}"
        );
        assert_eq!(nine["max_abs_asb"].as_array().map(Vec::len), Some(9));
        let seven = json(&[
            "cylinder",
            "frobenius",
            "--system",
            "pair7",
            "--config",
            config,
            "--json",
        ]);
        assert_eq!(seven["rank"].as_u64(), Some(7));
        assert_eq!(
            seven["integrable"],
            serde_json::json!([false, false, true, false, false, true, true])
        );
    }
}

#[test]
fn statics_writes_figures() {
    let dir = common::temp_dir("cylinder-statics");
    let _ = std::fs::remove_dir_all(&dir);
    let (ok, _, stderr) = run(&[
        "cylinder",
        "statics",
        "--r-over-h",
        "0.1",
        "--mu",
        "0.2",
        "--points",
        "91",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    for file in [
        "fig3_3.csv",
        "fig3_3.png",
        "fig3_4.png",
        "fig3_5.png",
        "fig3_7.png",
        "fig3_8.png",
        "fig3_7_fig3_8.csv",
        "run.json",
    ] {
        assert!(dir.join(file).exists(), "missing {file}");
    }
    let csv = std::fs::read_to_string(dir.join("fig3_3.csv")).unwrap();
    assert!(csv.starts_with("theta,theta_deg,n_over_mg_plus,n_over_mg_smooth,n_over_mg_minus\n"));
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn frobenius_refuses_a_non_finite_contact_and_one_for_the_single_cylinder() {
    for (args, says) in [
        (
            &["--system", "pair9", "--contact-at", "nan"][..],
            "--contact-at",
        ),
        (
            &["--system", "pair7", "--contact-at", "inf"],
            "--contact-at",
        ),
        (&["--contact-at", "nan"], "--contact-at"),
        (&["--contact-at", "0.3"], "--system single"),
        (
            &["--system", "single", "--contact-at", "-0.1"],
            "--system single",
        ),
    ] {
        let mut all = vec!["cylinder", "frobenius"];
        all.extend(args);
        let (ok, stdout, stderr) = run(&all);
        assert!(!ok && stdout.is_empty(), "{args:?}: {stdout}");
        assert!(
            stderr.contains(says) && stderr.contains("--contact-at"),
            "{args:?}: {stderr}"
        );
        let first = stderr.lines().next().unwrap_or("");
        assert!(first.contains(says) && !first.contains("  "), "{stderr}");
    }
    // Given for a pair, it is used: another contact, another configuration.
    let at = |x: &str| {
        json(&[
            "cylinder",
            "frobenius",
            "--system",
            "pair9",
            "--contact-at",
            x,
            "--json",
        ])["q"]
            .clone()
    };
    assert_ne!(at("0.1"), at("0.2"));
}

#[test]
fn library_checks_reach_the_user_as_the_flag_they_typed() {
    // Each was refused with the library's symbol (ℓ, φ1, φ2, r/h, μ, μ_s, μ_k, mass).
    let cases: [(&[&str], &str); 11] = [
        (
            &[
                "holonomy", "circle", "--ell", "0", "--theta", "0.4", "--h", "1",
            ],
            "--ell must be positive, got 0",
        ),
        (
            &[
                "holonomy",
                "rectangle",
                "--theta",
                "0.4",
                "--phi1",
                "-1",
                "--phi2",
                "1",
            ],
            "--phi1 must be positive, got -1",
        ),
        (
            &[
                "holonomy",
                "rectangle",
                "--theta",
                "0.4",
                "--phi1",
                "1",
                "--phi2",
                "0",
            ],
            "--phi2 must be positive, got 0",
        ),
        (
            &["statics", "--r-over-h", "-1"],
            "--r-over-h must not be negative",
        ),
        (&["statics", "--mu", "-1"], "--mu must not be negative"),
        (
            &["support", "--theta", "0.5", "--r-over-h", "-1"],
            "--r-over-h must not be negative",
        ),
        (
            &["support", "--theta", "0.5", "--mu", "-1"],
            "--mu must not be negative",
        ),
        (
            &["support", "--theta", "0.5", "--mass", "-2"],
            "--mass must be positive, got -2",
        ),
        (
            &["pair", "--theta", "0.5", "--mu-floor", "-1"],
            "--mu-floor must not be negative",
        ),
        (
            &["pair", "--theta", "0.5", "--mu-k", "-1"],
            "--mu-k must not be negative",
        ),
        (
            &["sweep", "push", "--theta", "0.5", "--mu-floor", "-1"],
            "--mu-floor must not be negative",
        ),
    ];
    for (args, said) in cases {
        let (ok, _, stderr) = run(&[&["cylinder"], args].concat());
        assert!(!ok, "{args:?}");
        assert!(
            stderr.starts_with(&format!("error: {said}")),
            "{args:?}: {stderr}"
        );
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
    }
}

/// `cylinder work-precision`: its files, and JSON whose rows and orders are the
/// study's: each row's error falls with Δt, and an order fitted is the slope of the
/// errors of the rows marked fitted.
#[test]
fn cylinder_work_precision_writes_csv_png_and_json() {
    let dir = common::temp_dir("cylinder-wp");
    let out = common::rollstack(&[
        "cylinder",
        "work-precision",
        "--dts",
        "2e-2,1e-2,5e-3",
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
    assert_eq!(rows.len(), 6);
    for (scheme, rows) in ["nsga", "moreau"].iter().zip(rows.chunks(3)) {
        let errors: Vec<f64> = rows.iter().map(|r| r["error"].as_f64().unwrap()).collect();
        assert!(errors[2] < errors[0], "{scheme}: {errors:?}");
        let order = &v["orders"][scheme];
        let fitted: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r["fitted"] == true)
            .map(|r| {
                (
                    r["dt"].as_f64().unwrap().ln(),
                    r["error"].as_f64().unwrap().ln(),
                )
            })
            .collect();
        if order["status"] == "fitted" {
            let n = fitted.len() as f64;
            let mx = fitted.iter().map(|p| p.0).sum::<f64>() / n;
            let my = fitted.iter().map(|p| p.1).sum::<f64>() / n;
            let sxy: f64 = fitted.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
            let sxx: f64 = fitted.iter().map(|p| (p.0 - mx).powi(2)).sum();
            let slope = order["order"].as_f64().unwrap();
            assert!((slope - sxy / sxx).abs() < 1e-9, "{scheme}: {order}");
        } else {
            assert!(fitted.is_empty() && order["order"].is_null(), "{order}");
        }
    }
    let csv = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    assert!(csv.starts_with("scheme,dt,error,static_error,drift,final_floor_slip,wall_time_s"));
    assert_eq!(csv.lines().count(), 7);
    assert!(dir.join("work_precision.png").exists() && dir.join("run.json").exists());
    let (ok, _, stderr) = run(&["cylinder", "work-precision", "--dts", "0"]);
    assert!(!ok && stderr.contains("--dts"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
