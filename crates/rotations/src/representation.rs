//! A rotation given in one of the representations of §2.2 and App. A: axis–angle
//! (2.2.1)₁, quaternion (2.2.1)₂, matrix, or the angles of an Euler set (A.1.2).
//!
//! This is the typed entry point of `rollstack rotation --from ... --values ...`: the
//! command line reads the numbers, [`Representation::rotation`] checks them and builds
//! the rotation.

use crate::axis_angle::rotation_from_axis_angle;
use crate::euler::EulerSet;
use crate::quaternion::{rotation_from_matrix, rotation_from_quaternion};
use crate::RotationError;
use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// How far a matrix given as input may be from orthogonal (Frobenius norm of RᵀR − I)
/// before it is refused: loose enough for matrices printed to 6 digits, which are then
/// projected onto the nearest rotation ([`rotation_from_matrix`]).
pub const MATRIX_INPUT_TOLERANCE: f64 = 1e-4;

/// The representation a rotation is given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Representation {
    /// `x, y, z, θ`: the axis r (on E1, E2, E3, need not be unit) and the angle θ of
    /// R(θ, r), (2.2.1)₁.
    AxisAngle,
    /// `q0, q1, q2, q3`: a quaternion, scalar first, normalised before use, (2.2.1)₂.
    Quaternion,
    /// Nine entries row by row, entry (i, j) = Eᵢ · R Eⱼ.
    Matrix,
    /// The three angles of an Euler set, R = R(a3, g3) R(a2, g2) R(a1, g1) (A.1.2).
    Euler(EulerSet),
}

impl Representation {
    /// The representation named `axis-angle`, `quaternion`, `matrix` or `euler:SET`
    /// (SET one of the twelve Euler sets, e.g. `euler:3-1-3`).
    ///
    /// # Errors
    /// [`RotationError::UnknownRepresentation`], or [`RotationError::UnknownEulerSet`]
    /// for `euler:` followed by something else than a set.
    pub fn from_name(name: &str) -> Result<Self, RotationError> {
        Ok(match name {
            "axis-angle" => Self::AxisAngle,
            "quaternion" => Self::Quaternion,
            "matrix" => Self::Matrix,
            other => match other.strip_prefix("euler:") {
                Some(set) => Self::Euler(EulerSet::from_name(set)?),
                None => return Err(RotationError::UnknownRepresentation(name.to_owned())),
            },
        })
    }

    /// How many numbers describe a rotation in this representation: 4, 4, 9 or 3.
    #[must_use]
    pub fn value_count(self) -> usize {
        match self {
            Self::AxisAngle | Self::Quaternion => 4,
            Self::Matrix => 9,
            Self::Euler(_) => 3,
        }
    }

    /// Whether value `index` is an angle (radians): the last value of axis–angle and all
    /// three Euler angles. A reader of text input may accept degrees there.
    #[must_use]
    pub fn is_angle(self, index: usize) -> bool {
        match self {
            Self::Euler(_) => true,
            Self::AxisAngle => index == 3,
            Self::Quaternion | Self::Matrix => false,
        }
    }

    /// The rotation described by `values` in this representation: R(θ, r) of (2.2.1)₁,
    /// R̃(q0, q) of (2.2.1)₂ after normalising, the nearest rotation to a matrix within
    /// `matrix_tolerance` of orthogonal (see [`MATRIX_INPUT_TOLERANCE`]), or the Euler
    /// product (A.1.2).
    ///
    /// # Errors
    /// [`RotationError::WrongValueCount`], and the errors of the constructors: a zero
    /// axis or quaternion, non-finite values, a matrix that is not a rotation.
    pub fn rotation(
        self,
        values: &[f64],
        matrix_tolerance: f64,
    ) -> Result<Rotation3<f64>, RotationError> {
        let expected = self.value_count();
        if values.len() != expected {
            return Err(RotationError::WrongValueCount {
                expected,
                got: values.len(),
            });
        }
        let v = values;
        match self {
            Self::AxisAngle => rotation_from_axis_angle(v[3], &Vector3::new(v[0], v[1], v[2])),
            Self::Quaternion => Ok(rotation_from_quaternion([v[0], v[1], v[2], v[3]])?.1),
            Self::Matrix => rotation_from_matrix(&Matrix3::from_row_slice(v), matrix_tolerance),
            Self::Euler(set) => {
                if v.iter().any(|a| !a.is_finite()) {
                    return Err(RotationError::Input(input::InputError::NonFinite(
                        "Euler angles".into(),
                    )));
                }
                Ok(set.rotation([v[0], v[1], v[2]]))
            }
        }
    }
}

impl fmt::Display for Representation {
    /// The name [`Representation::from_name`] reads.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AxisAngle => f.write_str("axis-angle"),
            Self::Quaternion => f.write_str("quaternion"),
            Self::Matrix => f.write_str("matrix"),
            Self::Euler(set) => write!(f, "euler:{set}"),
        }
    }
}

impl FromStr for Representation {
    type Err = RotationError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{rotation_distance, AxisAngle};
    use std::f64::consts::PI;

    #[test]
    fn names_round_trip() {
        for name in [
            "axis-angle",
            "quaternion",
            "matrix",
            "euler:3-1-3",
            "euler:2-3-1",
        ] {
            assert_eq!(Representation::from_name(name).unwrap().to_string(), name);
        }
        assert_eq!(
            Representation::from_name("rodrigues"),
            Err(RotationError::UnknownRepresentation("rodrigues".into()))
        );
        assert!(matches!(
            Representation::from_name("euler:3-3-1"),
            Err(RotationError::UnknownEulerSet(_))
        ));
    }

    #[test]
    fn every_representation_gives_the_same_rotation() {
        let expected = AxisAngle::new(0.75 * PI, Vector3::new(1.0, -2.0, 0.5))
            .unwrap()
            .to_rotation();
        let q = AxisAngle::from_rotation(&expected).to_quaternion();
        let m = expected.matrix();
        let set = EulerSet::from_name("3-1-3").unwrap();
        let cases: [(Representation, Vec<f64>); 4] = [
            (Representation::AxisAngle, vec![1.0, -2.0, 0.5, 0.75 * PI]),
            // Not normalised: scaled by 2.
            (
                Representation::Quaternion,
                vec![2.0 * q.w, 2.0 * q.i, 2.0 * q.j, 2.0 * q.k],
            ),
            (
                Representation::Matrix,
                (0..9).map(|k| m[(k / 3, k % 3)]).collect(),
            ),
            (Representation::Euler(set), set.angles(&expected).to_vec()),
        ];
        for (repr, values) in cases {
            assert_eq!(values.len(), repr.value_count());
            let r = repr.rotation(&values, MATRIX_INPUT_TOLERANCE).unwrap();
            assert!(rotation_distance(&r, &expected) < 1e-14, "{repr}");
        }
    }

    #[test]
    fn bad_values_are_typed_errors() {
        let tol = MATRIX_INPUT_TOLERANCE;
        assert_eq!(
            Representation::Quaternion.rotation(&[1.0, 0.0, 0.0], tol),
            Err(RotationError::WrongValueCount {
                expected: 4,
                got: 3
            })
        );
        assert_eq!(
            Representation::AxisAngle.rotation(&[0.0, 0.0, 0.0, 1.0], tol),
            Err(RotationError::ZeroAxis)
        );
        let reflection = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0];
        assert!(matches!(
            Representation::Matrix.rotation(&reflection, tol),
            Err(RotationError::NotARotation { .. })
        ));
        let set = EulerSet::from_name("3-2-1").unwrap();
        assert!(Representation::Euler(set)
            .rotation(&[1.0, 2.0, f64::INFINITY], tol)
            .is_err());
        assert!(Representation::AxisAngle.is_angle(3) && !Representation::AxisAngle.is_angle(0));
        assert!(Representation::Euler(set).is_angle(0) && !Representation::Matrix.is_angle(8));
    }
}
