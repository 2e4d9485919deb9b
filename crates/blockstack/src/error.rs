//! Errors of the block-stack model: bad blocks, bad base motions, bad scenes.

/// Why an input does not describe a valid block stack.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BlockError {
    /// A value is NaN or infinite.
    #[error("{0} is not finite")]
    NonFinite(String),
    /// A size or mass that must be positive is not.
    #[error("{name} must be positive, got {value}")]
    NotPositive {
        /// What the value is (e.g. "block 2 width").
        name: String,
        /// The offending value.
        value: f64,
    },
    /// A value that must not be negative is.
    #[error("{name} must not be negative, got {value}")]
    Negative {
        /// What the value is (e.g. "mu").
        name: String,
        /// The offending value.
        value: f64,
    },
    /// A value lies outside its admissible interval.
    #[error("{name} must lie in {range}, got {value}")]
    OutOfRange {
        /// What the value is.
        name: String,
        /// The admissible interval, as text (e.g. "[0, 1]").
        range: &'static str,
        /// The offending value.
        value: f64,
    },
    /// Two blocks of a scene overlap in their initial configuration.
    #[error("{first} and {second} overlap by {depth:.3e} in the initial configuration")]
    Overlap {
        /// The lower (or first) body, e.g. "the base" or "block 1".
        first: String,
        /// The other body.
        second: String,
        /// Penetration depth (length units).
        depth: f64,
    },
    /// A scene file or a scene description is malformed.
    #[error("invalid scene: {0}")]
    Scene(String),
}
