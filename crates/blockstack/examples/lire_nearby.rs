//! The Lire collapse and its nine neighbours (`scenarios::nearby_lire_collapses`): solver
//! time, failed Newton steps and linear solves of each run, and their means; with
//! `--floor`, the same collapses landing on a floor (`scenarios::nearby_lire_landings`).
//!
//! One collapse's cost depends on round-off-sized luck (it passes an unstable
//! equilibrium); the mean over the neighbours measures the solver, the single run only
//! one realisation. Run with
//! `cargo run --release -p blockstack --example lire_nearby [COUNT] [--floor] [--tuning
//! NAME=VALUE]...` (default 10 runs; `--tuning` sets nsga's options by name, as the
//! commands' hidden flag does, so that a variant of docs/tuning.md is measured over the
//! neighbours).

use blockstack::scenarios::{nearby_lire_collapses, nearby_lire_landings};
use blockstack::{simulate, RunOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut options = RunOptions {
        t_end: Some(9.99),
        explore_branches: true,
        ..RunOptions::default()
    };
    let mut count = 10;
    let mut floor = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--floor" {
            floor = true;
        } else if a == "--tuning" {
            options
                .tuning
                .push(args.next().ok_or("--tuning needs NAME=VALUE")?);
        } else {
            count = a.parse().map_err(|e| format!("COUNT '{a}': {e}"))?;
        }
    }
    let scenes = if floor {
        nearby_lire_landings(4, count)?
    } else {
        nearby_lire_collapses(4, count)?
    };
    println!("   k  solver ms  failed steps  linear solves  error");
    let (mut ms, mut failed, mut solves) = (Vec::new(), 0, 0);
    for (k, scene) in scenes.iter().enumerate() {
        let s = simulate(scene, &options, |_| {})?;
        println!(
            "{k:4} {:10.1} {:13} {:14}  {}",
            s.wall_time_s * 1e3,
            s.failed_steps,
            s.linear_solves,
            s.error
                .as_ref()
                .map_or_else(|| "none".to_owned(), ToString::to_string)
        );
        ms.push(s.wall_time_s * 1e3);
        failed += s.failed_steps;
        solves += s.linear_solves;
    }
    let n = scenes.len() as f64;
    ms.sort_by(f64::total_cmp);
    println!(
        "mean {:.1} ms (median {:.1}), {:.1} failed steps, {:.0} linear solves per run",
        ms.iter().sum::<f64>() / n,
        ms[ms.len() / 2],
        failed as f64 / n,
        solves as f64 / n
    );
    Ok(())
}
