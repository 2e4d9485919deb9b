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

/// The first steps find the piles at rest (docs/method.md §8.2, "At rest"): the run
/// evaluates the step's equations in a handful of steps, not in each, and ends where
/// the run that solves every step ends.
#[test]
fn piles_at_rest_are_held_without_solving_where_solving_keeps_them() {
    let scene = Scene::from_toml(include_str!("../../../examples/scenes/pile-at-rest.toml"))
        .expect("the example scene loads");
    let held = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = simulate(&scene, &solving_every_step(), |_| {}).unwrap();
    assert_eq!(held.steps, solved.steps);
    // At rest within the first ten steps, and from then on not evaluated.
    let solved_steps = held.steps - held.resting_steps as usize;
    assert!(solved_steps <= 10, "{solved_steps} steps solved");
    assert_eq!(held.newton_work.evaluations as usize, solved_steps);
    assert_eq!(solved.resting_steps, 0);
    assert_eq!(solved.newton_work.evaluations as usize, solved.steps);
    assert!(apart(&held, &solved) < 1e-12, "{:e}", apart(&held, &solved));
}

/// Issue 62's exactness, on a pile a collapse leaves: the Lire tower topples onto the
/// floor and comes to rest leaning on itself by t ≈ 12; held at rest from then on, it
/// ends where the run that solves every step ends, to the solver's tolerance (that run
/// drifts by the round-off its velocities keep), with a third fewer evaluations.
#[test]
fn a_collapsed_tower_held_at_rest_ends_where_solving_every_step_ends() {
    let scene =
        blockstack::scenarios::lire_on_floor(4, blockstack::scenarios::Perturbation::Bottom)
            .expect("the Lire tower on a floor");
    let t_end = Some(30.0);
    let held = simulate(
        &scene,
        &RunOptions {
            t_end,
            ..RunOptions::default()
        },
        |_| {},
    )
    .unwrap();
    let solved = simulate(
        &scene,
        &RunOptions {
            t_end,
            ..solving_every_step()
        },
        |_| {},
    )
    .unwrap();
    assert!(
        held.resting_steps > 1000,
        "{} resting steps",
        held.resting_steps
    );
    assert_eq!(held.linear_solves, solved.linear_solves);
    assert!(held.newton_work.evaluations < solved.newton_work.evaluations * 9 / 10);
    let tol = scene.solver.tol;
    assert!(apart(&held, &solved) < tol, "{:e}", apart(&held, &solved));
}

/// A shaken base never stands still: no step is held.
#[test]
fn a_pile_on_a_shaken_base_is_solved_every_step() {
    let toml = pile_with_base_motion("motion = \"harmonic\"\namplitude = 0.0\nomega = 2.0");
    let still = Scene::from_toml(&toml).expect("a harmonic base of zero amplitude");
    let run = simulate(&still, &RunOptions::default(), |_| {}).unwrap();
    assert!(
        run.resting_steps > 0,
        "a harmonic motion of zero amplitude stands still"
    );
    let shaken = Scene::from_toml(&toml.replace("amplitude = 0.0", "amplitude = 1e-9"))
        .expect("a harmonic base");
    let run = simulate(&shaken, &RunOptions::default(), |_| {}).unwrap();
    assert_eq!(run.resting_steps, 0);
}

/// A base that will move is not standing still: the piles beside it are solved every
/// step until its pulse is over, and held at rest after it.
#[test]
fn piles_beside_a_pulsed_base_are_held_only_once_the_pulse_is_over() {
    let toml = pile_with_base_motion(
        "[base.x]\nmotion = \"pulse\"\nshape = \"one-sine\"\namplitude = 0.5\nperiod = 1.0\nstart = 1.0",
    );
    let scene = Scene::from_toml(&toml).expect("a pulsed base");
    let run = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = run.steps - run.resting_steps as usize;
    let pulse_over = (2.0 / scene.solver.dt).floor() as usize;
    assert!(
        solved >= pulse_over,
        "{solved} steps solved, the pulse ends at step {pulse_over}"
    );
    assert!(solved <= pulse_over + 10, "{solved} steps solved");
}

/// The piles' scene with its fixed base's motion replaced by the TOML `lines`.
fn pile_with_base_motion(lines: &str) -> String {
    include_str!("../../../examples/scenes/pile-at-rest.toml").replace("motion = \"fixed\"", lines)
}

fn solving_every_step() -> RunOptions {
    RunOptions {
        tuning: vec!["policy.rest=false".into()],
        ..RunOptions::default()
    }
}

/// The largest difference between the final coordinates of two runs.
fn apart(a: &blockstack::RunSummary, b: &blockstack::RunSummary) -> f64 {
    a.final_poses
        .iter()
        .zip(&b.final_poses)
        .flat_map(|(p, q)| [p.x - q.x, p.y - q.y, p.theta - q.theta])
        .fold(0.0, |m: f64, d| m.max(d.abs()))
}
