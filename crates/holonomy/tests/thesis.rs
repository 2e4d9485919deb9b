//! The thesis's printed numbers (Ch. 2), corrected by ERRATA items 1–7.

use holonomy::rectangle::{no_holonomy_family, special_path_rotation, NoHolonomy};
use holonomy::{
    euler_plan, plan_rectangles, rectangle_holonomy, rectangle_holonomy_closed_form, shortest,
    Direction, Rectangle,
};
use nalgebra::{Rotation3, Unit, Vector3};
use rotations::{rotation_distance, AxisAngle, EulerSet};
use std::f64::consts::{FRAC_PI_2, PI};

fn rect(theta: f64, phi1: f64, phi2: f64, d: Direction) -> Rectangle {
    Rectangle::new(theta, phi1, phi2, d).unwrap()
}

/// (2.4.10): Ŝ(4π/3 − 0.5, π/2 − 0.4, 3π, ccw) = R(62.7042°, −0.389418 A1 − 0.921061 A3),
/// and e3(t1) = 0.194194 A1 + 0.346057 A2 + 0.917896 E3 (ERRATA items 2, 4).
#[test]
fn equation_2_4_10() {
    let r = rect(
        4.0 * PI / 3.0 - 0.5,
        FRAC_PI_2 - 0.4,
        3.0 * PI,
        Direction::Ccw,
    );
    let s = rectangle_holonomy(&r);
    let aa = AxisAngle::from_rotation(&s);
    assert_eq!(format!("{:.4}", aa.angle.to_degrees()), "62.7042");
    assert_eq!(format!("{:.6}", aa.axis.x), "-0.389418");
    assert!(aa.axis.y.abs() < 1e-14);
    assert_eq!(format!("{:.6}", aa.axis.z), "-0.921061");
    let e3 = s * Vector3::z();
    assert_eq!(
        format!("{:.6} {:.6} {:.6}", e3.x, e3.y, e3.z),
        "0.194194 0.346057 0.917896"
    );
    // It is the special path (2.4.9)₁ with φ2 = 3π: R(2ϑ, −A_r) (ERRATA item 4).
    let (angle, axis) = special_path_rotation(&r, 1e-12).unwrap();
    let special = Rotation3::from_axis_angle(&axis, angle);
    assert!(rotation_distance(&special, &s) < 1e-14);
}

/// ERRATA item 1: the corrected closed form (2.4.6) agrees with the product (2.4.2);
/// the printed one (without the factor 2) does not.
#[test]
fn closed_form_needs_the_factor_two() {
    let r = rect(1.3, 0.2, 2.1, Direction::Ccw);
    let s = rectangle_holonomy(&r);
    let q = rectangle_holonomy_closed_form(&r);
    assert!(rotation_distance(&q.to_rotation_matrix(), &s) < 1e-14);
    let printed_q0 = 1.0 - (0.5 * r.theta).sin().powi(2) * (0.5 * r.phi2).sin().powi(2);
    let half_angle = 0.5 * AxisAngle::from_rotation(&s).angle;
    assert!((q.w.abs() - half_angle.cos()).abs() < 1e-14);
    assert!((printed_q0.abs() - half_angle.cos()).abs() > 1e-2);
}

/// (2.4.12) and ERRATA items 2, 7: the three counter-clockwise rectangles printed for
/// R(3π/2, 0.1 A1 + √0.98 A2 + 0.1 A3) are found (to the printed digits), each
/// reproducing the target, and they are the complete set of counter-clockwise solutions
/// with the quaternion sign q0 = cos(ψ/2).
#[test]
fn equation_2_4_12() {
    let axis = Vector3::new(0.1, 0.98_f64.sqrt(), 0.1);
    let target = AxisAngle::new(1.5 * PI, axis).unwrap().to_rotation();
    let plans = plan_rectangles(&target).unwrap();
    let printed = [
        (3.0333, 3.5379, 8.6465),
        (3.2499, 0.39626, 2.3633),
        (3.2499, 6.6794, 8.6465),
    ];
    for (t, p1, p2) in printed {
        let hit = plans.iter().find(|p| {
            p.rectangle.direction == Direction::Ccw
                && (p.rectangle.theta - t).abs() < 6e-5
                && (p.rectangle.phi1 - p1).abs() < 6e-5
                && (p.rectangle.phi2 - p2).abs() < 6e-5
        });
        let hit = hit.unwrap_or_else(|| panic!("({t}, {p1}, {p2}) not found in {plans:#?}"));
        assert!(hit.error < 1e-13);
        // The printed digits themselves reproduce the target to their precision.
        let printed_rect = rect(t, p1, p2, Direction::Ccw);
        assert!(rotation_distance(&rectangle_holonomy(&printed_rect), &target) < 2e-4);
    }
    // With the sign of the printed ψ (q0 = cos(3π/4) < 0), these are all the ccw solutions.
    let q0_sign_of_psi: Vec<_> = plans
        .iter()
        .filter(|p| {
            p.rectangle.direction == Direction::Ccw
                && rectangle_holonomy_closed_form(&p.rectangle).w < 0.0
        })
        .collect();
    assert_eq!(q0_sign_of_psi.len(), 3, "{q0_sign_of_psi:#?}");
    // Every solution is verified by the forward product.
    assert!(plans.iter().all(|p| p.error < 1e-13));
    // ERRATA item 7: the symmetries relating the three.
    let a = rect(3.2499, 0.39626, 2.3633, Direction::Ccw);
    let b = rect(
        3.2499,
        0.39626 + 2.0 * PI,
        2.3633 + 2.0 * PI,
        Direction::Ccw,
    );
    let c = rect(
        2.0 * PI - 3.2499,
        0.39626 + PI,
        2.3633 + 2.0 * PI,
        Direction::Ccw,
    );
    let sa = rectangle_holonomy(&a);
    assert!(rotation_distance(&sa, &rectangle_holonomy(&b)) < 1e-13);
    assert!(rotation_distance(&sa, &rectangle_holonomy(&c)) < 1e-13);
    // The shortest path for a robot.
    let best = shortest(&plans).unwrap();
    assert!(plans
        .iter()
        .all(|p| p.rectangle.path_length() >= best.rectangle.path_length()));
}

/// (2.4.8): the no-holonomy families give the identity.
#[test]
fn equation_2_4_8() {
    let cases = [
        (
            rect(PI, 0.3, PI, Direction::Ccw),
            NoHolonomy::OddMultiplesOfPi,
        ),
        (
            rect(3.0 * PI, 1.0, 5.0 * PI, Direction::Cw),
            NoHolonomy::OddMultiplesOfPi,
        ),
        (
            rect(2.0 * PI, 0.7, 1.9, Direction::Ccw),
            NoHolonomy::ThetaMultipleOfTwoPi,
        ),
        (
            rect(0.8, 3.0, 4.0 * PI, Direction::Cw),
            NoHolonomy::Phi2MultipleOfTwoPi,
        ),
    ];
    for (r, family) in cases {
        assert_eq!(no_holonomy_family(&r, 1e-12), Some(family));
        assert!(rotation_distance(&rectangle_holonomy(&r), &Rotation3::identity()) < 1e-14);
    }
    assert_eq!(
        no_holonomy_family(&rect(1.0, 0.2, 2.0, Direction::Ccw), 1e-12),
        None
    );
}

/// (2.4.9)₁,₂: φ2 = π gives R(2ϑ, A_r); ϑ = π gives R(2φ2, A2) for any start φ1.
#[test]
fn equation_2_4_9() {
    for phi1 in [0.0, 0.4, 1.0, PI] {
        let r = rect(0.9, phi1, PI, Direction::Ccw);
        let (angle, axis) = special_path_rotation(&r, 1e-12).unwrap();
        assert!((angle - 1.8).abs() < 1e-15);
        let a_r = holonomy::rectangle::axis_a_r(phi1, PI);
        assert!((axis.into_inner() - a_r).norm() < 1e-15);
        let expected = Rotation3::from_axis_angle(&Unit::new_normalize(a_r), 1.8);
        assert!(rotation_distance(&expected, &rectangle_holonomy(&r)) < 1e-14);
        let r2 = rect(PI, phi1.min(1.3), 1.3, Direction::Ccw);
        let expected = Rotation3::from_axis_angle(&Vector3::y_axis(), 2.6);
        assert!(rotation_distance(&expected, &rectangle_holonomy(&r2)) < 1e-14);
    }
    // Johnson's Lemma 1: φ1 = π/2, φ2 = π gives 2ϑ about −A3 (ccw).
    let r = rect(0.6, FRAC_PI_2, PI, Direction::Ccw);
    let expected = Rotation3::from_axis_angle(&-Vector3::z_axis(), 1.2);
    assert!(rotation_distance(&expected, &rectangle_holonomy(&r)) < 1e-14);
}

/// (2.5.7), (2.5.8), (2.5.11): each rectangle of the 3-2-3 construction gives its
/// elementary rotation, with the directions of ERRATA item 6.
#[test]
fn euler_323_rectangles_one_by_one() {
    let (n1, n2, n3) = (0.7, 1.1, 2.3);
    let plan = euler_plan(EulerSet::from_name("3-2-3").unwrap(), [n1, n2, n3]).unwrap();
    let e2p = Vector3::new(-f64::sin(n1), n1.cos(), 0.0);
    let e1p = Vector3::new(n1.cos(), n1.sin(), 0.0);
    let e3pp = n2.sin() * e1p + n2.cos() * Vector3::z();
    let expect = [
        Rotation3::from_axis_angle(&Vector3::z_axis(), n1),
        Rotation3::from_axis_angle(&Unit::new_normalize(e2p), n2),
        Rotation3::from_axis_angle(&Unit::new_normalize(e3pp), n3),
    ];
    for (r, e) in plan.rectangles.iter().zip(expect) {
        assert!(rotation_distance(&r.holonomy(), &e) < 1e-14);
    }
    assert!(plan.error < 1e-14);
}

/// ERRATA item 6: every rectangle of the four constructions produces its elementary
/// rotation R(νᵢ, gᵢ); reversing rectangle 1 or 3 breaks it.
#[test]
fn euler_constructions_and_directions() {
    for (name, nu2) in [
        ("3-2-3", 1.1),
        ("3-1-3", 2.9),
        ("3-2-1", -0.7),
        ("3-1-2", 0.4),
        ("3-2-1", 0.4),
        ("3-1-2", -1.2),
    ] {
        let set = EulerSet::from_name(name).unwrap();
        let plan = euler_plan(set, [0.7, nu2, 2.3]).unwrap();
        for e in plan.rectangle_errors {
            assert!(e < 1e-14, "{name}: {:?}", plan.rectangle_errors);
        }
        assert!(plan.error < 1e-14);
        for i in [0, 2] {
            let mut rects = plan.rectangles;
            rects[i].rectangle.direction = rects[i].rectangle.direction.reversed();
            let achieved = rects[2].holonomy() * rects[1].holonomy() * rects[0].holonomy();
            assert!(
                rotation_distance(&achieved, &plan.target) > 0.1,
                "{name}: reversing rectangle {} still works",
                i + 1
            );
        }
    }
}
