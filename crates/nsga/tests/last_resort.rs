//! The last resort of a step (docs/method.md §8, step 7): when every attempt of the
//! fallback policy fails, the stepper takes a Moreau–Jean step whose contact problem
//! Lemke's method solves. Here the generalized-α attempts are starved (one Newton
//! iteration, no retries), so the last resort takes the steps that one iteration does
//! not solve, and the motion is checked against the closed form of the paper's bouncing
//! ball.

use nsga::systems::ball::{Ball, BallCase};
use nsga::systems::rocking::RockingBlock;
use nsga::System;
use nsga::{FailurePolicy, NewtonOptions, Options, PolicyOptions, StepError, Stepper};

/// Options under which a step with a contact event cannot converge: one Newton
/// iteration, no ρ∞ retries, no re-solves, no halving.
fn starved(dt: f64, last_resort: bool) -> Options {
    Options {
        dt,
        newton: NewtonOptions {
            max_iter: 1,
            ..NewtonOptions::default()
        },
        policy: PolicyOptions {
            retry_max_iter: 1,
            rho_inf_retries: Vec::new(),
            branch_trials: false,
            on_failure: FailurePolicy::Error,
            max_halvings: 0,
            last_resort,
            ..PolicyOptions::default()
        },
        ..Options::default()
    }
}

fn stepper(case: &BallCase, options: Options) -> Stepper<Ball> {
    Stepper::new(case.ball, 0.0, &case.q0, &case.u0, options).unwrap()
}

#[test]
fn the_last_resort_lands_the_ball_slides_it_and_rolls_it_as_the_closed_form_says() {
    let case = BallCase::new(2).unwrap();
    let dt = 1e-3;
    let mut s = stepper(&case, starved(dt, true));
    let steps = (case.t_end / dt).round() as usize;
    let mut lowest = f64::INFINITY;
    for _ in 0..steps {
        let stats = s.step().unwrap().clone();
        if let Some(last) = &stats.last_resort {
            // Lemke's solution satisfies the complementarity conditions to round-off.
            assert!(last.residual < 1e-12, "{last:?}");
        }
        lowest = lowest.min(s.state().q[1] - case.ball.radius);
    }
    // The landing needs the last resort. After it the generalized-α state restarts from
    // a consistent start, which Newton's single iteration does not find and Lemke's
    // method does (docs/method.md §5, step 5b); the ball's sliding and rolling steps are
    // then solved by one update each. (Before that stage, every restart failed and the
    // last resort took more than 10 of these steps.)
    let taken = s.run_stats().last_resort_steps;
    assert!(
        (1..=3).contains(&taken),
        "the starved stepper took {taken} steps by the last resort"
    );
    // No gap below −1e-8, and the ball rolls at the closed form's speed.
    assert!(lowest >= -1e-8, "lowest gap {lowest}");
    let rolling = case.ball.rolling_velocity(case.u0[0], case.u0[2]);
    assert!((s.state().u[0] - rolling).abs() < 1e-2, "{:?}", s.state().u);
    let x = case.exact_x(case.t_end).unwrap();
    assert!(
        (s.state().q[0] - x).abs() < 1e-2,
        "x {} vs {x}",
        s.state().q[0]
    );
}

#[test]
fn without_the_last_resort_the_starved_step_is_an_error() {
    let case = BallCase::new(2).unwrap();
    let mut s = stepper(&case, starved(1e-3, false));
    let failed = (0..1500).find_map(|_| s.step().err());
    assert!(
        matches!(
            failed,
            Some(StepError::NotConverged { .. } | StepError::Linear { .. })
        ),
        "{failed:?}"
    );
    assert_eq!(s.run_stats().last_resort_steps, 0);
}

/// A stepper whose consistent start fails still starts where the last resort covers the
/// system: it says why (`start_failure`), and its first step is a last-resort step (a
/// Moreau–Jean step needs no initial accelerations). Here a block of half-width 0.1 and
/// half-height 0.2 slides at unit speed on both bottom corners with μ = 1.5, past
/// Painlevé's bound 4/3: pressing the leading corner down accelerates it into the
/// ground, no contact forces satisfy the laws on acceleration level, and the motion
/// starts with a tangential impact. With the last resort off the start is an error.
#[test]
fn a_failed_start_is_followed_by_a_last_resort_step() {
    let block = RockingBlock {
        mass: 1.0,
        half_width: 0.1,
        half_height: 0.2,
        gravity: 9.81,
        mu: 1.5,
        e_n: 0.0,
    };
    let (q0, u0) = ([0.0, 0.2, 0.0], [1.0, 0.0, 0.0]);
    let options = |last_resort| Options {
        dt: 1e-3,
        policy: PolicyOptions {
            last_resort,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let strict = Stepper::new(block, 0.0, &q0, &u0, options(false));
    assert!(matches!(strict, Err(StepError::Start { .. })), "{strict:?}");
    let mut s = Stepper::new(block, 0.0, &q0, &u0, options(true)).unwrap();
    let why = s.start_failure().expect("the start failed");
    assert!(why.starts_with("consistent start at t = 0 failed"), "{why}");
    assert!(why.contains("Painlevé"), "{why}");
    assert_eq!(s.state().k, 0);
    let initial = s.state().clone();
    let first = s.step().unwrap().clone();
    let last = first
        .last_resort
        .expect("the first step is the last resort's");
    assert!(last.residual < 1e-12, "{last:?}");
    assert_eq!(s.run_stats().last_resort_steps, 1);
    // The impact slows the slip at once (friction alone would take 1.5·9.81·10⁻³ off in
    // a step), and no corner goes below the ground.
    let u = s.state().u.clone();
    assert!(u[0] < 1.0 - 0.1, "{u:?}");
    let mut e = nsga::Evaluation::new(&block.layout());
    block.evaluate(s.state().t, &s.state().q, &u, &mut e);
    assert!(e.position.iter().all(|&g| g >= -1e-8), "{:?}", e.position);
    // The start's failure stays on record, and the initial state, set again, is again
    // stepped by the last resort (a redone first step).
    assert!(s.start_failure().is_some());
    let after_one = s.state().clone();
    s.set_state(initial);
    assert!(s.step().unwrap().last_resort.is_some());
    assert_eq!(s.state(), &after_one);
}
