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
    // Two rows, each scheme's observed order and the reference: no file written.
    let rows = text.lines().filter(|l| l.contains(" dt=")).count();
    assert!(
        ok && rows == 2 && text.lines().count() == 5 && !text.contains("wrote"),
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
    let (ok, _, err) = run(&[
        "cylinder",
        "holonomy",
        "rectangle",
        "--theta",
        "pi/10",
        "--phi1",
        "13pi/3",
        "--phi2",
        "7",
        "--max-step",
        "0.1",
    ]);
    assert!(ok, "{err}");
}

#[test]
fn cylinder_support_forces_in_newtons() {
    let over_mg = common::json(&["cylinder", "support", "--theta", "30deg", "--json"]);
    assert!(over_mg.get("forces_newton").is_none());
    let v = common::json(&[
        "cylinder",
        "support",
        "--theta",
        "30deg",
        "--mass",
        "2",
        "--gravity",
        "10",
        "--json",
    ]);
    let n = &v["forces_newton"];
    assert_eq!(n["weight"], 20.0);
    let f3 = over_mg["min_force"]["f3_over_mg"].as_f64().unwrap();
    assert!((n["f3_up"].as_f64().unwrap() - 20.0 * f3).abs() < 1e-12);
    // The /mg values are unchanged.
    let mut without = v.clone();
    without.as_object_mut().unwrap().remove("forces_newton");
    assert_eq!(without, over_mg);
    let (ok, text, _) = run(&["cylinder", "support", "--theta", "30deg", "--mass", "2"]);
    assert!(ok);
    assert!(text.contains("F3/mg = ") && text.contains(" (vertical, up), F/mg = "));
    assert!(text.contains("(horizontal, along e′2)"), "{text}");
    assert!(
        text.contains("in newtons (m = 2 kg, g = 9.81 m/s²"),
        "{text}"
    );
    let (ok, _, err) = run(&["cylinder", "support", "--theta", "30deg", "--gravity", "10"]);
    assert!(
        !ok && err.contains("--mass"),
        "--gravity needs --mass: {err}"
    );
}

/// Options whose value is a name, never a number: there a leading `-` is a flag.
const NAMED_VALUES: &[(&str, &str)] = &[
    ("rotation", "from"),
    ("sphere euler-plan", "set"),
    ("slurm", "partition"),
    ("tour", "only"),
];

/// Options whose value starts with a name in every command that has them: the hidden
/// `--tuning NAME=VALUE` of the measurement harness.
const NAMED_EVERYWHERE: &[&str] = &["tuning"];

/// Every option of every command, with its command path.
fn options() -> Vec<(String, clap::Arg)> {
    fn walk(path: &str, cmd: &clap::Command, out: &mut Vec<(String, clap::Arg)>) {
        for arg in cmd.get_arguments() {
            let takes_value = matches!(
                arg.get_action(),
                clap::ArgAction::Set | clap::ArgAction::Append
            );
            if takes_value && !arg.is_positional() {
                out.push((path.trim().to_owned(), arg.clone()));
            }
        }
        for sub in cmd.get_subcommands() {
            walk(&format!("{path} {}", sub.get_name()), sub, out);
        }
    }
    let mut out = Vec::new();
    walk(
        "",
        &<rollstack_cli::Cli as clap::CommandFactory>::command(),
        &mut out,
    );
    out
}

#[test]
fn every_option_that_may_be_negative_takes_a_leading_minus() {
    use std::any::TypeId;
    // A path, a shard, a choice among words or a name: a leading '-' is a flag there.
    let not_numbers = [
        TypeId::of::<std::path::PathBuf>(),
        TypeId::of::<rollstack_cli::sweep::ShardChoice>(),
    ];
    let mut missing = Vec::new();
    for (path, arg) in options() {
        let id = arg.get_id().as_str();
        let parser = arg.get_value_parser();
        let words = !arg.get_possible_values().is_empty();
        let named = NAMED_VALUES.contains(&(path.as_str(), id))
            || arg
                .get_long()
                .is_some_and(|l| NAMED_EVERYWHERE.contains(&l));
        if words || named || not_numbers.iter().any(|t| parser.type_id() == *t) {
            continue;
        }
        if !arg.is_allow_hyphen_values_set() {
            missing.push(format!("{path} --{}", arg.get_long().unwrap_or(id)));
        }
    }
    assert!(
        missing.is_empty(),
        "'--flag -1' is clap's 'unexpected argument' for: {missing:?}"
    );
    // And what the user sees: the value is read, and refused by its own check.
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

#[test]
fn a_huge_value_is_printed_short_under_its_flag() {
    for (args, expected) in [
        (
            "blocks shake --omega -1e300",
            "--omega must be positive, got -1e300",
        ),
        (
            "blocks run shaking --t-end -1e300",
            "--t-end must be positive, got -1e300",
        ),
        (
            "nsga ball --case 2 --dt 1e300",
            "--dt must be in (0, 0.1] s, got 1e300",
        ),
        (
            "cylinder frobenius --r-over-h -1e300",
            "--r-over-h must be positive, got -1e300",
        ),
        (
            "blocks sweep scene shaking --set contact.mu=1e300,-1e300",
            "got -1e300",
        ),
        // A setting of every inclination is refused under its own flag, not --theta's.
        (
            "cylinder sweep push --theta 30deg --dt -1e300",
            "error: --dt must be positive, got -1e300",
        ),
        (
            "cylinder sweep pair --theta 30deg --steps 0",
            "error: --steps must be at least 1, got 0",
        ),
    ] {
        let (ok, _, err) = run(&args.split(' ').collect::<Vec<_>>());
        assert!(!ok && err.contains(expected), "{args}: {err}");
        assert!(err.len() < 300, "{args}: {err}");
    }
}
