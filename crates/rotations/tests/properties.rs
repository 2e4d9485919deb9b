//! Property tests of the rotation tools over random rotations, including the hard cases:
//! angles near 0 and π, and Euler angles at and next to their singular values.

use proptest::prelude::*;
use rotations::{
    canonical_quaternion, compound, quaternion_from_matrix, rotation_distance,
    rotation_from_quaternion, AxisAngle, EulerKind, EulerSet, Rotation3, UnitQuaternion, Vector3,
};
use std::f64::consts::{FRAC_PI_2, PI};

fn unit_vector() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, 0.0..std::f64::consts::TAU).prop_map(|(z, phi)| {
        let s = (1.0 - z * z).sqrt();
        Vector3::new(s * phi.cos(), s * phi.sin(), z)
    })
}

fn quaternion() -> impl Strategy<Value = UnitQuaternion<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_filter("non-zero", |(a, b, c, d)| {
            a * a + b * b + c * c + d * d > 1e-3
        })
        .prop_map(|(a, b, c, d)| {
            UnitQuaternion::new_normalize(nalgebra::Quaternion::new(a, b, c, d))
        })
}

fn rotation() -> impl Strategy<Value = Rotation3<f64>> {
    quaternion().prop_map(UnitQuaternion::to_rotation_matrix)
}

fn euler_set() -> impl Strategy<Value = EulerSet> {
    (0..12usize).prop_map(|i| EulerSet::ALL[i])
}

/// A second angle at a singular value plus `offset`.
fn singular_second_angle(set: EulerSet, which: bool, offset: f64) -> f64 {
    match (set.kind(), which) {
        (EulerKind::Symmetric, false) => offset.abs(),
        (EulerKind::Symmetric, true) => PI - offset.abs(),
        (EulerKind::Asymmetric, false) => FRAC_PI_2 - offset.abs(),
        (EulerKind::Asymmetric, true) => -FRAC_PI_2 + offset.abs(),
    }
}

fn matrix_error(a: &Rotation3<f64>, b: &Rotation3<f64>) -> f64 {
    (a.matrix() - b.matrix()).amax()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Rotation → Euler angles → rotation is exact for every set.
    #[test]
    fn euler_round_trip_from_rotation(r in rotation(), set in euler_set()) {
        let a = set.angles(&r);
        prop_assert!(a.iter().all(|v| v.is_finite()));
        let (lo, hi) = set.second_angle_range();
        prop_assert!(a[1] >= lo && a[1] <= hi);
        prop_assert!(a[0].abs() <= PI && a[2].abs() <= PI);
        prop_assert!(matrix_error(&set.rotation(a), &r) < 1e-12);
    }

    /// Angles in the principal ranges come back unchanged (away from singularities).
    #[test]
    fn euler_round_trip_from_angles(
        set in euler_set(), a1 in -3.1..3.1f64, t in 0.02..0.98f64, a3 in -3.1..3.1f64,
    ) {
        let (lo, hi) = set.second_angle_range();
        let a2 = lo + t * (hi - lo);
        let back = set.angles(&set.rotation([a1, a2, a3]));
        for (x, y) in back.iter().zip([a1, a2, a3]) {
            prop_assert!((x - y).abs() < 1e-11, "{:?} vs {:?}", back, [a1, a2, a3]);
        }
    }

    /// At and next to the singular values of the second angle the angles stay finite and
    /// the composed rotation is still exact.
    #[test]
    fn euler_near_singular(
        set in euler_set(), a1 in -3.1..3.1f64, a3 in -3.1..3.1f64, which in any::<bool>(),
        exponent in 0usize..18,
    ) {
        let offset = if exponent == 17 { 0.0 } else { 10f64.powi(-(exponent as i32)) };
        let r = set.rotation([a1, singular_second_angle(set, which, offset), a3]);
        let a = set.angles(&r);
        prop_assert!(a.iter().all(|v| v.is_finite()));
        prop_assert!(matrix_error(&set.rotation(a), &r) < 1e-12);
        if offset == 0.0 {
            prop_assert_eq!(a[0], 0.0, "documented choice: a1 = 0 at the singular value");
        }
    }

    /// Axis-angle round trip, with the canonical angle in [0, π], including near π.
    #[test]
    fn axis_angle_round_trip(axis in unit_vector(), t in 0.0..1.0f64, near_pi in any::<bool>()) {
        let angle = if near_pi { PI - 1e-9 * t } else { 1e-3 + t * (PI - 2e-3) };
        let aa = AxisAngle::new(angle, axis).unwrap();
        let back = AxisAngle::from_rotation(&aa.to_rotation());
        prop_assert!((back.angle - angle).abs() < 1e-12);
        prop_assert!((back.axis.into_inner() - axis).norm() < 1e-12, "axis {:?} vs {:?}", back.axis, axis);
    }

    /// Tiny angles: the angle is recovered to round-off, the rotation exactly.
    #[test]
    fn axis_angle_tiny(axis in unit_vector(), e in 4.0..15.0f64) {
        let angle = 10f64.powf(-e);
        let r = AxisAngle::new(angle, axis).unwrap().to_rotation();
        let back = AxisAngle::from_rotation(&r);
        prop_assert!((back.angle - angle).abs() < 1e-15);
        prop_assert!(matrix_error(&back.to_rotation(), &r) < 1e-15);
    }

    /// (2.2.4): (q0, q) and (−q0, −q) give the same rotation; canonical form has q0 ≥ 0.
    #[test]
    fn two_to_one_cover(q in quaternion()) {
        let (_, r1) = rotation_from_quaternion([q.w, q.i, q.j, q.k]).unwrap();
        let (_, r2) = rotation_from_quaternion([-q.w, -q.i, -q.j, -q.k]).unwrap();
        prop_assert!(matrix_error(&r1, &r2) < 1e-15);
        let c = quaternion_from_matrix(r1.matrix());
        prop_assert!(c.w >= 0.0);
        prop_assert!((c.coords - canonical_quaternion(&q).coords).norm() < 1e-12);
    }

    /// Footnote 3 of Ch. 2: the compound quaternion of C = B A matches the matrix product.
    #[test]
    fn compound_rotation_formula(a in quaternion(), b in quaternion()) {
        let c = compound(&a, &b);
        let product = b.to_rotation_matrix() * a.to_rotation_matrix();
        prop_assert!(matrix_error(&c.to_rotation_matrix(), &product) < 1e-14);
        prop_assert!((c.norm() - 1.0).abs() < 1e-14);
    }

    /// The dual basis is dual (A.2.2), and rates → ω → rates is the identity.
    #[test]
    fn dual_basis_and_rates(
        set in euler_set(), a1 in -3.1..3.1f64, t in 0.05..0.95f64, a3 in -3.1..3.1f64,
        rates in prop::array::uniform3(-5.0..5.0f64),
    ) {
        let (lo, hi) = set.second_angle_range();
        let angles = [a1, lo + t * (hi - lo), a3];
        let g = set.basis(angles);
        let d = set.dual_basis(angles).unwrap();
        for i in 0..3 {
            for k in 0..3 {
                let expect = if i == k { 1.0 } else { 0.0 };
                prop_assert!((g[k].dot(&d[i]) - expect).abs() < 1e-12);
            }
        }
        let w = set.angular_velocity(angles, rates);
        let back = set.angle_rates(angles, &w).unwrap();
        for (x, y) in back.iter().zip(rates) {
            prop_assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()) / t.min(1.0 - t));
        }
    }
}

#[test]
fn dual_basis_is_none_at_singularity() {
    for set in EulerSet::ALL {
        let a2 = singular_second_angle(set, false, 0.0);
        assert!(set.dual_basis([0.3, a2, -0.2]).is_none(), "{set}");
        assert!(set.is_singular([0.3, a2, -0.2], 1e-12));
    }
}

#[test]
fn distance_is_the_relative_angle() {
    let a = AxisAngle::new(0.3, Vector3::x()).unwrap().to_rotation();
    let b = AxisAngle::new(0.8, Vector3::x()).unwrap().to_rotation();
    assert!((rotation_distance(&a, &b) - 0.5).abs() < 1e-15);
}
