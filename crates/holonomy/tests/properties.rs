//! Random property tests and hard cases.

use holonomy::roll::{axis_angle, circle_holonomy, roll, CentrePath, Integrator};
use holonomy::{
    euler_plan, euler_plan_for_rotation, holonomy_components, plan_rectangles, rectangle_holonomy,
    rectangle_holonomy_closed_form, Direction, HolonomyError, Rectangle,
};
use nalgebra::{Rotation3, Unit, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rotations::{rotation_distance, AxisAngle, EulerSet};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn direction() -> impl Strategy<Value = Direction> {
    prop_oneof![Just(Direction::Ccw), Just(Direction::Cw)]
}

fn rectangle() -> impl Strategy<Value = Rectangle> {
    (0.0..4.0 * PI, 0.0..1.0_f64, 0.0..4.0 * PI, direction())
        .prop_map(|(t, f, p2, d)| Rectangle::new(t, f * p2, p2, d).unwrap())
}

fn target() -> impl Strategy<Value = Rotation3<f64>> {
    (1e-6..PI, -1.0..1.0_f64, -1.0..1.0_f64, -1.0..1.0_f64)
        .prop_filter("non-zero axis", |(_, x, y, z)| x * x + y * y + z * z > 1e-4)
        .prop_map(|(a, x, y, z)| {
            AxisAngle::new(a, Vector3::new(x, y, z))
                .unwrap()
                .to_rotation()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// The product (2.4.2)/(2.4.5), the closed form (2.4.6) and the components (B.1.2)
    /// agree to 1e-12.
    #[test]
    fn three_forms_agree(r in rectangle()) {
        let s = rectangle_holonomy(&r);
        prop_assert!((holonomy_components(&r) - s.matrix()).norm() < 1e-12);
        let q = rectangle_holonomy_closed_form(&r);
        prop_assert!((q.norm() - 1.0).abs() < 1e-14);
        prop_assert!(rotation_distance(&q.to_rotation_matrix(), &s) < 1e-12);
    }

    /// Clockwise is the transpose (2.4.5), and n circuits give n ψ about s.
    #[test]
    fn reversal_and_repetition(r in rectangle()) {
        let back = Rectangle { direction: r.direction.reversed(), ..r };
        prop_assert!((rectangle_holonomy(&back).matrix() - rectangle_holonomy(&r).matrix().transpose()).norm() < 1e-13);
        let s = rectangle_holonomy(&r);
        let aa = AxisAngle::from_rotation(&s);
        let thrice = AxisAngle::new(3.0 * aa.angle, aa.axis.into_inner()).unwrap().to_rotation();
        prop_assert!(rotation_distance(&(s * s * s), &thrice) < 1e-12);
    }

    /// Every planned rectangle reproduces the target, and the planner finds a rectangle
    /// that was used to make the target.
    #[test]
    fn planner_is_complete_and_verified(r in rectangle()) {
        prop_assume!(r.theta > 1e-3 && r.phi2 > 1e-3 && r.phi2 <= 3.0 * PI);
        let s = rectangle_holonomy(&r);
        prop_assume!(AxisAngle::from_rotation(&s).angle > 1e-6);
        let plans = plan_rectangles(&s).unwrap();
        prop_assert!(plans.iter().all(|p| p.error < 1e-12), "{plans:?}");
        // Reduce the generator's rectangle to the planner's ranges: ϑ mod 2π, and
        // φ1 into [φ2 − 2π, φ2].
        let theta = r.theta.rem_euclid(TAU);
        // Near ϑ = 0 and π (mod 2π: 2π is 0 again) the holonomy depends on φ only to
        // second order in the distance, and φ is found only to ε over its square: at
        // ϑ = 4π − 2.2e-5 a plan of error 1e-15 had φ2 8e-7 off the generator's. The
        // generator's own margin from ϑ = 0, 1e-3, applies to every degenerate angle.
        let off = theta.rem_euclid(PI);
        prop_assume!(off.min(PI - off) > 1e-3);
        let low = r.phi2 - TAU;
        let phi1 = low + (r.phi1 - low).rem_euclid(TAU);
        let found = plans.iter().any(|p| p.rectangle.direction == r.direction
            && (p.rectangle.theta - theta).abs() < 1e-7
            && (p.rectangle.phi2 - r.phi2).abs() < 1e-7
            && ((p.rectangle.phi1 - phi1).abs() < 1e-7 || (p.rectangle.phi1 - phi1).abs() > TAU - 1e-7));
        prop_assert!(found, "{r:?} not in {plans:?}");
    }

    /// Random targets: at least one solution, all verified to 1e-12.
    #[test]
    fn planner_reaches_any_rotation(t in target()) {
        let plans = plan_rectangles(&t).unwrap();
        prop_assert!(!plans.is_empty());
        prop_assert!(plans.iter().all(|p| p.error < 1e-12 && p.rectangle.phi2 <= 3.0 * PI + 1e-9), "{plans:?}");
    }

    /// The Euler three-rectangle plan reproduces random targets for all four sets.
    #[test]
    fn euler_plan_random(t in target(), which in 0usize..4) {
        let set = EulerSet::from_name(["3-2-3", "3-1-3", "3-2-1", "3-1-2"][which]).unwrap();
        let plan = euler_plan_for_rotation(set, &t).unwrap();
        prop_assert!(plan.error < 1e-12, "{}", plan.error);
        let from_angles = euler_plan(set, set.angles(&t)).unwrap();
        prop_assert!(from_angles.error < 1e-12);
    }

    /// Exact rolling around a rectangle equals (2.4.2) whatever the step count.
    #[test]
    fn exact_roll_matches_product(r in rectangle(), steps in 5usize..40) {
        prop_assume!(r.theta > 1e-3 && r.phi2 > 1e-3);
        let path = CentrePath::rectangle(&r, 1.0).unwrap();
        let traj = roll(&path, 1.0, Integrator::Exact, steps.max(path.segments().len())).unwrap();
        let q = traj.final_orientation();
        prop_assert!(rotation_distance(&q.to_rotation_matrix(), &rectangle_holonomy(&r)) < 1e-12);
    }
}

/// ν2 at its singular values (ERRATA item 6): 0 and π (3-x-3), ±π/2 (3-x-y).
#[test]
fn euler_plan_singular() {
    for (name, nu2s) in [
        ("3-2-3", vec![0.0, PI]),
        ("3-1-3", vec![0.0, PI]),
        ("3-2-1", vec![FRAC_PI_2, -FRAC_PI_2, 0.0]),
        ("3-1-2", vec![FRAC_PI_2, -FRAC_PI_2, 0.0]),
    ] {
        let set = EulerSet::from_name(name).unwrap();
        for nu2 in nu2s {
            for (n1, n3) in [(0.3, 1.7), (-2.0, 3.0), (0.0, 0.0)] {
                let plan = euler_plan(set, [n1, nu2, n3]).unwrap();
                assert!(plan.error < 1e-13, "{name} {nu2} {}", plan.error);
                let t = set.rotation([n1, nu2, n3]);
                assert!(euler_plan_for_rotation(set, &t).unwrap().error < 1e-13);
            }
        }
    }
    assert!(matches!(
        euler_plan(EulerSet::from_name("1-2-3").unwrap(), [0.1, 0.2, 0.3]),
        Err(HolonomyError::UnsupportedEulerSet(_))
    ));
    assert!(euler_plan(EulerSet::from_name("3-2-3").unwrap(), [f64::NAN, 0.2, 0.3]).is_err());
}

fn plan_ok(angle: f64, axis: Vector3<f64>) -> Vec<holonomy::PlannedRectangle> {
    let t = AxisAngle::new(angle, axis).unwrap().to_rotation();
    let plans = plan_rectangles(&t).unwrap();
    assert!(!plans.is_empty(), "no plan for {angle} {axis:?}");
    for p in &plans {
        assert!(p.error < 1e-12, "{angle} {axis:?}: {p:?}");
    }
    plans
}

/// ψ → 0 and ψ → π, axes along A2 or A3 exactly.
#[test]
fn planner_hard_targets() {
    let axes = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        -Vector3::y(),
        Vector3::new(0.3, -0.2, 0.9),
    ];
    for axis in axes {
        for angle in [1e-12, 1e-8, 1e-4, PI - 1e-9, PI, 2.0, TAU - 1e-8] {
            plan_ok(angle, axis);
        }
    }
    // Axis along A2: ϑ = π, φ1 free ((2.4.9)₂).
    let plans = plan_ok(0.8, Vector3::y());
    assert!(plans
        .iter()
        .any(|p| p.phi1_free && (p.rectangle.theta - PI).abs() < 1e-12));
    // Axis along A3 exactly: φ2 = π ((2.4.9)₁ with A_r = ±A3).
    let plans = plan_ok(0.8, Vector3::z());
    assert!(plans.iter().any(|p| (p.rectangle.phi2 - PI).abs() < 1e-12));
    // Bad input.
    assert!(AxisAngle::new(1.0, Vector3::zeros()).is_err());
    let nan = Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_element(f64::NAN));
    assert_eq!(
        plan_rectangles(&nan),
        Err(HolonomyError::Input(input::InputError::NonFinite(
            "target rotation".into()
        )))
    );
}

/// φ2 near nπ and huge path lengths (multiples of 2π added).
#[test]
fn near_multiples_of_pi_and_long_paths() {
    for n in 1..=3 {
        for eps in [1e-12, 1e-8, 1e-5] {
            for phi2 in [f64::from(n) * PI - eps, f64::from(n) * PI + eps] {
                let r = Rectangle::new(1.1, 0.3, phi2, Direction::Ccw).unwrap();
                let s = rectangle_holonomy(&r);
                assert!(
                    rotation_distance(&rectangle_holonomy_closed_form(&r).to_rotation_matrix(), &s)
                        < 1e-13
                );
                if AxisAngle::from_rotation(&s).angle > 1e-9 {
                    let plans = plan_rectangles(&s).unwrap();
                    assert!(plans.iter().all(|p| p.error < 1e-12));
                }
            }
        }
    }
    let base = Rectangle::new(0.9, 0.4, 1.7, Direction::Cw).unwrap();
    let s = rectangle_holonomy(&base);
    for m in [1.0, 10.0, 1000.0] {
        let long = Rectangle::new(0.9 + TAU * m, 0.4, 1.7 + TAU * m, Direction::Cw).unwrap();
        assert!(rotation_distance(&rectangle_holonomy(&long), &s) < 1e-12 * m.max(1.0) * 10.0);
        assert!(
            rotation_distance(
                &rectangle_holonomy_closed_form(&long).to_rotation_matrix(),
                &s
            ) < 1e-12 * m * 10.0
        );
    }
}

/// Rolling around circles: the exact integrator matches the closed form, RK4 converges
/// at 4th order, and both directions work.
#[test]
fn circle_rolling() {
    for d in [Direction::Ccw, Direction::Cw] {
        for rho in [0.5, 2.0] {
            let path = CentrePath::circle(rho, d).unwrap();
            let exact = circle_holonomy(rho, 1.0, d).unwrap();
            let traj = roll(&path, 1.0, Integrator::Exact, 50).unwrap();
            assert!(
                rotation_distance(&traj.final_orientation().to_rotation_matrix(), &exact) < 1e-12
            );
            let e1 = rk4_error(&path, &exact, 100);
            let e2 = rk4_error(&path, &exact, 200);
            let order = (e1 / e2).log2();
            assert!((3.6..4.4).contains(&order), "order {order}");
        }
    }
    // The centre comes back, and the sphere radius scales the angle.
    let path = CentrePath::circle(2.0, Direction::Ccw).unwrap();
    let traj = roll(&path, 2.0, Integrator::Exact, 64).unwrap();
    let last = traj.samples.last().unwrap();
    assert!(last.centre[0].abs() < 1e-12 && last.centre[1].abs() < 1e-12);
    let (angle, _) = axis_angle(&traj.final_orientation());
    let full = TAU * 2.0_f64.sqrt();
    let expected = (full.rem_euclid(TAU)).min(TAU - full.rem_euclid(TAU));
    assert!((angle - expected).abs() < 1e-12);
}

fn rk4_error(path: &CentrePath, exact: &Rotation3<f64>, steps: usize) -> f64 {
    let traj = roll(path, 1.0, Integrator::Rk4, steps).unwrap();
    rotation_distance(&traj.final_orientation().to_rotation_matrix(), exact)
}

/// A general polygon: exact per-segment rolling equals the product of the segment
/// rotations, the marked point starts at the contact, and bad paths are rejected.
#[test]
fn polygon_rolling() {
    let verts = [[0.0, 0.0], [2.0, 0.0], [3.0, 1.5], [0.5, 2.5]];
    let path = CentrePath::polygon(&verts).unwrap();
    let mut expected = UnitQuaternion::identity();
    for i in 0..4 {
        let (a, b) = (verts[i], verts[(i + 1) % 4]);
        let d = Vector3::new(b[0] - a[0], b[1] - a[1], 0.0);
        let axis = Unit::new_normalize(Vector3::z().cross(&d));
        expected = UnitQuaternion::from_axis_angle(&axis, d.norm()) * expected;
    }
    let traj = roll(&path, 1.0, Integrator::Exact, 40).unwrap();
    assert!(traj.final_orientation().angle_to(&expected) < 1e-12);
    let first = traj.samples[0];
    assert_eq!(first.marked_point, [0.0, 0.0, 0.0]);
    let rk = roll(&path, 1.0, Integrator::Rk4, 400).unwrap();
    assert!(rk.final_orientation().angle_to(&expected) < 1e-8);
    assert!(CentrePath::polygon(&[[0.0, 0.0], [0.0, 0.0]]).is_err());
    assert!(CentrePath::polygon(&[[0.0, f64::NAN], [1.0, 0.0]]).is_err());
    assert!(CentrePath::circle(-1.0, Direction::Ccw).is_err());
    assert!(roll(&path, 0.0, Integrator::Exact, 10).is_err());
    assert!(roll(&path, 1.0, Integrator::Exact, 2).is_err());
}

/// The App. C root-finding route (C.2.4)–(C.2.8) finds the same rectangles as the
/// closed-form planner: the (2.4.12) target and random ones.
#[test]
fn root_finding_agrees_with_closed_form_planner() {
    use holonomy::appendix_c::plan_by_root_finding;
    let mut targets = vec![
        AxisAngle::new(1.5 * PI, Vector3::new(0.1, 0.98_f64.sqrt(), 0.1))
            .unwrap()
            .to_rotation(),
    ];
    // A deterministic spread of axes and angles (no axis along A2: there φ1 is free).
    for i in 0..40 {
        let x = f64::from(i);
        let axis = Vector3::new(
            (1.3 * x).sin(),
            (0.7 * x + 0.4).cos(),
            (2.1 * x + 1.0).sin() + 0.05,
        );
        targets.push(AxisAngle::new(0.1 + 0.075 * x, axis).unwrap().to_rotation());
    }
    for t in &targets {
        let closed = plan_rectangles(t).unwrap();
        let roots = plan_by_root_finding(t).unwrap();
        for p in &roots {
            assert!(p.error < 1e-9);
        }
        for p in &closed {
            let r = p.rectangle;
            let found = roots.iter().any(|q| {
                q.rectangle.direction == r.direction
                    && (q.rectangle.theta - r.theta).abs() < 1e-6
                    && (q.rectangle.phi1 - r.phi1).abs() < 1e-6
                    && (q.rectangle.phi2 - r.phi2).abs() < 1e-6
            });
            assert!(
                found,
                "closed-form {r:?} not found by root finding: {roots:#?}"
            );
        }
        assert_eq!(
            closed.len(),
            roots.len(),
            "closed {closed:#?}\nroots {roots:#?}"
        );
    }
}
