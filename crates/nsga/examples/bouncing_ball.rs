//! The paper's rotating bouncing ball, all four cases, with NSGA and Moreau–Jean.
//!
//! `cargo run -p nsga --release --example bouncing_ball`

use nsga::studies::ball::{run_ball, Scheme};
use nsga::systems::ball::BallCase;
use nsga::Prox;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for case in 1..=4 {
        let c = BallCase::new(case)?;
        for scheme in [Scheme::Nsga, Scheme::Moreau] {
            let r = run_ball(&c, scheme, 2e-3, 0.5, Prox::Scaled(1.0))?;
            println!(
                "case {case} {scheme:?}: first impact {:?}, rolling from {:?}, rest {:?}, final (xdot, phidot) = ({:.5}, {:.4}), min gap {:.3e}, mean Newton {:.2}, {:.3} ms",
                r.first_impact_time,
                r.rolling_onset_time,
                r.rest_time,
                r.final_velocity[0],
                r.final_velocity[1],
                r.min_gap,
                r.newton_iterations_mean,
                r.wall_time_s * 1e3
            );
        }
    }
    Ok(())
}
