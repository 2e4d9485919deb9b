//! The input checks every rollstack crate makes, defined once: a value must be finite,
//! positive, non-negative, or within a range. Each crate's error type wraps
//! [`InputError`] (`#[error(transparent)] Input(#[from] InputError)`), so a bad μ reads
//! the same whether the sphere, the cylinders or the block stack refuses it.
//!
//! [`text`] reads the forms a user types: angles (`1.2`, `90deg`, `3pi/2`), finite
//! numbers, comma-separated lists and `A:B:STEP` ranges.
//!
//! ```
//! use input::{in_range, non_negative, positive, InputError};
//!
//! assert_eq!(positive("dt", 0.01)?, 0.01);
//! assert_eq!(
//!     non_negative("mu", -0.1).unwrap_err().to_string(),
//!     "mu must not be negative, got -0.1"
//! );
//! assert_eq!(
//!     positive("width", f64::NAN).unwrap_err(),
//!     InputError::NonFinite("width".into())
//! );
//! assert!(in_range("e_n", 1.5, 0.0..=1.0, "[0, 1]").is_err());
//! # Ok::<(), InputError>(())
//! ```
#![warn(missing_docs)]

pub mod text;
pub mod watchdog;

use std::ops::RangeInclusive;

/// A value that is not acceptable input, named by what it is (`"block 2 width"`,
/// `"mu"`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// The value is NaN or infinite.
    #[error("{0} is not finite")]
    NonFinite(String),
    /// A size, mass or step that must be positive is zero or negative.
    #[error("{name} must be positive, got {}", Short(*.value))]
    NotPositive {
        /// What the value is.
        name: String,
        /// The value given.
        value: f64,
    },
    /// A value that must not be negative is.
    #[error("{name} must not be negative, got {}", Short(*.value))]
    Negative {
        /// What the value is.
        name: String,
        /// The value given.
        value: f64,
    },
    /// A value lies outside its admissible interval.
    #[error("{name} must lie in {range}, got {}", Short(*.value))]
    OutOfRange {
        /// What the value is.
        name: String,
        /// The admissible interval, as text (e.g. "[0, 1]").
        range: &'static str,
        /// The value given.
        value: f64,
    },
    /// A value that would make the computation larger than it can be (steps, samples).
    #[error("{name} = {} needs {needed:.1e} {what}, more than the {limit:.0e} allowed", Short(*.value))]
    TooLarge {
        /// What the value is.
        name: String,
        /// The value given.
        value: f64,
        /// How many it needs.
        needed: f64,
        /// Of what (`"integration steps"`).
        what: &'static str,
        /// The most allowed.
        limit: f64,
    },
}

impl InputError {
    /// The same error with its value's name prefixed (`"width"` → `"block 2 width"`).
    #[must_use]
    pub fn prefixed(self, prefix: &str) -> Self {
        let named = |name: String| format!("{prefix} {name}");
        match self {
            Self::NonFinite(name) => Self::NonFinite(named(name)),
            Self::NotPositive { name, value } => Self::NotPositive {
                name: named(name),
                value,
            },
            Self::Negative { name, value } => Self::Negative {
                name: named(name),
                value,
            },
            Self::OutOfRange { name, range, value } => Self::OutOfRange {
                name: named(name),
                range,
                value,
            },
            Self::TooLarge {
                name,
                value,
                needed,
                what,
                limit,
            } => Self::TooLarge {
                name: named(name),
                value,
                needed,
                what,
                limit,
            },
        }
    }
}

/// A number as a message prints it: as Rust writes it where that is short (`0.1`,
/// `-2.5`, `1234`), else in scientific notation, so that `1e300` is not printed as three
/// hundred digits and `1e-30` not as thirty zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Short(pub f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let size = self.0.abs();
        if size == 0.0 || !size.is_finite() || (1e-5..1e16).contains(&size) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// `value` if it is finite.
///
/// # Errors
/// [`InputError::NonFinite`].
pub fn finite(name: &str, value: f64) -> Result<f64, InputError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(InputError::NonFinite(name.to_owned()))
    }
}

/// `value` if it is finite and > 0.
///
/// # Errors
/// [`InputError::NonFinite`], [`InputError::NotPositive`].
pub fn positive(name: &str, value: f64) -> Result<f64, InputError> {
    if finite(name, value)? > 0.0 {
        Ok(value)
    } else {
        Err(InputError::NotPositive {
            name: name.to_owned(),
            value,
        })
    }
}

/// `value` if it is finite and ≥ 0.
///
/// # Errors
/// [`InputError::NonFinite`], [`InputError::Negative`].
pub fn non_negative(name: &str, value: f64) -> Result<f64, InputError> {
    if finite(name, value)? >= 0.0 {
        Ok(value)
    } else {
        Err(InputError::Negative {
            name: name.to_owned(),
            value,
        })
    }
}

/// `value` if it is finite and within `range` (inclusive), described as `text`.
///
/// # Errors
/// [`InputError::NonFinite`], [`InputError::OutOfRange`].
pub fn in_range(
    name: &str,
    value: f64,
    range: RangeInclusive<f64>,
    text: &'static str,
) -> Result<f64, InputError> {
    if range.contains(&finite(name, value)?) {
        Ok(value)
    } else {
        Err(InputError::OutOfRange {
            name: name.to_owned(),
            range: text,
            value,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_check_refuses_nan_and_names_the_value() {
        for check in [finite, positive, non_negative] {
            assert_eq!(
                check("x", f64::NAN).unwrap_err().to_string(),
                "x is not finite"
            );
        }
        assert_eq!(
            positive("dt", 0.0).unwrap_err().to_string(),
            "dt must be positive, got 0"
        );
        assert_eq!(non_negative("mu", 0.0), Ok(0.0));
        assert_eq!(
            in_range("rho_inf", 1.5, 0.0..=1.0, "[0, 1]")
                .unwrap_err()
                .to_string(),
            "rho_inf must lie in [0, 1], got 1.5"
        );
        assert_eq!(
            positive("width", -1.0)
                .unwrap_err()
                .prefixed("block 2")
                .to_string(),
            "block 2 width must be positive, got -1"
        );
    }

    #[test]
    fn huge_and_tiny_values_are_printed_short() {
        assert_eq!(
            in_range("mu", 1e300, 0.0..=1.0, "[0, 1]")
                .unwrap_err()
                .to_string(),
            "mu must lie in [0, 1], got 1e300"
        );
        assert_eq!(
            positive("dt", -1e-30).unwrap_err().to_string(),
            "dt must be positive, got -1e-30"
        );
        for (v, text) in [(0.1, "0.1"), (-2.5, "-2.5"), (1234.0, "1234"), (0.0, "0")] {
            assert_eq!(Short(v).to_string(), text);
        }
        assert_eq!(Short(-1.5e20).to_string(), "-1.5e20");
    }
}
