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
    // Its blocks that come to rest before the whole tower does are held as islands.
    assert!(held.linear_solves <= solved.linear_solves);
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

/// Issue 62's resting islands (docs/method.md §8.2, "Islands at rest"): beside a base
/// that shakes for the whole run, the piles are never at rest as a whole system, but
/// each pile is an island at rest, held out of the solve from its first steps. Each
/// step is then one evaluation and no factorization, and the run ends where the run
/// that solves every step ends, to the solver's tolerance.
#[test]
fn piles_beside_a_shaken_base_are_held_as_islands_where_solving_keeps_them() {
    let toml = pile_with_base_motion("motion = \"harmonic\"\namplitude = 0.2\nomega = 2.0");
    let scene = Scene::from_toml(&toml).expect("a shaken base beside the piles");
    let held = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = simulate(&scene, &solving_every_step(), |_| {}).unwrap();
    assert_eq!(
        held.resting_steps, 0,
        "the base shakes: the system never rests"
    );
    let unheld = held.steps - held.held_island_steps as usize;
    assert!(unheld <= 10, "{unheld} steps without a held island");
    assert_eq!(held.island_wakes, 0);
    assert!(
        held.linear_solves * 10 < solved.linear_solves.max(10),
        "{} linear solves held, {} solved",
        held.linear_solves,
        solved.linear_solves
    );
    assert!(
        (held.newton_work.evaluations as usize) <= held.steps + 20,
        "{} evaluations in {} steps",
        held.newton_work.evaluations,
        held.steps
    );
    let tol = scene.solver.tol;
    assert!(apart(&held, &solved) < tol, "{:e}", apart(&held, &solved));
}

/// Issue 62's exactness on a pile a collapse leaves: a three-block column shaken at
/// ω = 8 (a run of the matrix of docs/method.md §8) falls off its base by t ≈ 3; its
/// blocks come to rest on the floor beside the base, which shakes on, and are held
/// there as islands. The run ends where the run that solves every step ends, to the
/// solver's tolerance (measured: 2·10⁻¹¹). Solved every step, the pile at rest converges
/// at each step's start, as held it is checked by one evaluation: holding it costs at
/// most one factorization more, at the step its islands are first held (the kept
/// factors were made with them in the solve), and no evaluation more. (Measured with
/// `rollstack blocks shake --blocks 3 --omega 8 --mu 0.5 --amplitude 0.2
/// --steps-per-period 200 --t-end 20 --json`, with and without `--tuning
/// policy.rest=false`: 462 linear solves and 10 871 evaluations both ways.) Where
/// holding saves the solves and evaluations of a pile, the test above asserts it.
#[test]
fn the_pile_a_shaken_column_leaves_is_held_beside_the_base() {
    let scene = blockstack::scenarios::shaking_column(&blockstack::scenarios::Shaking {
        blocks: 3,
        amplitude: 0.2,
        omega: 8.0,
        mu: 0.5,
        steps_per_period: 200.0,
        periods: 20.0 * 8.0 / std::f64::consts::TAU,
        start_with_base: false,
    })
    .expect("the shaken column");
    let held = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = simulate(&scene, &solving_every_step(), |_| {}).unwrap();
    assert!(
        held.failure_time.is_some_and(|t| t < 5.0),
        "the column falls"
    );
    assert_eq!(held.failure_time, solved.failure_time);
    assert!(
        held.held_island_steps > held.steps as u64 / 2,
        "{} held",
        held.held_island_steps
    );
    assert!(
        held.linear_solves <= solved.linear_solves + 1,
        "{} linear solves held, {} solved",
        held.linear_solves,
        solved.linear_solves
    );
    assert!(
        held.newton_work.evaluations <= solved.newton_work.evaluations,
        "{} evaluations held, {} solved",
        held.newton_work.evaluations,
        solved.newton_work.evaluations
    );
    let tol = scene.solver.tol;
    assert!(apart(&held, &solved) < tol, "{:e}", apart(&held, &solved));
}

/// A held island wakes where a body reaches it: a block dropped onto the three-block
/// pile joins its island before it lands, the pile returns to the solve, takes the
/// impact and comes to rest again. No block sinks into another, and the run ends where
/// the run that solves every step ends.
#[test]
fn a_block_dropped_onto_a_held_pile_wakes_it() {
    let toml = pile_with_base_motion("motion = \"harmonic\"\namplitude = 0.2\nomega = 2.0")
        + "\n[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = -1.25\ny = 1.0\ntheta = 1.5707963267948966\n";
    let scene = Scene::from_toml(&toml).expect("a block above the piles");
    let held = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = simulate(&scene, &solving_every_step(), |_| {}).unwrap();
    assert!(held.held_island_steps > held.steps as u64 / 2);
    let top = |run: &blockstack::RunSummary| run.final_poses[6].y;
    assert!(
        (top(&held) - 0.65).abs() < 1e-6,
        "the dropped block lies at y = {}",
        top(&held)
    );
    let depth = held.deepest.depth();
    assert!(depth < 1e-9, "sank by {depth:e}");
    let tol = scene.solver.tol;
    assert!(apart(&held, &solved) < tol, "{:e}", apart(&held, &solved));
}

/// A held island wakes where a force on it changes: a block lying at rest on a base
/// whose pulse starts at t = 1 s is held until then; at the pulse its contact rows
/// exceed the tolerance, the island returns to the solve, and the block rides the
/// pulse as in the run that solves every step, to the solver's tolerance: each step
/// leaves velocities within tol/m of an exact solution's (the U rows of eq. 127 are
/// impulses), so over the N steps of the one-second pulse two runs solved to the
/// tolerance part by at most (tol/m) Δt N²/2 (measured: 8·10⁻¹⁰, of a bound of
/// 3·10⁻⁹; with the tolerance at 10⁻¹², both runs agree to 10⁻¹⁴).
#[test]
fn a_block_held_on_a_base_wakes_when_the_base_moves() {
    let toml = pile_with_base_motion(
        "[base.x]\nmotion = \"pulse\"\nshape = \"one-sine\"\namplitude = 0.5\nperiod = 1.0\nstart = 1.0",
    ) + "\n[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = 0.0\ny = 0.15\ntheta = 1.5707963267948966\n";
    let scene = Scene::from_toml(&toml).expect("a block on a pulsed base");
    let held = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    let solved = simulate(&scene, &solving_every_step(), |_| {}).unwrap();
    assert!(held.island_wakes >= 1, "{} wakes", held.island_wakes);
    let pulse = (1.0 / scene.solver.dt).floor() as u64;
    assert!(
        held.held_island_steps >= pulse - 10,
        "{} held steps",
        held.held_island_steps
    );
    let rider = |run: &blockstack::RunSummary| run.final_poses[6].x;
    assert!(
        rider(&held) > 0.05,
        "the block rode the pulse to x = {}",
        rider(&held)
    );
    let (tol, dt) = (scene.solver.tol, scene.solver.dt);
    let (m, n) = (scene.blocks()[6].mass(), 1.0 / dt);
    let bound = tol / m * dt * n * n / 2.0;
    assert!(
        apart(&held, &solved) < bound,
        "{:e} of {bound:e}",
        apart(&held, &solved)
    );
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
