//! Errors of the cylinder models.

/// Why an input does not describe a valid cylinder problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CylinderError {
    /// An input value is NaN or infinite.
    #[error("{0} must be a finite number")]
    NonFinite(&'static str),
    /// A length or ratio that must be positive is not.
    #[error("{name} must be positive, got {value}")]
    NotPositive {
        /// Which input.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A quantity that must not be negative is.
    #[error("{name} must not be negative, got {value}")]
    Negative {
        /// Which input.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The inclination is outside the range where the cylinder touches the plane at
    /// one rim point (§3.2: ϑ ∈ (0, π/2)).
    #[error("the inclination ϑ = {0} rad is outside (0, π/2): the point-contact assumption of §3.2 fails (at ϑ = 0 the base lies flat, at π/2 the side does)")]
    NotPointContact(f64),
    /// An input outside its documented range.
    #[error("{name} = {value} is outside {range}")]
    OutOfRange {
        /// Which input.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// No applied force can sustain the steady motion at this inclination (the static
    /// friction criterion and F3 ≥ 0, N ≥ 0 cannot all hold), §3.3.
    #[error("no steady support exists at ϑ = {theta} rad for r/h = {r_over_h}, μ = {mu}")]
    NoSupport {
        /// Inclination.
        theta: f64,
        /// Aspect ratio r/h.
        r_over_h: f64,
        /// Friction coefficient.
        mu: f64,
    },
    /// The circle traced by the centre of mass would have a non-positive radius.
    #[error("the centre of mass would trace a circle of radius k = {k} ≤ 0 for ℓ = {ell}: choose a larger ℓ")]
    DegenerateCircle {
        /// Radius of the path of P.
        ell: f64,
        /// Resulting radius of the path of the centre of mass, (3.4.15).
        k: f64,
    },
    /// The two axes are parallel, so the closest points are not unique and their rates
    /// (E.2.5) do not exist (line contact, H singular).
    #[error("the cylinder axes are parallel (|e3_I · e3_II| = {0}): H in (E.2.4) is singular")]
    ParallelAxes(f64),
    /// A dimension mismatch between a system and the coordinates given to it.
    #[error("expected {expected} coordinates, got {got}")]
    Dimension {
        /// Number of coordinates of the system.
        expected: usize,
        /// Number given.
        got: usize,
    },
}

/// Rejects a non-finite value.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, CylinderError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(CylinderError::NonFinite(name))
    }
}

/// Rejects a non-finite or non-positive value.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, CylinderError> {
    if finite(name, value)? > 0.0 {
        Ok(value)
    } else {
        Err(CylinderError::NotPositive { name, value })
    }
}

/// Rejects a non-finite or negative value.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, CylinderError> {
    if finite(name, value)? >= 0.0 {
        Ok(value)
    } else {
        Err(CylinderError::Negative { name, value })
    }
}
