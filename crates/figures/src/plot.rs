//! PNG plots with plotters and a bundled font.
//!
//! DejaVu Sans is compiled into the binary and registered through plotters' `ab_glyph`
//! feature, so plots render on machines without any installed font. [`with_png`] is
//! the one entry point that owns the file: it registers the font, draws into a
//! temporary sibling and renames it into place.

use crate::{file, write_error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;
use std::sync::Once;

/// The font family name every plot uses.
pub const FONT: &str = "sans-serif";

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the bundled font with plotters (idempotent).
pub fn register_font() {
    REGISTER.call_once(|| {
        // The bytes are a valid TrueType font compiled in; failure would be a build error
        // in spirit, so it is ignored rather than propagated from every plot.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES);
    });
}

/// The drawing area handed to [`with_png`]'s closure.
pub type Canvas<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Draws a PNG of `size` pixels at `path`, atomically.
///
/// # Errors
/// Any drawing error of `draw`, or a failure to write the file.
pub fn with_png<F>(path: &Path, size: (u32, u32), draw: F) -> Result<()>
where
    F: FnOnce(&Canvas<'_>) -> Result<()>,
{
    register_font();
    let tmp = file::temp_sibling(path);
    {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        root.fill(&WHITE).map_err(crate::err)?;
        draw(&root)?;
        root.present().map_err(|e| write_error(path, e))?;
    }
    file::commit_temp(path).map_err(|e| write_error(path, e))
}

pub use crate::err;

/// A named polyline of a [`LinePlot`].
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Draw markers at the points instead of a line.
    pub markers: bool,
    /// With `markers`: also join the markers by a line of the same colour.
    pub joined: bool,
}

impl Series {
    /// A line through `points`.
    #[must_use]
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: false,
            joined: false,
        }
    }

    /// Markers at `points`.
    #[must_use]
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: true,
            joined: false,
        }
    }

    /// Markers at `points`, joined by a line of the same colour.
    #[must_use]
    pub fn joined_markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            joined: true,
            ..Self::markers(label, points)
        }
    }
}

/// The palette of series colours (colour-blind safe, Okabe–Ito).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

/// A 2D line/marker plot with a title, axis labels and a legend.
#[derive(Debug, Clone)]
pub struct LinePlot {
    /// Caption above the plot.
    pub title: String,
    /// Label of the horizontal axis, with units.
    pub x_label: String,
    /// Label of the vertical axis, with units.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// Logarithmic axes (x, y), e.g. for work-precision diagrams.
    pub log: (bool, bool),
    /// Equal scales on both axes (paths in a plane).
    pub equal_aspect: bool,
}

impl LinePlot {
    /// An empty plot with a title and axis labels.
    #[must_use]
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            log: (false, false),
            equal_aspect: false,
        }
    }

    /// Adds a series.
    #[must_use]
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// The data range of all series, padded by 5 % (and made non-empty).
    fn bounds(&self) -> (Range<f64>, Range<f64>) {
        let pts = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| {
                p.0.is_finite()
                    && p.1.is_finite()
                    && (!self.log.0 || p.0 > 0.0)
                    && (!self.log.1 || p.1 > 0.0)
            });
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        if self.equal_aspect {
            let half = 0.5 * (x1 - x0).max(y1 - y0);
            let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            (x0, x1, y0, y1) = (cx - half, cx + half, cy - half, cy + half);
        }
        (pad(x0, x1, self.log.0), pad(y0, y1, self.log.1))
    }

    /// Draws the plot into a PNG file of `size` pixels.
    ///
    /// # Errors
    /// When drawing or writing fails.
    pub fn save(&self, path: &Path, size: (u32, u32)) -> Result<()> {
        with_png(path, size, |root| self.draw(root))
    }

    /// Draws the plot onto an existing canvas (for multi-panel figures).
    ///
    /// # Errors
    /// When drawing fails.
    pub fn draw(&self, root: &Canvas<'_>) -> Result<()> {
        let (xr, yr) = self.bounds();
        match self.log {
            (false, false) => self.draw_in(root, xr, yr),
            (true, false) => self.draw_in(root, xr.log_scale(), yr),
            (false, true) => self.draw_in(root, xr, yr.log_scale()),
            (true, true) => self.draw_in(root, xr.log_scale(), yr.log_scale()),
        }
    }

    fn draw_in<X, Y>(&self, root: &Canvas<'_>, xr: X, yr: Y) -> Result<()>
    where
        X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
        Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
        X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
        Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
    {
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FONT, 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(xr, yr)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()
            .map_err(err)?;
        for (i, s) in self.series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let pts = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite());
            let anno = if s.markers {
                if s.joined {
                    chart
                        .draw_series(LineSeries::new(pts.clone(), color.stroke_width(1)))
                        .map_err(err)?;
                }
                chart
                    .draw_series(pts.map(|p| Circle::new(p, 3, color.filled())))
                    .map_err(err)?
            } else {
                chart
                    .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                    .map_err(err)?
            };
            if !s.label.is_empty() {
                anno.label(&s.label).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
            }
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .label_font((FONT, 14))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(err)?;
        }
        Ok(())
    }
}

fn pad(lo: f64, hi: f64, log: bool) -> Range<f64> {
    if log {
        let (lo, hi) = if hi > lo {
            (lo, hi)
        } else {
            (lo * 0.5, lo * 2.0)
        };
        return lo / 1.5..hi * 1.5;
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    lo - 0.05 * span..hi + 0.05 * span
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_a_png_with_text() {
        let dir = std::env::temp_dir().join(format!("rollstack-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("p.png");
        LinePlot::new("sin", "t [s]", "x [m]")
            .with(Series::line(
                "sin t",
                (0..50)
                    .map(|i| (f64::from(i) * 0.1, (f64::from(i) * 0.1).sin()))
                    .collect(),
            ))
            .with(Series::markers("pts", vec![(1.0, 0.5), (2.0, f64::NAN)]))
            .with(Series::joined_markers(
                "joined",
                vec![(1.0, 0.2), (2.0, 0.3)],
            ))
            .save(&p, (400, 300))
            .unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        std::fs::remove_dir_all(dir).unwrap();
    }
}
