//! Where a run's work goes, step by step: how many steps take 0, 1, 2, … linear solves
//! (factorizations) and Newton evaluations, with the solver time of each kind of step,
//! and how many of the solves are in steps whose first attempt failed
//! (docs/experiments.md §4). The run is stepped as `rollstack` steps it
//! ([`CornerStepping`]), so its totals are those of the command's `--json`.
//!
//! - `lire N`: the Lire tower of N blocks collapsing onto a floor, to t = 10
//!   (`rollstack blocks lire --blocks N --perturb bottom --floor`; the peers' `lire10`);
//! - `shake N OMEGA MU [T_END]`: a run of the shaken-column matrix (`rollstack blocks
//!   shake --blocks N --omega OMEGA --mu MU --amplitude 0.2 --steps-per-period 200
//!   --t-end T_END`, default T_END = 20).
//!
//! Counts of 20 or more are shown together on the line of 20.
//!
//! With `--hard N` after the scene, every step of N linear solves or more is listed
//! first, with its solves by stage of the step's policy (docs/method.md §8.2), its
//! retries and whether it was halved or taken without the friction shift:
//! where a run's hard steps go (docs/experiments.md §8.2).
//!
//! `cargo run --release -p blockstack --example step_costs -- lire 10`
//! `cargo run --release -p blockstack --example step_costs -- shake 6 2 0.3 --hard 20`

use blockstack::scenarios::{lire_on_floor, shaking_column, Perturbation, Shaking};
use blockstack::simulation::stepper_options;
use blockstack::stepping::CornerStepping;
use blockstack::{RunOptions, Scene};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::time::Instant;

/// Steps by their count of something: how many, that something summed over them, and
/// their solver seconds.
#[derive(Default)]
struct Histogram(BTreeMap<u64, (u64, u64, f64)>);

impl Histogram {
    fn add(&mut self, count: u64, seconds: f64) {
        let bin = self.0.entry(count.min(20)).or_default();
        bin.0 += 1;
        bin.1 += count;
        bin.2 += seconds;
    }

    fn print(&self, what: &str, run_seconds: f64) {
        for (count, (steps, total, seconds)) in &self.0 {
            println!(
                "  {count:>3} {what}: {steps:>6} steps, {total:>7} {what} in all, {:5.1} % of \
                 the solver time",
                100.0 * seconds / run_seconds
            );
        }
    }
}

/// The value of `--hard N` (steps of N linear solves or more are listed), taken out of
/// `args`.
fn hard_from_args(args: &mut Vec<String>) -> Result<Option<u64>, Box<dyn std::error::Error>> {
    let Some(i) = args.iter().position(|a| a == "--hard") else {
        return Ok(None);
    };
    let n = args
        .get(i + 1)
        .ok_or("--hard needs a number of linear solves")?;
    let n = n.parse::<u64>().map_err(|e| format!("--hard '{n}': {e}"))?;
    args.drain(i..i + 2);
    Ok(Some(n))
}

/// One hard step: its times, its solves by stage (`before` the step's, `after`), its
/// evaluations and what its policy did (docs/method.md §8.2).
fn print_hard_step(
    t0: f64,
    stats: &nsga::StepStats,
    before: nsga::SolvesByStage,
    after: nsga::SolvesByStage,
    evaluations: u64,
) {
    let halved = if stats.substeps > 1 {
        format!(", halved into {} substeps", stats.substeps)
    } else {
        String::new()
    };
    let unshifted = if stats.unshifted { ", unshifted" } else { "" };
    println!(
        "  t = {t0:.4} → {:.4}: {} linear solves (first attempt {}, fixed-set re-solves {}, \
         unshifted {}, ρ∞ retries {}, flip probes {}), {evaluations} evaluations, {} retries \
         (`StepStats::retries`){halved}{unshifted}",
        stats.t,
        after.total() - before.total(),
        after.first_attempt - before.first_attempt,
        after.branch_trials - before.branch_trials,
        after.unshifted - before.unshifted,
        after.rho_retries - before.rho_retries,
        after.other - before.other,
        stats.retries,
    );
}

/// The scene and its end time from the command line `args`.
fn scene_from_args(args: &[String]) -> Result<(Scene, f64), Box<dyn std::error::Error>> {
    let number = |i: usize| -> Result<f64, Box<dyn std::error::Error>> {
        let a = args
            .get(i)
            .ok_or("missing argument (see the example's docs)")?;
        Ok(a.parse::<f64>().map_err(|e| format!("'{a}': {e}"))?)
    };
    let blocks = args.get(1).ok_or("missing block count")?.parse::<usize>()?;
    match args.first().map(String::as_str) {
        Some("lire") => Ok((lire_on_floor(blocks, Perturbation::Bottom)?, 10.0)),
        Some("shake") => {
            let (omega, mu) = (number(2)?, number(3)?);
            let t_end = if args.len() > 4 { number(4)? } else { 20.0 };
            let shaking = Shaking {
                blocks,
                amplitude: 0.2,
                omega,
                periods: t_end * omega / (2.0 * PI),
                steps_per_period: 200.0,
                mu,
                start_with_base: false,
            };
            Ok((shaking_column(&shaking)?, t_end))
        }
        _ => Err("the first argument is `lire` or `shake`".into()),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let hard = hard_from_args(&mut args)?;
    let (scene, t_end) = scene_from_args(&args)?;
    if let Some(n) = hard {
        println!("steps of {n} linear solves or more:");
    }
    let options = stepper_options(&scene, &RunOptions::default())?;
    let (mut corners, mut stepper) = CornerStepping::start_scene(&scene, options)?;
    let (mut solves, mut evaluations) = (Histogram::default(), Histogram::default());
    let (mut steps, mut retried, mut retried_solves) = (0, 0, 0);
    let mut run_seconds = 0.0;
    while stepper.state().t < t_end - 1e-9 {
        let (solves_before, evaluations_before) =
            (stepper.linear_solves(), stepper.newton_work().evaluations);
        let (t0, by_stage_before) = (stepper.state().t, stepper.solves_by_stage());
        let clock = Instant::now();
        if let Err(e) = corners.step(&scene, &mut stepper, 1e-8) {
            println!("stopped: {e}");
            break;
        }
        let seconds = clock.elapsed().as_secs_f64();
        run_seconds += seconds;
        let step_solves = stepper.linear_solves() - solves_before;
        let step_evaluations = stepper.newton_work().evaluations - evaluations_before;
        solves.add(step_solves, seconds);
        evaluations.add(step_evaluations, seconds);
        if let (Some(n), Some(stats)) = (hard, stepper.last_step()) {
            if step_solves >= n {
                let after = stepper.solves_by_stage();
                print_hard_step(t0, stats, by_stage_before, after, step_evaluations);
            }
        }
        steps += 1;
        if stepper.last_step().is_some_and(|s| s.retries > 0) {
            retried += 1;
            retried_solves += step_solves;
        }
    }
    println!(
        "{steps} steps, {} linear solves, {} evaluations, {:.1} µs per step; {retried} steps \
         whose first attempt failed took {retried_solves} of the linear solves",
        stepper.linear_solves(),
        stepper.newton_work().evaluations,
        1e6 * run_seconds / f64::from(steps.max(1))
    );
    solves.print("linear solves", run_seconds);
    evaluations.print("evaluations", run_seconds);
    Ok(())
}
