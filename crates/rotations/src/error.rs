//! Errors of the rotation constructors.

/// Why an input does not describe a rotation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RotationError {
    /// The axis of rotation has zero length, so it has no direction.
    #[error("the axis of rotation is zero")]
    ZeroAxis,
    /// A quaternion of zero norm cannot be normalised.
    #[error("the quaternion is zero")]
    ZeroQuaternion,
    /// An input value is not finite.
    #[error(transparent)]
    Input(#[from] input::InputError),
    /// A matrix is not close to a proper orthogonal one.
    #[error("the matrix is not a rotation (|RᵀR − I| = {orthogonality:.2e}, det = {det:.6})")]
    NotARotation {
        /// Frobenius norm of RᵀR − I.
        orthogonality: f64,
        /// Determinant of the matrix.
        det: f64,
    },
    /// The name of an Euler-angle set is not one of the twelve.
    #[error("unknown Euler-angle set '{0}' (expected one of 1-2-1, 1-2-3, 1-3-1, 1-3-2, 2-1-2, 2-1-3, 2-3-1, 2-3-2, 3-1-2, 3-1-3, 3-2-1, 3-2-3)")]
    UnknownEulerSet(String),
    /// The name of a representation is not one of `axis-angle`, `quaternion`, `matrix`,
    /// `euler:SET`.
    #[error("unknown representation '{0}' (expected axis-angle, quaternion, matrix or euler:SET)")]
    UnknownRepresentation(String),
    /// A representation got the wrong number of values.
    #[error("{expected} values are needed for this representation, got {got}")]
    WrongValueCount {
        /// How many the representation takes.
        expected: usize,
        /// How many were given.
        got: usize,
    },
}
