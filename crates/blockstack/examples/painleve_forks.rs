//! A block sliding on one corner (App. I), at angles θ from −1.5 to 1.5 rad, sliding
//! either way, either spin, μ = 2 (or the argument), with the corner's free normal
//! acceleration A = 0.5 g: where B < 0 the first step has three solutions (sliding
//! contact with n = −A/B, jam, lift-off). Prints, per case, B, −A/B and each solution
//! the flip probe finds, with its mean normal force P_N/(mg Δt), then the counts.
//!
//! `cargo run --release -p blockstack --example painleve_forks [mu]`
use blockstack::studies::painleve::{corner_scan, CornerMotion};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mu: f64 = std::env::args().nth(1).map_or(Ok(2.0), |a| a.parse())?;
    println!("theta  slip  spin      B   -A/B  solutions (P_N/Δt)");
    let (mut paradoxes, mut all_three, mut forks) = (0, 0, 0);
    for c in corner_scan(mu)? {
        let found: Vec<String> = c
            .solutions
            .iter()
            .map(|s| format!("{} {:.4}", s.motion.name(), s.impulse))
            .collect();
        println!(
            "{:5.2} {:5.1} {:5.1} {:6.3} {:6.3}  {}",
            c.case.theta,
            c.case.slip,
            c.case.spin_sign,
            c.b,
            c.sliding_force,
            found.join(", ")
        );
        if c.b < 0.0 {
            paradoxes += 1;
            forks += usize::from(c.solutions.len() > 1);
            let motions = [
                CornerMotion::SlidingContact,
                CornerMotion::Jam,
                CornerMotion::LiftOff,
            ];
            all_three += usize::from(motions.iter().all(|&m| c.find(m).is_some()));
        }
    }
    println!("μ = {mu}: {paradoxes} cases with B < 0, {forks} with several solutions, {all_three} with all three");
    Ok(())
}
