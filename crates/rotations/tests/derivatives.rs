//! Angular-velocity formulas (2.2.5) and (A.2.1) against central finite differences of
//! the rotation: skewt(ω) = Ṙ Rᵀ.

use rotations::{
    axial, axis_angle_angular_velocity, AxisAngle, EulerSet, Matrix3, Rotation3, Vector3,
};

/// ω from a central difference of R(t), via skewt(ω) = Ṙ Rᵀ.
fn finite_difference_omega(r: impl Fn(f64) -> Rotation3<f64>, t: f64) -> Vector3<f64> {
    let h = 1e-6;
    let rdot: Matrix3<f64> = (r(t + h).matrix() - r(t - h).matrix()) / (2.0 * h);
    axial(&(rdot * r(t).matrix().transpose()))
}

#[test]
fn axis_angle_angular_velocity_matches_finite_differences() {
    // r(t) on the unit sphere, θ(t) arbitrary: both change.
    let axis = |t: f64| {
        Vector3::new(
            (0.7 * t).cos() * (0.3 + t).sin(),
            (0.7 * t).sin() * (0.3 + t).sin(),
            (0.3 + t).cos(),
        )
    };
    let angle = |t: f64| 0.4 + 2.0 * t - t * t;
    for &t in &[0.0, 0.37, 1.1, 2.4] {
        let h = 1e-6;
        let r = axis(t);
        let rdot = (axis(t + h) - axis(t - h)) / (2.0 * h);
        let thetadot = (angle(t + h) - angle(t - h)) / (2.0 * h);
        let w = axis_angle_angular_velocity(angle(t), thetadot, &r, &rdot);
        let fd = finite_difference_omega(
            |s| AxisAngle::new(angle(s), axis(s)).unwrap().to_rotation(),
            t,
        );
        assert!((w - fd).norm() < 1e-8, "t = {t}: {w:?} vs {fd:?}");
    }
}

#[test]
fn euler_angular_velocity_matches_finite_differences_for_all_sets() {
    let angles = |t: f64| [0.3 + 1.2 * t, 0.7 - 0.4 * t, -1.0 + 2.0 * t * t];
    let rates = |t: f64| [1.2, -0.4, 4.0 * t];
    for set in EulerSet::ALL {
        for &t in &[0.1, 0.5, 0.9] {
            let w = set.angular_velocity(angles(t), rates(t));
            let fd = finite_difference_omega(|s| set.rotation(angles(s)), t);
            assert!((w - fd).norm() < 1e-8, "{set} t = {t}: {w:?} vs {fd:?}");
        }
    }
}

#[test]
fn inverse_rotation_by_negated_angle() {
    // (2.2.3) on a rotation built from Euler angles.
    let r = EulerSet::from_name("3-2-1")
        .unwrap()
        .rotation([0.2, -0.5, 1.3]);
    let aa = AxisAngle::from_rotation(&r);
    let inv = AxisAngle::new(-aa.angle, aa.axis.into_inner())
        .unwrap()
        .to_rotation();
    assert!((inv.matrix() - r.transpose().matrix()).norm() < 1e-15);
}
