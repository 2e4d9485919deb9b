//! The step at which a tall column moving with its base starts to tip, solved two ways
//! (docs/method.md §8.2, tall columns).
//!
//! A column of n blocks on x = 0.001 sin 2t that starts moving with its base tips once
//! the base acceleration 0.004 sin 2t exceeds g w/(h n) = 0.5/n. At Δt ≈ 0.001 the base
//! interface lifts one corner and the column turns as one body, one Newton update per
//! step. At Δt ≈ 0.01 the free semismooth Newton iteration of the first tipping step
//! wanders through hundreds of updates to another solution of the step: the lower part
//! turns about the base corner, about 30 interfaces in the middle open a corner, and the
//! upper part is tilted as a whole. This example takes the column to the step before,
//! then solves the tipping step
//!
//! - freely (plain semismooth Newton),
//! - with the previous step's index sets and one corner of the base interface open at
//!   every level (A, B, C), as the statics say, and
//! - as `Stepper::step` takes it: for a column this tall, the held-sets attempt first
//!   (the previous step's sets held, then one opening per update; docs/method.md §8.2),
//!
//! and prints, for each, the updates, the largest block angle, the interfaces with a
//! lifted corner and, for the first two, whether the solution is self-consistent (the
//! sets recomputed from it are the ones it was solved with); for the free iteration also
//! the interfaces its sets open on position level along the way. Run with
//! `cargo run --release -p blockstack --example tipping_onset [BLOCKS]` (default 300).

use blockstack::scenarios::{shaking_column, Shaking};
use blockstack::simulation::stepper_options;
use blockstack::stepping::CornerStepping;
use blockstack::RunOptions;
use nsga::IndexSets;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = match std::env::args().nth(1) {
        Some(a) => a.parse().map_err(|e| format!("BLOCKS '{a}': {e}"))?,
        None => 300,
    };
    let column = Shaking::tall_column(n, true);
    let scene = shaking_column(&column)?;
    let dt = scene.solver.dt;
    // The statics: the base interface lifts a corner once A ω² sin ωt > g w/(h n).
    let block = scene.size(1);
    let limit = scene.solver.gravity * block.width / (block.height * n as f64);
    let peak = column.amplitude * column.omega.powi(2);
    if limit >= peak {
        return Err(format!("a column of {n} blocks does not tip on this base").into());
    }
    let onset = (limit / peak).asin() / column.omega;
    let tipping_step = (onset / dt).ceil() as usize;
    let options = stepper_options(&scene, &RunOptions::default())?;
    let rho_inf = options.rho_inf;
    // The two gaps of interface k are normal contacts 2k and 2k + 1 (blockstack::stack);
    // interface 0 is the base's.
    let base_corners = [0, 1];
    // Stepped as a run steps it: the broad phase decides once per step whether each
    // interface holds its contact (docs/contacts.md). A bare system decides it at every
    // Newton iterate instead, and the free iteration of the tipping step then cycles
    // without converging.
    let (mut corners, mut stepper) = CornerStepping::start_scene(&scene, options)?;
    let mut before = None;
    for _ in 1..tipping_step {
        corners.step(&scene, &mut stepper, 1e-8)?;
        before = stepper.last_step().map(|s| s.sets.clone());
    }
    let before = before.ok_or("the column tips in its first step")?;
    println!(
        "{n} blocks, Δt = {dt:.5}: statics put the onset at t = {onset:.4}, \
         solving the step to t = {:.4}",
        dt * tipping_step as f64
    );
    let mut report = |name: &str, fixed: Option<&IndexSets>| match stepper.trial(fixed, rho_inf) {
        Ok(trial) => {
            if fixed.is_none() {
                print_path(&trial.visited, n);
            }
            let sets = stepper.sets_of(&trial.state.x, rho_inf);
            let consistent = *fixed.unwrap_or(&trial.stats.sets) == sets;
            let tilt = (0..n).map(|k| trial.state.q[3 * k + 2].abs());
            let lifted: Vec<usize> = (0..n)
                .filter(|&k| (0..2).any(|c| !sets.c[2 * k + c]))
                .collect();
            println!(
                "{name}: {} updates, largest |θ| {:.2e}, self-consistent {consistent}, \
                     {} interfaces with a lifted corner: {}",
                trial.stats.iterations,
                tilt.fold(0.0, f64::max),
                lifted.len(),
                summarize(&lifted)
            );
        }
        Err(e) => println!("{name}: no solution found ({e})"),
    };
    report("free Newton", None);
    for corner in base_corners {
        let mut sets = before.clone();
        (sets.a[corner], sets.b[corner], sets.c[corner]) = (false, false, false);
        report(&format!("base corner {corner} open"), Some(&sets));
    }
    let solves = stepper.linear_solves();
    let stats = stepper.step()?.clone();
    let q = &stepper.state().q;
    let tilt = (0..n).map(|k| q[3 * k + 2].abs()).fold(0.0, f64::max);
    let lifted: Vec<usize> = (0..n)
        .filter(|&k| (0..2).any(|c| !stats.sets.c[2 * k + c]))
        .collect();
    println!(
        "Stepper::step: {} updates, {} linear solves, largest |θ| {tilt:.2e}, \
         {} interfaces with a lifted corner: {}",
        stats.iterations,
        stepper.linear_solves() - solves,
        lifted.len(),
        summarize(&lifted)
    );
    Ok(())
}

/// The interfaces with a corner open on position level (not in A) in the first sets the
/// free iteration visits, then in every 50th: where its updates go.
fn print_path(visited: &[IndexSets], n: usize) {
    for (i, v) in visited.iter().enumerate() {
        if i < 4 || i % 50 == 0 {
            let open: Vec<usize> = (0..n).filter(|&k| !v.a[2 * k] || !v.a[2 * k + 1]).collect();
            println!(
                "  sets {i:>3}: corners open in A at interfaces {}",
                summarize(&open)
            );
        }
    }
}

/// "0, 146-170, 172-173": runs of consecutive interfaces.
fn summarize(k: &[usize]) -> String {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &i in k {
        match runs.last_mut() {
            Some((_, end)) if *end + 1 == i => *end = i,
            _ => runs.push((i, i)),
        }
    }
    let text: Vec<String> = runs
        .iter()
        .map(|&(a, b)| {
            if a == b {
                a.to_string()
            } else {
                format!("{a}-{b}")
            }
        })
        .collect();
    text.join(", ")
}
