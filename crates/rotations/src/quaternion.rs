//! The unit-quaternion form R̃(q0, q) of a rotation, (2.2.1)₂–(2.2.2), and the
//! compound-rotation formula of footnote 3 of Ch. 2.

use crate::skew::skewt;
use crate::RotationError;
use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

/// R̃(q0, q) = (q0² − q·q) I + 2 q⊗q + 2 q0 skewt(q), (2.2.1)₂, for the quaternion
/// [q0, q1, q2, q3] (scalar first), which is normalised first.
///
/// # Errors
/// A zero or non-finite quaternion.
pub fn rotation_from_quaternion(
    q: [f64; 4],
) -> Result<(UnitQuaternion<f64>, Rotation3<f64>), RotationError> {
    if !q.iter().all(|v| v.is_finite()) {
        return Err(RotationError::Input(input::InputError::NonFinite(
            "quaternion".into(),
        )));
    }
    // Scale by the largest component first, so that a quaternion of huge (or tiny)
    // components normalizes instead of overflowing to a zero matrix.
    let scale = q.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return Err(RotationError::ZeroQuaternion);
    }
    let raw = Quaternion::new(q[0], q[1], q[2], q[3]) / scale;
    let unit = UnitQuaternion::new_unchecked(raw / raw.norm());
    Ok((unit, quaternion_matrix(&unit)))
}

/// The matrix of (2.2.1)₂ for a unit quaternion.
pub(crate) fn quaternion_matrix(q: &UnitQuaternion<f64>) -> Rotation3<f64> {
    let q0 = q.scalar();
    let v = q.vector().into_owned();
    let m = (q0 * q0 - v.dot(&v)) * Matrix3::identity()
        + 2.0 * v * v.transpose()
        + 2.0 * q0 * skewt(&v);
    Rotation3::from_matrix_unchecked(m)
}

/// The unit quaternion of a rotation matrix (Shepperd's method: the largest of
/// q0², q1², q2², q3² is taken from the diagonal, the others from off-diagonal sums,
/// so no division by a small number occurs). Canonical sign: q0 ≥ 0.
#[must_use]
pub fn quaternion_from_matrix(m: &Matrix3<f64>) -> UnitQuaternion<f64> {
    let t = m.trace();
    let d = [t, m[(0, 0)], m[(1, 1)], m[(2, 2)]];
    let mut k = 0;
    for i in 1..4 {
        if d[i] > d[k] {
            k = i;
        }
    }
    let (w, x, y, z) = match k {
        0 => {
            let s = 2.0 * (1.0 + t).sqrt();
            (
                0.25 * s,
                (m[(2, 1)] - m[(1, 2)]) / s,
                (m[(0, 2)] - m[(2, 0)]) / s,
                (m[(1, 0)] - m[(0, 1)]) / s,
            )
        }
        1 => {
            let s = 2.0 * (1.0 + m[(0, 0)] - m[(1, 1)] - m[(2, 2)]).sqrt();
            (
                (m[(2, 1)] - m[(1, 2)]) / s,
                0.25 * s,
                (m[(0, 1)] + m[(1, 0)]) / s,
                (m[(0, 2)] + m[(2, 0)]) / s,
            )
        }
        2 => {
            let s = 2.0 * (1.0 - m[(0, 0)] + m[(1, 1)] - m[(2, 2)]).sqrt();
            (
                (m[(0, 2)] - m[(2, 0)]) / s,
                (m[(0, 1)] + m[(1, 0)]) / s,
                0.25 * s,
                (m[(1, 2)] + m[(2, 1)]) / s,
            )
        }
        _ => {
            let s = 2.0 * (1.0 - m[(0, 0)] - m[(1, 1)] + m[(2, 2)]).sqrt();
            (
                (m[(1, 0)] - m[(0, 1)]) / s,
                (m[(0, 2)] + m[(2, 0)]) / s,
                (m[(1, 2)] + m[(2, 1)]) / s,
                0.25 * s,
            )
        }
    };
    canonical_quaternion(&UnitQuaternion::new_normalize(Quaternion::new(w, x, y, z)))
}

/// The representative of ±(q0, q) (2.2.4) with q0 > 0, or, when q0 = 0, with the first
/// non-zero component of q positive.
#[must_use]
pub fn canonical_quaternion(q: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    let c = q.coords; // (x, y, z, w) storage
    let first = [c.w, c.x, c.y, c.z]
        .into_iter()
        .find(|v| *v != 0.0)
        .unwrap_or(1.0);
    if first < 0.0 {
        UnitQuaternion::new_unchecked(-q.into_inner())
    } else {
        *q
    }
}

/// The compound rotation C = B A (A first) of two unit quaternions, footnote 3 of Ch. 2:
/// c0 = a0 b0 − a·b, c = a0 b + b0 a + b × a.
#[must_use]
pub fn compound(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    let (a0, av) = (a.scalar(), a.vector().into_owned());
    let (b0, bv) = (b.scalar(), b.vector().into_owned());
    let c0 = a0 * b0 - av.dot(&bv);
    let c: Vector3<f64> = a0 * bv + b0 * av + bv.cross(&av);
    UnitQuaternion::new_unchecked(Quaternion::from_parts(c0, c))
}

/// A rotation from a 3×3 matrix given row by row, checked and projected.
///
/// The matrix must be within `tolerance` (Frobenius norm of RᵀR − I) of orthogonal and
/// have a positive determinant; it is then replaced by the nearest rotation (polar
/// decomposition R = U Vᵀ from the SVD), so 6-digit printed matrices are accepted.
///
/// # Errors
/// Non-finite entries, or a matrix that is not close to a rotation.
pub fn rotation_from_matrix(
    m: &Matrix3<f64>,
    tolerance: f64,
) -> Result<Rotation3<f64>, RotationError> {
    if !m.iter().all(|v| v.is_finite()) {
        return Err(RotationError::Input(input::InputError::NonFinite(
            "matrix".into(),
        )));
    }
    let orthogonality = (m.transpose() * m - Matrix3::identity()).norm();
    let det = m.determinant();
    if orthogonality > tolerance || det <= 0.0 {
        return Err(RotationError::NotARotation { orthogonality, det });
    }
    let svd = m.svd(true, true);
    match (svd.u, svd.v_t) {
        (Some(u), Some(v_t)) => Ok(Rotation3::from_matrix_unchecked(u * v_t)),
        _ => Err(RotationError::NotARotation { orthogonality, det }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_quaternions_normalize_to_the_same_rotation() {
        let (_, r) = rotation_from_quaternion([1.0, 2.0, 3.0, 4.0]).unwrap();
        for scale in [1e200, 1e300, 1e-200, 1e-310] {
            let q = [scale, 2.0 * scale, 3.0 * scale, 4.0 * scale];
            let (_, big) = rotation_from_quaternion(q).unwrap();
            assert!((big.matrix() - r.matrix()).norm() < 1e-15, "scale {scale}");
        }
    }
    use nalgebra::Unit;

    #[test]
    fn quaternion_matrix_matches_nalgebra() {
        let q =
            UnitQuaternion::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)), 2.5);
        let m = quaternion_matrix(&q);
        assert!((m.matrix() - q.to_rotation_matrix().matrix()).norm() < 1e-15);
        let back = quaternion_from_matrix(m.matrix());
        assert!((back.coords - canonical_quaternion(&q).coords).norm() < 1e-15);
    }

    #[test]
    fn rejects_non_rotations() {
        assert!(rotation_from_quaternion([0.0; 4]).is_err());
        assert!(rotation_from_quaternion([f64::NAN, 0.0, 0.0, 1.0]).is_err());
        let reflection = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        assert!(rotation_from_matrix(&reflection, 1e-6).is_err());
        assert!(rotation_from_matrix(&(2.0 * Matrix3::identity()), 1e-6).is_err());
    }

    #[test]
    fn projects_rounded_matrices() {
        let r = Rotation3::from_axis_angle(&Vector3::y_axis(), 0.3);
        let rounded = r.matrix().map(|v: f64| (v * 1e6).round() / 1e6);
        let p = rotation_from_matrix(&rounded, 1e-4).unwrap();
        assert!((p.matrix() - r.matrix()).norm() < 2e-6);
        assert!((p.matrix().transpose() * p.matrix() - Matrix3::identity()).norm() < 1e-14);
    }
}
