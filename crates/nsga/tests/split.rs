//! Robustness fallbacks of the stepper: a step taken as substeps lands back on the time
//! grid (`Stepper::split_step`), and redundant closed contacts
//! (a singular Newton matrix) are carried by the regularized update
//! (`LinearOptions::regularization`); the ρ∞ retries follow the failures
//! `PolicyOptions::rho_inf_retry` names.

use nsga::system::{Evaluation, Layout, Scalar, System};
use nsga::systems::free_fall::FreeFall;
use nsga::systems::rocking::RockingBlock;
use nsga::{LinearOptions, NewtonOptions, Options, PolicyOptions, RhoInfRetry, StepError, Stepper};

fn free_fall() -> (FreeFall, Stepper<FreeFall>) {
    let sys = FreeFall {
        mass: 2.0,
        gravity: 9.81,
    };
    let opts = Options {
        dt: 0.01,
        ..Options::default()
    };
    (sys, Stepper::new(sys, 0.0, &[1.0], &[0.5], opts).unwrap())
}

#[test]
fn a_split_step_lands_on_the_grid_with_the_exact_state() {
    let (sys, mut s) = free_fall();
    s.step().unwrap();
    let stats = s.split_step(4, |s| s.step().map(|_| ())).unwrap().clone();
    assert_eq!(stats.substeps, 4);
    assert!(stats.retries >= 1, "a split step counts as retried");
    // k and t are those of two whole steps, t exactly on the grid.
    assert_eq!(s.state().k, 2);
    assert_eq!(s.state().t, 2.0 * 0.01);
    assert_eq!(s.options().dt, 0.01, "Δt is restored");
    // Free fall is integrated exactly for any Δt, so the substeps give the parabola.
    let (y, v) = sys.exact(1.0, 0.5, s.state().t);
    assert!((s.state().q[0] - y).abs() < 1e-12);
    assert!((s.state().u[0] - v).abs() < 1e-12);
    // One step for the run statistics, marked as split.
    assert_eq!(s.run_stats().steps, 2);
    assert_eq!(s.run_stats().split_steps, 1);
    // The grid continues unchanged after it.
    s.step().unwrap();
    assert!((s.state().t - 0.03).abs() < 1e-15);
}

#[test]
fn a_failed_substep_restores_state_options_and_statistics() {
    let (_, mut s) = free_fall();
    s.step().unwrap();
    let before = (
        s.state().clone(),
        s.options().clone(),
        s.run_stats().clone(),
    );
    let mut calls = 0;
    let err = s
        .split_step(2, |s| {
            calls += 1;
            if calls == 2 {
                return Err(StepError::InvalidInput("refused".into()));
            }
            s.step().map(|_| ())
        })
        .unwrap_err();
    assert!(err.to_string().contains("refused"));
    assert_eq!(s.state(), &before.0);
    assert_eq!(s.options(), &before.1);
    assert_eq!(s.run_stats(), &before.2);
    assert!(
        s.split_step(0, |_| Ok(())).is_err(),
        "zero parts is bad input"
    );
}

/// A unit point mass under gravity resting on two identical contacts g₁ = g₂ = y: the
/// contact rows of the Newton matrix are equal, so it is singular, and the normal forces
/// are not unique (only λ₁ + λ₂ = mg is). The load can pulse, mg (1 + `pulse` sin 5t),
/// so that every step needs a Newton update.
#[derive(Debug, Clone, Copy)]
struct TwoCoincidentSupports {
    pulse: f64,
}

impl System for TwoCoincidentSupports {
    fn layout(&self) -> Layout {
        Layout {
            nq: 1,
            nu: 1,
            e_n: vec![0.0, 0.0],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(1.0));
        out.forces[0] = T::from(-1.0 - self.pulse * (5.0 * t).sin());
        out.position[0] = q[0];
        out.position[1] = q[0];
        out.position_w.push(0, 0, T::from(1.0));
        out.position_w.push(0, 1, T::from(1.0));
    }
}

fn resting(regularization: f64, pulse: f64) -> Result<Stepper<TwoCoincidentSupports>, StepError> {
    resting_with(regularization, pulse, true)
}

fn resting_with(
    regularization: f64,
    pulse: f64,
    last_resort: bool,
) -> Result<Stepper<TwoCoincidentSupports>, StepError> {
    let opts = Options {
        dt: 0.01,
        linear: LinearOptions {
            regularization,
            ..LinearOptions::default()
        },
        policy: PolicyOptions {
            last_resort,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    Stepper::new(TwoCoincidentSupports { pulse }, 0.0, &[0.0], &[0.0], opts)
}

#[test]
fn redundant_contacts_rest_with_the_least_norm_forces() {
    let mut s = resting(nsga::DEFAULT_REGULARIZATION, 0.0).unwrap();
    for _ in 0..100 {
        s.step().unwrap();
    }
    let st = s.state();
    assert!(st.q[0].abs() < 1e-12 && st.u[0].abs() < 1e-12, "{st:?}");
    let (l1, l2) = (st.lambda_n[0], st.lambda_n[1]);
    assert!((l1 + l2 - 1.0).abs() < 1e-9, "λ₁ + λ₂ = mg: {l1} + {l2}");
    assert!((l1 - l2).abs() < 1e-6, "equal shares: {l1}, {l2}");
}

#[test]
fn known_singular_sets_go_straight_to_the_regularized_update() {
    let mut s = resting(nsga::DEFAULT_REGULARIZATION, 0.5).unwrap();
    s.step().unwrap();
    let (solves, iterations) = (s.linear_solves(), s.run_stats().newton_iterations);
    for _ in 0..20 {
        s.step().unwrap();
    }
    // The sets stay the same: every later Newton update is one (regularized) solve, not
    // a failed plain factorization followed by the regularized one.
    let more_solves = s.linear_solves() - solves;
    let more_iterations = s.run_stats().newton_iterations - iterations;
    assert!(more_iterations >= 20, "{more_iterations} iterations");
    assert_eq!(more_solves, more_iterations);
    let st = s.state();
    let load = 1.0 + 0.5 * (5.0 * st.t).sin();
    assert!((st.lambda_n[0] + st.lambda_n[1] - load).abs() < 1e-9);
}

/// With simplified updates (`LinearOptions::reuse_factorization`), the factors of the
/// regularized matrix serve the later updates of the same sets, as plain factors do:
/// the redundant supports' steps then cost fewer factorizations than updates, and the
/// forces still carry the load.
#[test]
fn regularized_factors_serve_simplified_updates() {
    let opts = Options {
        dt: 0.01,
        linear: LinearOptions {
            reuse_factorization: true,
            ..LinearOptions::default()
        },
        ..Options::default()
    };
    let sys = TwoCoincidentSupports { pulse: 0.5 };
    let mut s = Stepper::new(sys, 0.0, &[0.0], &[0.0], opts).unwrap();
    for _ in 0..40 {
        s.step().unwrap();
    }
    let w = s.newton_work();
    assert!(w.kept_updates > 0, "{w:?}");
    assert!(s.linear_solves() < s.run_stats().newton_iterations, "{w:?}");
    let st = s.state();
    let load = 1.0 + 0.5 * (5.0 * st.t).sin();
    assert!(
        (st.lambda_n[0] + st.lambda_n[1] - load).abs() < 1e-9,
        "{st:?}"
    );
    assert!(st.q[0].abs() < 1e-12, "{st:?}");
}

/// A load that varies (pulse 0.5), so that every step needs a Newton update and its
/// singular matrix. (Under a constant load the consistent start, which Lemke's method
/// finds without the Newton matrix, already solves every step.)
#[test]
fn without_regularization_redundant_contacts_fail_as_singular() {
    let failed = match resting_with(0.0, 0.5, false) {
        Err(_) => true,
        Ok(mut s) => (0..10).any(|_| s.step().is_err()),
    };
    assert!(failed, "the singular Newton matrix must not pass unnoticed");
    // With the last resort the run goes on: the steps are the last resort's.
    let mut s = resting(0.0, 0.5).unwrap();
    for _ in 0..10 {
        s.step().unwrap();
    }
    assert!(s.run_stats().last_resort_steps >= 1);
    assert!(s.state().q[0].abs() < 1e-12, "{:?}", s.state());
    // The start's Newton matrix is singular too, but Lemke's method finds the start, a
    // split of the load between the two supports (docs/method.md §5, step 5b).
    let s = resting(0.0, 0.5).unwrap();
    assert!(s.start_failure().is_none(), "{:?}", s.start_failure());
    let st = s.state();
    assert!(
        (st.lambda_n[0] + st.lambda_n[1] - 1.0).abs() < 1e-9,
        "{st:?}"
    );
    assert!(st.lambda_n.iter().all(|&l| l >= 0.0), "{st:?}");
}

#[test]
fn singular_sets_are_remembered_across_flights() {
    // With pulse 2 the load turns upward for part of each period (2π/5): the mass lifts
    // off (no contact closed: a regular Newton matrix), lands and rests on both supports
    // again (singular matrices), four times in 5 s.
    let mut s = resting(nsga::DEFAULT_REGULARIZATION, 2.0).unwrap();
    let (mut flights, mut was_resting) = (0, true);
    // Failed plain factorizations (one per set found singular), by flight.
    let mut rediscovered = Vec::new();
    for _ in 0..500 {
        let before = (s.linear_solves(), s.run_stats().newton_iterations);
        let stats = s.step().unwrap();
        assert_eq!(stats.retries, 0);
        let resting = stats.sets.a.iter().all(|&a| a);
        flights += usize::from(was_resting && !resting);
        was_resting = resting;
        let solves = s.linear_solves() - before.0;
        let updates = s.run_stats().newton_iterations - before.1;
        if solves > updates {
            rediscovered.push(flights);
        }
    }
    assert!(flights >= 3, "{flights} flights");
    // The first landings find the singular sets; later ones go straight to the
    // regularized update although regular matrices came in between (remembering only
    // the last singular set, every landing found them again).
    assert!(
        rediscovered.iter().all(|&f| f < 2),
        "singular sets found again in flights {rediscovered:?}"
    );
}

/// Linear solves of one step that fails on every attempt: a block rocking on a corner
/// (nonlinear in θ, over a long step) given one Newton iteration per attempt, no
/// fixed-set re-solves.
fn solves_of_a_failing_step(rho_inf_retry: RhoInfRetry) -> u64 {
    let block = RockingBlock::slender();
    let (q0, u0) = block.tilted(0.08);
    let opts = Options {
        dt: 0.1,
        newton: NewtonOptions {
            max_iter: 1,
            ..NewtonOptions::default()
        },
        policy: PolicyOptions {
            rho_inf_retry,
            branch_trials: false,
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let mut s = Stepper::new(block, 0.0, &q0, &u0, opts).unwrap();
    let err = s.step().unwrap_err();
    assert!(matches!(err, StepError::NotConverged { .. }), "{err}");
    s.linear_solves()
}

#[test]
fn rho_inf_retries_follow_the_failures_they_are_asked_for() {
    let retries = Options::default().policy.rho_inf_retries.len() as u64;
    // Iterates that do not converge: the first attempt and every retry take one update.
    assert_eq!(
        solves_of_a_failing_step(RhoInfRetry::AnyFailure),
        1 + retries
    );
    assert_eq!(solves_of_a_failing_step(RhoInfRetry::SingularMatrix), 1);
    // A singular Newton matrix (redundant contacts, no regularization) is retried with
    // the other ρ∞ under either choice.
    for choice in [RhoInfRetry::AnyFailure, RhoInfRetry::SingularMatrix] {
        // Started with regularization (the consistent start needs it), stepped without.
        let mut s = resting(nsga::DEFAULT_REGULARIZATION, 0.5).unwrap();
        s.set_options(Options {
            linear: LinearOptions {
                regularization: 0.0,
                ..s.options().linear.clone()
            },
            policy: PolicyOptions {
                rho_inf_retry: choice,
                last_resort: false,
                ..s.options().policy.clone()
            },
            ..s.options().clone()
        })
        .unwrap();
        let err = s.step().unwrap_err();
        assert!(matches!(err, StepError::Linear { .. }), "{err}");
        assert_eq!(s.linear_solves(), 1 + retries, "{choice:?}");
    }
}
