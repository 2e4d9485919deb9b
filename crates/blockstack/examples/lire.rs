//! The Leaning Tower of Lire (§4.3, Figure 4.4): run the three perturbations and print
//! what happens to each block.
//!
//! `cargo run --release -p blockstack --example lire`

use blockstack::scenarios::{lire, Perturbation};
use blockstack::{simulate, BlockError, RunOptions};

fn main() -> Result<(), BlockError> {
    for p in [Perturbation::None, Perturbation::Top, Perturbation::Bottom] {
        let scene = lire(4, p)?;
        let opts = RunOptions {
            explore_branches: true,
            ..RunOptions::default()
        };
        let s = simulate(&scene, &opts, |_| {})?;
        println!(
            "{p:?}: {} steps, failure at {:?}, opening at {:?}, min gap {:.1e}, error: {}",
            s.steps,
            s.failure_time,
            s.opening_time,
            s.min_gap,
            s.error
                .as_ref()
                .map_or_else(|| "none".to_owned(), ToString::to_string)
        );
        for (k, b) in s.final_poses.iter().enumerate() {
            println!(
                "  block {}: x = {:.4}, y = {:.4}, theta = {:.4}",
                k + 1,
                b.x,
                b.y,
                b.theta
            );
        }
    }
    Ok(())
}
