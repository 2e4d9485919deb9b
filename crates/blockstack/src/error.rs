//! Errors of the block-stack model: bad blocks, bad base motions, bad scenes.

/// Why an input does not describe a valid block stack.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BlockError {
    /// A value that is not finite, positive, non-negative or in its range.
    #[error(transparent)]
    Input(#[from] input::InputError),
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
    /// A recorded acceleration that cannot be read or used ([`crate::base::record_file`]);
    /// the message names the file (and the line).
    #[error("{0}")]
    Record(String),
    /// A scene key (`contact.mu`, `blocks.0.width`) that names no number of the scene
    /// ([`crate::studies::scene_sweep`]); the message names the keys that exist.
    #[error("{0}")]
    Key(String),
    /// No built-in scene has this name ([`crate::scenes`]).
    #[error("no built-in scene '{name}' (built-in scenes: {known})")]
    UnknownScene {
        /// The name asked for.
        name: String,
        /// The built-in names, comma-separated.
        known: String,
    },
}
