//! The contact rows of whole scenes against finite differences, including the explicit
//! time dependence from a moving base, and property tests of the App. G geometry.

use blockstack::scenarios::{lire, lire_on_floor, shaking_column, Perturbation, Shaking};
use blockstack::{BodyState, Interface, Pose, Scene, Size, Support, Twist};
use proptest::prelude::*;

/// q(s) = q + s u + ½ s² a, u(s) = u + s a.
fn along(q: &[f64], u: &[f64], a: &[f64], s: f64) -> (Vec<f64>, Vec<f64>) {
    let qs = q
        .iter()
        .zip(u)
        .zip(a)
        .map(|((q, u), a)| q + s * u + 0.5 * s * s * a)
        .collect();
    let us = u.iter().zip(a).map(|(u, a)| u + s * a).collect();
    (qs, us)
}

/// Checks ġ = wᵀu + χ, g̈ = wᵀa + ζ for the gaps and γ = wᵀu + χ, γ̇ = wᵀa + ζ for the
/// slips, by central differences in time along a trajectory with accelerations a.
fn check_scene(scene: &Scene, t: f64, q: &[f64], u: &[f64], a: &[f64]) {
    let c = scene.contacts(t, q, u);
    let h = 1e-4;
    let at = |s: f64| {
        let (qs, us) = along(q, u, a, s);
        scene.contacts(t + s, &qs, &us)
    };
    let (p, m) = (at(h), at(-h));
    for (i, row) in c.normals.iter().enumerate() {
        let (Some(row), Some(rp), Some(rm)) = (row, p.normals[i], m.normals[i]) else {
            continue;
        };
        let rate = (rp.value - rm.value) / (2.0 * h);
        let second = (rp.value - 2.0 * row.value + rm.value) / (h * h);
        let expect_rate = row.w.dot(u) + row.chi;
        let expect_second = row.w.dot(a) + row.zeta;
        assert!(
            (rate - expect_rate).abs() < 1e-6,
            "gap {i}: rate {rate} vs {expect_rate}"
        );
        assert!(
            (second - expect_second).abs() < 1e-4,
            "gap {i}: second {second} vs {expect_second}"
        );
    }
    for (i, row) in c.slips.iter().enumerate() {
        assert!(
            (row.w.dot(u) + row.chi - row.value).abs() < 1e-13,
            "slip {i} value"
        );
        let rate = (p.slips[i].value - m.slips[i].value) / (2.0 * h);
        let expect = row.w.dot(a) + row.zeta;
        assert!(
            (rate - expect).abs() < 1e-6,
            "slip {i}: rate {rate} vs {expect}"
        );
    }
}

fn perturbed_state(scene: &Scene, seed: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q = scene.initial_coordinates();
    let n = q.len();
    for (i, qi) in q.iter_mut().enumerate() {
        let k = i as f64 + seed;
        *qi += 0.002 * (1.3 * k).sin()
            + if i % 3 == 2 {
                0.01 * (0.7 * k).cos()
            } else {
                0.0
            };
    }
    let u = (0..n)
        .map(|i| 0.3 * (0.9 * (i as f64 + seed)).sin())
        .collect();
    let a = (0..n)
        .map(|i| 0.5 * (1.7 * (i as f64 + seed)).cos())
        .collect();
    (q, u, a)
}

#[test]
fn lire_rows_match_finite_differences() {
    // With the floor: the interface and the floor rows.
    let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
    for seed in [0.0, 1.0, 2.5] {
        let (q, u, a) = perturbed_state(&scene, seed);
        check_scene(&scene, 0.0, &q, &u, &a);
    }
}

#[test]
fn shaken_column_rows_include_the_base_motion() {
    let scene = shaking_column(&Shaking {
        omega: 3.0,
        amplitude: 0.2,
        ..Shaking::default()
    })
    .unwrap();
    for (seed, t) in [(0.0, 0.1), (3.0, 0.77)] {
        let (q, u, a) = perturbed_state(&scene, seed);
        check_scene(&scene, t, &q, &u, &a);
        // The base–block-1 rows depend on time: χ ≠ 0 while the base moves.
        let c = scene.contacts(t, &q, &u);
        assert!(c.slips[0].chi.abs() > 1e-3);
    }
}

#[test]
fn a_resting_column_has_closed_contacts_and_zero_rates() {
    let scene = shaking_column(&Shaking::default()).unwrap();
    let q = scene.initial_coordinates();
    let u = vec![0.0; q.len()];
    let c = scene.contacts(0.0, &q, &u);
    for row in &c.normals[..8] {
        let row = row.expect("supported");
        assert!(row.value.abs() < 1e-14);
    }
    // The floor is 0.1 below the base's top: block 1's bottom corners are 0.1 above it.
    assert!((c.normals[8 + 2].unwrap().value - 0.1).abs() < 1e-14);
    assert_eq!(scene.friction_laws()[0].normals, vec![0, 1]);
    assert_eq!(scene.friction_laws()[4].normals, vec![8, 9, 10, 11]);
    assert!((c.min_gap().unwrap()).abs() < 1e-14);
}

fn state(x: f64, y: f64, th: f64) -> BodyState {
    BodyState::new(Pose::new(x, y, th), Twist::new(0.2, -0.1, 0.3))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Rows of either gap match finite differences wherever the case of (G.2.2) does not
    /// change within the difference stencil.
    #[test]
    fn interface_gap_rows_match_finite_differences(
        x in -0.6..0.6f64, y in 0.18..0.3f64, th in -0.4..0.4f64, thl in -0.2..0.2f64,
        vx in -1.0..1.0f64, om in -2.0..2.0f64, oml in -2.0..2.0f64,
    ) {
        let i = Interface::new(Size::new(1.0, 0.2), Size::new(0.8, 0.2));
        let lower = BodyState::new(Pose::new(0.0, 0.0, thl), Twist::new(-0.3, 0.1, oml));
        let upper = BodyState::new(Pose::new(x, y, th), Twist::new(vx, 0.4, om));
        let h = 1e-6;
        for left in [true, false] {
            let pick = |l: &BodyState, u: &BodyState| if left { i.left_gap(l, u) } else { i.right_gap(l, u) };
            let g = pick(&lower, &upper);
            for k in 0..3 {
                let shifted = |s: f64| {
                    let mut p = upper.pose;
                    match k { 0 => p.x += s, 1 => p.y += s, _ => p.theta += s }
                    pick(&lower, &BodyState::new(p, upper.twist))
                };
                let (gp, gm) = (shifted(h), shifted(-h));
                prop_assume!(gp.case == g.case && gm.case == g.case);
                let fd = (gp.row.value - gm.row.value) / (2.0 * h);
                prop_assert!((fd - g.row.w_second[k]).abs() < 1e-7);
            }
        }
    }

    /// The support test depends on the angles only modulo 2π, and declares a block turned
    /// by more than π/2 relative to the one below as unsupported, whatever its position
    /// (ERRATA 23).
    #[test]
    fn support_is_periodic_and_robust_past_a_quarter_turn(
        x in -1.5..1.5f64, y in 0.05..1.5f64, th in -3.1..3.1f64, turns in -3i32..3,
    ) {
        let i = Interface::new(Size::new(1.0, 0.2), Size::new(1.0, 0.2));
        let lower = state(0.0, 0.0, 0.0);
        let s1 = i.support(&lower, &state(x, y, th));
        let s2 = i.support(&lower, &state(x, y, th + f64::from(turns) * std::f64::consts::TAU));
        prop_assert_eq!(s1, s2);
        if th.abs() > std::f64::consts::FRAC_PI_2 + 1e-9 {
            prop_assert_eq!(s1, Support::TurnedOver);
        }
    }

    /// A block resting flat anywhere on the one below (overlapping) has both gaps zero.
    #[test]
    fn flat_contact_closes_both_gaps(x in -0.89..0.89f64, thl in -0.3..0.3f64) {
        let i = Interface::new(Size::new(1.0, 0.2), Size::new(0.8, 0.4));
        let lower = BodyState::new(Pose::new(0.1, -0.2, thl), Twist::default());
        let pose = lower.pose;
        let c = pose.point(&blockstack::Vec2::new(x, 0.1 + 0.2));
        let upper = BodyState::new(Pose::new(c.x, c.y, thl), Twist::default());
        let k = i.contacts(&lower, &upper);
        prop_assert_eq!(k.support, Support::Supported);
        prop_assert!(k.left.row.value.abs() < 1e-12 && k.right.row.value.abs() < 1e-12);
    }
}

/// W and ζ agree with forward-mode automatic differentiation through the same geometry
/// to round-off: W = ∂g/∂q (Dual64 seeds) and ζ = uᵀ(∂²g/∂q²)u (Dual2 along u), on a
/// perturbed Lire tower and a toppled block on the floor.
#[test]
fn rows_agree_with_automatic_differentiation() {
    use num_dual::{Dual2_64, Dual64};
    let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
    let (mut q, u, _) = perturbed_state(&scene, 0.7);
    // Block 4 turned over and lying on the floor far to the right.
    q[9] = 3.0;
    q[10] = -0.05;
    q[11] = 2.0;
    let c = scene.contacts(0.0, &q, &u);
    let n = q.len();
    for j in 0..n {
        let qd: Vec<Dual64> = (0..n)
            .map(|i| Dual64::new(q[i], if i == j { 1.0 } else { 0.0 }))
            .collect();
        let ud: Vec<Dual64> = u.iter().map(|&x| Dual64::from(x)).collect();
        let cd = scene.contacts(0.0, &qd, &ud);
        for (row, rd) in c.normals.iter().zip(&cd.normals) {
            let (Some(row), Some(rd)) = (row, rd) else {
                continue;
            };
            let w_j = row
                .w
                .iter()
                .filter(|(i, _)| *i == j)
                .map(|(_, w)| w)
                .sum::<f64>();
            assert!((rd.value.eps - w_j).abs() < 1e-13, "dg/dq_{j}");
        }
    }
    // ζ for the gaps: second derivative of g(q + s u) at s = 0.
    let qs: Vec<Dual2_64> = q
        .iter()
        .zip(&u)
        .map(|(&q, &u)| Dual2_64::new(q, u, 0.0))
        .collect();
    let zero: Vec<Dual2_64> = vec![Dual2_64::from(0.0); n];
    let c2 = scene.contacts(0.0, &qs, &zero);
    let mut checked = 0;
    for (row, r2) in c.normals.iter().zip(&c2.normals) {
        let (Some(row), Some(r2)) = (row, r2) else {
            continue;
        };
        assert!(
            (r2.value.v2 - row.zeta).abs() < 1e-12,
            "zeta {} vs {}",
            r2.value.v2,
            row.zeta
        );
        checked += 1;
    }
    assert_eq!(
        checked,
        6 + 16,
        "three interfaces supported, the fourth lost"
    );
}

#[test]
fn failure_detection_finds_lost_support_and_open_interfaces() {
    let scene = lire(4, Perturbation::None).unwrap();
    let mut q = scene.initial_coordinates();
    let u = vec![0.0; q.len()];
    let c = scene.contacts(0.0, &q, &u);
    assert_eq!(c.first_unsupported(), None);
    assert_eq!(c.first_open(1e-9), None);
    // Lift blocks 3 and 4 by 1 mm: the interface between blocks 2 and 3 (k = 2) opens.
    for k in 2..4 {
        q[3 * k + 1] += 1e-3;
    }
    let c = scene.contacts(0.0, &q, &u);
    assert_eq!(c.first_unsupported(), None);
    assert_eq!(c.first_open(1e-9), Some(2));
    // Slide the top block off: interface 3 loses its support; its gaps cannot close.
    q[9] += 1.2;
    let c = scene.contacts(0.0, &q, &u);
    assert_eq!(c.first_unsupported(), Some(3));
    assert!(c.normals[6].is_none() && c.normals[7].is_none());
}
