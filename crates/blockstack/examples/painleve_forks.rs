//! A block sliding on one corner (App. I), at angles θ from −1.5 to 1.5 rad, sliding
//! either way, either spin, μ = 2 (or the argument), with the corner's free normal
//! acceleration A = 0.5 g: where B < 0 the first step has three solutions (sliding
//! contact with n = −A/B, jam, lift-off). Prints, per case, B, −A/B and each solution
//! the flip probe finds, with its mean normal force P_N/(mg Δt), then the counts.
//!
//! `cargo run --release -p blockstack --example painleve_forks [mu]`
use blockstack::scenarios::PainleveCorner;
use blockstack::studies::painleve::{corner_solutions, CornerMotion};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mu: f64 = std::env::args().nth(1).map_or(Ok(2.0), |a| a.parse())?;
    println!("theta  slip  spin      B   -A/B  solutions (P_N/Δt)");
    let (mut paradoxes, mut all_three, mut forks) = (0, 0, 0);
    for i in -30..=30 {
        for slip in [-0.5, 0.5] {
            for spin_sign in [-1.0, 1.0] {
                let case = PainleveCorner {
                    theta: f64::from(i) * 0.05,
                    mu,
                    slip,
                    spin_sign,
                    ..PainleveCorner::default()
                };
                let b = case.response();
                let solutions = corner_solutions(&case)?;
                let found: Vec<String> = solutions
                    .iter()
                    .map(|s| format!("{} {:.4}", s.motion.name(), s.impulse))
                    .collect();
                println!(
                    "{:5.2} {slip:5.1} {spin_sign:5.1} {b:6.3} {:6.3}  {}",
                    case.theta,
                    -case.free_acceleration / b,
                    found.join(", ")
                );
                if b < 0.0 {
                    paradoxes += 1;
                    forks += usize::from(solutions.len() > 1);
                    let has = |m| solutions.iter().any(|s| s.motion == m);
                    all_three += usize::from(
                        has(CornerMotion::SlidingContact)
                            && has(CornerMotion::Jam)
                            && has(CornerMotion::LiftOff),
                    );
                }
            }
        }
    }
    println!("μ = {mu}: {paradoxes} cases with B < 0, {forks} with several solutions, {all_three} with all three");
    Ok(())
}
