//! Islands (docs/method.md §7, "Islands"): a pile at rest on the floor beside blocks that
//! move is solved once per step, by one evaluation, and left out of the linear solves of
//! the moving blocks' updates; the motion is the one the whole system's solve gives.

use blockstack::{simulate, BlockPose, RunOptions, Scene, StepRecord};

/// Two blocks standing on a base shaken at 2 Hz, and away from it a pile of three blocks
/// lying at rest on the floor.
const SHAKEN_BESIDE_A_PILE: &str = r#"
[base]
width = 1.0
height = 0.1
motion = "harmonic"
amplitude = 0.05
omega = 12.566370614359172

[[blocks]]
width = 0.2
height = 0.4
x = 0.0
y = 0.25
[[blocks]]
width = 0.2
height = 0.4
x = 0.0
y = 0.65
[[blocks]]
width = 0.2
height = 0.4
x = -1.6
y = 0.05
theta = 1.5707963267948966
[[blocks]]
width = 0.2
height = 0.4
x = -1.2
y = 0.05
theta = 1.5707963267948966
[[blocks]]
width = 0.2
height = 0.4
x = -1.4
y = 0.25
theta = 1.5707963267948966

[contact]
mu = 0.3

[solver]
dt = 0.005
t_end = 2

[floor]
"#;

/// Every step's poses of a run with the islands option `on` or off.
fn run(scene: &Scene, on: bool) -> (blockstack::RunSummary, Vec<Vec<BlockPose>>) {
    let options = RunOptions {
        tuning: vec![format!("newton.islands={on}")],
        ..RunOptions::default()
    };
    let mut poses = Vec::new();
    let summary = simulate(scene, &options, |r: &StepRecord| {
        poses.push(r.poses.clone());
    })
    .expect("the run succeeds");
    (summary, poses)
}

fn distance(a: &[BlockPose], b: &[BlockPose]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| [p.x - q.x, p.y - q.y, p.theta - q.theta])
        .fold(0.0, |m, d| m.max(d.abs()))
}

#[test]
fn a_pile_at_rest_beside_moving_blocks_is_left_out_of_their_solves_and_moves_alike() {
    let scene = Scene::from_toml(SHAKEN_BESIDE_A_PILE).expect("the scene loads");
    let (with, with_poses) = run(&scene, true);
    let (without, without_poses) = run(&scene, false);
    // The shaken blocks move, so most steps need updates, and in them the pile was
    // solved at the first iterate.
    assert!(without.linear_solves > 100, "{}", without.linear_solves);
    assert!(
        with.newton_work.fixed_islands * 2 > without.newton_work.exact_updates / 4,
        "islands fixed in {} attempts, {} exact updates",
        with.newton_work.fixed_islands,
        without.newton_work.exact_updates
    );
    assert_eq!(without.newton_work.fixed_islands, 0);
    // The same motion, step by step, to the solver's tolerance (10⁻¹⁰ on impulses,
    // accumulated over 400 steps).
    assert_eq!(with_poses.len(), without_poses.len());
    let worst = with_poses
        .iter()
        .zip(&without_poses)
        .map(|(a, b)| distance(a, b))
        .fold(0.0, f64::max);
    assert!(worst < 1e-8, "the runs differ by {worst:e}");
    // The pile stays exactly where it lay.
    let start = scene.initial_coordinates();
    for (k, pose) in with.final_poses.iter().enumerate().skip(2) {
        let moved = (pose.x - start[3 * k]).abs() + (pose.y - start[3 * k + 1]).abs();
        assert!(moved < 1e-12, "block {k} moved by {moved:e}");
    }
    assert!(with.deepest.penetration.depth < 1e-9, "{:?}", with.deepest);
}
