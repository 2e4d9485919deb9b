//! The hidden `--tuning NAME=VALUE` flag: nsga's options set by name for the block and
//! cylinder commands of the reference workload (scripts/reference_workload.py).

mod common;

use common::{json, run};

/// A shaken 3-block column, a few hundred steps.
const SHAKE: &[&str] = &[
    "blocks",
    "shake",
    "--blocks",
    "3",
    "--omega",
    "4",
    "--mu",
    "0.5",
    "--amplitude",
    "0.1",
    "--steps-per-period",
    "100",
    "--t-end",
    "3",
    "--json",
];

fn with(base: &[&'static str], extra: &[&'static str]) -> Vec<&'static str> {
    base.iter().chain(extra).copied().collect()
}

#[test]
fn a_tuning_assignment_changes_the_solver_of_a_block_run() {
    let plain = json(SHAKE);
    let starved = json(&with(SHAKE, &["--tuning", "newton.max_iter=1"]));
    let work = |v: &serde_json::Value| (v["linear_solves"].clone(), v["failed_steps"].clone());
    assert_ne!(work(&starved), work(&plain));
    // The default's value set by name is the default run, to the linear solve.
    let same = json(&with(SHAKE, &["--tuning", "tuning.stall_iterations=3"]));
    assert_eq!(same["linear_solves"], plain["linear_solves"]);
}

#[test]
fn a_bad_tuning_assignment_is_refused_before_any_run_naming_the_flag() {
    for args in [
        with(SHAKE, &["--tuning", "newton.max_iters=3"]),
        vec![
            "cylinder",
            "pair",
            "--theta",
            "30deg",
            "--tuning",
            "newton.max_iters=3",
        ],
    ] {
        let (ok, out, err) = run(&args);
        assert!(!ok && out.is_empty(), "{args:?}: {out}");
        assert!(
            err.contains("--tuning") && err.contains("max_iter,"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let (ok, _, err) = run(&with(SHAKE, &["--tuning", "tuning.progress=-1"]));
    assert!(!ok && err.contains("tuning.progress"), "{err}");
}

#[test]
fn the_cylinder_pair_takes_tuning_assignments() {
    let pair = [
        "cylinder", "pair", "--theta", "30deg", "--steps", "40", "--json",
    ];
    let plain = json(&pair);
    let same = json(&with(&pair, &["--tuning", "tuning.far_correction=4"]));
    assert_eq!(same["newton_iterations"], plain["newton_iterations"]);
    let (ok, _, err) = run(&with(&pair, &["--tuning", "newton.max_iter=0"]));
    assert!(!ok && err.contains("max_iter"), "{err}");
}
