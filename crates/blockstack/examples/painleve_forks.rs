//! A block sliding on one corner (App. I), at angles θ from −1.5 to 1.5 rad, sliding
//! either way, μ = 2, with the corner's free normal acceleration A = 0.5 g: where
//! B < 0 the contact problem has two solutions (contact or lift-off). Explored with the
//! flip probe and each fork checked against refinement, it prints, per case, B, the
//! forks found and their labels.
//!
//! `cargo run --release -p blockstack --example painleve_forks [mu]`
use blockstack::exploration::{explore_scene, fork_records, ForkRecord, WalkSettings};
use blockstack::scenarios::PainleveCorner;
use blockstack::RunOptions;
use nsga::explore::ExploreOptions;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mu: f64 = std::env::args().nth(1).map_or(Ok(2.0), |a| a.parse())?;
    let run = RunOptions {
        probe_flips: true,
        ..RunOptions::default()
    };
    let settings = WalkSettings {
        sample_every: 1,
        classify: true,
        ..WalkSettings::default()
    };
    println!("theta  slip  spin      B  forks  labels");
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
                let scene = case.scene()?;
                let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings)?;
                let forks = fork_records(&tree, 1);
                let labels: Vec<&str> = forks.iter().map(ForkRecord::label).collect();
                println!(
                    "{:5.2} {slip:5.1} {spin_sign:5.1} {:6.2} {:6} {labels:?}",
                    case.theta,
                    case.response(),
                    forks.len()
                );
            }
        }
    }
    Ok(())
}
