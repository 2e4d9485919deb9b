//! The bring-your-own-system example (`examples/pendulum_wall.rs`, walked through in
//! docs/architecture.md) runs in CI: a system defined outside the crate's sources,
//! through its public API only, checked against its closed form.

#[path = "../examples/pendulum_wall.rs"]
#[allow(dead_code)]
mod pendulum_wall;

use pendulum_wall::{run, PendulumWall};

#[test]
fn the_example_runs_and_matches_its_closed_form() {
    pendulum_wall::main().unwrap();
}

#[test]
fn elastic_and_plastic_walls_give_the_closed_form_rebound() {
    let pendulum = |restitution| PendulumWall {
        mass: 2.0,
        length: 0.5,
        gravity: 9.81,
        restitution,
        mu: 0.8,
    };
    // e_N = 1: back to the release angle; e_N = 0: the mass stays at the wall.
    for (e, theta0, theta1) in [(1.0, 0.6, 0.6), (0.0, 0.6, 0.0), (0.8, 1.2, f64::NAN)] {
        let c = run(pendulum(e), theta0, 5e-4).unwrap();
        let expected = if theta1.is_nan() {
            c.rebound_angle.1
        } else {
            theta1
        };
        assert!((c.rebound_angle.1 - expected).abs() < 1e-12);
        assert!(
            (c.rebound_angle.0 - expected).abs() < 1e-3,
            "e_N = {e}: {c:?}"
        );
        assert!((c.impact_time.0 - c.impact_time.1).abs() <= 5e-4, "{c:?}");
        assert!(c.rod_drift < 1e-10 && c.min_gap > -1e-10, "{c:?}");
    }
}
