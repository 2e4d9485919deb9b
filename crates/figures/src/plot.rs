//! PNG plots with plotters and a bundled font.
//!
//! DejaVu Sans is compiled into the binary and registered through plotters' `ab_glyph`
//! feature, so plots render on machines without any installed font. [`with_png`] is
//! the one entry point that owns the file: it registers the font, draws into a
//! temporary sibling and renames it into place.
//!
//! What every [`LinePlot`] promises its reader:
//! - every series has a style of its own ([`Style::nth`]): the twelve colours of
//!   [`PALETTE`] first, then the same colours dashed, then dotted, so no two curves of
//!   one plot look alike; markers differ in shape as well as colour;
//! - a series of computed points shows a marker at each point, and one series carries
//!   both its line and its markers in one colour ([`Series::computed`]);
//! - ticks are round numbers, decades on logarithmic axes ([`crate::axis`]), and the
//!   label area is as wide as the widest tick label;
//! - the legend is placed where it hides no data: inside the plot in a corner (or edge)
//!   that no point or line passes through, otherwise outside, on the right ([`Legend`]);
//! - the title is fitted to the width: a smaller font, or two lines ([`fit_title`]).

use crate::axis::{TickedRange, Ticks};
use crate::{file, write_error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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

/// The colours of data series and of the blocks of a stack: twelve hues that stay
/// apart from each other and legible on white (the Okabe–Ito colours without black and
/// yellow, then darker and muted hues). Neither black nor grey is among them: those
/// are [`BASE_COLOR`]'s and the axes'.
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(136, 34, 85),   // wine
    RGBColor(153, 153, 51),  // olive
    RGBColor(51, 34, 136),   // indigo
    RGBColor(17, 119, 51),   // dark green
    RGBColor(255, 102, 102), // salmon
    RGBColor(140, 81, 10),   // brown
];

/// The colour of what is not a data series: the base (table) of a block stack. No
/// block or series is ever drawn in it ([`PALETTE`] holds no grey).
pub const BASE_COLOR: RGBColor = RGBColor(64, 64, 64);

/// Light grey for guides: a line that only joins markers drawn in colour.
pub const GUIDE_COLOR: RGBColor = RGBColor(170, 170, 170);

/// The pattern of a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// Unbroken.
    Solid,
    /// Long dashes.
    Dashed,
    /// Dots.
    Dotted,
}

/// The shape of a marker.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A filled disc.
    Circle,
    /// A filled triangle, point up.
    Triangle,
    /// A filled square.
    Square,
    /// A filled diamond.
    Diamond,
}

/// How one series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Style {
    /// Line and marker colour.
    pub color: RGBColor,
    /// Line pattern.
    pub dash: Dash,
    /// Marker shape.
    pub marker: Marker,
    /// Line width, pixels.
    pub width: u32,
    /// Markers drawn open (outlined, white inside) rather than filled.
    pub hollow: bool,
}

impl Style {
    /// The `i`-th style of a plot: the [`PALETTE`] solid, then the palette again dashed,
    /// then dotted; markers cycle through the shapes. The first 36 are all different,
    /// and the first 12 differ in colour.
    #[must_use]
    pub fn nth(i: usize) -> Self {
        const DASHES: [Dash; 3] = [Dash::Solid, Dash::Dashed, Dash::Dotted];
        const MARKERS: [Marker; 4] = [
            Marker::Circle,
            Marker::Triangle,
            Marker::Square,
            Marker::Diamond,
        ];
        Self {
            color: PALETTE[i % PALETTE.len()],
            dash: DASHES[(i / PALETTE.len()) % DASHES.len()],
            marker: MARKERS[i % MARKERS.len()],
            width: 2,
            hollow: false,
        }
    }

    /// A solid style of one colour.
    #[must_use]
    pub fn color(color: RGBColor) -> Self {
        Self {
            color,
            dash: Dash::Solid,
            marker: Marker::Circle,
            width: 2,
            hollow: false,
        }
    }

    /// This style with another line pattern.
    #[must_use]
    pub fn dash(self, dash: Dash) -> Self {
        Self { dash, ..self }
    }

    /// This style with another marker.
    #[must_use]
    pub fn marker(self, marker: Marker) -> Self {
        Self { marker, ..self }
    }

    /// This style with another line width.
    #[must_use]
    pub fn width(self, width: u32) -> Self {
        Self { width, ..self }
    }

    /// This style with open markers.
    #[must_use]
    pub fn hollow(self) -> Self {
        Self {
            hollow: true,
            ..self
        }
    }
}

/// Below this many points a series of computed points is shown as markers only: a line
/// through a few samples would claim values nobody computed.
pub const DENSE_POINTS: usize = 20;

/// A named polyline of a [`LinePlot`].
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text (an empty label leaves the series out of the legend).
    pub label: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Join the points by a line.
    pub line: bool,
    /// Draw a marker at each point.
    pub markers: bool,
    /// Arrowheads along the line showing the direction of travel.
    pub arrows: bool,
    /// The style, or `None` for the plot's next automatic one ([`Style::nth`]).
    pub style: Option<Style>,
}

impl Series {
    fn build(label: impl Into<String>, points: Vec<(f64, f64)>, line: bool, markers: bool) -> Self {
        Self {
            label: label.into(),
            points,
            line,
            markers,
            arrows: false,
            style: None,
        }
    }

    /// A line through `points`.
    #[must_use]
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::build(label, points, true, false)
    }

    /// Markers at `points`.
    #[must_use]
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::build(label, points, false, true)
    }

    /// A line through `points` with a marker at each, in one colour.
    #[must_use]
    pub fn line_and_markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::build(label, points, true, true)
    }

    /// Points computed one by one (a sweep): a marker at each, joined by a line (same
    /// colour) only when there are at least [`DENSE_POINTS`] of them.
    #[must_use]
    pub fn computed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        let dense = points.len() >= DENSE_POINTS;
        Self::build(label, points, dense, true)
    }

    /// This series in a given style.
    #[must_use]
    pub fn styled(mut self, style: Style) -> Self {
        self.style = Some(style);
        self
    }

    /// This series with arrowheads showing the direction of travel.
    #[must_use]
    pub fn with_arrows(mut self) -> Self {
        self.arrows = true;
        self
    }
}

/// Where a plot's legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    /// Inside the plot where no data lies (a corner first, then the middle of an edge);
    /// outside on the right when every such place would hide data or the legend is long.
    #[default]
    Auto,
    /// Outside the plot, on the right.
    Right,
}

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
    /// Equal scales on both axes (paths in a plane): one unit is as many pixels across
    /// as up.
    pub equal_aspect: bool,
    /// Where the legend goes.
    pub legend: Legend,
    /// Fixed ranges of the axes (x, y) in data units, instead of the data's own range
    /// padded by 5 % (panels drawn to one scale).
    pub bounds: Option<(Range<f64>, Range<f64>)>,
}

/// Largest title font, pixels.
pub const TITLE_PX: u32 = 22;
/// Smallest title font, pixels.
const MIN_TITLE_PX: u32 = 12;
/// Tick labels.
const TICK_PX: u32 = 14;
/// Axis descriptions.
const DESC_PX: u32 = 16;
/// Legend text.
const LEGEND_PX: u32 = 14;
/// Space around the chart, pixels.
const MARGIN: u32 = 12;
/// Legends longer than this go outside the plot.
const MAX_INSIDE_ENTRIES: usize = 8;

/// Lays a title out in `width` pixels: one line at the largest font from `max_px` down
/// to ¾ of it that fits, else two lines split at the space that balances them (fonts
/// down to 12 px), else one line at 12 px cut with an ellipsis. `measure(text, px)` is
/// the width of `text` at `px` pixels. Returns the lines and the font size. A title with
/// line breaks (a caption under it, [`Numerics::under`](crate::numerics::Numerics::under))
/// keeps its lines: the largest font at which each fits, else each cut at 12 px.
#[must_use]
pub fn fit_title(
    text: &str,
    width: u32,
    max_px: u32,
    measure: impl Fn(&str, u32) -> u32,
) -> (Vec<String>, u32) {
    let max_px = max_px.max(MIN_TITLE_PX);
    if text.contains('\n') {
        return fit_lines(text.lines(), width, max_px, measure);
    }
    let min_one = (max_px * 3 / 4).max(MIN_TITLE_PX);
    for px in (min_one..=max_px).rev() {
        if measure(text, px) <= width {
            return (vec![text.to_owned()], px);
        }
    }
    let spaces: Vec<usize> = text.match_indices(' ').map(|(i, _)| i).collect();
    for px in (MIN_TITLE_PX..=max_px).rev() {
        let best = spaces
            .iter()
            .map(|&i| {
                let (a, b) = (text[..i].trim_end(), text[i..].trim_start());
                (measure(a, px).max(measure(b, px)), a, b)
            })
            .min_by_key(|c| c.0);
        if let Some((w, a, b)) = best {
            if w <= width {
                return (vec![a.to_owned(), b.to_owned()], px);
            }
        }
    }
    (vec![cut_to_fit(text, width, &measure)], MIN_TITLE_PX)
}

/// Lines kept as given, at the largest font from `max_px` down to 12 px at which every
/// one fits, else each cut at 12 px.
fn fit_lines<'a>(
    lines: impl Iterator<Item = &'a str>,
    width: u32,
    max_px: u32,
    measure: impl Fn(&str, u32) -> u32,
) -> (Vec<String>, u32) {
    let lines: Vec<&str> = lines.collect();
    for px in (MIN_TITLE_PX..=max_px).rev() {
        if lines.iter().all(|l| measure(l, px) <= width) {
            return (lines.iter().map(|&l| l.to_owned()).collect(), px);
        }
    }
    let cut = lines.iter().map(|l| cut_to_fit(l, width, &measure));
    (cut.collect(), MIN_TITLE_PX)
}

/// `text` whole if it fits at 12 px, else cut with an ellipsis where it does.
fn cut_to_fit(text: &str, width: u32, measure: &impl Fn(&str, u32) -> u32) -> String {
    if measure(text, MIN_TITLE_PX) <= width {
        return text.to_owned();
    }
    let mut cut: Vec<char> = text.chars().collect();
    while !cut.is_empty() {
        let s: String = cut.iter().collect::<String>() + "…";
        if measure(&s, MIN_TITLE_PX) <= width {
            return s;
        }
        cut.pop();
    }
    String::new()
}

/// Width and height of `text` at `px` pixels on `area`.
fn text_size<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, text: &str, px: u32) -> (u32, u32) {
    area.estimate_text_size(text, &TextStyle::from((FONT, px).into_font()))
        .unwrap_or((0, 0))
}

/// Draws `text` as the area's title, fitted to its width ([`fit_title`]), and returns
/// the area below it.
///
/// # Errors
/// When drawing fails.
pub fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    max_px: u32,
) -> Result<DrawingArea<DB, Shift>> {
    if text.is_empty() {
        return Ok(area.clone());
    }
    draw_title_reserving(area, text, max_px, 1)
}

/// [`draw_title`] that keeps room for at least `lines` lines at `max_px`, so that the
/// frames of an animation, whose titles differ, keep one plotting area.
///
/// # Errors
/// When drawing fails.
pub fn draw_title_reserving<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    max_px: u32,
    lines: usize,
) -> Result<DrawingArea<DB, Shift>> {
    let (w, _) = area.dim_in_pixel();
    let (drawn, px) = fit_title(text, w.saturating_sub(2 * MARGIN), max_px, |s, px| {
        text_size(area, s, px).0
    });
    let top = 6;
    let style = (FONT, px)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (i, line) in (0u32..).zip(&drawn) {
        #[allow(clippy::cast_possible_wrap)]
        area.draw_text(
            line,
            &style,
            ((w / 2) as i32, (top + i * px * 5 / 4) as i32),
        )
        .map_err(err)?;
    }
    #[allow(clippy::cast_possible_truncation)]
    let used =
        (top + (px * 5 / 4) * drawn.len() as u32).max(top + (max_px * 5 / 4) * lines as u32) + 4;
    Ok(area.split_vertically(used).1)
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
            legend: Legend::Auto,
            bounds: None,
        }
    }

    /// Adds a series.
    #[must_use]
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Each series' style: its own, or the next automatic one ([`Style::nth`]) that no
    /// series has claimed.
    #[must_use]
    pub fn styles(&self) -> Vec<Style> {
        let claimed: Vec<Style> = self.series.iter().filter_map(|s| s.style).collect();
        let mut next = 0;
        self.series
            .iter()
            .map(|s| {
                s.style.unwrap_or_else(|| loop {
                    let st = Style::nth(next);
                    next += 1;
                    if !claimed
                        .iter()
                        .any(|c| c.color == st.color && c.dash == st.dash)
                    {
                        break st;
                    }
                })
            })
            .collect()
    }

    /// The points of each series in display coordinates (log₁₀ on a logarithmic axis);
    /// a point that cannot be drawn (non-finite, or not positive on a log axis) becomes
    /// `None` and breaks the line there.
    fn display_points(&self) -> Vec<Vec<Option<(f64, f64)>>> {
        self.series
            .iter()
            .map(|s| s.points.iter().map(|&p| self.to_display(p)).collect())
            .collect()
    }

    /// A data point in display coordinates, `None` when it cannot be drawn.
    fn to_display(&self, p: (f64, f64)) -> Option<(f64, f64)> {
        let tx = |v: f64, log: bool| {
            if log {
                (v > 0.0).then(|| v.log10())
            } else {
                Some(v)
            }
        };
        let (x, y) = (tx(p.0, self.log.0)?, tx(p.1, self.log.1)?);
        (x.is_finite() && y.is_finite()).then_some((x, y))
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
        let area = draw_title(root, &self.title, TITLE_PX)?;
        let styles = self.styles();
        let data = self.display_points();
        let entries: Vec<LegendEntry> = self
            .series
            .iter()
            .zip(&styles)
            .filter(|(s, _)| !s.label.is_empty())
            .map(|(s, st)| LegendEntry {
                label: s.label.clone(),
                style: *st,
                line: s.line,
                markers: s.markers,
            })
            .collect();
        let (xr, yr) = match &self.bounds {
            Some((x, y)) => {
                let lo = self.to_display((x.start, y.start)).unwrap_or((0.0, 0.0));
                let hi = self.to_display((x.end, y.end)).unwrap_or((1.0, 1.0));
                (lo.0..hi.0, lo.1..hi.1)
            }
            None => data_bounds(&data),
        };
        let legend_dim = legend_size(&area, &entries);
        let (w, _) = area.dim_in_pixel();
        let outside_w = legend_dim.0 + 2 * MARGIN;
        let fits_outside = outside_w * 100 <= w * 45;
        let (layout, placement) = if entries.is_empty() {
            (self.layout(&area, &xr, &yr, 0), None)
        } else if self.legend == Legend::Right && fits_outside {
            (
                self.layout(&area, &xr, &yr, outside_w),
                Some(Placement::Right),
            )
        } else {
            let inside = self.layout(&area, &xr, &yr, 0);
            let (at, hits) = inside.emptiest_spot(&self.series, &data, legend_dim);
            if (hits == 0 && entries.len() <= MAX_INSIDE_ENTRIES) || !fits_outside {
                (inside, Some(Placement::Inside(at)))
            } else {
                (
                    self.layout(&area, &xr, &yr, outside_w),
                    Some(Placement::Right),
                )
            }
        };
        let (chart_area, legend_area) = if placement == Some(Placement::Right) {
            let (a, b) = area.split_horizontally(w - outside_w);
            (a, Some(b))
        } else {
            (area.clone(), None)
        };
        let mut layout = layout;
        let plot_area = layout.draw_axes(&chart_area, &self.x_label, &self.y_label)?;
        // The pixels plotters gave the plotting area (the layout's estimate may be off
        // by one).
        layout.plot_px = plot_area.dim_in_pixel();
        let to_px = |p: (f64, f64)| layout.to_px(p);
        for ((s, st), pts) in self.series.iter().zip(&styles).zip(&data) {
            for run in pts.split(Option::is_none) {
                let px: Vec<(i32, i32)> = run.iter().flatten().map(|&p| to_px(p)).collect();
                if s.line {
                    let fractions: Vec<(f64, f64)> = run
                        .iter()
                        .flatten()
                        .map(|&p| layout.to_fraction(p))
                        .collect();
                    for line in clipped_runs(&fractions) {
                        let line: Vec<(i32, i32)> =
                            line.into_iter().map(|f| layout.fraction_to_px(f)).collect();
                        draw_polyline(&plot_area, &line, st)?;
                    }
                }
                if s.arrows {
                    draw_arrows(&plot_area, &px, st.color)?;
                }
                if s.markers {
                    // Few points: larger markers, each one a computed value to be seen.
                    let r = if s.points.len() < DENSE_POINTS { 5 } else { 4 };
                    for &p in &px {
                        draw_marker(&plot_area, p, st, r)?;
                    }
                }
            }
        }
        match placement {
            Some(Placement::Inside(at)) => draw_legend(&plot_area, at, &entries)?,
            Some(Placement::Right) => {
                if let Some(l) = legend_area {
                    #[allow(clippy::cast_possible_wrap)]
                    draw_legend(&l, (0, MARGIN as i32), &entries)?;
                }
            }
            None => {}
        }
        Ok(())
    }

    /// The axes' ranges, ticks and the label areas for a chart on `area` that leaves
    /// `legend_w` pixels on the right.
    fn layout<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        xr: &Range<f64>,
        yr: &Range<f64>,
        legend_w: u32,
    ) -> Layout {
        let (w, h) = area.dim_in_pixel();
        let ticks = |r: &Range<f64>, log: bool| {
            if log {
                Ticks::log(r.start, r.end)
            } else {
                Ticks::linear(r.start, r.end)
            }
        };
        let widest = |t: &Ticks| {
            t.labels
                .iter()
                .map(|l| text_size(area, l, TICK_PX).0)
                .max()
                .unwrap_or(0)
        };
        let (_, tick_h) = text_size(area, "0", TICK_PX);
        let (_, desc_h) = text_size(area, "Ag", DESC_PX);
        let x_area = tick_h + desc_h + 22;
        let (mut xr, mut yr) = (xr.clone(), yr.clone());
        let mut y_area = 0;
        let mut right = MARGIN;
        let mut plot_px = (1, 1);
        // Twice: the equal-aspect ranges change the ticks, the ticks the label area.
        for _ in 0..2 {
            let yt = ticks(&yr, self.log.1);
            let xt = ticks(&xr, self.log.0);
            y_area = widest(&yt) + desc_h + 24;
            right = MARGIN.max(
                xt.labels
                    .last()
                    .map_or(0, |l| text_size(area, l, TICK_PX).0 / 2 + 4),
            );
            plot_px = (
                w.saturating_sub(MARGIN + right + y_area + legend_w).max(20),
                h.saturating_sub(2 * MARGIN + x_area).max(20),
            );
            if !self.equal_aspect {
                break;
            }
            (xr, yr) = equal_aspect(&xr, &yr, plot_px);
        }
        Layout {
            xt: ticks(&xr, self.log.0),
            yt: ticks(&yr, self.log.1),
            xr,
            yr,
            x_area,
            y_area,
            right,
            plot_px,
        }
    }
}

/// The padded range of all display points (a unit box when there are none).
fn data_bounds(data: &[Vec<Option<(f64, f64)>>]) -> (Range<f64>, Range<f64>) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in data.iter().flatten().flatten() {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    (pad(x0, x1), pad(y0, y1))
}

/// [`lo`, `hi`] widened by 5 % on each side. A range narrower than a millionth of its
/// values (or than 1e-9 about zero) is drawn as a constant, 5 % of its size (at least 1)
/// on each side: a quantity constant to round-off is drawn flat with ticks that can be
/// read, instead of magnifying its last bits.
fn pad(lo: f64, hi: f64) -> Range<f64> {
    if hi - lo < (1e-6 * lo.abs().max(hi.abs())).max(1e-9) {
        let mid = 0.5 * (lo + hi);
        let span = mid.abs().max(1.0);
        return mid - 0.05 * span..mid + 0.05 * span;
    }
    let span = hi - lo;
    lo - 0.05 * span..hi + 0.05 * span
}

/// The ranges widened about their centres so that a unit spans as many pixels across
/// as up on a plot of `px` pixels.
fn equal_aspect(xr: &Range<f64>, yr: &Range<f64>, px: (u32, u32)) -> (Range<f64>, Range<f64>) {
    let (w, h) = (f64::from(px.0), f64::from(px.1));
    let scale = ((xr.end - xr.start) / w).max((yr.end - yr.start) / h);
    let (cx, cy) = (0.5 * (xr.start + xr.end), 0.5 * (yr.start + yr.end));
    (
        cx - 0.5 * scale * w..cx + 0.5 * scale * w,
        cy - 0.5 * scale * h..cy + 0.5 * scale * h,
    )
}

/// A legend's place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Placement {
    /// Inside the plot, top-left corner of the box in plot pixels.
    Inside((i32, i32)),
    /// Outside, right of the plot.
    Right,
}

/// A chart's ranges, ticks and pixel layout.
#[derive(Debug, Clone)]
struct Layout {
    xr: Range<f64>,
    yr: Range<f64>,
    xt: Ticks,
    yt: Ticks,
    x_area: u32,
    y_area: u32,
    /// Right margin of the chart (the legend's room, if outside, is split off first).
    right: u32,
    /// Size of the plotting area.
    plot_px: (u32, u32),
}

impl Layout {
    /// Where a display point lies in the plotting area, as fractions of its width and
    /// height (0 to 1 inside, y up).
    fn to_fraction(&self, p: (f64, f64)) -> (f64, f64) {
        (
            (p.0 - self.xr.start) / (self.xr.end - self.xr.start),
            (p.1 - self.yr.start) / (self.yr.end - self.yr.start),
        )
    }

    /// Pixel position of a point given as fractions of the plotting area, held within
    /// [`FAR`] plot sizes of it: a point far outside (a run that drifted by 10⁴ units in a
    /// plot of 1) would otherwise become a pixel coordinate whose offsets overflow in
    /// plotters. Lines are clipped before they get here ([`clipped_runs`]), so the hold
    /// moves only markers and arrows that are not seen anyway.
    fn fraction_to_px(&self, (fx, fy): (f64, f64)) -> (i32, i32) {
        let (w, h) = (
            f64::from(self.plot_px.0.max(2) - 1),
            f64::from(self.plot_px.1.max(2) - 1),
        );
        let hold = |f: f64| f.clamp(-FAR, 1.0 + FAR);
        #[allow(clippy::cast_possible_truncation)]
        (
            (hold(fx) * w).round() as i32,
            ((1.0 - hold(fy)) * h).round() as i32,
        )
    }

    /// Pixel position of a display point within the plotting area.
    fn to_px(&self, p: (f64, f64)) -> (i32, i32) {
        self.fraction_to_px(self.to_fraction(p))
    }

    /// Draws the mesh, ticks and axis labels on `area` and returns the plotting area
    /// (pixel coordinates, origin at its top-left corner).
    fn draw_axes<'a>(&self, area: &Canvas<'a>, x_label: &str, y_label: &str) -> Result<Canvas<'a>> {
        let mut chart = ChartBuilder::on(area)
            .margin(MARGIN)
            .margin_right(self.right)
            .x_label_area_size(self.x_area)
            .y_label_area_size(self.y_area)
            .build_cartesian_2d(
                TickedRange::new(self.xr.clone(), self.xt.clone()),
                TickedRange::new(self.yr.clone(), self.yt.clone()),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style((FONT, TICK_PX))
            .axis_desc_style((FONT, DESC_PX))
            .bold_line_style(RGBColor(200, 200, 200))
            .light_line_style(RGBColor(236, 236, 236))
            .draw()
            .map_err(err)?;
        Ok(chart.plotting_area().strip_coord_spec())
    }

    /// The spot for a legend box of `dim` pixels that hides the fewest drawn pixels of
    /// the series: a corner first (upper right, upper left, lower right, lower left),
    /// then the middle of an edge. Returns its top-left corner and the pixels it hides.
    fn emptiest_spot(
        &self,
        series: &[Series],
        data: &[Vec<Option<(f64, f64)>>],
        dim: (u32, u32),
    ) -> ((i32, i32), usize) {
        #[allow(clippy::cast_possible_wrap)]
        let (w, h, bw, bh) = (
            self.plot_px.0 as i32,
            self.plot_px.1 as i32,
            dim.0 as i32,
            dim.1 as i32,
        );
        let inset = 6;
        let (left, right, top, bottom) = (inset, w - bw - inset, inset, h - bh - inset);
        let (mid_x, mid_y) = ((w - bw) / 2, (h - bh) / 2);
        let spots = [
            (right, top),
            (left, top),
            (right, bottom),
            (left, bottom),
            (mid_x, top),
            (mid_x, bottom),
            (right, mid_y),
            (left, mid_y),
        ];
        let drawn: Vec<(i32, i32)> = series
            .iter()
            .zip(data)
            .flat_map(|(s, pts)| {
                let mut out = Vec::new();
                for run in pts.split(Option::is_none) {
                    let px: Vec<(i32, i32)> =
                        run.iter().flatten().map(|&p| self.to_px(p)).collect();
                    if s.markers || px.len() == 1 {
                        out.extend(px.iter().copied());
                    }
                    if s.line {
                        out.extend(px.windows(2).flat_map(|p| segment_samples(p[0], p[1])));
                    }
                }
                out
            })
            .collect();
        let pad = 5;
        spots
            .iter()
            .map(|&(x, y)| {
                let hits = drawn
                    .iter()
                    .filter(|p| {
                        p.0 >= x - pad
                            && p.0 <= x + bw + pad
                            && p.1 >= y - pad
                            && p.1 <= y + bh + pad
                    })
                    .count();
                ((x, y), hits)
            })
            .min_by_key(|s| s.1)
            .unwrap_or(((left, top), 0))
    }
}

/// Points every 3 pixels along a segment, its ends included.
fn segment_samples(a: (i32, i32), b: (i32, i32)) -> impl Iterator<Item = (i32, i32)> {
    let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = ((dx.hypot(dy) / 3.0).ceil() as usize).clamp(1, 2000);
    (0..=n).map(move |k| {
        let f = k as f64 / n as f64;
        #[allow(clippy::cast_possible_truncation)]
        (a.0 + (f * dx).round() as i32, a.1 + (f * dy).round() as i32)
    })
}

/// The pieces of a polyline (pixels) that a dash pattern of `on` pixels drawn and
/// `off` pixels left out keeps; the whole polyline, segment by segment, for a solid
/// line (`off` = 0).
#[must_use]
pub fn dash_pieces(px: &[(i32, i32)], on: f64, off: f64) -> Vec<((i32, i32), (i32, i32))> {
    if off <= 0.0 {
        return px.windows(2).map(|p| (p[0], p[1])).collect();
    }
    #[allow(clippy::cast_possible_truncation)]
    let round = |x: f64, y: f64| (x.round() as i32, y.round() as i32);
    let period = on + off;
    let mut pieces = Vec::new();
    // Position within the pattern where the current segment starts.
    let mut phase = 0.0;
    for p in px.windows(2) {
        let (a, b) = (p[0], p[1]);
        let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
        let len = dx.hypot(dy);
        if len == 0.0 {
            continue;
        }
        let at = |s: f64| round(f64::from(a.0) + dx * s / len, f64::from(a.1) + dy * s / len);
        // Walk the segment one dash period at a time.
        let mut s = -phase;
        while s < len {
            let (from, to) = (s.max(0.0), (s + on).min(len));
            if to > from {
                pieces.push((at(from), at(to)));
            }
            s += period;
        }
        phase = (phase + len) % period;
    }
    pieces
}

/// Draws a polyline in pixel coordinates in a style (solid, dashed or dotted).
///
/// A line `width` pixels wide is drawn as width × width copies of the anti-aliased
/// one-pixel line, shifted by whole pixels: plotters fills wide lines as polygons with
/// rounded corners, which makes one segment of a polyline look twice as thick as the
/// next. Each segment is drawn left to right (top to bottom when vertical): plotters'
/// bitmap backend leaves out the end pixel of a horizontal line drawn leftwards, which
/// breaks a dense polyline into dashes.
/// How far outside the plotting area, in plot sizes, a point keeps its own pixel
/// position; lines are clipped to this margin, markers held at it.
const FAR: f64 = 1.0;

/// The parts of a polyline (points as fractions of the plotting area) that lie within
/// [`FAR`] plot sizes of it, each segment clipped there (Liang–Barsky), so that a line
/// running far outside keeps its direction where it is seen.
fn clipped_runs(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for pair in points.windows(2) {
        let Some((a, b)) = clip_segment(pair[0], pair[1], -FAR, 1.0 + FAR) else {
            open = false;
            continue;
        };
        match runs.last_mut() {
            Some(run) if open && run.last() == Some(&a) => run.push(b),
            _ => runs.push(vec![a, b]),
        }
        // The run goes on only while the segment ends where the polyline does.
        open = b == pair[1];
    }
    runs
}

/// The part of the segment a–b inside the square [lo, hi]², if any (Liang–Barsky).
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    lo: f64,
    hi: f64,
) -> Option<((f64, f64), (f64, f64))> {
    if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - lo),
        (dx, hi - a.0),
        (-dy, a.1 - lo),
        (dy, hi - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

fn draw_polyline(area: &Canvas<'_>, px: &[(i32, i32)], st: &Style) -> Result<()> {
    if px.len() < 2 {
        return Ok(());
    }
    let thin = st.color.stroke_width(1);
    let pieces = match st.dash {
        Dash::Solid => dash_pieces(px, 1.0, 0.0),
        Dash::Dashed => dash_pieces(px, 9.0, 6.0),
        Dash::Dotted => dash_pieces(px, 2.0, 4.0),
    };
    #[allow(clippy::cast_possible_wrap)]
    let w = st.width.max(1) as i32;
    for (a, b) in pieces {
        let (a, b) = if (a.0, a.1) <= (b.0, b.1) {
            (a, b)
        } else {
            (b, a)
        };
        for dx in 0..w {
            for dy in 0..w {
                let (ox, oy) = (dx - (w - 1) / 2, dy - (w - 1) / 2);
                area.draw(&PathElement::new(
                    vec![(a.0 + ox, a.1 + oy), (b.0 + ox, b.1 + oy)],
                    thin,
                ))
                .map_err(err)?;
            }
        }
    }
    Ok(())
}

/// Draws a marker of `style` of half-size `r` centred at `at` (pixels): filled, or
/// open (white inside a two-pixel outline).
fn draw_marker(area: &Canvas<'_>, at: (i32, i32), style: &Style, r: i32) -> Result<()> {
    if style.hollow {
        draw_marker_shape(area, at, style.marker, style.color.filled(), r)?;
        return draw_marker_shape(area, at, style.marker, WHITE.filled(), r - 2);
    }
    draw_marker_shape(area, at, style.marker, style.color.filled(), r)
}

/// Draws the shape `marker` of half-size `r` centred at `at` (pixels) in `fill`.
fn draw_marker_shape(
    area: &Canvas<'_>,
    at: (i32, i32),
    marker: Marker,
    fill: ShapeStyle,
    r: i32,
) -> Result<()> {
    let (x, y) = at;
    match marker {
        Marker::Circle => area.draw(&Circle::new(at, r, fill)),
        Marker::Square => area.draw(&Rectangle::new([(x - r, y - r), (x + r, y + r)], fill)),
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x + r + 1, y + r), (x - r - 1, y + r)],
            fill,
        )),
        Marker::Diamond => area.draw(&Polygon::new(
            vec![
                (x, y - r - 1),
                (x + r + 1, y),
                (x, y + r + 1),
                (x - r - 1, y),
            ],
            fill,
        )),
    }
    .map_err(err)
}

/// Where arrowheads go along a polyline (pixels): at the middle of every segment of a
/// path with few corners (a rectangle's sides), else evenly along its length. Each is
/// (point, unit direction).
#[must_use]
pub fn arrow_spots(px: &[(i32, i32)]) -> Vec<((f64, f64), (f64, f64))> {
    let seg = |a: (i32, i32), b: (i32, i32)| {
        let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
        (dx, dy, dx.hypot(dy))
    };
    let mut out = Vec::new();
    if px.len() <= 12 {
        for p in px.windows(2) {
            let (dx, dy, len) = seg(p[0], p[1]);
            if len >= 24.0 {
                let mid = (
                    0.5 * f64::from(p[0].0 + p[1].0),
                    0.5 * f64::from(p[0].1 + p[1].1),
                );
                out.push((mid, (dx / len, dy / len)));
            }
        }
        return out;
    }
    let total: f64 = px.windows(2).map(|p| seg(p[0], p[1]).2).sum();
    let n = (total / 160.0).round().clamp(1.0, 8.0);
    let mut targets = (0..)
        .map(|k| (f64::from(k) + 0.5) * total / n)
        .take_while(|&s| s < total);
    let mut next = targets.next();
    let mut walked = 0.0;
    for p in px.windows(2) {
        let (dx, dy, len) = seg(p[0], p[1]);
        while let Some(s) = next.filter(|&s| len > 0.0 && s <= walked + len) {
            let f = (s - walked) / len;
            out.push((
                (f64::from(p[0].0) + f * dx, f64::from(p[0].1) + f * dy),
                (dx / len, dy / len),
            ));
            next = targets.next();
        }
        walked += len;
    }
    out
}

/// Draws arrowheads along a polyline ([`arrow_spots`]).
fn draw_arrows(area: &Canvas<'_>, px: &[(i32, i32)], color: RGBColor) -> Result<()> {
    for ((x, y), (ux, uy)) in arrow_spots(px) {
        let (len, half) = (8.0, 5.5);
        #[allow(clippy::cast_possible_truncation)]
        let pt = |a: f64, b: f64| (a.round() as i32, b.round() as i32);
        let tip = pt(x + len * ux, y + len * uy);
        let back = (x - 0.6 * len * ux, y - 0.6 * len * uy);
        let l = pt(back.0 - half * uy, back.1 + half * ux);
        let r = pt(back.0 + half * uy, back.1 - half * ux);
        area.draw(&Polygon::new(vec![tip, l, r], color.filled()))
            .map_err(err)?;
    }
    Ok(())
}

/// One line of a legend.
#[derive(Debug, Clone)]
pub struct LegendEntry {
    /// Text.
    pub label: String,
    /// The series' style.
    pub style: Style,
    /// Show a line sample.
    pub line: bool,
    /// Show a marker.
    pub markers: bool,
}

/// Height of a legend row, pixels.
const ROW_H: u32 = 20;
/// Width of a legend's line sample, pixels.
const SAMPLE_W: u32 = 32;

/// Size of the legend box of `entries`, pixels.
fn legend_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> (u32, u32) {
    let text = entries
        .iter()
        .map(|e| text_size(area, &e.label, LEGEND_PX).0)
        .max()
        .unwrap_or(0);
    #[allow(clippy::cast_possible_truncation)]
    let rows = entries.len() as u32;
    (8 + SAMPLE_W + 8 + text + 10, 8 + rows * ROW_H + 4)
}

/// Draws a legend box with its top-left corner at `at` (pixels of `area`).
///
/// # Errors
/// When drawing fails.
pub fn draw_legend(area: &Canvas<'_>, at: (i32, i32), entries: &[LegendEntry]) -> Result<()> {
    let (bw, bh) = legend_size(area, entries);
    #[allow(clippy::cast_possible_wrap)]
    let (bw, bh, row, sample) = (bw as i32, bh as i32, ROW_H as i32, SAMPLE_W as i32);
    let (x, y) = at;
    area.draw(&Rectangle::new(
        [(x, y), (x + bw, y + bh)],
        WHITE.mix(0.9).filled(),
    ))
    .map_err(err)?;
    area.draw(&Rectangle::new(
        [(x, y), (x + bw, y + bh)],
        BLACK.stroke_width(1),
    ))
    .map_err(err)?;
    let text = (FONT, LEGEND_PX)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (i, e) in (0i32..).zip(entries) {
        let yc = y + 8 + row * i + row / 2;
        if e.line {
            draw_polyline(area, &[(x + 8, yc), (x + 8 + sample, yc)], &e.style)?;
        }
        if e.markers {
            draw_marker(area, (x + 8 + sample / 2, yc), &e.style, 4)?;
        }
        area.draw_text(&e.label, &text, (x + 16 + sample, yc))
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_is_clipped_to_the_square_keeping_its_direction() {
        // Inside: unchanged.
        let inside = clip_segment((0.2, 0.3), (0.8, 0.9), -1.0, 2.0);
        assert_eq!(inside, Some(((0.2, 0.3), (0.8, 0.9))));
        // From inside to far away: cut at the edge, on the same line.
        let (a, b) = clip_segment((0.5, 0.5), (2.0e4, 0.5), -1.0, 2.0).unwrap();
        assert_eq!(a, (0.5, 0.5));
        assert!((b.0 - 2.0).abs() < 1e-12 && (b.1 - 0.5).abs() < 1e-12);
        // Through the square from both sides far out: the chord.
        let (a, b) = clip_segment((-1e9, -1e9), (1e9, 1e9), -1.0, 2.0).unwrap();
        assert!((a.0 + 1.0).abs() < 1e-6 && (b.1 - 2.0).abs() < 1e-6);
        // Wholly outside, or not finite: nothing.
        assert_eq!(clip_segment((5.0, 5.0), (9.0, 5.0), -1.0, 2.0), None);
        assert_eq!(clip_segment((0.5, 0.5), (f64::NAN, 0.5), -1.0, 2.0), None);
    }

    #[test]
    fn a_polyline_that_leaves_and_comes_back_is_two_runs() {
        let runs = clipped_runs(&[(0.1, 0.5), (0.5, 0.5), (1e6, 0.5), (0.9, 0.5), (0.9, 0.1)]);
        assert_eq!(runs.len(), 2, "{runs:?}");
        assert_eq!(runs[0][..2], [(0.1, 0.5), (0.5, 0.5)]);
        assert_eq!(*runs[1].last().unwrap(), (0.9, 0.1));
    }

    /// `cylinder pair --theta 0.5 --steps 2 --dt 7662315786 --out DIR` drifted by 2·10⁴ in
    /// a view of about 1 and panicked in plotters ("attempt to add with overflow").
    #[test]
    fn points_far_outside_a_fixed_view_are_drawn_without_overflow() {
        let dir = std::env::temp_dir().join(format!("figures-far-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut plot = LinePlot::new("far", "x", "y")
            .with(Series::line(
                "drifted",
                vec![(0.0, 0.0), (2.2e4, 1e9), (0.5, 0.5)],
            ))
            .with(Series::markers("far", vec![(1e300, -1e300), (0.5, 0.5)]).with_arrows());
        plot.bounds = Some((0.0..1.0, 0.0..1.0));
        plot.save(&dir.join("far.png"), (400, 300)).unwrap();
        std::fs::remove_dir_all(&dir).ok();
    }

    fn distance(a: RGBColor, b: RGBColor) -> f64 {
        let d = |x: u8, y: u8| f64::from(x) - f64::from(y);
        (d(a.0, b.0).powi(2) + d(a.1, b.1).powi(2) + d(a.2, b.2).powi(2)).sqrt()
    }

    #[test]
    fn palette_colours_are_distinct_and_none_is_the_base_or_grey() {
        for (i, &a) in PALETTE.iter().enumerate() {
            for &b in &PALETTE[i + 1..] {
                assert!(distance(a, b) > 60.0, "{a:?} too close to {b:?}");
            }
            assert!(distance(a, BASE_COLOR) > 70.0, "{a:?} near the base");
            assert!(distance(a, BLACK) > 80.0, "{a:?} near black");
            // Coloured: the channels differ (grey has r = g = b).
            let (hi, lo) = (a.0.max(a.1).max(a.2), a.0.min(a.1).min(a.2));
            assert!(hi - lo > 60, "{a:?} is greyish");
            // Legible on white.
            let lum = 0.2126 * f64::from(a.0) + 0.7152 * f64::from(a.1) + 0.0722 * f64::from(a.2);
            assert!(lum < 200.0, "{a:?} too light");
        }
        assert!(!PALETTE.contains(&BASE_COLOR) && !PALETTE.contains(&GUIDE_COLOR));
    }

    #[test]
    fn styles_of_a_plot_never_repeat() {
        let mut plot = LinePlot::new("t", "x [m]", "y [m]");
        for i in 0..30 {
            plot = plot.with(Series::line(format!("{i}"), vec![(0.0, 0.0)]));
        }
        let styles = plot.styles();
        for (i, a) in styles.iter().enumerate() {
            for b in &styles[i + 1..] {
                assert!(a.color != b.color || a.dash != b.dash);
            }
        }
        // Twelve curves or fewer: twelve different colours.
        let colours: Vec<RGBColor> = styles[..12].iter().map(|s| s.color).collect();
        assert!((0..12).all(|i| !colours[i + 1..].contains(&colours[i])));
        // A series' own style is not handed out again.
        let plot = LinePlot::new("t", "x", "y")
            .with(Series::line("mine", vec![]).styled(Style::color(PALETTE[0])))
            .with(Series::line("auto", vec![]));
        assert_eq!(plot.styles()[1].color, PALETTE[1]);
    }

    #[test]
    fn computed_points_get_markers_and_a_line_only_when_dense() {
        let few = Series::computed("a", vec![(0.0, 1.0); 5]);
        assert!(few.markers && !few.line);
        let many = Series::computed("a", vec![(0.0, 1.0); DENSE_POINTS]);
        assert!(many.markers && many.line);
    }

    #[test]
    fn titles_fit_their_width() {
        // A fake font: every character is px/2 wide.
        let measure = |s: &str, px: u32| {
            #[allow(clippy::cast_possible_truncation)]
            let n = s.chars().count() as u32;
            n * px / 2
        };
        let (lines, px) = fit_title("short", 400, 22, measure);
        assert_eq!((lines.len(), px), (1, 22));
        let long = "Lire tower, 4 blocks, free fall from the table, t = 12.34";
        let (lines, px) = fit_title(long, 480, 22, measure);
        assert!(lines.iter().all(|l| measure(l, px) <= 480));
        assert_eq!(lines.join(" "), long);
        let (lines, px) = fit_title(long, 200, 22, measure);
        assert!(lines.iter().all(|l| measure(l, px) <= 200), "{lines:?}");
        let (lines, _) = fit_title(&"x".repeat(300), 100, 22, measure);
        assert!(lines[0].ends_with('…'));
        // A caption keeps its own line, at the font at which both lines fit.
        let (lines, px) = fit_title("Lire\nΔt = 0.01, prox r = 0.3", 200, 22, measure);
        assert_eq!(lines, ["Lire", "Δt = 0.01, prox r = 0.3"]);
        assert_eq!(px, 17);
        let (lines, px) = fit_title(&format!("a\n{}", "x".repeat(300)), 100, 22, measure);
        assert_eq!((lines[0].as_str(), px), ("a", 12));
        assert!(lines[1].ends_with('…'));
    }

    #[test]
    fn arrows_sit_on_every_side_of_a_rectangle() {
        let rect = [(0, 0), (100, 0), (100, 50), (0, 50), (0, 0)];
        let spots = arrow_spots(&rect);
        assert_eq!(spots.len(), 4);
        assert_eq!(spots[0], ((50.0, 0.0), (1.0, 0.0)));
        assert_eq!(spots[1], ((100.0, 25.0), (0.0, 1.0)));
        // A dense curve: a few arrows spread along it, pointing forward.
        let curve: Vec<(i32, i32)> = (0..100).map(|i| (i * 8, 0)).collect();
        let spots = arrow_spots(&curve);
        assert!(spots.len() >= 3 && spots.iter().all(|s| s.1 == (1.0, 0.0)));
    }

    /// Runs `check` on a 600 × 400 canvas in memory.
    fn on_canvas(check: impl FnOnce(&Canvas<'_>)) {
        register_font();
        let mut buf = vec![0u8; 600 * 400 * 3];
        let root = BitMapBackend::with_buffer(&mut buf, (600, 400)).into_drawing_area();
        check(&root);
    }

    #[test]
    fn the_legend_goes_where_no_data_is() {
        on_canvas(|root| {
            // x⁴ on [0, 1]: the curve ends in the upper right and hugs the bottom; the
            // upper left is empty.
            let plot = LinePlot::new("", "x [m]", "y [m]").with(Series::line(
                "x⁴",
                (0..=50)
                    .map(|i| f64::from(i) / 50.0)
                    .map(|x| (x, x.powi(4)))
                    .collect(),
            ));
            let data = plot.display_points();
            let (xr, yr) = data_bounds(&data);
            let layout = plot.layout(root, &xr, &yr, 0);
            let ((x, y), hits) = layout.emptiest_spot(&plot.series, &data, (150, 40));
            assert_eq!(hits, 0);
            #[allow(clippy::cast_possible_wrap)]
            let (w, h) = (layout.plot_px.0 as i32, layout.plot_px.1 as i32);
            assert!(x < w / 2 && y < h / 2, "upper left, got ({x}, {y})");
            // Points everywhere: every spot hides some; the plot then puts the legend
            // outside.
            let grid: Vec<(f64, f64)> = (0..400)
                .map(|i| (f64::from(i % 20), f64::from(i / 20)))
                .collect();
            let full = LinePlot::new("", "x", "y").with(Series::markers("all", grid));
            let data = full.display_points();
            let (xr, yr) = data_bounds(&data);
            let layout = full.layout(root, &xr, &yr, 0);
            assert!(layout.emptiest_spot(&full.series, &data, (150, 40)).1 > 0);
        });
    }

    #[test]
    fn log_axes_get_decade_labels_and_room_for_them() {
        on_canvas(|root| {
            let mut plot = LinePlot::new("", "wall time [s]", "error [m]").with(
                Series::line_and_markers("e", vec![(1e-4, 7e-3), (1e-3, 2e-5), (5e-3, 3e-8)]),
            );
            plot.log = (true, true);
            let data = plot.display_points();
            let (xr, yr) = data_bounds(&data);
            let layout = plot.layout(root, &xr, &yr, 0);
            assert_eq!(
                layout.yt.labels,
                ["1e-7", "1e-6", "1e-5", "1e-4", "1e-3", "1e-2"]
            );
            assert_eq!(layout.xt.labels, ["1e-4", "1e-3"]);
            let widest = text_size(root, "1e-7", TICK_PX).0;
            assert!(widest > 20 && layout.y_area >= widest + 24);
        });
    }

    #[test]
    fn dashes_follow_the_path_and_solid_lines_keep_every_segment() {
        let path = [(0, 0), (30, 0), (30, 30)];
        assert_eq!(
            dash_pieces(&path, 1.0, 0.0),
            [((0, 0), (30, 0)), ((30, 0), (30, 30))]
        );
        let dashes = dash_pieces(&path, 9.0, 6.0);
        // 60 pixels, a 15-pixel period: four dashes, the pattern carried round the corner.
        assert_eq!(dashes[0], ((0, 0), (9, 0)));
        assert_eq!(dashes[1], ((15, 0), (24, 0)));
        assert_eq!(dashes[2], ((30, 0), (30, 9)));
        assert_eq!(dashes.len(), 4);
    }

    #[test]
    fn a_range_constant_to_round_off_is_drawn_flat() {
        assert_eq!(pad(0.0, 1.0), -0.05..1.05);
        // The Lire tower at rest: its top block's height varies in the last bits only.
        let r = pad(0.8, 0.8 + 4e-16);
        assert!(
            (r.start - 0.75).abs() < 1e-12 && (r.end - 0.85).abs() < 1e-12,
            "{r:?}"
        );
        let r = pad(-1e-15, 3e-15);
        assert!(
            (r.start + 0.05).abs() < 1e-12 && (r.end - 0.05).abs() < 1e-12,
            "{r:?}"
        );
        // A small but real variation keeps its own range.
        let r = pad(1.0, 1.001);
        assert!(r.end - r.start < 0.0012, "{r:?}");
    }

    #[test]
    fn equal_aspect_gives_equal_scales() {
        let (x, y) = equal_aspect(&(0.0..1.0), &(0.0..4.0), (400, 200));
        let sx = (x.end - x.start) / 400.0;
        let sy = (y.end - y.start) / 200.0;
        assert!((sx - sy).abs() < 1e-12 && y.end - y.start >= 4.0);
    }

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
            .save(&p, (400, 300))
            .unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        std::fs::remove_dir_all(dir).unwrap();
    }
}
