//! The transport of two touching cylinders (§3.6, Figure 3.14) against the smooth-floor
//! statics (3.3.10) (docs/errata.md item 14), and its hard cases.

use cylinders::kinematics::Cylinder;
use cylinders::studies::pair::{run_pair, PairReport, PairSettings};
use cylinders::transport::{inclination_range, SpinProfile};
use std::f64::consts::{FRAC_PI_4, PI};

fn check_targets(r: &PairReport) {
    assert!(
        r.static_error < 1e-8,
        "ϑ = {}: (3.3.10) off by {}",
        r.theta,
        r.static_error
    );
    assert!(r.max_contact_normal_force < 1e-8, "ϑ = {}: {r:?}", r.theta);
    assert!(r.drift < 1e-10, "ϑ = {}: drift {}", r.theta, r.drift);
    assert!(r.min_gap > -1e-10, "ϑ = {}: gap {}", r.theta, r.min_gap);
}

/// Figure 3.14's range, both ends included: close to arctan(2r/h) (F3 → 0) and π/4
/// (perpendicular axes), 2000 steps of 2 ms each.
#[test]
fn steady_transport_equals_the_smooth_floor_statics_over_the_range() {
    let (lo, _) = inclination_range(&Cylinder::gas_cylinder());
    for theta in [lo + 1e-3, 0.25, 0.35, 0.5, 0.65, FRAC_PI_4] {
        let r = run_pair(&PairSettings::thesis(theta), false).unwrap();
        check_targets(&r);
        assert_eq!(r.steps, 2000);
        assert!((r.n_over_mg[0] - r.n_over_mg[1]).abs() < 1e-12);
        assert!(r.n_over_mg[0] > 0.0 && r.f3_over_mg[0] > 0.0, "{r:?}");
    }
    // Close to arctan(2r/h) the tops carry almost nothing.
    let r = run_pair(&PairSettings::thesis(lo + 1e-3), false).unwrap();
    assert!(r.f3_over_mg[0] < 1e-2, "{r:?}");
}

/// A smooth spin-up: cylinder I pushes II through the mutual contact, which carries a
/// force while the pair accelerates and none once the transport is steady.
#[test]
fn smooth_spin_up_settles_on_the_statics() {
    let settings = PairSettings {
        spin: SpinProfile::ramp(-6.0 * PI, 0.5),
        ..PairSettings::thesis(0.5)
    };
    let r = run_pair(&settings, true).unwrap();
    check_targets(&r);
    let t = r.trajectory.as_ref().unwrap();
    let peak = t.iter().map(|s| s.contact_normal_force).fold(0.0, f64::max);
    assert!(peak > 0.1, "the spin-up pushes II: peak {peak}");
    assert!((t.last().unwrap().spin_rates[1] - 6.0 * PI).abs() < 1e-8);
}

/// Spin-ups far shorter than before: a ramp of one to five steps spins I from 1 % of
/// −6π so fast that its floor contact, rolling at t = 0, must slide in the first step.
/// Its slip velocity is then round-off, and the sliding row's direction comes from the
/// prox argument (docs/method.md §3, "Negligible slip outside D"); with ξ/‖ξ‖ the
/// Newton matrix held entries of 10³¹ and every attempt failed as singular.
#[test]
fn abrupt_spin_ups_start_and_settle_on_the_statics() {
    for (theta, ramp) in [(0.5, 0.002), (0.5, 0.01), (0.7, 0.01), (0.3, 0.004)] {
        let settings = PairSettings {
            spin: SpinProfile::ramp(-6.0 * PI, ramp),
            ..PairSettings::thesis(theta)
        };
        let r = run_pair(&settings, false)
            .unwrap_or_else(|e| panic!("ϑ = {theta}, ramp {ramp} s: {e}"));
        check_targets(&r);
    }
}

/// A spin reversal: I rolls back, the mutual contact opens and stays open, nothing
/// penetrates, and each cylinder still rolls on the smooth-floor support.
#[test]
fn spin_reversal_opens_the_contact() {
    let settings = PairSettings {
        spin: SpinProfile {
            initial: -6.0 * PI,
            target: 6.0 * PI,
            ramp_start: 1.0,
            ramp_duration: 0.5,
        },
        ..PairSettings::thesis(0.4)
    };
    let r = run_pair(&settings, false).unwrap();
    check_targets(&r);
    assert!(r.final_mutual_gap > 1.0, "{r:?}");
}

/// Bad inputs are rejected with one line naming the input.
#[test]
fn bad_inputs_are_rejected_with_one_line() {
    let (lo, _) = inclination_range(&Cylinder::gas_cylinder());
    let fails = |s: PairSettings, word: &str| {
        let e = run_pair(&s, false).unwrap_err().to_string();
        assert!(e.contains(word) && !e.contains('\n'), "{e}");
    };
    fails(PairSettings::thesis(lo - 1e-3), "inclination");
    fails(PairSettings::thesis(1.6), "inclination");
    fails(PairSettings::thesis(f64::NAN), "inclination");
    fails(
        PairSettings {
            cylinder: Cylinder::new(0.7, 1.2954).unwrap(),
            ..PairSettings::thesis(0.5)
        },
        "radius r",
    );
    fails(
        PairSettings {
            dt: -2e-3,
            ..PairSettings::thesis(0.5)
        },
        "time step",
    );
    fails(
        PairSettings {
            steps: 0,
            ..PairSettings::thesis(0.5)
        },
        "steps",
    );
}

/// The mutual contact opens and closes again: I slows down to a third of its spin (the
/// contact opens, II rolls on), then spins up to five thirds and catches II (an
/// inelastic impact closes it).
/// Nothing penetrates, and the bilateral constraints hold through the impact.
#[test]
fn the_contact_opens_and_closes_again() {
    use cylinders::transport::PairTransport;
    use nsga::{Options, PolicyOptions, Stepper, System};
    let theta = 0.5;
    let mut sys = PairTransport::thesis(theta);
    sys.spin = SpinProfile {
        initial: -6.0 * PI,
        target: -2.0 * PI,
        ramp_start: 0.2,
        ramp_duration: 0.5,
    };
    let (q0, u0) = sys.initial_state(theta).unwrap();
    let options = Options {
        policy: PolicyOptions {
            max_halvings: 2,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    let layout = sys.layout();
    let mut stepper = Stepper::new(sys, 0.0, &q0, &u0, options).unwrap();
    let mut eval = nsga::Evaluation::<f64>::new(&layout);
    let (mut opened, mut closed_again, mut min_gap, mut drift) = (false, false, 0.0_f64, 0.0_f64);
    for k in 0..2500 {
        if k == 600 {
            stepper.system_mut().spin = SpinProfile {
                initial: -2.0 * PI,
                target: -10.0 * PI,
                ramp_start: 1.2,
                ramp_duration: 0.5,
            };
        }
        stepper.step().unwrap();
        let st = stepper.state();
        eval.reset();
        stepper.system().evaluate(st.t, &st.q, &st.u, &mut eval);
        let gap = eval.position[6];
        min_gap = min_gap.min(gap).min(eval.position[4]).min(eval.position[5]);
        drift = eval.position[..4].iter().fold(drift, |m, g| m.max(g.abs()));
        opened |= gap > 0.1;
        closed_again |= opened && gap < 1e-9 && st.lambda_n[2] > 0.0;
    }
    assert!(
        opened && closed_again,
        "opened {opened}, closed again {closed_again}"
    );
    assert!(min_gap > -1e-10, "gap {min_gap}");
    assert!(drift < 1e-10, "drift {drift}");
}
