//! The figures of rollstack, drawn with plotters into PNG and GIF files.
//!
//! The physics crates return typed data (trajectories, study rows, frames of a run);
//! this crate turns that data into pictures, so that the command line, the tour and a
//! user's own program draw the same figures, and no physics crate depends on a plotting
//! library.
//!
//! - [`page`]: the tour's HTML page of sections (numbers, tables, figures, data links).
//! - [`plot`]: line plots ([`plot::LinePlot`], [`plot::Series`]) with a bundled font, so
//!   plots render on machines without installed fonts: a style of its own per curve,
//!   legends placed off the data, titles fitted to the width.
//! - [`axis`]: round ticks, decades on logarithmic axes (`1e-6`).
//! - [`blocks`]: the block stack: snapshots (Figure 4.4), the animation, the top block's
//!   angle and height (Figure 4.5).
//! - [`convergence`]: a convergence study's failure time against Δt, with the
//!   perturbation ensemble's spread as a band.
//! - [`fragility`](mod@fragility): fragility curves with their bands and the fraction
//!   collapsed per level.
//! - [`cylinders`]: the support-force curves of §3.3 (Figures 3.3–3.5, 3.7, 3.8) and
//!   the plan view of a rolled trace (Figures 3.10, 3.12).
//! - [`nsga`]: the bouncing ball and work-precision diagrams.
//! - [`numerics`]: the caption line of a block-stack figure: the branch rule where it
//!   applies, Δt and the prox parameter.
//! - [`painleve`]: Figure I.2.
//! - [`sphere`]: the rolling sphere: traces (Figure 2.1), rectangles and their panels
//!   (Figures 2.6–2.9), the level sets of Figure 2.5, the integrator study.
//! - [`rotations`]: a rotated basis and its axis in an oblique 3D view.
//! - [`animation`]: animated GIFs, frames drawn in parallel, one palette per animation.
//! - [`file`](mod@file): every file is written to a temporary sibling and renamed into place.
//!
//! ```
//! use figures::plot::{LinePlot, Series};
//!
//! let dir = std::env::temp_dir().join(format!("figures-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let parabola = (0..=20).map(|i| f64::from(i) / 10.0).map(|x| (x, x * x)).collect();
//! LinePlot::new("y = x²", "x", "y")
//!     .with(Series::line("x²", parabola))
//!     .save(&dir.join("parabola.png"), (400, 300))?;
//! assert!(dir.join("parabola.png").exists());
//! # std::fs::remove_dir_all(&dir).ok();
//! # Ok::<(), figures::FigureError>(())
//! ```
#![warn(missing_docs)]

pub mod animation;
pub mod axis;
pub mod blocks;
pub mod convergence;
pub mod cylinders;
pub mod exploration;
pub mod file;
pub mod fragility;
pub mod nsga;
pub mod numerics;
pub mod page;
pub mod painleve;
pub mod plot;
pub mod rotations;
pub mod sphere;

use std::path::PathBuf;

/// Why a figure could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// The plotting backend refused to draw.
    #[error("plot: {0}")]
    Draw(String),
    /// The file could not be written.
    #[error("cannot write {}: {message}", path.display())]
    Write {
        /// The figure's final path.
        path: PathBuf,
        /// What the backend or the file system said.
        message: String,
    },
    /// The data cannot be drawn (non-finite coordinates, no frame at all).
    #[error("{0}")]
    Data(&'static str),
}

/// The result of drawing a figure.
pub type Result<T> = std::result::Result<T, FigureError>;

/// Converts any plotters error into a [`FigureError::Draw`].
pub fn err<E: std::fmt::Display>(e: E) -> FigureError {
    FigureError::Draw(e.to_string())
}

/// A [`FigureError::Write`] for `path`.
fn write_error(path: &std::path::Path, message: impl std::fmt::Display) -> FigureError {
    FigureError::Write {
        path: path.to_owned(),
        message: message.to_string(),
    }
}
