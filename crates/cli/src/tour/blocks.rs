//! Tour section: the block stack (Ch. 4, App. I): the Leaning Tower of Lire in its
//! harmonic maximum-overhang configuration (ERRATA 16) left alone and perturbed (§4.3,
//! Figure 4.4), a shaken column with its failure time (§4.4), the column on a pulled base
//! in its three regimes (§4.5, Figure 4.7), the prox parameter's effect on Newton
//! failures, and Painlevé's paradoxes for one block (Figure I.2, ERRATA 18).

use super::{Block, Section};
use crate::commands::blocks::painleve::write_painleve_files;
use crate::commands::blocks::sweep::write_slide_files;
use crate::commands::blocks::{shake_inputs, simulate_with_output, OutputPlan, LIRE_SNAPSHOTS};
use anyhow::Result;
use blockstack::scenarios::{
    lire, lire_on_floor, maximum_overhang, shaking_column, Perturbation, Shaking, Sliding,
};
use blockstack::simulation::{simulate, Prox, RunOptions};
use blockstack::studies::lire::{blocks_fallen, largest_drift};
use blockstack::studies::painleve::painleve_report;
use blockstack::studies::slide::{slide_row, SlideRegime};
use blockstack::Defaults;
use figures::blocks::snapshot_name;
use figures::blocks::{plot_stack, SlideSweep};
use std::path::Path;

/// Builds the section.
///
/// # Errors
/// When a file cannot be written or a scenario cannot be built.
pub fn section(dir: &Path) -> Result<Section> {
    let mut summary = Vec::new();
    let mut blocks = Vec::new();
    overhang(dir, &mut summary, &mut blocks)?;
    lire_runs(dir, &mut summary, &mut blocks)?;
    shaking(dir, &mut summary, &mut blocks)?;
    slide(dir, &mut summary, &mut blocks)?;
    prox_comparison(&mut summary, &mut blocks)?;
    painleve(dir, &mut summary, &mut blocks)?;
    Ok(Section {
        title: "Block stack (Ch. 4, App. I)".into(),
        summary,
        blocks,
    })
}

fn overhang(dir: &Path, summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let scene = lire(4, Perturbation::None)?;
    let q = scene.initial_coordinates();
    let contacts = scene.contacts(0.0, &q, &vec![0.0; q.len()]);
    summary.push(format!(
        "Lire tower, 4 blocks w = 1: maximum overhang {:.6} = 25/24 w (ERRATA 16; (4.3.1) as printed gives w/2); largest |gap| at rest {:.1e}",
        maximum_overhang(4, 1.0),
        contacts.normals.iter().flatten().take(8).map(|r| r.value.abs()).fold(0.0, f64::max)
    ));
    plot_stack(
        &dir.join("blocks_lire_overhang.png"),
        &scene,
        &q,
        0.0,
        "Figure 4.3: maximum overhang, offsets w/8, w/6, w/4, w/2",
    )?;
    blocks.push(Block::image("blocks_lire_overhang.png", "The four-block Leaning Tower of Lire on a fixed table (black) in the harmonic maximum-overhang configuration (ERRATA 16)."));
    Ok(())
}

/// The runs of the tour resolve cycling contact states as the thesis's Algorithm 1
/// does (docs/method.md §8): re-solve with each set seen, continue with the first
/// self-consistent candidate, record a branch point.
fn tour_options() -> RunOptions {
    RunOptions {
        explore_branches: true,
        ..RunOptions::default()
    }
}

fn time_text(t: Option<f64>) -> String {
    t.map_or_else(|| "never".to_owned(), |t| format!("t = {t:.2}"))
}

fn lire_runs(dir: &Path, summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let mut rows = Vec::new();
    // The thesis's scene (nothing below the table), then the collapse on a floor (beyond
    // the thesis), whose blocks land.
    for (name, perturbation, floor) in [
        ("none", Perturbation::None, false),
        ("top", Perturbation::Top, false),
        ("bottom", Perturbation::Bottom, false),
        ("bottom, on a floor", Perturbation::Bottom, true),
    ] {
        let scene = if floor {
            lire_on_floor(4, perturbation)?
        } else {
            lire(4, perturbation)?
        };
        // Files (snapshots at 0, 5, 6.4, animation, trajectory) for the collapses only.
        let sub = (perturbation == Perturbation::Bottom)
            .then(|| dir.join(if floor { "lire_floor" } else { "lire_bottom" }));
        let plan = OutputPlan {
            dir: sub,
            snapshots: LIRE_SNAPSHOTS.to_vec(),
            max_frames: 100,
            title: format!("Lire tower, perturbation {name}"),
            defaults: Defaults::default(),
        };
        let inputs =
            serde_json::json!({"blocks": 4, "perturb": name, "floor": floor, "t_end": 10.0});
        let out = simulate_with_output(&scene, &tour_options(), &plan, "blocks lire", &inputs)?;
        let fallen = blocks_fallen(&scene, &out.summary.final_poses);
        let drift = out
            .recording
            .snapshots
            .iter()
            .find(|(ts, _)| (*ts - 5.0).abs() < 1e-12)
            .map_or(f64::NAN, |(_, f)| largest_drift(&scene, f));
        let r = &out.report;
        summary.push(format!(
            "Lire tower, perturbation {name}: drift at t = 5 {drift:.1e}; loses support {}; {fallen} of 4 blocks fallen below the table top at t = {:.2}; {} steps in {:.1} ms of solver time",
            time_text(r.failure_time),
            r.t_final,
            r.steps,
            1e3 * r.wall_time_s
        ));
        rows.push(vec![
            name.to_owned(),
            format!("{drift:.2e}"),
            time_text(r.failure_time),
            format!("{fallen} of 4"),
            format!("{:.2}", r.t_final),
            r.min_gap
                .map_or_else(|| "none".to_owned(), |g| format!("{g:.3e}")),
            format!("{:.2}", r.newton_iterations_mean),
            r.failed_steps.to_string(),
            r.branch_points.to_string(),
            format!("{:.1}", 1e3 * r.wall_time_s),
            r.error.clone().unwrap_or_default(),
        ]);
    }
    blocks.push(Block::table(
        &[
            "perturbation",
            "drift at t = 5",
            "loss of support",
            "blocks fallen below the table top at the end",
            "t reached",
            "min gap",
            "Newton its/step",
            "failed steps",
            "branch points",
            "solver ms",
            "error",
        ],
        rows,
    ));
    for ts in LIRE_SNAPSHOTS {
        blocks.push(Block::image(format!("lire_bottom/{}", snapshot_name(ts)), format!("Figure 4.4 at t = {ts}: the lowest block shifted right by 1 % of w makes the tower collapse. Black: the fixed table (the title shows the time of the state drawn).")));
    }
    blocks.push(Block::image("lire_bottom/animation.gif", "The collapse, every 10th step: as in the thesis, nothing lies below the table and the blocks fall freely."));
    blocks.push(Block::data(
        "lire_bottom/trajectory.csv",
        "trajectory of the collapse: poses and interface forces per step",
    ));
    blocks.push(Block::image("lire_floor/animation.gif", "The same collapse on a floor at the bottom of the table (line; beyond the thesis): the blocks land and come to rest on the floor and the table edge."));
    blocks.push(Block::data(
        "lire_floor/trajectory.csv",
        "trajectory of the collapse on a floor",
    ));
    Ok(())
}

/// The shaken column of the tour (§4.4): four blocks, ω = 4, A = 0.2, ten periods.
fn tour_shaking() -> Shaking {
    Shaking {
        omega: 4.0,
        ..Shaking::default()
    }
}

fn shaking(dir: &Path, summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let p = tour_shaking();
    let scene = shaking_column(&p)?;
    let plan = OutputPlan {
        dir: Some(dir.join("shaking")),
        snapshots: vec![0.0],
        max_frames: 100,
        title: format!("shaken column, ω = {}", p.omega),
        defaults: Defaults::default(),
    };
    let inputs = shake_inputs(&p);
    let out = simulate_with_output(&scene, &tour_options(), &plan, "blocks shake", &inputs)?;
    let r = &out.report;
    summary.push(format!(
        "shaken column (§4.4), 4 blocks, x = {} sin({} t), μ = {}: failure (loss of support) {}, first full opening {}; {} steps, {} failed Newton steps{}",
        p.amplitude,
        p.omega,
        p.mu,
        time_text(r.failure_time),
        time_text(r.opening_time),
        r.steps,
        r.failed_steps,
        r.error.as_ref().map_or_else(String::new, |e| format!(", stopped: {e}"))
    ));
    blocks.push(Block::image("shaking/animation.gif", format!(
            "A column of four blocks w = 0.2, h = 0.4 on a base shaken as x = {} sin({} t); failure {}.",
            p.amplitude,
            p.omega,
            time_text(r.failure_time)
        )));
    blocks.push(Block::image(
        "shaking/top_block.png",
        "Angle and height of the top block of the shaken column (cf. Figure 4.5 (b), (c)).",
    ));
    Ok(())
}

/// Base speeds of the tour's slide sweep: one or more in each regime of §4.5.
const SLIDE_SPEEDS: [f64; 7] = [0.05, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0];

fn slide(dir: &Path, summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let t_end = 3.0;
    let options = RunOptions {
        t_end: Some(t_end),
        ..tour_options()
    };
    let rows = crate::sweep::par_map_ordered(&SLIDE_SPEEDS, "v0", |&v0| {
        let p = Sliding {
            v0,
            t_end,
            ..Sliding::default()
        };
        slide_row(&p, &options)
    });
    let sliding = Sliding::default();
    write_slide_files(
        dir,
        &rows,
        &SlideSweep {
            blocks: sliding.blocks,
            t_end,
            mu: sliding.mu,
        },
    )?;
    let regimes: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                "v0 = {}: {}",
                r.v0,
                r.regime.map_or("error", SlideRegime::name)
            )
        })
        .collect();
    summary.push(format!(
        "pulled base (§4.5, Figure 4.7), t = {t_end}: {}",
        regimes.join(", ")
    ));
    blocks.push(Block::table(
        &["v0", "top angle at t = 3 (rad)", "regime", "error"],
        rows.iter()
            .map(|r| {
                vec![
                    r.v0.to_string(),
                    r.top_angle.map_or_else(String::new, |a| format!("{a:.4}")),
                    r.regime.map_or("", SlideRegime::name).to_owned(),
                    r.error.clone().unwrap_or_default(),
                ]
            })
            .collect(),
    ));
    blocks.push(Block::image("sweep_slide.png", "Figure 4.7 (few points): top block angle at t = 3 against the base speed; small v0 rides along, intermediate v0 topples, large v0 drops almost straight (tablecloth trick)."));
    blocks.push(Block::data("sweep_slide.csv", "the slide sweep"));
    Ok(())
}

/// The thesis's constant prox parameter (§4.2).
const THESIS_R: f64 = 0.3;

/// Failed Newton steps and branch points with the thesis's r = 0.3 against the scaled r,
/// for the Lire collapse and the shaken column.
fn prox_comparison(summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let mut rows = Vec::new();
    let cases = [
        ("Lire collapse", lire(4, Perturbation::Bottom)?),
        ("shaken column", shaking_column(&tour_shaking())?),
    ];
    for (name, scene) in &cases {
        for (prox_name, prox) in [
            ("scaled (alpha = 1)", None),
            ("constant r = 0.3", Some(Prox::Constant(THESIS_R))),
        ] {
            let options = RunOptions {
                prox,
                explore_branches: true,
                ..RunOptions::default()
            };
            let s = simulate(scene, &options, |_| {})?;
            rows.push(vec![
                (*name).to_owned(),
                prox_name.to_owned(),
                s.steps.to_string(),
                s.failed_steps.to_string(),
                s.branch_points.len().to_string(),
                format!("{:.2}", s.newton_iterations_mean),
                s.error.map(|e| e.to_string()).unwrap_or_default(),
            ]);
        }
    }
    summary.push(format!(
        "prox parameter (failed Newton steps / branch points): {}",
        rows.iter()
            .map(|r| format!("{}, {}: {} / {}", r[0], r[1], r[3], r[4]))
            .collect::<Vec<_>>()
            .join("; ")
    ));
    blocks.push(Block::table(
        &[
            "run",
            "prox parameter",
            "steps",
            "failed Newton steps",
            "branch points",
            "Newton its/step",
            "error",
        ],
        rows,
    ));
    Ok(())
}

fn painleve(dir: &Path, summary: &mut Vec<String>, blocks: &mut Vec<Block>) -> Result<()> {
    let report = painleve_report(0.5, 0.2)?;
    write_painleve_files(dir, 0.5, 3.0, 121, &report)?;
    summary.push(format!(
        "Painlevé (App. I, ERRATA 18): least μ_d = {:.6} (4/3) at ϑ = ±{:.3}°; w/h = 0.5: ϑ ∈ ({:.3}°, {:.3}°)",
        report.mu_min,
        report.theta_at_mu_min.abs().to_degrees(),
        report.theta_min.to_degrees(),
        report.theta_max.to_degrees()
    ));
    let lc = &report.line_contact.sliding_right[0];
    summary.push(format!(
        "line contact (I.2.10), w/h = 0.5, μ_d = 0.2, sliding right: n_R = {:.4}, n_L = {:.4}",
        lc.n_right, lc.n_left
    ));
    blocks.push(Block::image("painleve.png", "Figure I.2 for w/h = 0.5: (a) admissible angles (I.1.3); (b) where b ≤ 0 (paradox) per slip direction, faded outside the admissible range; i, ii: least μ_d = 4/3."));
    blocks.push(Block::data(
        "painleve_b_grid.csv",
        "b(ϑ, ±1, μ_d) on a 121 × 121 grid",
    ));
    Ok(())
}
