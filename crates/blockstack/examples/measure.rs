//! The "Measure it": failed Newton steps and branch points of the Lire collapse
//! (as in the thesis, and on a floor) and of one shaking run with the thesis's constant r = 0.3 and with the scaled prox
//! (docs/method.md §4), plus the long rest test (a column of 10 blocks, 10⁴ steps).
//!
//! `cargo run --release -p blockstack --example measure`

use blockstack::scenarios::{
    lire, lire_on_floor, resting_column, shaking_column, Perturbation, Shaking,
};
use blockstack::{simulate, BlockError, Prox, RunOptions, RunSummary, Scene};

fn report(name: &str, scene: &Scene, prox: Prox) -> Result<RunSummary, BlockError> {
    let opts = RunOptions {
        prox: Some(prox),
        explore_branches: true,
        ..RunOptions::default()
    };
    let s = simulate(scene, &opts, |_| {})?;
    let distinct: usize = s.branch_points.iter().filter(|b| b.distinct > 1).count();
    println!(
        "{name:<28} {prox:<16} steps {:>5}  failed Newton steps {:>3}  branch points {:>3} \
         (with >1 distinct state {distinct})  mean its {:.2}  solver {:.1} ms  error: {}",
        s.steps,
        s.failed_steps,
        s.branch_points.len(),
        s.newton_iterations_mean,
        1e3 * s.wall_time_s,
        s.error
            .as_ref()
            .map_or_else(|| "none".to_owned(), ToString::to_string),
        prox = format!("{prox:?}"),
    );
    Ok(s)
}

fn main() -> Result<(), BlockError> {
    let collapse = lire(4, Perturbation::Bottom)?;
    let landing = lire_on_floor(4, Perturbation::Bottom)?;
    let shaking = shaking_column(&Shaking::default())?;
    for prox in [Prox::Constant(0.3), Prox::Scaled(1.0)] {
        report("Lire collapse (bottom)", &collapse, prox)?;
        report("Lire collapse on a floor", &landing, prox)?;
        report("shaking A=0.2 omega=2", &shaking, prox)?;
    }
    // A column of 10 blocks at rest for 10⁴ steps.
    let column = resting_column(10, 100.0)?;
    let q0 = column.initial_coordinates();
    let mut drift = 0.0f64;
    let mut chatter = 0.0f64;
    let s = simulate(&column, &RunOptions::default(), |r| {
        for (k, p) in r.poses.iter().enumerate() {
            drift = drift
                .max((p.x - q0[3 * k]).abs())
                .max((p.y - q0[3 * k + 1]).abs())
                .max(p.theta.abs());
        }
        for (k, f) in r.forces.iter().enumerate() {
            let weight = (10 - k) as f64;
            chatter = chatter.max((f.normal[0] + f.normal[1] - weight).abs());
        }
    })?;
    println!(
        "10-block column at rest: {} steps, max drift {drift:.2e}, max |sum lambda_N - weight| \
         {chatter:.2e}, min gap {:.2e}, max energy increase {:.2e}, error: {}",
        s.steps,
        s.min_gap,
        s.max_energy_increase,
        s.error
            .as_ref()
            .map_or_else(|| "none".to_owned(), ToString::to_string)
    );
    Ok(())
}
