//! Exact Jacobians against a finite-difference oracle, index-set control, bilateral
//! constraints, and typed errors.

use nsga::system::forward_derivatives;
use nsga::systems::ball::Ball;
use nsga::systems::rocking::RockingBlock;
use nsga::{
    Derivatives, Evaluation, IndexSets, Layout, NewtonOptions, Options, PolicyOptions, Probes,
    Scalar, StepError, Stepper, System,
};

/// A point on a circle x² + y² = L² (bilateral position constraint, GGL-stabilised)
/// carrying a coordinate z with the nonholonomic constraint ż − y ẋ = 0 (bilateral
/// velocity constraint), under gravity −y.
#[derive(Debug, Clone, Copy)]
struct Pendulum {
    length: f64,
}

impl System for Pendulum {
    fn layout(&self) -> Layout {
        Layout {
            nq: 3,
            nu: 3,
            n_bilateral_position: 1,
            n_bilateral_velocity: 1,
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        for i in 0..3 {
            out.mass.push(i, i, T::from(1.0));
        }
        out.forces[1] = T::from(-9.81);
        out.position[0] = (q[0] * q[0] + q[1] * q[1] - self.length * self.length) * 0.5;
        out.position_w.push(0, 0, q[0]);
        out.position_w.push(1, 0, q[1]);
        out.position_zeta[0] = u[0] * u[0] + u[1] * u[1];
        out.velocity_w.push(2, 0, T::from(1.0));
        out.velocity_w.push(0, 0, -q[1]);
        out.velocity_zeta[0] = -u[1] * u[0];
    }
}

fn fd_check<S: System>(s: &mut Stepper<S>, x: &[f64], sets: &IndexSets) {
    let (_, j) = s.newton_system(x, sets, 0.5, true);
    let n = x.len();
    let mut worst: f64 = 0.0;
    for c in 0..n {
        let h = 1e-6 * (1.0 + x[c].abs());
        let mut xp = x.to_vec();
        xp[c] += h;
        let (rp, _) = s.newton_system(&xp, sets, 0.5, false);
        let mut xm = x.to_vec();
        xm[c] -= h;
        let (rm, _) = s.newton_system(&xm, sets, 0.5, false);
        for r in 0..n {
            let fd = (rp[r] - rm[r]) / (2.0 * h);
            let scale = 1.0 + j[(r, c)].abs();
            worst = worst.max((fd - j[(r, c)]).abs() / scale);
            assert!(
                (fd - j[(r, c)]).abs() <= 1e-6 * scale,
                "J[{r},{c}] = {} but finite differences give {fd} (sets {})",
                j[(r, c)],
                sets.describe()
            );
        }
    }
    assert!(worst < 1e-6);
}

fn perturbed(x: &[f64]) -> Vec<f64> {
    x.iter()
        .enumerate()
        .map(|(i, v)| v + 0.01 * ((i as f64 * 1.7).sin() + 0.3))
        .collect()
}

#[test]
fn rocking_block_jacobian_matches_finite_differences_for_every_case() {
    let blk = RockingBlock {
        mass: 1.3,
        half_width: 0.2,
        half_height: 0.6,
        gravity: 9.81,
        mu: 0.4,
        e_n: 0.5,
    };
    let (q0, u0) = blk.tilted(0.1);
    let mut s = Stepper::new(
        blk,
        0.0,
        &q0,
        &u0,
        Options {
            dt: 1e-2,
            ..Options::default()
        },
    )
    .unwrap();
    s.run(5, |_, _| {}).unwrap();
    let x = perturbed(&s.state().x.clone());
    let t = true;
    let f = false;
    let cases = [
        IndexSets {
            a: vec![t, t],
            b: vec![t, t],
            c: vec![t, t],
            d: vec![t, t],
            e: vec![t, t],
        },
        IndexSets {
            a: vec![t, t],
            b: vec![t, f],
            c: vec![f, f],
            d: vec![f, f],
            e: vec![f, f],
        },
        IndexSets {
            a: vec![t, f],
            b: vec![t, f],
            c: vec![t, f],
            d: vec![t, f],
            e: vec![f, f],
        },
        IndexSets {
            a: vec![f, f],
            b: vec![f, f],
            c: vec![f, f],
            d: vec![f, f],
            e: vec![f, f],
        },
    ];
    for sets in &cases {
        fd_check(&mut s, &x, sets);
    }
}

#[test]
fn bilateral_constraints_jacobian_and_drift() {
    let sys = Pendulum { length: 0.8 };
    let q0 = [0.8, 0.0, 0.0];
    let u0 = [0.0, -1.0, 0.0];
    let mut s = Stepper::new(
        sys,
        0.0,
        &q0,
        &u0,
        Options {
            dt: 5e-3,
            ..Options::default()
        },
    )
    .unwrap();
    s.run(400, |st, _| {
        let g = 0.5 * (st.q[0] * st.q[0] + st.q[1] * st.q[1] - 0.64);
        let gd = st.q[0] * st.u[0] + st.q[1] * st.u[1];
        let gamma = st.u[2] - st.q[1] * st.u[0];
        // GGL stabilisation keeps the constraint on all levels to the tolerance.
        assert!(
            g.abs() < 1e-10 && gd.abs() < 1e-9 && gamma.abs() < 1e-9,
            "t = {}: {g} {gd} {gamma}",
            st.t
        );
    })
    .unwrap();
    let x = perturbed(&s.state().x.clone());
    fd_check(&mut s, &x, &IndexSets::default());
}

#[test]
fn analytic_ball_derivatives_equal_automatic_differentiation() {
    let ball = Ball {
        mass: 0.7,
        radius: 0.1,
        gravity: 9.81,
        mu: 0.2,
        e_n: 0.5,
        e_f: 0.3,
    };
    let (q, u, a) = ([0.1, 0.3, 0.2], [1.0, -2.0, 3.0], [0.5, -9.0, 1.0]);
    let lam = [2.0];
    let probes = Probes {
        a: &a,
        u_old: &u,
        dynamics: [(&a, &lam, &lam), (&a, &lam, &lam), (&a, &lam, &lam)],
        unused_position: &[],
        unused_velocity: &[],
    };
    let mut analytic = Derivatives::default();
    ball.derivatives(0.0, &q, &u, &probes, &mut analytic);
    let mut ad = Derivatives::default();
    forward_derivatives(&ball, 0.0, &q, &u, &probes, &mut ad);
    assert_eq!(analytic.position_q.entries, ad.position_q.entries);
    assert!(ad.dynamics_q.iter().all(|t| t.entries.is_empty()));
    assert!(ad.velocity_accel_q.entries.is_empty() && ad.forces_q.entries.is_empty());
}

#[test]
fn fixed_sets_reproduce_the_free_step_and_can_be_changed() {
    let ball = Ball {
        mass: 1.0,
        radius: 0.1,
        gravity: 9.81,
        mu: 0.2,
        e_n: 0.0,
        e_f: 0.0,
    };
    let mut s = Stepper::new(
        ball,
        0.0,
        &[0.0, 0.1, 0.0],
        &[0.0, 0.0, 50.0],
        Options::default(),
    )
    .unwrap();
    s.run(3, |_, _| {}).unwrap();
    let saved = s.state().clone();
    let free = s.trial(None, 0.5).unwrap();
    // Sliding on the ground: closed on every level, not sticking.
    assert_eq!(free.stats.sets.describe(), "A=[0] B=[0] C=[0] D=[] E=[]");
    let fixed = s.trial(Some(&free.stats.sets), 0.5).unwrap();
    assert_eq!(fixed.state.q, free.state.q);
    // Forcing stick gives another (non self-consistent) solution: rolling at once.
    let mut stick = free.stats.sets.clone();
    stick.d[0] = true;
    stick.e[0] = true;
    let forced = s.trial(Some(&stick), 0.5).unwrap();
    assert!((forced.state.u[0] + 0.1 * forced.state.u[2]).abs() < 1e-9);
    assert_ne!(s.sets_of(&forced.state.x, 0.5), stick);
    assert_eq!(s.state(), &saved, "trials do not advance the stepper");
    s.commit(free);
    assert_eq!(s.state().k, 4);
    // Inconsistent sets are rejected.
    let bad = IndexSets {
        a: vec![false],
        b: vec![true],
        c: vec![false],
        d: vec![false],
        e: vec![false],
    };
    assert!(matches!(
        s.trial(Some(&bad), 0.5),
        Err(StepError::InvalidInput(_))
    ));
}

#[test]
fn bad_input_is_a_typed_error() {
    let ball = Ball {
        mass: 1.0,
        radius: 0.1,
        gravity: 9.81,
        mu: 0.2,
        e_n: 0.0,
        e_f: 0.0,
    };
    assert!(matches!(
        Stepper::new(ball, 0.0, &[0.0, 1.0], &[0.0; 3], Options::default()),
        Err(StepError::InvalidInput(_))
    ));
    assert!(matches!(
        Stepper::new(
            ball,
            0.0,
            &[0.0, f64::NAN, 0.0],
            &[0.0; 3],
            Options::default()
        ),
        Err(StepError::InvalidInput(_))
    ));
    let opts = Options {
        dt: -1.0,
        ..Options::default()
    };
    assert!(Stepper::new(ball, 0.0, &[0.0, 1.0, 0.0], &[0.0; 3], opts).is_err());
    let bad_mu = Ball { mu: -0.1, ..ball };
    assert!(Stepper::new(bad_mu, 0.0, &[0.0, 1.0, 0.0], &[0.0; 3], Options::default()).is_err());
}

#[test]
fn failed_step_carries_state_and_run_can_continue() {
    // The light ball with the thesis's constant r fails (without the last resort, which
    // would take the step); the error keeps the last good state, and switching to the
    // scaled prox continues from it.
    let ball = Ball {
        mass: 0.1,
        radius: 0.1,
        gravity: 9.81,
        mu: 0.2,
        e_n: 0.0,
        e_f: 0.0,
    };
    let opts = Options {
        prox: nsga::Prox::Constant(0.3),
        policy: PolicyOptions {
            last_resort: false,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let mut s = Stepper::new(ball, 0.0, &[0.0, 1.0, 0.0], &[0.0, 0.0, 50.0], opts.clone()).unwrap();
    let mut err = None;
    for _ in 0..750 {
        if let Err(e) = s.step() {
            err = Some(e);
            break;
        }
    }
    let Some(StepError::NotConverged { t, state, .. }) = err else {
        panic!("expected a NotConverged error, got {err:?}")
    };
    assert_eq!(state.t, t);
    assert_eq!(s.state().t, t);
    s.set_options(Options {
        prox: nsga::Prox::Scaled(1.0),
        ..opts
    })
    .unwrap();
    s.run(500, |st, _| assert!(st.q[1] - 0.1 >= -1e-8)).unwrap();
    assert!(
        (s.state().u[0] + 0.1 * s.state().u[2]).abs() < 1e-8,
        "rolls in the end"
    );
}

#[test]
fn fixed_set_resolves_report_branch_points() {
    // With a Newton budget too small for the impact step, the free iteration fails while
    // its sets change; the stepper then re-solves with each visited set fixed, keeps the
    // self-consistent candidates and reports them.
    let ball = Ball {
        mass: 1.0,
        radius: 0.1,
        gravity: 9.81,
        mu: 0.2,
        e_n: 0.5,
        e_f: 0.0,
    };
    let opts = Options {
        newton: NewtonOptions {
            max_iter: 1,
            ..NewtonOptions::default()
        },
        policy: PolicyOptions {
            rho_inf_retries: vec![],
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let mut s = Stepper::new(ball, 0.0, &[0.0, 1.0, 0.0], &[0.0, 0.0, 10.0], opts).unwrap();
    let mut branch_steps = 0;
    for _ in 0..300 {
        match s.step().map(|st| st.branch.clone()) {
            Ok(branch) => {
                if let Some(b) = &branch {
                    branch_steps += 1;
                    assert!(!b.candidates.is_empty() && b.tried >= b.candidates.len());
                    // Every candidate is self-consistent and distinct.
                    for (sets, state) in &b.candidates {
                        assert!(state.q.iter().all(|x| x.is_finite()));
                        assert!(sets.is_consistent(1, 1));
                    }
                    assert_eq!(&b.candidates[b.chosen].1, s.state());
                }
            }
            Err(e) => panic!("{e}"),
        }
        assert!(s.state().q[1] - 0.1 >= -1e-8);
    }
    assert!(branch_steps > 0, "no step needed the fixed-set re-solves");
    assert_eq!(s.run_stats().retried_steps, branch_steps);
}

/// A puck on the plane z = 0 with isotropic Coulomb friction (a two-component law:
/// prox onto a disk), optionally pushed sideways by a constant force.
#[derive(Debug, Clone, Copy)]
struct Puck3 {
    push: f64,
}

impl System for Puck3 {
    fn layout(&self) -> Layout {
        Layout {
            nq: 3,
            nu: 3,
            e_n: vec![0.0],
            friction: vec![nsga::FrictionLaw {
                components: 2,
                mu: 0.4,
                e_f: 0.0,
                normals: vec![0],
            }],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        for i in 0..3 {
            out.mass.push(i, i, T::from(2.0));
        }
        out.forces[1] = T::from(self.push);
        out.forces[2] = T::from(-2.0 * 9.81);
        out.position[0] = q[2];
        out.position_w.push(2, 0, T::from(1.0));
        out.velocity_w.push(0, 0, T::from(1.0));
        out.velocity_w.push(1, 1, T::from(1.0));
    }
}

#[test]
fn disk_friction_decelerates_along_the_slip_direction() {
    let (v0x, v0y) = (1.2, -0.5);
    let mut s = Stepper::new(
        Puck3 { push: 0.0 },
        0.0,
        &[0.0; 3],
        &[v0x, v0y, 0.0],
        Options::default(),
    )
    .unwrap();
    s.run(400, |st, _| assert!(st.q[2] >= -1e-10)).unwrap();
    let v0 = f64::hypot(v0x, v0y);
    let dist = v0 * v0 / (2.0 * 0.4 * 9.81);
    let st = s.state();
    // Straight line along the initial slip, stopping after v0²/(2μg) (stop within 0.8 s).
    assert!(st.u[0].abs() < 1e-9 && st.u[1].abs() < 1e-9);
    assert!((st.q[0] - dist * v0x / v0).abs() < 2e-3 && (st.q[1] - dist * v0y / v0).abs() < 2e-3);
    assert!(
        (st.q[0] * v0y - st.q[1] * v0x).abs() < 1e-10,
        "not on the initial line"
    );
    // Jacobian of the two-component slip rows against finite differences.
    let mut s = Stepper::new(
        Puck3 { push: 3.0 },
        0.0,
        &[0.0; 3],
        &[v0x, v0y, 0.0],
        Options::default(),
    )
    .unwrap();
    s.run(3, |_, _| {}).unwrap();
    let x = perturbed(&s.state().x.clone());
    let t = true;
    let f = false;
    for sets in [
        IndexSets {
            a: vec![t],
            b: vec![t],
            c: vec![t],
            d: vec![f],
            e: vec![f],
        },
        IndexSets {
            a: vec![t],
            b: vec![t],
            c: vec![t],
            d: vec![t],
            e: vec![f],
        },
        IndexSets {
            a: vec![t],
            b: vec![t],
            c: vec![t],
            d: vec![t],
            e: vec![t],
        },
    ] {
        fd_check(&mut s, &x, &sets);
    }
}
