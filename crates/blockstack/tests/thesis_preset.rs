//! `--preset thesis` (docs/exploration.md, "The thesis's algorithm"): the options it
//! sets, its finite-difference Jacobian against the exact one on a step of the stack,
//! and an exploration that branches where Newton fails.

use blockstack::exploration::thesis::{self, rho_inf_cycle, NEWTON_ITERATIONS, PROX};
use blockstack::exploration::{explore_scene, fork_records, WalkSettings};
use blockstack::scene_file::{SceneFile, THESIS_BASE_HEIGHT};
use blockstack::simulation::stepper_options;
use blockstack::stepping::CornerStepping;
use blockstack::system::StackSystem;
use blockstack::{simulate, RunOptions, Scene};
use nsga::explore::ExploreOptions;
use nsga::{BranchRule, JacobianChoice, Prox, RhoInfRetry, Stepper, THESIS_FD_EPSILON};

/// The built-in scene `name` as the thesis's code models it.
fn thesis_scene(name: &str) -> Scene {
    let text = blockstack::scenes::find(name).unwrap().toml;
    SceneFile::parse(text)
        .unwrap()
        .as_in_the_thesis_code()
        .to_scene()
        .unwrap()
}

/// The preset's run options for `scene`, to `t_end`.
fn thesis_run(scene: &Scene, t_end: f64) -> RunOptions {
    RunOptions {
        t_end: Some(t_end),
        ..thesis::run_options(RunOptions::default(), scene.solver.rho_inf)
    }
}

#[test]
fn the_thesis_preset_sets_what_it_says() {
    let scene = thesis_scene("abundance-author");
    assert!(scene.floor().is_none());
    assert_eq!(scene.base().height(), THESIS_BASE_HEIGHT);
    assert!(scene.neighbours_only());
    let plain = blockstack::scenes::find("abundance-author").unwrap();
    let plain = SceneFile::parse(plain.toml).unwrap().to_scene().unwrap();
    assert!(!plain.neighbours_only() && plain.floor().is_some());

    let run = thesis::run_options(RunOptions::default(), scene.solver.rho_inf);
    assert_eq!(run.prox, Some(Prox::Constant(PROX)));
    assert_eq!(run.branch_rule, BranchRule::Converged);
    let o = stepper_options(&scene, &run).unwrap();
    assert_eq!(o.prox, Prox::Constant(0.3));
    assert_eq!(o.newton.max_iter, 20);
    assert_eq!(NEWTON_ITERATIONS, 20);
    assert_eq!(o.newton.max_iter_per_contact, 0);
    assert_eq!(o.newton.line_search, 0);
    assert_eq!(o.newton.max_openings_per_update, 0);
    assert!(!o.newton.predict_start && !o.newton.prune_open_contacts);
    assert_eq!(
        o.linear.jacobian,
        JacobianChoice::FiniteDifference(THESIS_FD_EPSILON)
    );
    assert_eq!(THESIS_FD_EPSILON, 1e-6);
    assert!(!o.linear.reuse_factorization && !o.linear.low_rank_updates);
    let p = &o.policy;
    assert_eq!(p.retry_max_iter, 20);
    assert_eq!(p.rho_inf_retry, RhoInfRetry::SingularMatrix);
    assert_eq!(p.rho_inf_retries, rho_inf_cycle(0.5));
    assert_eq!(p.rho_inf_retries.len(), 20);
    for (a, b) in p.rho_inf_retries.iter().zip(&p.rho_inf_retries[1..]) {
        let step = b - a;
        assert!(
            (step - 0.05).abs() < 1e-12 || (*a, *b) == (1.0, 0.0),
            "{a} -> {b}"
        );
    }
    assert!(p.branch_trials && p.branch_on_any_failure && p.continue_inconsistent);
    assert_eq!(p.branch_rule, BranchRule::Converged);
    assert!(!p.retry_without_friction_shift && !p.last_resort);
    assert_eq!(p.max_halvings, 0);
    assert!(thesis::walk_settings(WalkSettings::default()).stop_at_failure);
}

/// Figure 4.5's column as the author's scripts shake it, stepped 60 times under the
/// preset: the base drags the bottom block, which slides, and the column rocks.
fn shaken_column() -> Stepper<StackSystem> {
    let scene = thesis_scene("abundance-author");
    let run = thesis::run_options(RunOptions::default(), scene.solver.rho_inf);
    let options = stepper_options(&scene, &run).unwrap();
    let (mut corners, mut stepper) = CornerStepping::start_scene(&scene, options).unwrap();
    for _ in 0..60 {
        corners.step(&scene, &mut stepper, 1e-6).unwrap();
    }
    assert!(stepper.last_step().unwrap().sets.a.iter().any(|&a| a));
    stepper
}

/// The next step's residual at `x` for the last step's sets, and its Jacobian (dense, in
/// the unknowns x) with `jacobian`.
fn newton_system(
    stepper: &mut Stepper<StackSystem>,
    x: &[f64],
    jacobian: JacobianChoice,
) -> (Vec<f64>, nalgebra::DMatrix<f64>) {
    let mut options = stepper.options().clone();
    options.linear.jacobian = jacobian;
    stepper.set_options(options).unwrap();
    let sets = stepper.last_step().unwrap().sets.clone();
    let rho = stepper.options().rho_inf;
    stepper.newton_system(x, &sets, rho, false)
}

/// The largest difference of `a` and `b`, relative to 1 + |b|, entry by entry.
fn relative_difference(a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs() / (1.0 + y.abs()))
        .fold(0.0, f64::max)
}

#[test]
fn the_finite_difference_jacobian_agrees_with_the_exact_one_on_a_blocks_step() {
    let mut stepper = shaken_column();
    // Off the last solution (x plus 10⁻³ times a fixed pattern): there the interfaces
    // lie flat, where the residual has a kink (the next test).
    let x: Vec<f64> = stepper
        .state()
        .x
        .iter()
        .enumerate()
        .map(|(i, v)| v + 1e-3 * ((i as f64 * 1.7).sin() + 0.3))
        .collect();
    let fd = newton_system(&mut stepper, &x, JacobianChoice::FiniteDifference(1e-6)).1;
    let exact = newton_system(&mut stepper, &x, JacobianChoice::Exact).1;
    assert!(exact.amax() > 1.0, "{}", exact.amax());
    let worst = relative_difference(&fd, &exact);
    assert!(worst <= 1e-5, "largest relative difference {worst:e}");
    assert!(worst > 0.0, "the two matrices are formed differently");
}

#[test]
fn at_a_flat_interface_the_differences_take_the_other_side_of_a_kink() {
    // At the solution two interfaces lie flat and stick: the slip's corner changes
    // with the sign of the blocks' relative rotation. The forward difference takes the
    // derivative on the +ε side; the exact matrix is the derivative on the other side,
    // as a backward difference shows.
    let mut stepper = shaken_column();
    let x = stepper.state().x.clone();
    let (r, fd) = newton_system(&mut stepper, &x, JacobianChoice::FiniteDifference(1e-6));
    let exact = newton_system(&mut stepper, &x, JacobianChoice::Exact).1;
    let h = 1e-6;
    let mut kinks = 0;
    for c in 0..x.len() {
        let mut back = x.clone();
        back[c] -= h;
        let (r_back, _) = newton_system(&mut stepper, &back, JacobianChoice::Exact);
        for row in 0..x.len() {
            let (f, e) = (fd[(row, c)], exact[(row, c)]);
            if (f - e).abs() <= 1e-5 * (1.0 + e.abs()) {
                continue;
            }
            kinks += 1;
            let backward = (r[row] - r_back[row]) / h;
            assert!(
                (backward - e).abs() <= 1e-5 * (1.0 + e.abs()),
                "({row}, {c}): forward {f:e}, backward {backward:e}, exact {e:e}"
            );
        }
    }
    assert!(kinks > 0, "the flat interfaces make a kink");
}

#[test]
fn a_thesis_exploration_branches_where_newton_fails() {
    // The author's setting to t = 1.13: its first fork (about step 168).
    let scene = thesis_scene("abundance-author");
    let run = thesis_run(&scene, 1.13);
    let settings = thesis::walk_settings(WalkSettings {
        sample_every: 10,
        ..WalkSettings::default()
    });
    let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings).unwrap();
    let forks = fork_records(&tree, scene.n_interfaces());
    assert!(
        !forks.is_empty(),
        "the thesis's algorithm branches by t = 1.13"
    );
    let dt = scene.solver.dt;
    for f in &forks {
        // A branch point: Newton failed, every visited set was solved again, and each
        // converged solve became a branch starting at the end of the forking step.
        assert!(f.tried >= f.distinct && f.distinct >= 2, "{f:?}");
        assert!(f.followed && f.children.len() == f.distinct, "{f:?}");
        for &c in &f.children {
            let start = tree.branches[c].start.0;
            assert!((start - (f.t + dt)).abs() < 1e-9, "{start} vs {}", f.t);
        }
    }
    // The first fork: the step's solution, and a fixed-set solve beyond the friction
    // cone (docs/exploration.md, "What the thesis's abundance is").
    let f = &forks[0];
    assert_eq!(
        (f.distinct, f.consistent, f.breaking_laws()),
        (2, 1, 1),
        "{f:?}"
    );
    let cone = |c: &blockstack::contact_laws::ContactCheck| {
        c.broken.iter().any(|(law, _)| law.name() == "cone")
    };
    assert!(f.candidates.iter().any(cone), "{f:?}");
    // Without the re-solves, the run stops at the first fork's step: its Newton attempt
    // did not converge within 20 iterations, and its iterates did not cycle (a branch
    // point only by `policy.branch_on_any_failure`; docs/exploration.md).
    let first = forks[0].t;
    let mut plain = run.clone();
    plain.tuning.push("policy.branch_trials=false".into());
    let summary = simulate(&scene, &plain, |_| {}).unwrap();
    let e = summary.error.expect("the run stops").to_string();
    assert!(e.contains("did not converge"), "{e}");
    assert!(
        e.contains("2 index sets visited") && !e.contains("cycling"),
        "{e}"
    );
    assert!(
        e.contains(&format!("step from t = {first}")),
        "{e} (fork at {first})"
    );
}

#[test]
fn a_converged_solve_continues_a_step_that_has_no_self_consistent_one() {
    // Figure 4.5's column as the thesis states it (A = 1): at t = 0.0667 Newton fails
    // and no fixed-set solve is self-consistent; the author's code goes on with a
    // converged one, as the preset does.
    let scene = thesis_scene("abundance");
    let run = thesis_run(&scene, 0.1);
    let summary = simulate(&scene, &run, |_| {}).unwrap();
    assert!(summary.error.is_none(), "{:?}", summary.error);
    let mut strict = run.clone();
    strict
        .tuning
        .push("policy.continue_inconsistent=false".into());
    let summary = simulate(&scene, &strict, |_| {}).unwrap();
    let e = summary.error.expect("the strict run stops").to_string();
    assert!(e.contains("did not converge"), "{e}");
}
