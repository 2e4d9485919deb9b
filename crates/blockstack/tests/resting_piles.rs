//! Piles at rest on the floor (`examples/scenes/pile-at-rest.toml`, the scene of the bench
//! `islands_pile_at_rest`): nothing moves, and no step needs a Newton update.

use blockstack::{simulate, RunOptions, Scene};

#[test]
fn piles_at_rest_stay_put_without_a_newton_update() {
    let scene = Scene::from_toml(include_str!("../../../examples/scenes/pile-at-rest.toml"))
        .expect("the example scene loads");
    let start = scene.initial_coordinates();
    let run = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    assert!(run.steps > 1000, "{} steps", run.steps);
    assert_eq!(run.linear_solves, 0, "a resting pile factorizes nothing");
    let end = run.final_poses.iter().flat_map(|p| [p.x, p.y, p.theta]);
    let moved = start
        .iter()
        .zip(end)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(moved < 1e-12, "moved by {moved:e}");
}
