//! `rollstack blocks …` end to end: JSON keys of docs/cli.md, the thesis's numbers
//! (corrected by ERRATA 18), output files (progressive trajectory, sweeps in input
//! order), and clean errors on bad input. Runs are short (t_end ≤ 1, few sweep points).

mod common;

use common::{json, rollstack, run, temp_dir};
use serde_json::Value;
use std::path::Path;

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
fn painleve_out_writes_the_corner_scan_with_three_solutions_where_b_is_negative() {
    let dir = common::temp_dir("blocks-painleve-scan");
    let d = dir.to_str().unwrap();
    let out = rollstack(&[
        "blocks", "painleve", "--aspect", "0.5", "--mu", "2", "--grid", "2", "--out", d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("painleve_corner_scan.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "theta_rad,slip,spin_sign,b,minus_a_over_b,solutions,sliding_contact_force,jam_force,lift_off,contact,dt"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 61 * 4);
    // With B < 0 away from θ = 0 (a line contact): all three solutions, the sliding
    // contact's force near −A/B.
    let paradoxes: Vec<_> = rows
        .iter()
        .filter(|r| r[9] == "point" && r[3].parse::<f64>().unwrap() < 0.0)
        .collect();
    assert_eq!(paradoxes.len(), 76);
    for r in paradoxes {
        assert_eq!((r[5], r[8]), ("3", "1"), "{r:?}");
        let (force, analytic): (f64, f64) = (r[6].parse().unwrap(), r[4].parse().unwrap());
        assert!((force / analytic - 1.0).abs() < 0.25, "{r:?}");
        assert!(r[7].parse::<f64>().unwrap() > 50.0, "{r:?}");
    }
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

/// The docs/cli.md keys of `blocks run` / `blocks lire`, then the documented extras.
const RUN_KEYS: [&str; 6] = [
    "steps",
    "failure_time",
    "final",
    "min_gap",
    "newton_iterations_mean",
    "wall_time_s",
];
const RUN_EXTRAS: [&str; 5] = [
    "opening_time",
    "failed_steps",
    "branch_points",
    "max_energy_increase",
    "error",
];

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header = r.headers().unwrap().iter().map(str::to_owned).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(str::to_owned).collect())
        .collect();
    (header, rows)
}

#[test]
fn lire_unperturbed_stays_put_with_the_design_keys() {
    let v = json(&[
        "blocks",
        "lire",
        "--blocks",
        "4",
        "--perturb",
        "none",
        "--t-end",
        "1",
        "--json",
    ]);
    for key in RUN_KEYS.iter().chain(&RUN_EXTRAS) {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    // t_end = 1 with Δt = 0.01.
    assert_eq!(v["steps"].as_u64(), Some(100));
    assert!(v["failure_time"].is_null());
    assert!(v["error"].is_null());
    assert!(f(&v["min_gap"]) > -1e-8);
    assert!(f(&v["newton_iterations_mean"]) >= 0.0);
    assert!(f(&v["wall_time_s"]) >= 0.0);
    assert!(f(&v["max_energy_increase"]) <= 1e-12);
    // An unstable equilibrium, but it holds for 1 s: final poses = initial to 1e-6.
    let q0 = blockstack::scenarios::lire(4, blockstack::scenarios::Perturbation::None)
        .unwrap()
        .initial_coordinates();
    let fin = v["final"].as_array().unwrap();
    assert_eq!(fin.len(), 4);
    for (k, p) in fin.iter().enumerate() {
        for (i, key) in ["x", "y", "theta"].iter().enumerate() {
            let d = (f(&p[key]) - q0[3 * k + i]).abs();
            assert!(d < 1e-6, "block {} {key} moved by {d}", k + 1);
        }
    }
}

#[test]
fn lire_out_writes_a_row_per_step_and_the_figures() {
    let dir = temp_dir("blocks-lire-out");
    let d = dir.to_str().unwrap();
    let v = json(&[
        "blocks",
        "lire",
        "--perturb",
        "top",
        "--t-end",
        "0.3",
        "--out",
        d,
        "--json",
    ]);
    let steps = usize::try_from(v["steps"].as_u64().unwrap()).unwrap();
    let text = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let mut lines = text.lines();
    let mut expected = vec!["t".to_owned()];
    for k in 1..=4 {
        expected.extend([format!("x{k}"), format!("y{k}"), format!("theta{k}")]);
    }
    for k in 1..=4 {
        expected.extend([format!("n{k}a"), format!("n{k}b"), format!("f{k}")]);
    }
    expected.extend(["base_x", "min_gap", "newton_iterations", "energy"].map(String::from));
    assert_eq!(lines.next().unwrap(), expected.join(","));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|c| c.parse::<f64>().expect("a number"))
                .collect()
        })
        .collect();
    // One row per step plus the initial state, all finite, times increasing from 0.
    assert_eq!(rows.len(), steps + 1);
    assert!(rows.iter().all(|r| r.len() == expected.len()));
    assert!(rows.iter().flatten().all(|x| x.is_finite()));
    assert_eq!(rows[0][0], 0.0);
    assert!(rows.windows(2).all(|w| w[1][0] > w[0][0]));
    // The consistent start (§4.3): the base carries the weight of the four blocks
    // (g = 1, m = 1) less m·ÿ of the top block, which starts to tip over its edge.
    let n1 = rows[0][13] + rows[0][14];
    assert!(n1 > 3.9 && n1 < 4.0, "{:?}", &rows[0][13..15]);
    let bp = std::fs::read_to_string(dir.join("branch_points.csv")).unwrap();
    assert_eq!(bp.lines().next(), Some("t,candidates,distinct"));
    for png in [
        "snapshot_t0.png",
        "snapshot_t5.png",
        "snapshot_t6.4.png",
        "top_block.png",
    ] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
    }
    let gif = std::fs::read(dir.join("animation.gif")).unwrap();
    assert_eq!(&gif[..3], b"GIF");
    let run: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["command"], "blocks lire");
    assert_eq!(run["inputs"]["perturb"], "top");
    // No temporary file left behind.
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".tmp"), "{name}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

const GOOD_SCENE: &str = "[base]\nwidth = 1.0\nheight = 0.1\n\n[[blocks]]\nwidth = 0.2\nheight = 0.4\ncount = 2\n\n[contact]\nmu = 0.2\n\n[solver]\nt_end = 0.1\n";

#[test]
fn run_scene_file_prints_the_design_keys() {
    let dir = temp_dir("blocks-run");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("two.toml");
    std::fs::write(&scene, GOOD_SCENE).unwrap();
    let out = dir.join("out");
    let v = json(&[
        "blocks",
        "run",
        scene.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    // At rest: each interface carries the weight above it (g = 1, m = 1), no friction.
    let (header, rows) = read_csv(&out.join("trajectory.csv"));
    assert_eq!(&header[7..13], ["n1a", "n1b", "f1", "n2a", "n2b", "f2"]);
    assert_eq!(rows.len(), 11);
    for r in &rows {
        let x: Vec<f64> = r.iter().map(|c| c.parse().unwrap()).collect();
        assert!((x[7] + x[8] - 2.0).abs() < 1e-9, "{r:?}");
        assert!((x[10] + x[11] - 1.0).abs() < 1e-9, "{r:?}");
        assert!(x[9].abs() < 1e-9 && x[12].abs() < 1e-9, "{r:?}");
    }
    for key in RUN_KEYS.iter().chain(&RUN_EXTRAS) {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["steps"].as_u64(), Some(10));
    assert_eq!(v["final"].as_array().unwrap().len(), 2);
    // Two blocks at rest on a fixed base stay there.
    assert!((f(&v["final"][1]["y"]) - 0.65).abs() < 1e-9);
    // Default snapshots of a scene file: 0, t_end/2, t_end.
    for png in ["snapshot_t0.png", "snapshot_t0.05.png", "snapshot_t0.1.png"] {
        assert!(out.join(png).exists(), "{png}");
    }
    // The override of t_end, the constant prox parameter of the thesis, chosen
    // snapshots and no animation.
    let out2 = dir.join("out2");
    let v = json(&[
        "blocks",
        "run",
        scene.to_str().unwrap(),
        "--t-end",
        "0.05",
        "--prox-constant",
        "0.3",
        "--snapshots",
        "0.02",
        "--max-frames",
        "0",
        "--out",
        out2.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["steps"].as_u64(), Some(5));
    assert!(v["prox"].as_str().unwrap().contains("0.3"), "{}", v["prox"]);
    assert!(out2.join("snapshot_t0.02.png").exists());
    assert!(!out2.join("snapshot_t0.png").exists());
    assert!(!out2.join("animation.gif").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_scenes_and_options_give_one_error_line() {
    let dir = temp_dir("blocks-bad-scenes");
    std::fs::create_dir_all(&dir).unwrap();
    let base = "[base]\nwidth = 1.0\nheight = 0.1\n";
    let block = "[[blocks]]\nwidth = 0.2\nheight = 0.4\n";
    let contact = "[contact]\nmu = 0.2\n";
    let cases = [
        (
            "negative",
            format!("[base]\nwidth = -1.0\nheight = 0.1\n{block}{contact}"),
            "positive",
        ),
        ("mu", format!("{base}{block}[contact]\nmu = -0.2\n"), "mu"),
        (
            "key",
            format!("{base}{block}colour = 1\n{contact}"),
            "colour",
        ),
        (
            "overlap",
            format!("{base}{block}{block}y = 0.3\n{contact}"),
            "overlap",
        ),
        (
            "syntax",
            format!("{base}{block}{contact}mu = = 1\n"),
            "line",
        ),
        ("empty", String::new(), "invalid scene"),
    ];
    for (name, text, needle) in &cases {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let (ok, stdout, stderr) = run(&["blocks", "run", path.to_str().unwrap(), "--json"]);
        assert!(!ok, "{name}");
        assert!(stdout.is_empty(), "{name}: {stdout}");
        assert_eq!(stderr.trim().lines().count(), 1, "{name}: {stderr}");
        assert!(stderr.starts_with("error: "), "{name}: {stderr}");
        assert!(stderr.contains(needle), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
    }
    let missing = dir.join("missing.toml");
    let (ok, _, stderr) = run(&["blocks", "run", missing.to_str().unwrap()]);
    assert!(!ok);
    assert!(stderr.contains("cannot read scene"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    for bad in [
        vec!["blocks", "lire", "--t-end", "0", "--json"],
        vec![
            "blocks",
            "lire",
            "--t-end",
            "0.1",
            "--prox-constant",
            "-0.3",
        ],
        vec!["blocks", "lire", "--blocks", "0"],
        vec![
            "blocks", "sweep", "slide", "--v0", "1:0:1", "--out", "/tmp/x",
        ],
        vec![
            "blocks",
            "sweep",
            "frequency",
            "--omega",
            "1",
            "--periods",
            "0",
            "--out",
            "/tmp/x",
        ],
    ] {
        let (ok, stdout, stderr) = run(&bad);
        assert!(!ok, "{bad:?}");
        assert!(stdout.is_empty(), "{bad:?}");
        assert_eq!(stderr.trim().lines().count(), 1, "{bad:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{bad:?}: {stderr}");
    }
    let out = rollstack(&["blocks", "lire", "--perturb", "sideways"]);
    assert!(!out.status.success());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn slide_sweep_shards_write_rows_in_input_order() {
    let dir = temp_dir("blocks-slide");
    let mut all = Vec::new();
    for shard in ["1/2", "2/2"] {
        let sub = dir.join(shard.replace('/', "of"));
        let out = rollstack(&[
            "blocks",
            "sweep",
            "slide",
            "--v0",
            "0.5:2:0.5",
            "--t-end",
            "0.1",
            "--shard",
            shard,
            "--out",
            sub.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (header, rows) = read_csv(&sub.join("sweep_slide.csv"));
        assert_eq!(
            &header[..5],
            ["v0", "top_angle", "regime", "steps", "error"]
        );
        for r in &rows {
            assert_eq!(r[3], "10", "{r:?}");
            assert!(r[4].is_empty(), "{r:?}");
            assert!(["rides-along", "topples", "drops"].contains(&r[2].as_str()));
            assert!(r[1].parse::<f64>().unwrap().is_finite());
        }
        all.extend(rows.into_iter().map(|r| r[0].parse::<f64>().unwrap()));
        assert!(
            std::fs::metadata(sub.join("sweep_slide.png"))
                .unwrap()
                .len()
                > 1000
        );
        let run: Value =
            serde_json::from_str(&std::fs::read_to_string(sub.join("run.json")).unwrap()).unwrap();
        assert_eq!(run["command"], "blocks sweep slide");
    }
    assert_eq!(all, vec![0.5, 1.0, 1.5, 2.0]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn frequency_sweep_keeps_order_and_refuses_bad_values_before_any_run() {
    let dir = temp_dir("blocks-frequency");
    let d = dir.to_str().unwrap();
    // ω = −2 and 0 cannot be run: the sweep names the first and runs nothing.
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "sweep",
        "frequency",
        "--omega",
        "-2:4:2",
        "--periods",
        "0.1",
        "--out",
        d,
    ]);
    assert!(!ok && stdout.is_empty(), "{stdout}");
    assert_eq!(stderr.trim_end(), "error: --omega must be positive, got -2");
    assert!(
        !dir.exists(),
        "nothing is written before the values are checked"
    );
    let v = json(&[
        "blocks",
        "sweep",
        "frequency",
        "--omega",
        "2:4:1",
        "--periods",
        "0.1",
        "--out",
        d,
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    let omegas: Vec<f64> = rows.iter().map(|r| f(&r["omega"])).collect();
    assert_eq!(omegas, vec![2.0, 3.0, 4.0]);
    for r in rows {
        assert!(r["error"].is_null(), "{r}");
        // Δt = 2π/(100ω): a tenth of a period is 10 steps (or fewer after a failure).
        assert!(r["steps"].as_u64().unwrap() <= 10);
        match r["failure_time"].as_f64() {
            Some(t) => {
                assert!((f(&r["inv_failure_time"]) - 1.0 / t).abs() < 1e-12);
                assert_eq!(r["outcome"], "failed");
            }
            None => {
                assert_eq!(f(&r["inv_failure_time"]), 0.0);
                assert_eq!(r["outcome"], "no_failure_by_horizon");
            }
        }
        // A tenth of a period: 0.2π/ω time units.
        let horizon = 0.2 * std::f64::consts::PI / f(&r["omega"]);
        assert!((f(&r["horizon"]) - horizon).abs() < 1e-12, "{r}");
    }
    let (header, csv_rows) = read_csv(&dir.join("sweep_frequency.csv"));
    assert_eq!(
        &header[..8],
        [
            "omega",
            "horizon",
            "outcome",
            "failure_time",
            "inv_failure_time",
            "opening_time",
            "steps",
            "error"
        ]
    );
    let csv_omegas: Vec<f64> = csv_rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(csv_omegas, omegas);
    assert!(
        std::fs::metadata(dir.join("sweep_frequency.png"))
            .unwrap()
            .len()
            > 1000
    );
    // A shard holds its contiguous part of the values.
    let sub = dir.join("shard");
    let v = json(&[
        "blocks",
        "sweep",
        "frequency",
        "--omega",
        "2:5:1",
        "--periods",
        "0.05",
        "--shard",
        "2/2",
        "--out",
        sub.to_str().unwrap(),
        "--json",
    ]);
    let omegas: Vec<f64> = v["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| f(&r["omega"]))
        .collect();
    assert_eq!(omegas, vec![4.0, 5.0]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn scene_sweep_refuses_degrees_for_a_key_that_is_not_an_angle() {
    // `contact.mu=30deg` was read as 0.52 (30° in radians): a friction coefficient is
    // not an angle.
    for set in [
        "contact.mu=30deg",
        "contact.mu=0.1,30deg",
        "base.amplitude=0:1deg:0.1",
    ] {
        let (ok, _, stderr) = run(&["blocks", "sweep", "scene", "shaking", "--set", set]);
        let key = set.split('=').next().unwrap();
        assert!(!ok, "{set}");
        assert!(
            stderr.contains(&format!("{key} is not an angle")) && stderr.contains("deg"),
            "{set}: {stderr}"
        );
        // docs/cli.md names the keys that take degrees as the error does.
        let listed = stderr.split("deg is for ").nth(1).unwrap();
        let listed = listed.split(')').next().unwrap();
        let doc = include_str!("../../../docs/cli.md");
        for k in listed.split(" and ") {
            assert!(doc.contains(&format!("`{k}`")), "{k} not in docs/cli.md");
        }
    }
    // An angle and an angular rate take degrees.
    let (ok, stdout, stderr) = run(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "blocks.theta=0deg,1deg",
        "--set",
        "base.omega=229.1831deg",
        "--t-end",
        "0.05",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let theta = v["rows"][1]["set"][0]["value"].as_f64().unwrap();
    assert!((theta - 1f64.to_radians()).abs() < 1e-15, "{v}");
    let omega = v["rows"][0]["set"][1]["value"].as_f64().unwrap();
    assert!((omega - 4.0).abs() < 1e-5, "{v}");
}

#[test]
fn scene_sweep_runs_the_product_of_its_keys_in_order() {
    let dir = temp_dir("blocks-sweep-scene");
    let d = dir.to_str().unwrap();
    // A value the scene refuses (μ = −0.1) stops the sweep before any run, naming it.
    let (ok, _, stderr) = run(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "contact.mu=-0.1:0.1:0.1",
        "--set",
        "base.amplitude=0.1,0.2",
        "--out",
        d,
    ]);
    assert!(
        !ok && stderr.contains("--set contact.mu=-0.1 --set base.amplitude=0.1"),
        "{stderr}"
    );
    assert!(stderr.contains("mu must not be negative"), "{stderr}");
    assert!(
        !dir.exists(),
        "nothing is written before the values are checked"
    );
    // 3 × 2 combinations, the first --set slowest.
    let v = json(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "contact.mu=0:0.2:0.1",
        "--set",
        "base.amplitude=0.1,0.2",
        "--set",
        "blocks.count=2",
        "--t-end",
        "0.05",
        "--out",
        d,
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    let set: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|r| {
            (
                f(&r["set"][0]["value"]),
                f(&r["set"][1]["value"]),
                f(&r["set"][2]["value"]),
            )
        })
        .collect();
    assert_eq!(
        set,
        [
            (0.0, 0.1, 2.0),
            (0.0, 0.2, 2.0),
            (0.1, 0.1, 2.0),
            (0.1, 0.2, 2.0),
            (0.2, 0.1, 2.0),
            (0.2, 0.2, 2.0)
        ]
    );
    assert_eq!(rows[0]["set"][0]["key"], "contact.mu");
    for r in rows {
        assert!(r["error"].is_null(), "{r}");
        assert!(r["steps"].as_u64().unwrap() > 0 && f(&r["top_y"]) > 0.0);
    }
    assert!(rows.iter().all(|r| r["linear_solves"].as_u64().is_some()));
    let (header, csv_rows) = read_csv(&dir.join("sweep_scene.csv"));
    let solves = header.iter().position(|h| h == "linear_solves").unwrap();
    for (row, csv) in rows.iter().zip(&csv_rows) {
        assert_eq!(csv[solves], row["linear_solves"].to_string());
    }
    assert_eq!(
        header[..5],
        [
            "contact.mu",
            "base.amplitude",
            "blocks.count",
            "failure_time",
            "opening_time"
        ]
    );
    let first_cells: Vec<(&str, &str)> = csv_rows
        .iter()
        .map(|r| (r[0].as_str(), r[1].as_str()))
        .collect();
    assert_eq!(
        first_cells,
        [
            ("0.0", "0.1"),
            ("0.0", "0.2"),
            ("0.1", "0.1"),
            ("0.1", "0.2"),
            ("0.2", "0.1"),
            ("0.2", "0.2")
        ]
    );
    assert!(
        std::fs::metadata(dir.join("sweep_scene.png"))
            .unwrap()
            .len()
            > 1000
    );
    let run: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).unwrap()).unwrap();
    assert_eq!(run["command"], "blocks sweep scene");
    assert_eq!(run["inputs"]["set"][0], "contact.mu=0:0.2:0.1");
    // A shard holds its contiguous part of the combinations.
    let v = json(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "contact.mu=0.1,0.2",
        "--set",
        "solver.periods=0.01,0.02",
        "--shard",
        "2/2",
        "--out",
        d,
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    let mus: Vec<f64> = rows.iter().map(|r| f(&r["set"][0]["value"])).collect();
    assert_eq!(mus, [0.2, 0.2]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn scene_sweep_refuses_unknown_keys_before_any_run() {
    let dir = temp_dir("blocks-sweep-scene-bad");
    let d = dir.to_str().unwrap();
    let sweep = |set: &str| {
        run(&[
            "blocks", "sweep", "scene", "shaking", "--set", set, "--out", d,
        ])
    };
    for (set, says) in [
        ("contact.muu=0.1", "mu, e_n, e_f"),
        ("blocks.3.width=0.1", "1 [[blocks]] entry"),
        ("base.motion=1", "not a number"),
        ("wind.speed=1", "base, blocks, contact, solver, floor"),
    ] {
        let (ok, _, stderr) = sweep(set);
        assert!(!ok, "{set}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(says), "{set}: {stderr}");
    }
    assert!(
        !dir.exists(),
        "nothing is written before the keys are checked"
    );
    let out = rollstack(&[
        "blocks",
        "sweep",
        "scene",
        "shaking",
        "--set",
        "contact.mu",
        "--out",
        d,
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn lire_top_perturbation_resolves_branch_points_by_default() {
    // The top block tips over the edge and lands on the floor: its contact states
    // alternate on the way (at t = 6.33), which the default resolves by fixed-set
    // re-solves instead of ending the run. (With `--explore-branches false` that step now
    // goes through as two half steps.)
    let v = json(&[
        "blocks",
        "lire",
        "--blocks",
        "4",
        "--perturb",
        "top",
        "--floor",
        "--t-end",
        "7",
        "--json",
    ]);
    assert!(v["error"].is_null(), "{}", v["error"]);
    assert_eq!(v["steps"].as_u64(), Some(700));
    let failure = v["failure_time"]
        .as_f64()
        .expect("the top block loses support");
    assert!(failure > 1.0 && failure < 7.0, "{failure}");
    assert!(v["min_gap"].as_f64().unwrap() >= -1e-8);
    // It has come down onto the floor at the table's bottom (y = -0.1), turned over,
    // leaning on the table's edge.
    let top = &v["final"][3];
    let (y, theta) = (top["y"].as_f64().unwrap(), top["theta"].as_f64().unwrap());
    assert!(y > -0.1 && y < 0.3 && theta.abs() > 1.0, "{top}");
}

#[test]
fn lire_without_floor_lets_the_falling_blocks_fall() {
    // The thesis's scene: nothing below the table.
    let v = json(&[
        "blocks",
        "lire",
        "--perturb",
        "top",
        "--t-end",
        "7",
        "--json",
    ]);
    assert!(v["error"].is_null(), "{}", v["error"]);
    assert!(
        v["final"][3]["y"].as_f64().unwrap() < -1.0,
        "{}",
        v["final"][3]
    );
}

#[test]
fn runs_estimated_over_ten_minutes_are_refused_before_any_step_unless_forced() {
    let dir = temp_dir("blocks-time-bound");
    let d = dir.to_str().unwrap();
    for args in [
        &["blocks", "shake", "--periods", "1e7", "--out", d][..],
        &["blocks", "lire", "--t-end", "1e9", "--out", d],
        &["blocks", "run", "shaking", "--t-end", "1e12", "--out", d],
        &[
            "blocks",
            "sweep",
            "frequency",
            "--omega",
            "1:1000:0.001",
            "--out",
            d,
        ],
        &[
            "blocks", "sweep", "slide", "--v0", "1", "--t-end", "1e8", "--out", d,
        ],
        &[
            "blocks",
            "sweep",
            "scene",
            "shaking",
            "--set",
            "solver.dt=1e-9",
            "--out",
            d,
        ],
    ] {
        let (ok, stdout, stderr) = run(args);
        assert!(!ok && stdout.is_empty(), "{args:?}");
        assert!(
            stderr.contains("more than 600 s") && stderr.contains("--force"),
            "{stderr}"
        );
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
    }
    assert!(!dir.exists(), "nothing is written before the estimate");
    // --force starts it (here a run that is short after all: the bound is on the estimate).
    let v = json(&["blocks", "shake", "--periods", "0.05", "--force", "--json"]);
    assert!(v["error"].is_null() && v["steps"] == 5, "{v}");
}

/// `blocks explore` on two blocks of Figure 4.5's setting under the thesis's rule, with
/// `threads` rayon threads: every file it writes but the figure, by name.
fn explore_files(threads: &str) -> Vec<(String, Vec<u8>)> {
    let dir = temp_dir(&format!("blocks-explore-threads-{threads}"));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("two.toml");
    let toml = String::from_utf8(rollstack(&["blocks", "scenes", "abundance"]).stdout).unwrap();
    std::fs::write(&scene, toml.replace("count = 5", "count = 2")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rollstack"))
        .args([
            "blocks",
            "explore",
            scene.to_str().unwrap(),
            "--branch-rule",
            "converged",
            "--classify",
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files = Vec::new();
    for sub in ["out", "out/trajectories"] {
        for e in std::fs::read_dir(dir.join(sub)).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            if p.is_file() && name.ends_with(".csv") {
                files.push((format!("{sub}/{name}"), std::fs::read(&p).unwrap()));
            }
        }
    }
    files.sort();
    let _ = std::fs::remove_dir_all(&dir);
    files
}

#[test]
fn explore_writes_the_same_files_with_one_or_two_threads() {
    let one = explore_files("1");
    let two = explore_files("2");
    let names: Vec<&str> = one.iter().map(|(n, _)| n.as_str()).collect();
    for f in ["out/branches.csv", "out/forks.csv", "out/outcomes.csv"] {
        assert!(names.contains(&f), "{names:?}");
    }
    assert!(names.len() > 5, "a tree of several branches: {names:?}");
    assert_eq!(one, two);
    // The columns docs/cli.md lists for branches.csv.
    let branches = &one.iter().find(|(n, _)| n == "out/branches.csv").unwrap().1;
    let header = String::from_utf8_lossy(branches)
        .lines()
        .next()
        .unwrap()
        .to_owned();
    assert_eq!(
        header,
        "id,parent,candidate,depth,t_start,t_end,steps,end,forks_passed,failure_time,\
         fallback_steps,unshifted_steps,outcome"
    ); // A branch's trajectory ends with the contact laws (docs/cli.md), a fork row with
       // each candidate's.
    let first = &one
        .iter()
        .find(|(n, _)| n.starts_with("out/trajectories/"))
        .unwrap()
        .1;
    let header = String::from_utf8_lossy(first)
        .lines()
        .next()
        .unwrap()
        .to_owned();
    assert!(
        header.ends_with(
            ",pn1a,pn1b,pf1,state1,pn2a,pn2b,pf2,state2,gap_violation,normal_violation,\
             cone_violation,complementarity_violation"
        ),
        "{header}"
    );
    let forks = String::from_utf8_lossy(&one.iter().find(|(n, _)| n == "out/forks.csv").unwrap().1)
        .into_owned();
    let header = forks.lines().next().unwrap();
    assert!(
        header.ends_with(
            ",refined_converged_dt2,refined_converged_dt4,window,stepped_back,\
             candidate_states,breaks,violation,why"
        ),
        "{header}"
    );
    // The thesis's rule keeps candidates that break a law, and says which.
    assert!(
        forks
            .lines()
            .skip(1)
            .any(|l| l.contains("cone") || l.contains("gap")),
        "{forks}"
    );
}

#[test]
fn explore_refuses_an_empty_classify_window_naming_the_flag() {
    let out = rollstack(&[
        "blocks",
        "explore",
        "shaking",
        "--classify",
        "--classify-window",
        "0",
    ]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--classify-window must be at least 1"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}
