//! Repeats ball case 1 (for profiling): `cargo run -p nsga --release --example ball_profile`.

use nsga::studies::ball::{run_ball, Scheme};
use nsga::systems::ball::BallCase;
use nsga::Prox;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let c = BallCase::new(1)?;
    let mut best = f64::INFINITY;
    for _ in 0..200 {
        let r = run_ball(&c, Scheme::Nsga, 2e-3, 0.5, Prox::Scaled(1.0))?;
        best = best.min(r.wall_time_s);
    }
    println!(
        "ball case 1, 750 steps: best of 200 runs {:.3} ms",
        best * 1e3
    );
    Ok(())
}
