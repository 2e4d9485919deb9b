//! The cylinder pair of `rollstack cylinder pair` stepped by nsga's last resort alone
//! (`Stepper::step_by_last_resort`, docs/method.md §8.2): four bilateral position
//! constraints, a bilateral velocity constraint (the prescribed spin) and three disk
//! friction laws, which the last resort takes through a polygon inscribed in the disk.

use cylinders::studies::pair::PairSettings;
use cylinders::transport::PairTransport;
use nsga::friction_polygon::DISK_DIRECTIONS;
use nsga::{Evaluation, Options, Stepper, System};

/// What a run by the last resort alone measured.
#[derive(Debug, Default)]
struct Measured {
    /// Largest |g| of the bilateral position constraints after a step.
    bilateral: f64,
    /// Largest |γ| of the prescribed spin after a step (rad/s).
    spin: f64,
    /// Smallest gap (m).
    min_gap: f64,
    /// Largest growth of the energy T + V over its initial value (J).
    growth: f64,
    /// Largest floor slip speed (m/s).
    floor_slip: f64,
    /// Largest complementarity residual of a step.
    residual: f64,
}

/// T + V: ½uᵀMu and the centres' heights in gravity.
fn energy(mass_gravity: f64, e: &Evaluation<f64>, q: &[f64], u: &[f64]) -> f64 {
    let kinetic: f64 = e
        .mass
        .entries
        .iter()
        .map(|&(i, j, m)| 0.5 * u[i] * m * u[j])
        .sum();
    kinetic + mass_gravity * (q[2] + q[8])
}

/// v = W_vᵀu + χ_v.
fn velocity_level(e: &Evaluation<f64>, u: &[f64]) -> Vec<f64> {
    let mut v = e.velocity_chi.clone();
    for &(r, c, w) in &e.velocity_w.entries {
        v[c] += w * u[r];
    }
    v
}

fn by_last_resort(theta: f64, steps: usize) -> Measured {
    let settings = PairSettings::thesis(theta);
    let sys = settings.system().unwrap();
    let (q0, u0) = sys.initial_state(theta).unwrap();
    let layout = sys.layout();
    let options = Options {
        dt: settings.dt,
        ..Options::default()
    };
    let mg = sys.mass * sys.gravity;
    let mut s = Stepper::new(sys, 0.0, &q0, &u0, options).unwrap();
    let mut e = Evaluation::new(&layout);
    let evaluate = |s: &Stepper<PairTransport>, e: &mut Evaluation<f64>| {
        let st = s.state();
        e.reset();
        s.system().evaluate(st.t, &st.q, &st.u, e);
        energy(mg, e, &st.q, &st.u)
    };
    let e0 = evaluate(&s, &mut e);
    let mut m = Measured {
        min_gap: f64::INFINITY,
        ..Measured::default()
    };
    for _ in 0..steps {
        let last = s
            .step_by_last_resort()
            .unwrap()
            .last_resort
            .clone()
            .unwrap();
        m.residual = m.residual.max(last.residual);
        let energy = evaluate(&s, &mut e);
        m.growth = m.growth.max(energy - e0);
        let (g, gaps) = e.position.split_at(4);
        m.bilateral = g.iter().fold(m.bilateral, |a, x| a.max(x.abs()));
        m.min_gap = gaps.iter().fold(m.min_gap, |a, &x| a.min(x));
        let v = velocity_level(&e, &s.state().u);
        m.spin = m.spin.max(v[0].abs());
        m.floor_slip = m.floor_slip.max(v[1].hypot(v[2])).max(v[3].hypot(v[4]));
    }
    m
}

/// 300 steps of 2 ms by the last resort alone, at ϑ = 30° and 45°: the bilateral
/// constraints held to the projection's tolerance, the spin to round-off, no
/// interpenetration, the energy not growing, and the floor contacts rolling (sticking
/// is exact inside the friction polygon).
#[test]
fn the_cylinder_pair_goes_through_the_last_resort() {
    for theta in [30.0_f64.to_radians(), 45.0_f64.to_radians()] {
        let m = by_last_resort(theta, 300);
        assert!(m.residual < 1e-8, "ϑ = {theta}: {m:?}");
        assert!(m.bilateral <= 1e-12, "ϑ = {theta}: {m:?}");
        assert!(m.spin < 1e-9, "ϑ = {theta}: {m:?}");
        assert!(m.min_gap > -1e-10, "ϑ = {theta}: {m:?}");
        assert!(m.growth < 1e-9, "ϑ = {theta}: {m:?}");
        assert!(m.floor_slip < 1e-6, "ϑ = {theta}: {m:?}");
    }
}

/// Over a smooth spin-up (−6π rad/s in 0.5 s) cylinder I pushes II through the mutual
/// contact (disk friction, μ = 0.4), so the polygon's friction carries the transport.
/// Runs 0.6 s with 2 ms steps by the last resort and by the generalized-α policy.
///
/// The two agree where the polygon is exact: the prescribed spin angle φ1 differs by
/// O(Δt) only (0.019 rad; 0.0093 at 1 ms). The centres differ by what the polygon's
/// sliding directions, off Coulomb's by up to π/k, make of the travel: measured 0.039 m
/// in y with k = 16 directions (0.0105 m with k = 64, the same at Δt = 1 ms and
/// 0.5 ms), within travel × sin(π/k).
#[test]
fn a_spin_up_by_the_last_resort_follows_the_generalized_alpha_run_to_the_polygon_s_error() {
    let (theta, dt) = (0.5, 2e-3);
    let settings = PairSettings {
        spin: cylinders::transport::SpinProfile::ramp(-6.0 * std::f64::consts::PI, 0.5),
        dt,
        ..PairSettings::thesis(theta)
    };
    let sys = settings.system().unwrap();
    let (q0, u0) = sys.initial_state(theta).unwrap();
    let options = Options {
        dt,
        ..Options::default()
    };
    let mut by_lr = Stepper::new(sys, 0.0, &q0, &u0, options.clone()).unwrap();
    let mut by_ga = Stepper::new(sys, 0.0, &q0, &u0, options).unwrap();
    let (mut apart, mut pressed) = (vec![0.0_f64; q0.len()], 0.0_f64);
    for _ in 0..300 {
        by_lr.step_by_last_resort().unwrap();
        by_ga.step().unwrap();
        let (a, b) = (by_lr.state(), by_ga.state());
        assert_eq!(a.t, b.t);
        for (m, (x, y)) in apart.iter_mut().zip(a.q.iter().zip(&b.q)) {
            *m = m.max((x - y).abs());
        }
        pressed = pressed.max(a.p_n[2]);
    }
    let end = by_ga.state();
    let travel = (end.q[0] - q0[0]).hypot(end.q[1] - q0[1]);
    let polygon = travel * (std::f64::consts::PI / DISK_DIRECTIONS as f64).sin();
    assert!(pressed > 0.0, "the mutual contact carries the push");
    assert!(
        apart[5] < 2.0 * dt * 6.0 * std::f64::consts::PI,
        "{apart:?}"
    );
    for c in [0, 1, 6, 7] {
        assert!(
            apart[c] <= polygon,
            "coordinate {c}: {apart:?}, bound {polygon}"
        );
    }
}
