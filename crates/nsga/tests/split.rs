//! Robustness fallbacks of the stepper: a step taken as substeps lands back on the time
//! grid (`Stepper::split_step`), and redundant closed contacts
//! (a singular Newton matrix) are carried by the regularized update
//! (`Options::regularization`).

use nsga::system::{Evaluation, Layout, Scalar, System};
use nsga::systems::free_fall::FreeFall;
use nsga::{Options, StepError, Stepper};

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
    let opts = Options {
        dt: 0.01,
        regularization,
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

#[test]
fn without_regularization_redundant_contacts_fail_as_singular() {
    let failed = match resting(0.0, 0.0) {
        Err(_) => true,
        Ok(mut s) => (0..10).any(|_| s.step().is_err()),
    };
    assert!(failed, "the singular Newton matrix must not pass unnoticed");
}
