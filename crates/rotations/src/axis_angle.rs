//! The axis–angle form R(θ, r) of a rotation, (2.2.1)₁, and its canonical inverse.

use crate::quaternion::{canonical_quaternion, quaternion_from_matrix};
use crate::skew::skewt;
use crate::RotationError;
use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// R(θ, r) = cos θ (I − r⊗r) + sin θ skewt(r) + r⊗r, (2.2.1)₁.
///
/// `axis` need not be a unit vector; it is normalised.
///
/// # Errors
/// [`RotationError::ZeroAxis`] for a zero axis, [`RotationError::Input`] for NaN or
/// infinite input.
pub fn rotation_from_axis_angle(
    angle: f64,
    axis: &Vector3<f64>,
) -> Result<Rotation3<f64>, RotationError> {
    let r = unit_axis(axis)?;
    if !angle.is_finite() {
        return Err(RotationError::Input(input::InputError::NonFinite(
            "angle".into(),
        )));
    }
    Ok(axis_angle_matrix(angle, &r))
}

/// The matrix of (2.2.1)₁ for a unit axis.
fn axis_angle_matrix(angle: f64, r: &Unit<Vector3<f64>>) -> Rotation3<f64> {
    let rr = r.into_inner() * r.transpose();
    let (s, c) = angle.sin_cos();
    Rotation3::from_matrix_unchecked(c * (Matrix3::identity() - rr) + s * skewt(r) + rr)
}

/// Normalises an axis, rejecting zero and non-finite vectors.
pub(crate) fn unit_axis(axis: &Vector3<f64>) -> Result<Unit<Vector3<f64>>, RotationError> {
    if !axis.iter().all(|v| v.is_finite()) {
        return Err(RotationError::Input(input::InputError::NonFinite(
            "axis".into(),
        )));
    }
    // Scale by the largest component first: the norm of (1e300, 1e300, 0) overflows, and
    // dividing by an infinite norm would give a zero axis.
    let scale = axis.amax();
    if scale == 0.0 {
        return Err(RotationError::ZeroAxis);
    }
    Unit::try_new(axis / scale, 0.0).ok_or(RotationError::ZeroAxis)
}

/// A rotation as an angle θ and a unit axis r: R = R(θ, r).
///
/// Because R(θ, r) = R(−θ, −r) = R(θ + 2π, r) (2.2.3)–(2.2.4), the same rotation has
/// many pairs. [`AxisAngle::from_rotation`] returns the **canonical** one:
/// θ ∈ [0, π]; at θ = 0 the axis is E3 (any axis would do); at θ = π, where r and −r
/// give the same rotation, the axis whose first non-zero component is positive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxisAngle {
    /// Angle of rotation θ, radians.
    pub angle: f64,
    /// Unit axis of rotation r, components on E1, E2, E3.
    pub axis: Unit<Vector3<f64>>,
}

impl AxisAngle {
    /// An axis–angle pair; the axis is normalised (not canonicalised: use
    /// [`AxisAngle::canonical`] for that).
    ///
    /// # Errors
    /// A zero or non-finite axis, or a non-finite angle.
    pub fn new(angle: f64, axis: Vector3<f64>) -> Result<Self, RotationError> {
        if !angle.is_finite() {
            return Err(RotationError::Input(input::InputError::NonFinite(
                "angle".into(),
            )));
        }
        Ok(Self {
            angle,
            axis: unit_axis(&axis)?,
        })
    }

    /// The rotation tensor R(θ, r), (2.2.1)₁.
    #[must_use]
    pub fn to_rotation(&self) -> Rotation3<f64> {
        axis_angle_matrix(self.angle, &self.axis)
    }

    /// The unit quaternion q0 = cos(θ/2), q = sin(θ/2) r, (2.2.2).
    #[must_use]
    pub fn to_quaternion(&self) -> UnitQuaternion<f64> {
        let (s, c) = (0.5 * self.angle).sin_cos();
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::from_parts(
            c,
            s * self.axis.into_inner(),
        ))
    }

    /// The canonical axis–angle pair of a rotation (see the type's documentation).
    ///
    /// Computed from the canonical quaternion (q0 ≥ 0) as θ = 2 atan2(|q|, q0) and
    /// r = q/|q|: both stay accurate near θ = 0 and θ = π, unlike arccos of the trace.
    #[must_use]
    pub fn from_rotation(rotation: &Rotation3<f64>) -> Self {
        Self::from_quaternion(&quaternion_from_matrix(rotation.matrix()))
    }

    /// The canonical axis–angle pair of a unit quaternion.
    #[must_use]
    pub fn from_quaternion(q: &UnitQuaternion<f64>) -> Self {
        let q = canonical_quaternion(q);
        let v = q.vector().into_owned();
        let s = v.norm();
        let angle = 2.0 * s.atan2(q.scalar());
        let axis = if s > 0.0 {
            Unit::new_unchecked(v / s)
        } else {
            Vector3::z_axis()
        };
        Self { angle, axis }.canonical()
    }

    /// The canonical pair of the same rotation: θ in [0, π] (reduced modulo 2π, with the
    /// axis flipped where θ was negative), E3 at θ = 0, and at θ = π the axis whose first
    /// non-zero component is positive.
    #[must_use]
    pub fn canonical(self) -> Self {
        let mut angle = self.angle.rem_euclid(std::f64::consts::TAU);
        let mut axis = self.axis;
        if angle > std::f64::consts::PI {
            angle = std::f64::consts::TAU - angle;
            axis = -axis;
        }
        if angle == 0.0 {
            axis = Vector3::z_axis();
        } else if angle == std::f64::consts::PI {
            let first = axis
                .iter()
                .copied()
                .find(|c| c.abs() > 1e-15)
                .unwrap_or(1.0);
            if first < 0.0 {
                axis = -axis;
            }
        }
        Self { angle, axis }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_huge_axis_is_normalized_not_zeroed() {
        let unit = AxisAngle::new(0.7, Vector3::new(1.0, 1.0, 0.0)).unwrap();
        let huge = AxisAngle::new(0.7, Vector3::new(1e300, 1e300, 0.0)).unwrap();
        assert!((unit.axis.into_inner() - huge.axis.into_inner()).norm() < 1e-15);
        assert!((huge.to_rotation().matrix() - unit.to_rotation().matrix()).norm() < 1e-15);
    }
    use std::f64::consts::PI;

    #[test]
    fn agrees_with_nalgebra() {
        let axis = Vector3::new(0.3, -0.5, 0.8);
        let r = rotation_from_axis_angle(1.1, &axis).unwrap();
        let n = Rotation3::from_axis_angle(&Unit::new_normalize(axis), 1.1);
        assert!((r.matrix() - n.matrix()).norm() < 1e-15);
    }

    #[test]
    fn inverse_by_sign_of_angle_or_axis() {
        // (2.2.3): Rᵀ = R(−θ, r) = R(θ, −r); (2.2.4): R(θ, r) = R(−θ, −r).
        let axis = Vector3::new(1.0, 2.0, -0.5);
        let r = rotation_from_axis_angle(0.7, &axis).unwrap();
        let a = rotation_from_axis_angle(-0.7, &axis).unwrap();
        let b = rotation_from_axis_angle(0.7, &-axis).unwrap();
        let c = rotation_from_axis_angle(-0.7, &-axis).unwrap();
        assert!((r.transpose().matrix() - a.matrix()).norm() < 1e-15);
        assert!((a.matrix() - b.matrix()).norm() < 1e-15);
        assert!((r.matrix() - c.matrix()).norm() < 1e-15);
        // The axis is an eigenvector: R r = r.
        let unit = axis.normalize();
        assert!((r * unit - unit).norm() < 1e-15);
    }

    #[test]
    fn canonical_forms() {
        let aa = AxisAngle::new(-0.4, Vector3::x()).unwrap().canonical();
        assert!((aa.angle - 0.4).abs() < 1e-15 && (aa.axis.x + 1.0).abs() < 1e-15);
        let id = AxisAngle::from_rotation(&Rotation3::identity());
        assert_eq!(id.angle, 0.0);
        assert_eq!(id.axis.into_inner(), Vector3::z());
        let half = AxisAngle::from_rotation(&rotation_from_axis_angle(PI, &-Vector3::y()).unwrap());
        assert!((half.angle - PI).abs() < 1e-15);
        assert!((half.axis.y - 1.0).abs() < 1e-15);
    }

    #[test]
    fn rejects_bad_input() {
        assert_eq!(
            rotation_from_axis_angle(1.0, &Vector3::zeros()),
            Err(RotationError::ZeroAxis)
        );
        assert!(rotation_from_axis_angle(f64::NAN, &Vector3::x()).is_err());
        assert!(AxisAngle::new(1.0, Vector3::new(f64::NAN, 0.0, 1.0)).is_err());
    }
}
