//! The words the commands share (docs/cli.md, Conventions): one flag per quantity in every
//! command that takes it, the old names still accepted, and one explanation for the same
//! mistake wherever it is made.

mod common;

use common::run;

/// The explanation of a bare angle beyond 2π.
fn degrees_hint(value: &str) -> String {
    format!("{value} rad is more than 2π: write {value}deg for degrees, or give radians")
}

#[test]
fn nsga_ball_takes_prox_constant_and_its_old_name() {
    // run.json records the constant r under the one name, whichever name gave it.
    for (flag, tag) in [("--prox-constant", "new"), ("--prox-r", "old")] {
        let dir = common::temp_dir(&format!("vocabulary-prox-{tag}"));
        let d = dir.to_string_lossy().into_owned();
        let v = common::json(&[
            "nsga", "ball", "--case", "2", "--dt", "0.01", flag, "0.3", "--out", &d, "--json",
        ]);
        assert_eq!(v["case"], 2);
        let text = std::fs::read_to_string(dir.join("run.json")).unwrap();
        let run_json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(run_json["inputs"]["prox_constant"], 0.3, "{flag}");
        let _ = std::fs::remove_dir_all(dir);
    }
    let (ok, _, err) = run(&["nsga", "ball", "--case", "2", "--prox-constant", "-1"]);
    assert!(
        !ok && err.contains("--prox-constant must be positive"),
        "{err}"
    );
    // The old name stays out of the help.
    let (_, help, _) = run(&["nsga", "ball", "--help"]);
    assert!(help.contains("--prox-constant") && !help.contains("--prox-r"));
}

#[test]
fn cylinder_commands_take_r_over_h() {
    let rect = [
        "cylinder",
        "holonomy",
        "rectangle",
        "--theta",
        "pi/10",
        "--phi1",
        "1",
        "--phi2",
        "1",
        "--max-step",
        "0.05",
        "--json",
    ];
    let with = |extra: &[&str]| {
        let mut args = rect.to_vec();
        args.extend(extra);
        common::json(&args)
    };
    let default = with(&[]);
    // h/r = 25/3 is r/h = 0.12 (Figure 3.10), the default.
    assert_eq!(default, with(&["--h-over-r", "8.333333333333334"]));
    assert_eq!(default, with(&["--r-over-h", "0.12"]));
    let squat = with(&["--r-over-h", "0.5"]);
    assert_eq!(squat, with(&["--h-over-r", "2"]));
    assert_ne!(
        squat["rolling_closure_error"],
        default["rolling_closure_error"]
    );
    let mut both = rect.to_vec();
    both.extend(["--r-over-h", "0.5", "--h-over-r", "2"]);
    assert!(!run(&both).0, "the two forms of one value conflict");
    let (_, help, _) = run(&["cylinder", "holonomy", "rectangle", "--help"]);
    assert!(help.contains("--r-over-h") && !help.contains("--h-over-r"));

    // The circle and the Frobenius test: --r-over-h instead of --h.
    let circle = |size: &[&str]| {
        let mut args = vec![
            "cylinder",
            "holonomy",
            "circle",
            "--ell",
            "0.3",
            "--theta",
            "pi/10",
            "--max-step",
            "0.05",
            "--json",
        ];
        args.extend(size);
        common::json(&args)
    };
    assert_eq!(
        circle(&["--r", "0.1", "--h", "1"]),
        circle(&["--r", "0.1", "--r-over-h", "0.1"])
    );
    let (ok, _, err) = run(&[
        "cylinder", "holonomy", "circle", "--ell", "0.3", "--theta", "pi/10",
    ]);
    assert!(
        !ok && err.contains("--h"),
        "one of --h, --r-over-h is needed: {err}"
    );
    let frob = |size: &[&str]| {
        let mut args = vec!["cylinder", "frobenius", "--r", "0.1", "--json"];
        args.extend(size);
        let mut v = common::json(&args);
        v.as_object_mut().unwrap().remove("wall_time_s");
        v
    };
    assert_eq!(frob(&["--h", "0.5"]), frob(&["--r-over-h", "0.2"]));
}

#[test]
fn work_precision_runs_without_out() {
    let v = common::json(&[
        "nsga",
        "work-precision",
        "--system",
        "oscillator",
        "--dts",
        "0.01",
        "--rho-inf",
        "0.5",
        "--repeat",
        "1",
        "--json",
    ]);
    assert_eq!(v["rows"].as_array().unwrap().len(), 2);
    assert!(v["csv"].is_null());
    assert_eq!(v["rows"][1]["scheme"], "moreau");
    let (ok, text, _) = run(&[
        "nsga",
        "work-precision",
        "--system",
        "incline",
        "--dts",
        "0.01",
        "--rho-inf",
        "0.5",
        "--repeat",
        "1",
    ]);
    assert!(
        ok && text.lines().count() == 2 && !text.contains("wrote"),
        "{text}"
    );
}

#[test]
fn sweeps_and_statics_run_without_out() {
    let v = common::json(&[
        "blocks",
        "sweep",
        "frequency",
        "--omega",
        "10",
        "--periods",
        "0.2",
        "--blocks",
        "1",
        "--json",
    ]);
    assert_eq!(v["rows"].as_array().unwrap().len(), 1);
    let (ok, text, _) = run(&[
        "blocks", "sweep", "slide", "--v0", "0.1", "--t-end", "0.05", "--blocks", "1",
    ]);
    assert!(
        ok && text.starts_with("v0 = 0.1000: ") && !text.contains("wrote"),
        "{text}"
    );
    let (ok, text, _) = run(&["cylinder", "statics", "--points", "11"]);
    assert!(ok && text.starts_with("computed Figures 3.3"), "{text}");
}

#[test]
fn slide_sweep_takes_mu() {
    let slide = |mu: Option<&str>| {
        let mut args = vec![
            "blocks", "sweep", "slide", "--v0", "0.5", "--t-end", "0.3", "--blocks", "1", "--json",
        ];
        if let Some(mu) = mu {
            args.extend(["--mu", mu]);
        }
        common::json(&args)["rows"][0].clone()
    };
    let default = slide(None);
    assert_eq!(default, {
        let mut v = slide(Some("0.2"));
        v["wall_time_s"] = default["wall_time_s"].clone();
        v
    });
    let rough = slide(Some("0.5"));
    assert!(rough["error"].is_null() && default["error"].is_null());
    assert_ne!(
        rough["top_angle"], default["top_angle"],
        "{rough} vs {default}"
    );
    let (ok, _, err) = run(&["blocks", "sweep", "slide", "--v0", "0.5", "--mu", "-1"]);
    assert!(!ok && err.contains("--mu must not be negative"), "{err}");
    // run.json records it.
    let dir = common::temp_dir("vocabulary-slide-mu");
    let d = dir.to_string_lossy().into_owned();
    let (ok, _, _) = run(&[
        "blocks", "sweep", "slide", "--v0", "0.5", "--t-end", "0.05", "--blocks", "1", "--mu",
        "0.5", "--out", &d,
    ]);
    assert!(ok);
    let run_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(run_json["inputs"]["mu"], 0.5);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_rotation_angle_in_degrees_without_deg_is_explained() {
    let (ok, _, err) = run(&["sphere", "plan", "--angle", "90", "--axis", "0,0,1"]);
    assert!(!ok && err.contains(&degrees_hint("90")), "{err}");
    let (ok, _, err) = run(&["sphere", "plan", "--angle", "90deg", "--axis", "0,0,1"]);
    assert!(ok, "{err}");
    // The same words from every rotation angle, inclination and heading.
    for args in [
        vec!["cylinder", "support", "--theta", "45"],
        vec!["cylinder", "frobenius", "--theta", "45"],
        vec!["cylinder", "frobenius", "--heading", "45"],
        vec![
            "cylinder",
            "holonomy",
            "rectangle",
            "--theta",
            "45",
            "--phi1",
            "1",
            "--phi2",
            "1",
        ],
        vec![
            "cylinder",
            "holonomy",
            "rectangle",
            "--theta",
            "0.3",
            "--phi1",
            "1",
            "--phi2",
            "1",
            "--psi0",
            "45",
        ],
        vec![
            "cylinder", "holonomy", "circle", "--ell", "0.3", "--theta", "45", "--h", "1", "--r",
            "1",
        ],
        vec!["rotation", "--from", "axis-angle", "--values", "0,0,1,45"],
        vec![
            "sphere",
            "euler-plan",
            "--set",
            "3-1-3",
            "--angles",
            "30deg,45,60deg",
        ],
    ] {
        let (ok, _, err) = run(&args);
        assert!(!ok && err.contains(&degrees_hint("45")), "{args:?}: {err}");
    }
    let (ok, _, err) = run(&["cylinder", "support", "--theta", "45deg"]);
    assert!(ok, "{err}");
    // Path lengths given as angles may be long: φ2 = 9 rad, φ1 = 13π/3.
    assert!(run(&["sphere", "holonomy", "--theta", "1", "--phi1", "0", "--phi2", "9"]).0);
    let args = "cylinder holonomy rectangle --theta pi/10 --phi1 1 --phi2 1 --max-step -1";
    let (ok, _, err) = run(&args.split(' ').collect::<Vec<_>>());
    assert!(!ok && !err.contains("unexpected argument"), "{err}");
    assert!(
        err.contains("--max-step"),
        "the error names the flag: {err}"
    );
}

#[test]
fn ranges_take_what_single_values_take() {
    use std::f64::consts::PI;
    let thetas = |theta: &str| -> Vec<f64> {
        let v = common::json(&[
            "cylinder", "sweep", "pair", "--theta", theta, "--steps", "2", "--json",
        ]);
        v["rows"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["theta"].as_f64().unwrap())
            .collect()
    };
    assert_eq!(thetas("30deg"), [PI / 6.0]);
    assert_eq!(thetas("pi/6"), [PI / 6.0]);
    let degrees: Vec<f64> = [20.0f64, 30.0, 40.0]
        .iter()
        .map(|d| d.to_radians())
        .collect();
    assert_eq!(thetas("20deg:40deg:10deg"), degrees);
    // The single value of `cylinder pair` and the range's value are the same number.
    let single = common::json(&[
        "cylinder", "pair", "--theta", "30deg", "--steps", "2", "--json",
    ]);
    assert_eq!(single["theta"].as_f64(), Some(PI / 6.0));
    // A rate as its own help writes it: --spin −6π, the default.
    let spin = |extra: &[&str]| {
        let mut args = vec![
            "cylinder", "pair", "--theta", "30deg", "--steps", "2", "--json",
        ];
        args.extend(extra);
        common::json(&args)["n_over_mg"].clone()
    };
    assert_eq!(spin(&["--spin", "-6pi"]), spin(&[]));
    let (_, help, _) = run(&["cylinder", "pair", "--help"]);
    assert!(help.contains("-6pi"), "the help writes −6π as it is typed");
    // A scene key swept over multiples of π.
    let v = common::json(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "base.omega=2pi",
        "--t-end",
        "0.02",
        "--json",
    ]);
    assert_eq!(v["rows"][0]["set"][0]["value"].as_f64(), Some(2.0 * PI));
    // A bad single value is not called a malformed range.
    let (ok, _, err) = run(&["cylinder", "sweep", "pair", "--theta", "thirty"]);
    assert!(
        !ok && err.contains("'thirty'") && !err.contains("A:B:STEP"),
        "{err}"
    );
}

#[test]
fn an_inclination_out_of_range_is_told_in_degrees_and_radians() {
    for command in [
        &["cylinder", "pair"][..],
        &["cylinder", "sweep", "pair"][..],
    ] {
        let mut args = command.to_vec();
        args.extend(["--theta", "5deg", "--steps", "2"]);
        let (ok, _, err) = run(&args);
        assert!(!ok, "{args:?}");
        assert!(
            err.contains("--theta 5° (0.0873 rad) is outside (10.008°, 90°)"),
            "{args:?}: {err}"
        );
    }
}
