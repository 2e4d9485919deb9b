//! Cross-checks of Chapter 3 and Appendices D–F: closed forms against independent
//! numerical computations, and the numbers the thesis prints (corrected per ERRATA).

use cylinders::contact::{
    closest_point_rates, closest_points, AxisMotion, AxisSegment, ClosestKind,
};
use cylinders::frobenius::{
    bilinear, frobenius_test, skew_matrices, skew_matrices_central_difference,
};
use cylinders::holonomy::{initial_axis, Direction, PathCase, RectanglePath};
use cylinders::kinematics::Cylinder;
use cylinders::pair::{CylinderPair, PairConstraints, PairSystem, SingleCylinder};
use cylinders::statics::{FrictionLimit, MinForceCase, SteadyBalance, SupportProblem};
use nalgebra::{DVector, Rotation3, Unit, Vector3};
use num_dual::Dual64;
use proptest::prelude::*;
use rotations::rotation_distance;
use std::f64::consts::{FRAC_PI_2, PI};

// ---------------------------------------------------------------- statics (§3.3)

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// (3.3.8) and (3.3.10), corrected per ERRATA 9, against the balance laws (3.3.3)
    /// solved numerically at an arbitrary precession ψ.
    #[test]
    fn limiting_normal_forces_solve_the_balance_laws(
        rho in 0.0f64..1.0, mu in 0.0f64..1.0, theta in 0.02f64..(FRAC_PI_2 - 0.02), psi in -PI..PI,
    ) {
        let problem = SupportProblem::new(rho, mu).unwrap();
        let balance = SteadyBalance::new(&problem, theta, psi).unwrap();
        for limit in [FrictionLimit::Plus, FrictionLimit::Minus, FrictionLimit::Smooth] {
            if let Some(n) = problem.normal_force(theta, limit).unwrap() {
                if n < 1e3 {
                    // N grows without bound towards the edge of the admissible angles, and
                    // the numerical solve of the balance laws loses digits as it does: its
                    // error grows like N² ε (1.2e-9 measured at N = 910), on top of the
                    // 1e-12 relative agreement where N is moderate.
                    let numeric = balance.limiting_normal_force(limit);
                    let tol = 1e-12 * (1.0 + n) + 1e-14 * n * n;
                    prop_assert!((numeric - n).abs() < tol, "{limit:?}: {numeric} vs {n}");
                }
            }
        }
        // (3.3.5)₂,₃: no member of the family has an e′1 component (β1 = 0).
        prop_assert!(balance.e1_component(0.0).abs() < 1e-13);
        prop_assert!(balance.e1_component(3.0).abs() < 1e-13);
    }

    /// The minimum force of (3.3.15)–(3.3.19), found by the case analysis, against a direct
    /// minimisation over the numerical solution family of (3.3.3).
    #[test]
    fn minimum_force_matches_balance_laws(
        rho in 0.01f64..1.0, mu in 0.0f64..1.0, theta in 0.02f64..(FRAC_PI_2 - 0.02), psi in -PI..PI,
    ) {
        let problem = SupportProblem::new(rho, mu).unwrap();
        let balance = SteadyBalance::new(&problem, theta, psi).unwrap();
        match (problem.minimum_force(theta), balance.minimum_force()) {
            (Ok(closed), Ok((f3, f))) => {
                prop_assert!((closed.f3_over_mg - f3).abs() < 1e-12, "{closed:?} vs ({f3}, {f})");
                prop_assert!((closed.f_over_mg - f).abs() < 1e-12, "{closed:?} vs ({f3}, {f})");
                prop_assert!(closed.norm_over_mg.is_finite());
                if closed.case == MinForceCase::Unconstrained {
                    prop_assert!((closed.norm_over_mg - problem.unconstrained_minimum_norm(theta)).abs() < 1e-14);
                }
            }
            (Err(_), Err(_)) => {}
            (a, b) => prop_assert!(false, "disagree on feasibility: {a:?} vs {b:?}"),
        }
    }
}

#[test]
fn minimum_force_cases_of_figure_3_8() {
    // r/h = 0.1, μ = 0.2 (Figure 3.8): D at arctan 0.2, (3.3.15) near it, the friction
    // bound at steep angles, zero force at the ends (points E).
    let p = SupportProblem::new(0.1, 0.2).unwrap();
    let d = p.minimum_force(0.2f64.atan()).unwrap();
    assert!(d.norm_over_mg < 1e-15);
    assert!(p.satisfies_friction_criterion(0.2f64.atan()));
    let mut seen = std::collections::BTreeSet::new();
    for k in 0..=900 {
        let theta = FRAC_PI_2 * f64::from(k) / 900.0;
        if let Ok(m) = p.minimum_force(theta) {
            seen.insert(m.case.name());
            // Admissible: |F| ≤ μN, F3 ≥ 0.
            assert!(m.f_over_mg.abs() <= 0.2 * (1.0 - m.f3_over_mg) + 1e-14);
            assert!(m.f3_over_mg >= -1e-15);
            if m.case == MinForceCase::Unconstrained {
                assert!(p.satisfies_friction_criterion(theta));
            }
        }
    }
    assert!(
        seen.contains("unconstrained") && seen.contains("flat_contact"),
        "{seen:?}"
    );
    assert!(
        seen.contains("friction_positive") || seen.contains("friction_negative"),
        "{seen:?}"
    );
}

#[test]
fn bad_statics_input_is_an_error() {
    assert!(SupportProblem::new(-0.1, 0.2).is_err());
    assert!(SupportProblem::new(0.0, 0.2).is_ok()); // the slender rod of Figure 3.4
    assert!(SupportProblem::new(0.1, -0.2).is_err());
    assert!(SupportProblem::new(f64::NAN, 0.2).is_err());
    let p = SupportProblem::new(0.1, 0.2).unwrap();
    assert!(p.normal_force(0.0, FrictionLimit::Plus).is_err());
    assert!(p.normal_force(f64::NAN, FrictionLimit::Plus).is_err());
    assert!(p.minimum_force(f64::NAN).is_err());
}

// ---------------------------------------------------------------- holonomy (§3.4)

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The nine-rotation product (3.4.3) against (3.4.5), (3.4.7), (3.4.8) for any start s,
    /// inclination, heading, case and direction; the result does not depend on s.
    #[test]
    fn rectangle_product_is_closed_form(
        phi1 in 0.01f64..20.0, phi2 in 0.01f64..20.0, s in 0.0f64..=1.0,
        theta in 0.01f64..(FRAC_PI_2 - 0.01), psi0 in -PI..PI, case_two: bool, cw: bool,
    ) {
        let case = if case_two { PathCase::II } else { PathCase::I };
        let direction = if cw { Direction::Clockwise } else { Direction::CounterClockwise };
        let path = RectanglePath::new(phi1, phi2, s, case, direction).unwrap();
        let product = path.product(theta, psi0);
        prop_assert!(rotation_distance(&product, &path.closed_form(theta, psi0)) < 1e-12);
        let other = RectanglePath { s: 1.0 - s, ..path };
        prop_assert!(rotation_distance(&product, &other.product(theta, psi0)) < 1e-12);
        // Clockwise is the transpose of counter-clockwise.
        let reverse = RectanglePath { direction: if cw { Direction::CounterClockwise } else { Direction::Clockwise }, ..path };
        prop_assert!(rotation_distance(&product, &reverse.product(theta, psi0).transpose()) < 1e-12);
        // (3.4.9) including the sign of the raw quaternion.
        let q = path.product_quaternion(theta, psi0);
        prop_assert!((q.coords - path.quaternion_3_4_9(theta, psi0).coords).norm() < 1e-12);
    }
}

#[test]
fn holonomy_signs() {
    let make = |case, dir| {
        RectanglePath::new(1.0, 2.0, 0.3, case, dir)
            .unwrap()
            .delta_phi()
    };
    assert_eq!(make(PathCase::I, Direction::CounterClockwise), 3.0); // (3.4.6)
    assert_eq!(make(PathCase::I, Direction::Clockwise), -3.0); // (3.4.7)
    assert_eq!(make(PathCase::II, Direction::CounterClockwise), -3.0); // (3.4.8)₁
    assert_eq!(make(PathCase::II, Direction::Clockwise), 3.0); // (3.4.8)₂
                                                               // The holonomy is a rotation about ₀e3 of (3.4.4).
    let e = initial_axis(0.3, 0.2);
    let r = Rotation3::from_axis_angle(&Unit::new_normalize(e), 3.0);
    let path = RectanglePath::new(1.0, 2.0, 0.3, PathCase::I, Direction::CounterClockwise).unwrap();
    assert!(rotation_distance(&r, &path.product(0.3, 0.2)) < 1e-14);
    assert!(RectanglePath::new(1.0, 2.0, 1.5, PathCase::I, Direction::Clockwise).is_err());
    assert!(RectanglePath::new(-1.0, 2.0, 0.5, PathCase::I, Direction::Clockwise).is_err());
}

// ---------------------------------------------------------------- Frobenius (App. D, F)

fn single() -> SingleCylinder {
    SingleCylinder {
        cylinder: Cylinder::new(0.3, 2.0).unwrap(),
    }
}

#[test]
fn single_cylinder_reproduces_d21_and_d24() {
    let sys = single();
    let r = 0.3;
    for &(psi, theta) in &[(0.4, 0.5), (2.0, 1.1), (-1.3, 0.2)] {
        let q = [0.1, -0.4, 0.9, psi, theta, 0.6];
        let skew = skew_matrices(&sys, &q).unwrap();
        // (D.2.1): only the (ψ, φ) entries of S¹, S² are non-zero; S³ = 0.
        let mut expect1 = nalgebra::DMatrix::zeros(6, 6);
        expect1[(3, 5)] = r * f64::sin(psi);
        expect1[(5, 3)] = -r * f64::sin(psi);
        let mut expect2 = nalgebra::DMatrix::zeros(6, 6);
        expect2[(3, 5)] = -r * f64::cos(psi);
        expect2[(5, 3)] = r * f64::cos(psi);
        assert!((&skew.s[0] - expect1).amax() < 1e-15);
        assert!((&skew.s[1] - expect2).amax() < 1e-15);
        assert!(skew.s[2].amax() < 1e-15);
        // The null basis (D.2.2) and the values (D.2.4).
        let y = sys
            .printed_null_basis(psi, theta)
            .map(|v| DVector::from_row_slice(&v));
        for v in &y {
            assert!((&skew.w * v).amax() < 1e-15);
        }
        assert!((bilinear(&skew.s[0], &y[0], &y[2]) - r * f64::sin(psi)).abs() < 1e-15);
        assert!((bilinear(&skew.s[1], &y[0], &y[2]) + r * f64::cos(psi)).abs() < 1e-15);
        // (D.2.3): every other combination vanishes.
        for gamma in 0..3 {
            for (i, j) in [(0, 1), (1, 2)] {
                assert!(bilinear(&skew.s[gamma], &y[i], &y[j]).abs() < 1e-15);
            }
        }
        let report = frobenius_test(&sys, &q).unwrap();
        assert_eq!((report.rank, report.nullity), (3, 3));
        assert_eq!(
            report.integrable,
            vec![psi.sin().abs() < 1e-12, psi.cos().abs() < 1e-12, true]
        );
    }
}

#[test]
fn automatic_derivatives_match_central_differences() {
    let pair = CylinderPair::identical(Cylinder::gas_cylinder());
    let q = pair.generic_configuration(0.5, 0.2, 0.4).unwrap();
    for constraints in [PairConstraints::Seven, PairConstraints::Nine] {
        let sys = PairSystem { pair, constraints };
        let exact = skew_matrices(&sys, &q).unwrap();
        let oracle = skew_matrices_central_difference(&sys, &q, 1e-5).unwrap();
        assert!((&exact.w - &oracle.w).amax() < 1e-15);
        for (a, b) in exact.s.iter().zip(&oracle.s) {
            assert!((a - b).amax() < 1e-8, "{}", (a - b).amax());
            assert!((a + a.transpose()).amax() == 0.0, "S^Γ is skew");
        }
    }
}

#[test]
fn pair_rank_is_nine_errata_13() {
    let pair = CylinderPair::identical(Cylinder::gas_cylinder());
    for theta in [0.25, 0.5, 0.7] {
        for q in [
            pair.touching_configuration(theta, 0.3, 0.5).unwrap(),
            pair.generic_configuration(theta, 0.3, 0.5).unwrap(),
        ] {
            let nine = frobenius_test(
                &PairSystem {
                    pair,
                    constraints: PairConstraints::Nine,
                },
                &q,
            )
            .unwrap();
            assert_eq!(
                (nine.rank, nine.nullity),
                (9, 3),
                "ϑ = {theta}: {:?}",
                nine.singular_values
            );
            // Far from rank-deficient: σ9 is 13 orders of magnitude above round-off.
            assert!(
                nine.smallest_nonzero_singular_value() > 1e-2,
                "ϑ = {theta}: {:?}",
                nine.singular_values
            );
            assert!(!nine.system_integrable());
            let seven = frobenius_test(
                &PairSystem {
                    pair,
                    constraints: PairConstraints::Seven,
                },
                &q,
            )
            .unwrap();
            assert_eq!((seven.rank, seven.nullity), (7, 5));
            // Π3, Π6: S = 0 ((F.4.4), (F.4.7)). Π7 is the rate of the gap g_N3
            // (App. E footnote): integrable. Π1, Π2, Π4, Π5 are not.
            assert!(seven.max_abs_asb[2] < 1e-15 && seven.max_abs_asb[5] < 1e-15);
            assert!(seven.max_abs_asb[6] < 1e-12, "{}", seven.max_abs_asb[6]);
            assert_eq!(
                seven.integrable,
                vec![false, false, true, false, false, true, true]
            );
        }
    }
}

#[test]
fn pair_ground_rows_repeat_the_single_cylinder() {
    // The first six rows of the pair are two copies of (D.1.4), so S¹ has +r1 sin ψ1 in
    // its (ψ1, φ1) entry as in (D.2.1) and (F.4.5); (F.4.2)–(F.4.3) print −E¹, −E².
    let cyl = Cylinder::gas_cylinder();
    let pair = CylinderPair::identical(cyl);
    let q = pair.generic_configuration(0.5, 0.2, 0.4).unwrap();
    let skew = skew_matrices(
        &PairSystem {
            pair,
            constraints: PairConstraints::Nine,
        },
        &q,
    )
    .unwrap();
    let r = cyl.radius();
    assert!((skew.s[0][(3, 5)] - r * q[3].sin()).abs() < 1e-15);
    assert!((skew.s[1][(3, 5)] + r * q[3].cos()).abs() < 1e-15);
    assert!((skew.s[3][(9, 11)] - r * q[9].sin()).abs() < 1e-15);
    assert!((skew.s[4][(9, 11)] + r * q[9].cos()).abs() < 1e-15);
}

#[test]
fn normal_constraint_is_the_gap_rate() {
    // Π7 = (v3 − v4) · n equals ∓ ġ_N3 (n = ∓u): the derivative of the gap (E.3.1)₃ along
    // any velocity, computed with dual numbers through the closest-point geometry.
    let pair = CylinderPair::identical(Cylinder::gas_cylinder());
    let q = pair.touching_configuration(0.45, 0.25, 0.3).unwrap();
    let qdot = [
        0.3, -0.2, 0.05, 0.4, -0.1, 1.2, -0.25, 0.1, 0.02, -0.3, 0.2, -0.7,
    ];
    let qd: Vec<Dual64> = q
        .iter()
        .zip(qdot)
        .map(|(&a, b)| Dual64::new(a, b))
        .collect();
    let k = pair.contacts(&qd);
    let gap_rate = k.gaps[2].eps;
    let w7 = pair.rolling_matrix7(&q);
    let pi7: f64 = (0..12).map(|j| w7[(6, j)] * qdot[j]).sum();
    let side = pair.contacts(&q).mutual.u.dot(&pair.contacts(&q).normal);
    assert!((side.abs() - 1.0).abs() < 1e-14);
    assert!((pi7 + side * gap_rate).abs() < 1e-13, "{pi7} vs {gap_rate}");
    // The ground gaps' rates are −Π3, −Π6 … up to sign: ġ_N1 = v_P1 · E3.
    let w9 = pair.rolling_matrix9(&q);
    let pi3: f64 = (0..12).map(|j| w9[(2, j)] * qdot[j]).sum();
    assert!((pi3 - k.gaps[0].eps).abs() < 1e-14);
}

// ---------------------------------------------------------------- contact (App. E)

fn axis_motion(
    t: f64,
    x0: [f64; 3],
    v: [f64; 3],
    a: [f64; 3],
    e0: [f64; 3],
    spin_axis: [f64; 3],
    w: f64,
    beta: f64,
) -> AxisMotion {
    let axis = Unit::new_normalize(Vector3::from(spin_axis));
    let angle = w * t + 0.5 * beta * t * t;
    let rot = Rotation3::from_axis_angle(&axis, angle);
    let (x0, v, a) = (Vector3::from(x0), Vector3::from(v), Vector3::from(a));
    AxisMotion {
        center: x0 + v * t + a * (0.5 * t * t),
        velocity: v + a * t,
        acceleration: a,
        axis: rot * Vector3::from(e0).normalize(),
        angular_velocity: axis.into_inner() * (w + beta * t),
        angular_acceleration: axis.into_inner() * beta,
    }
}

#[test]
fn closest_point_rates_match_differences() {
    let first = |t| {
        axis_motion(
            t,
            [0.0, 0.1, 0.5],
            [0.3, -0.1, 0.0],
            [0.2, 0.1, -0.3],
            [0.1, 0.2, 1.0],
            [0.3, -1.0, 0.2],
            0.7,
            0.4,
        )
    };
    let second = |t| {
        axis_motion(
            t,
            [0.4, -0.2, 0.6],
            [-0.2, 0.3, 0.1],
            [0.0, -0.4, 0.1],
            [0.9, 0.1, 0.3],
            [1.0, 0.5, -0.4],
            -0.5,
            0.9,
        )
    };
    let h = |t| closest_point_rates(&first(t), &second(t)).unwrap().h;
    let t = 0.37;
    let rates = closest_point_rates(&first(t), &second(t)).unwrap();
    let dt = 1e-4;
    let d1 = (h(t + dt) - h(t - dt)) / (2.0 * dt);
    let d2 = (h(t + dt) - 2.0 * h(t) + h(t - dt)) / (dt * dt);
    assert!((rates.h_dot - d1).amax() < 1e-7, "{} vs {d1}", rates.h_dot);
    assert!(
        (rates.h_ddot - d2).amax() < 1e-5,
        "{} vs {d2}",
        rates.h_ddot
    );
    // h agrees with the clamped-segment solver when the points are interior.
    let (a, b) = (first(t), second(t));
    let seg = |m: &AxisMotion| AxisSegment {
        center: m.center,
        axis: m.axis,
        half_length: 10.0,
        radius: 0.1,
    };
    let cp = closest_points(&seg(&a), &seg(&b));
    assert_eq!(cp.kind, ClosestKind::Interior);
    assert!((cp.m - rates.h.x).abs() < 1e-13 && (cp.n - rates.h.y).abs() < 1e-13);
    // Parallel axes: H singular, a typed error.
    let mut c = a;
    c.center += Vector3::new(1.0, 0.0, 0.0);
    assert!(closest_point_rates(&a, &c).is_err());
    let mut nan = a;
    nan.velocity.x = f64::NAN;
    assert!(closest_point_rates(&nan, &b).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// The clamped closest points are no farther apart than any pair of sampled points of
    /// the two segments, also for (nearly) parallel axes.
    #[test]
    fn closest_points_are_closest(
        c2 in prop::array::uniform3(-2.0f64..2.0), e1 in prop::array::uniform3(-1.0f64..1.0),
        e2 in prop::array::uniform3(-1.0f64..1.0), parallel in 0usize..3, tilt in 0.0f64..1e-6,
    ) {
        let e1 = Vector3::from(e1);
        prop_assume!(e1.norm() > 0.1);
        let e1 = e1.normalize();
        let e2 = match parallel {
            0 => Vector3::from(e2),
            1 => e1 + Vector3::new(tilt, -tilt, 0.0),
            _ => -e1,
        };
        prop_assume!(e2.norm() > 0.1);
        let a = AxisSegment { center: Vector3::zeros(), axis: e1, half_length: 1.0, radius: 0.2 };
        let b = AxisSegment { center: Vector3::from(c2), axis: e2.normalize(), half_length: 0.7, radius: 0.3 };
        let cp = closest_points(&a, &b);
        prop_assert!(cp.m.abs() <= 1.0 && cp.n.abs() <= 0.7);
        let best = (0..=40).flat_map(|i| (0..=40).map(move |j| (i, j))).map(|(i, j)| {
            let m = -1.0 + 2.0 * f64::from(i) / 40.0;
            let n = -0.7 + 1.4 * f64::from(j) / 40.0;
            (b.center + b.axis * n - a.axis * m).norm()
        }).fold(f64::INFINITY, f64::min);
        prop_assert!(cp.distance <= best + 1e-12, "{} > {best}", cp.distance);
        prop_assert!((cp.gap - (cp.distance - 0.5)).abs() < 1e-15);
    }
}

#[test]
fn asb_is_the_lie_bracket() {
    // aᵀ S^Γ b = (W [a, b])_Γ for the smooth null fields (D.2.2): the skew matrices (D.1.5)
    // against the Lie bracket [a, b] = (∂b) a − (∂a) b taken by central differences.
    let sys = single();
    let q = [0.1, -0.4, 0.9, 0.8, 0.6, 0.2];
    let field =
        |q: &[f64], i: usize| DVector::from_row_slice(&sys.printed_null_basis(q[3], q[4])[i]);
    let along = |i: usize, dir: &DVector<f64>| {
        let h = 1e-6;
        let shifted = |s: f64| {
            q.iter()
                .zip(dir.iter())
                .map(|(a, d)| a + s * d)
                .collect::<Vec<_>>()
        };
        (field(&shifted(h), i) - field(&shifted(-h), i)) / (2.0 * h)
    };
    let skew = skew_matrices(&sys, &q).unwrap();
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let (a, b) = (field(&q, i), field(&q, j));
        let bracket = along(j, &a) - along(i, &b);
        let w_bracket = &skew.w * bracket;
        for gamma in 0..3 {
            let lhs = bilinear(&skew.s[gamma], &a, &b);
            assert!(
                (lhs - w_bracket[gamma]).abs() < 1e-8,
                "({i},{j}) Γ={gamma}: {lhs} vs {}",
                w_bracket[gamma]
            );
        }
    }
}
