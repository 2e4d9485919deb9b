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
    assert!(!p.retry_without_friction_shift && !p.boundary_resolves && !p.last_resort);
    assert_eq!(p.max_halvings, 0);
    assert!(thesis::walk_settings(WalkSettings::default()).stop_at_failure);
}

/// The scaled residual's Jacobian (dense, in the unknowns x) of the next step for the
/// last step's sets, with `jacobian`, at its unknowns moved off the last solution (`x`
/// plus 10⁻³ times a fixed pattern): at the solution the interfaces lie flat, where the
/// slip's point switches corners and the residual has a kink (see the test below).
fn jacobian_near_last_step(
    stepper: &mut Stepper<StackSystem>,
    jacobian: JacobianChoice,
) -> nalgebra::DMatrix<f64> {
    let mut options = stepper.options().clone();
    options.linear.jacobian = jacobian;
    stepper.set_options(options).unwrap();
    let sets = stepper.last_step().unwrap().sets.clone();
    let x: Vec<f64> = stepper
        .state()
        .x
        .iter()
        .enumerate()
        .map(|(i, v)| v + 1e-3 * ((i as f64 * 1.7).sin() + 0.3))
        .collect();
    let rho = stepper.options().rho_inf;
    stepper.newton_system(&x, &sets, rho, false).1
}

#[test]
fn the_finite_difference_jacobian_agrees_with_the_exact_one_on_a_blocks_step() {
    // Figure 4.5's column as the author's scripts shake it, 60 steps in: the base
    // drags the bottom block, which slides, and the column rocks on its corners.
    let scene = thesis_scene("abundance-author");
    let run = thesis::run_options(RunOptions::default(), scene.solver.rho_inf);
    let options = stepper_options(&scene, &run).unwrap();
    let (q0, u0) = (scene.initial_coordinates(), scene.initial_velocities());
    let mut system = StackSystem::new(scene.clone());
    let mut corners = CornerStepping::default();
    corners.start(&mut system, &q0, &u0, options.dt);
    let mut stepper = Stepper::new(system, 0.0, &q0, &u0, options).unwrap();
    for _ in 0..60 {
        corners.step(&scene, &mut stepper, 1e-6).unwrap();
    }
    let sets = &stepper.last_step().unwrap().sets;
    assert!(sets.a.iter().any(|&a| a), "contacts are closed");
    let fd = jacobian_near_last_step(&mut stepper, JacobianChoice::FiniteDifference(1e-6));
    let exact = jacobian_near_last_step(&mut stepper, JacobianChoice::Exact);
    assert!(exact.amax() > 1.0, "{}", exact.amax());
    let mut worst: f64 = 0.0;
    for (f, e) in fd.iter().zip(exact.iter()) {
        worst = worst.max((f - e).abs() / (1.0 + e.abs()));
    }
    assert!(worst <= 1e-5, "largest relative difference {worst:e}");
    assert!(worst > 0.0, "the two matrices are formed differently");
}

#[test]
fn a_thesis_exploration_branches_where_newton_fails() {
    // The author's setting to t = 1.13: its first fork (about step 168).
    let scene = thesis_scene("abundance-author");
    let run = RunOptions {
        t_end: Some(1.13),
        ..thesis::run_options(RunOptions::default(), scene.solver.rho_inf)
    };
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
    // Without the re-solves, the run stops at the first fork's step: its Newton attempt
    // did not converge within 20 iterations.
    let first = forks[0].t;
    let mut plain = run.clone();
    plain.tuning.push("policy.branch_trials=false".into());
    let summary = simulate(&scene, &plain, |_| {}).unwrap();
    let e = summary.error.expect("the run stops").to_string();
    assert!(e.contains("did not converge"), "{e}");
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
    let run = RunOptions {
        t_end: Some(0.1),
        ..thesis::run_options(RunOptions::default(), scene.solver.rho_inf)
    };
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
