//! The physical units of a shaken column: the blocks' size, gravity and the base's
//! frequency in cycles per time unit (`--hz`) as an alternative to ω (`--omega`).
//! Defaults are the thesis's (w = 0.2, h = 0.4, g = 1); blocks in metres with
//! `--gravity 9.81` make the time unit the second and `--hz` hertz.

use anyhow::Result;
use blockstack::scenarios::ColumnUnits;
use blockstack::scene::MAX_BLOCKS;
use clap::Args;
use input::text::parse_finite;
use std::f64::consts::PI;

/// `--width`, `--height` and `--gravity` of a shaken column.
#[derive(Debug, Clone, Args)]
pub struct UnitArgs {
    /// Width w of each free block (length units; > 0).
    #[arg(long, default_value_t = ColumnUnits::default().width, value_parser = parse_finite, allow_hyphen_values = true)]
    pub width: f64,
    /// Height h of each free block (length units; > 0).
    #[arg(long, default_value_t = ColumnUnits::default().height, value_parser = parse_finite, allow_hyphen_values = true)]
    pub height: f64,
    /// Gravity g along −y (length per time unit²; ≥ 0): 9.81 with lengths in metres
    /// makes the time unit the second.
    #[arg(long, default_value_t = ColumnUnits::default().gravity, value_parser = parse_finite, allow_hyphen_values = true)]
    pub gravity: f64,
}

impl UnitArgs {
    /// The units given, checked with the flags' names.
    ///
    /// # Errors
    /// A block size that is not positive, a height so large that a column of
    /// [`MAX_BLOCKS`] would rise to ∞ (the blocks' centres, (i + ½)h, must be finite),
    /// a negative gravity.
    pub fn units(&self) -> Result<ColumnUnits> {
        let height = input::positive("--height", self.height)?;
        let top = height * (MAX_BLOCKS as f64 + 1.0);
        anyhow::ensure!(
            top.is_finite(),
            "--height {height:e} is too large: a column of {MAX_BLOCKS} blocks would rise \
             to {top}"
        );
        Ok(ColumnUnits {
            width: input::positive("--width", self.width)?,
            height,
            gravity: input::non_negative("--gravity", self.gravity)?,
        })
    }
}

/// The angular frequency ω = 2πf of a frequency `hz` in cycles per time unit.
#[must_use]
pub fn omega_of_hz(hz: f64) -> f64 {
    2.0 * PI * hz
}
