//! Errors of the holonomy crate.

use rotations::RotationError;

/// Why a rectangle, a target rotation, a path or a rolling run is not acceptable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HolonomyError {
    /// A value that is not finite, positive or non-negative.
    #[error(transparent)]
    Input(#[from] input::InputError),
    /// The starting point S is not on the side of the rectangle: φ1 ∉ [0, φ2] (Figure 2.3).
    #[error("the start parameter phi1 = {phi1} must lie in [0, phi2] = [0, {phi2}]")]
    StartOffSide {
        /// φ1, radians.
        phi1: f64,
        /// φ2, radians.
        phi2: f64,
    },
    /// The target of the planner is the identity: every rectangle of (2.4.8) produces it.
    #[error("the target rotation is the identity: every rectangle of (2.4.8) (a side of length 2nπR, or all sides multiples of πR) produces it")]
    IdentityTarget,
    /// Only the four Euler sets of §2.5 have a three-rectangle construction.
    #[error("Euler set {0} has no three-rectangle construction (§2.5 covers 3-2-3, 3-1-3, 3-2-1 and 3-1-2)")]
    UnsupportedEulerSet(String),
    /// A centre path that cannot be rolled along (too few vertices, zero length, ...).
    #[error("invalid path: {0}")]
    InvalidPath(String),
    /// The number of integration steps must be at least one per segment.
    #[error("steps must be at least {minimum}, got {steps}")]
    TooFewSteps {
        /// Requested.
        steps: usize,
        /// Needed (one per segment of the path).
        minimum: usize,
    },
    /// An error of the rotation tools (zero axis, NaN, ...).
    #[error(transparent)]
    Rotation(#[from] RotationError),
}
