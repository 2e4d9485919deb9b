//! The last resort takes every contact law nsga offers (docs/method.md §8.2): here the
//! bring-your-own-system pendulum (a bilateral rod and a rough wall) is stepped by the
//! last resort alone (`Stepper::step_by_last_resort`) through its impact, and a system
//! the last resort cannot take (a redundant rod) is refused when the stepper is set up.
//! The cylinder pair (bilateral constraints and disk friction) is in
//! crates/cylinders/tests/pair_last_resort.rs.

#[path = "../examples/pendulum_wall.rs"]
#[allow(dead_code)]
mod pendulum_wall;

use nsga::{Evaluation, Layout, Options, PolicyOptions, Scalar, StepError, Stepper, System};
use pendulum_wall::PendulumWall;

/// What the pendulum did over a run by the last resort alone.
#[derive(Debug)]
struct Pendulum {
    /// Largest |x² + y² − L²| after a step (m²).
    rod: f64,
    /// Smallest wall gap x (m).
    min_gap: f64,
    /// The horizontal speed just before and just after the wall's percussion.
    speeds: (f64, f64),
    /// The largest angle after the bounce, and the closed form's θ1 (rad).
    rebound: (f64, f64),
    /// Steps taken, and those with a wall percussion.
    steps: usize,
    struck: usize,
}

fn pendulum(restitution: f64) -> PendulumWall {
    PendulumWall {
        mass: 1.0,
        length: 1.0,
        gravity: 9.81,
        restitution,
        mu: 0.3,
    }
}

/// Released at θ0 = 1 rad, stepped by the last resort alone with Δt = 1 ms past the apex
/// after the bounce and before the second impact: 1.3 s, 1300 steps (the bounce comes
/// at T/4 = 0.53 s, the apex about 0.51 s later).
fn by_last_resort(p: PendulumWall) -> Pendulum {
    let (theta0, dt) = (1.0_f64, 1e-3);
    let q0 = [p.length * theta0.sin(), -p.length * theta0.cos()];
    let options = Options {
        dt,
        ..Options::default()
    };
    let mut s = Stepper::new(p, 0.0, &q0, &[0.0, 0.0], options).unwrap();
    let mut run = Pendulum {
        rod: 0.0,
        min_gap: f64::INFINITY,
        speeds: (f64::NAN, f64::NAN),
        rebound: (
            0.0,
            (1.0 - p.restitution.powi(2) * (1.0 - theta0.cos())).acos(),
        ),
        steps: 0,
        struck: 0,
    };
    while s.state().t < 1.3 {
        let before = s.state().u[0];
        let stats = s.step_by_last_resort().unwrap().clone();
        let last = stats.last_resort.expect("a last-resort step");
        assert!(last.residual < 1e-10, "{last:?}");
        let st = s.state();
        let (x, y) = (st.q[0], st.q[1]);
        run.rod = run.rod.max((x * x + y * y - p.length * p.length).abs());
        run.min_gap = run.min_gap.min(x);
        run.steps += 1;
        if st.p_n[0] > 0.0 {
            run.struck += 1;
            if run.struck == 1 {
                run.speeds = (before, st.u[0]);
            }
        }
        if run.struck > 0 {
            run.rebound.0 = run.rebound.0.max(x.atan2(-y));
        }
    }
    assert_eq!(s.run_stats().last_resort_steps, run.steps as u64);
    run
}

/// The rod is held to the projection's tolerance, the wall is not crossed, the mass
/// leaves the wall with e_N times its approach speed (Newton's law, which Moreau–Jean's
/// step applies exactly), and the rebound angle is the closed form's to first order in
/// Δt (the bounce comes up to a step early or late).
#[test]
fn the_pendulum_goes_through_its_impact_by_the_last_resort() {
    for e in [0.5, 0.8] {
        let r = by_last_resort(pendulum(e));
        assert!(r.steps >= 1300, "{r:?}");
        assert!(r.rod <= 1e-12, "e_N = {e}: {r:?}");
        assert!(r.min_gap >= -1e-12, "e_N = {e}: {r:?}");
        // One impact (a single percussion step), at the speed the energy gives.
        assert_eq!(r.struck, 1, "e_N = {e}: {r:?}");
        let v = (2.0_f64 * 9.81 * (1.0 - 1.0_f64.cos())).sqrt();
        assert!((r.speeds.0 + v).abs() < 0.05 * v, "e_N = {e}: {r:?}");
        assert!(
            (r.speeds.1 + e * r.speeds.0).abs() < 1e-9,
            "e_N = {e}: {r:?}"
        );
        assert!((r.rebound.0 - r.rebound.1).abs() < 5e-3, "e_N = {e}: {r:?}");
    }
}

/// A point mass hung from two identical rods: the second bilateral constraint repeats
/// the first, so their multipliers are not determined and the last resort cannot
/// eliminate them.
#[derive(Debug, Clone, Copy)]
struct TwoRods;

impl System for TwoRods {
    fn layout(&self) -> Layout {
        Layout {
            nq: 2,
            nu: 2,
            n_bilateral_position: 2,
            ..Layout::default()
        }
    }

    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        out.mass.push(0, 0, T::from(1.0));
        out.mass.push(1, 1, T::from(1.0));
        out.forces[1] = T::from(-9.81);
        for rod in 0..2 {
            out.position[rod] = q[0] * q[0] + q[1] * q[1] - T::from(1.0);
            out.position_w.push(0, rod, q[0] * 2.0);
            out.position_w.push(1, rod, q[1] * 2.0);
            out.position_zeta[rod] = (u[0] * u[0] + u[1] * u[1]) * 2.0;
        }
    }
}

/// The refusal comes when the stepper is set up, names the option and the redundant
/// constraint, and not at a failing step.
#[test]
fn a_system_the_last_resort_cannot_take_is_refused_at_setup() {
    let (q0, u0) = ([0.6, -0.8], [0.0, 0.0]);
    let refused = Stepper::new(TwoRods, 0.0, &q0, &u0, Options::default());
    let Err(StepError::InvalidInput(why)) = refused else {
        panic!("{refused:?}")
    };
    assert!(why.starts_with("Options::last_resort"), "{why}");
    assert!(
        why.contains("bilateral position constraint 1 is redundant"),
        "{why}"
    );
    // With the option off, the refusal is not asked for: the stepper then fails as the
    // generalized-α start does, on the same redundancy (a singular Newton matrix).
    let off = Options {
        policy: PolicyOptions {
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let plain = Stepper::new(TwoRods, 0.0, &q0, &u0, off);
    assert!(matches!(plain, Err(StepError::Start { .. })), "{plain:?}");
}
