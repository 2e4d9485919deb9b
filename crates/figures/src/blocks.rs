//! Pictures of the stack: snapshots (Figure 4.4), the animation, and the top block's
//! angle and height (Figure 4.5 (b), (c)), and the sweeps' plots. The frames come from
//! [`blockstack::record`].

use crate::animation::write_gif;
use crate::axis::{TickedRange, Ticks, TARGET_TICKS};
use crate::convergence::{with_verdicts, JudgedPoint};
use crate::numerics::{extend_headline, Numerics, Step};
use crate::plot::{
    draw_title_reserving, fit_title, with_png, Canvas, LinePlot, Series, Style, BASE_COLOR, FONT,
    GUIDE_COLOR, PALETTE, TITLE_PX,
};
use crate::{err, FigureError, Result};
use blockstack::record::{Frame, Recording, TopSample};
use blockstack::scenarios::Shaking;
use blockstack::studies::scene_sweep::SceneRow;
use blockstack::studies::shaking::FrequencyRow;
use blockstack::studies::slide::{SlideRegime, SlideRow};
use blockstack::{Scene, SolverParams};
use nsga::{BranchRule, Prox};
use plotters::prelude::*;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The refusal to draw a frame whose coordinates are not all finite.
const NON_FINITE: FigureError =
    FigureError::Data("cannot draw a stack with non-finite coordinates");

/// The axis labels of a picture of the stack (model units, g = 1).
const X_LABEL: &str = "x [length unit]";
/// See [`X_LABEL`].
const Y_LABEL: &str = "y [length unit]";

/// The fill colour of body `k` of a stack (0: the base): the base in [`BASE_COLOR`],
/// block k in the k-th colour of [`PALETTE`] (cycling after twelve), so no block ever
/// has the base's colour.
#[must_use]
pub fn body_color(k: usize) -> RGBColor {
    if k == 0 {
        BASE_COLOR
    } else {
        PALETTE[(k - 1) % PALETTE.len()]
    }
}

/// A window onto the plane of the stack.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Horizontal range.
    pub x: Range<f64>,
    /// Vertical range.
    pub y: Range<f64>,
}

impl View {
    /// Whether any point of `poly` lies inside.
    fn shows(&self, poly: &[(f64, f64)]) -> bool {
        let b = Bounds::of(poly.iter().copied());
        b.x0 < self.x.end && b.x1 > self.x.start && b.y0 < self.y.end && b.y1 > self.y.start
    }
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Bounds {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Bounds {
    const EMPTY: Self = Self {
        x0: f64::MAX,
        x1: f64::MIN,
        y0: f64::MAX,
        y1: f64::MIN,
    };

    fn of(points: impl IntoIterator<Item = (f64, f64)>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, (x, y)| Self {
            x0: b.x0.min(x),
            x1: b.x1.max(x),
            y0: b.y0.min(y),
            y1: b.y1.max(y),
        })
    }

    fn union(self, o: Self) -> Self {
        Self {
            x0: self.x0.min(o.x0),
            x1: self.x1.max(o.x1),
            y0: self.y0.min(o.y0),
            y1: self.y1.max(o.y1),
        }
    }

    fn is_empty(&self) -> bool {
        self.x0 > self.x1
    }

    /// The larger side.
    fn size(&self) -> f64 {
        (self.x1 - self.x0).max(self.y1 - self.y0)
    }

    fn centre(&self) -> (f64, f64) {
        (0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1))
    }

    fn shifted(self, dx: f64, dy: f64) -> Self {
        Self {
            x0: self.x0 + dx,
            x1: self.x1 + dx,
            y0: self.y0 + dy,
            y1: self.y1 + dy,
        }
    }

    /// The distance between two boxes (0 when they overlap).
    fn gap(&self, o: &Self) -> f64 {
        let dx = (o.x0 - self.x1).max(self.x0 - o.x1).max(0.0);
        let dy = (o.y0 - self.y1).max(self.y0 - o.y1).max(0.0);
        dx.hypot(dy)
    }

    /// A view of `w` × `h` centred here, with a margin of [`VIEW_MARGIN`] times the
    /// larger side all round.
    fn view(&self, w: f64, h: f64) -> View {
        let (cx, cy) = self.centre();
        let m = VIEW_MARGIN * w.max(h);
        View {
            x: cx - 0.5 * w - m..cx + 0.5 * w + m,
            y: cy - 0.5 * h - m..cy + 0.5 * h + m,
        }
    }

    /// This box as a view, with the margin.
    fn padded(&self) -> View {
        self.view(self.x1 - self.x0, self.y1 - self.y0)
    }
}

/// The margin around the framed bodies, as a fraction of their size on each side.
const VIEW_MARGIN: f64 = 0.1;

/// A fixed camera frames at most this many times the largest extent of the bodies in
/// play in any one frame; beyond, the camera follows them.
const FIXED_CAMERA_LIMIT: f64 = 2.0;

/// A block is in play while it is within this fraction of the first frame's size from
/// where that frame's bodies were (carried along with the base).
const REACH: f64 = 0.5;

/// The views in which to draw `frames` (one per frame), framed on the bodies rather
/// than on everything every body ever reached:
///
/// 1. L is the size (larger side) of the first frame's bodies, the base included.
/// 2. In each frame the bodies *in play* are the base and every block within L/2 of
///    the first frame's box carried along with the base (the base's displacement
///    added). A block that has fallen or flown farther than that (a block dropping off
///    the Lire table, falling without a floor for ever) is ignored: it leaves the
///    picture, and the frame names it "out of view", rather than shrinking the stack to
///    a few pixels. A floor within L/4 below the bodies in play is kept in view.
/// 3. When all frames' bodies in play fit in a box at most twice as large as those of
///    the most spread-out frame, every frame gets that one box (a fixed camera, as for
///    a shaken column or a collapsing tower). Otherwise (a base pulled far) the camera
///    follows: a box as wide and as high as the largest one-frame extents, centred on
///    each frame's bodies in play.
///
/// Views have a margin of 10 % of their larger side; a picture widens them to its own
/// proportions (equal scales on both axes), adding room above a floor rather than
/// below it. Non-finite frames should be left out.
#[must_use]
pub fn frame_views(scene: &Scene, frames: &[&Frame]) -> Vec<View> {
    let Some(first) = frames.first() else {
        return Vec::new();
    };
    let bodies = |f: &Frame| -> Vec<Bounds> {
        f.outlines(scene)
            .iter()
            .map(|o| Bounds::of(o.iter().copied()))
            .collect()
    };
    let home = bodies(first).into_iter().fold(Bounds::EMPTY, Bounds::union);
    let size = home.size().max(1e-9);
    let reach = REACH * size;
    let in_play: Vec<Bounds> = frames
        .iter()
        .map(|f| {
            let carried = home.shifted(f.base.x - first.base.x, f.base.y - first.base.y);
            let mut b = bodies(f)
                .into_iter()
                .enumerate()
                .filter(|(k, b)| *k == 0 || b.gap(&carried) <= reach)
                .fold(Bounds::EMPTY, |acc, (_, b)| acc.union(b));
            if let Some(floor) = scene.floor() {
                if floor.y < b.y0 && floor.y >= b.y0 - 0.25 * size {
                    b.y0 = floor.y;
                }
            }
            b
        })
        .collect();
    let all = in_play.iter().fold(Bounds::EMPTY, |a, b| a.union(*b));
    if all.is_empty() {
        return vec![home.padded(); frames.len()];
    }
    let widest = in_play
        .iter()
        .map(Bounds::size)
        .fold(0.0, f64::max)
        .max(1e-9);
    if all.size() <= FIXED_CAMERA_LIMIT * widest {
        vec![all.padded(); frames.len()]
    } else {
        let w = in_play.iter().map(|b| b.x1 - b.x0).fold(0.0, f64::max);
        let h = in_play.iter().map(|b| b.y1 - b.y0).fold(0.0, f64::max);
        in_play.iter().map(|b| b.view(w, h)).collect()
    }
}

/// The one view of an animation: every body of every frame, with a margin of
/// 10 % of the larger side. Unlike [`frame_views`] (snapshots, which frame
/// the bodies in play), an animation loses no block out of frame: a block that falls or
/// flies far stays in the picture, smaller. Non-finite frames should be left out.
#[must_use]
pub fn animation_view(scene: &Scene, frames: &[&Frame]) -> View {
    frames
        .iter()
        .flat_map(|f| f.outlines(scene))
        .fold(Bounds::EMPTY, |b, o| b.union(Bounds::of(o)))
        .padded()
}

/// Height of a picture of the stack `width` pixels wide: as high as the views'
/// proportions ask (the tallest of them), between half and 1.25 times the width.
pub(crate) fn picture_height(width: u32, views: &[View]) -> u32 {
    let ratio = views
        .iter()
        .map(|v| (v.y.end - v.y.start) / (v.x.end - v.x.start))
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max)
        .clamp(0.5, 1.25);
    // Around the plotting area: label areas, margins and the title, about 80 pixels
    // across and 120 up.
    let plot_w = f64::from(width.saturating_sub(80));
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let plot_h = (plot_w * ratio).round() as u32;
    plot_h + 120
}

/// The part of a convex polygon inside a view (Sutherland–Hodgman), empty when none.
fn clip(poly: &[(f64, f64)], view: &View) -> Vec<(f64, f64)> {
    let mut out = poly.to_vec();
    let edges: [(usize, f64, bool); 4] = [
        (0, view.x.start, true),
        (0, view.x.end, false),
        (1, view.y.start, true),
        (1, view.y.end, false),
    ];
    for (axis, at, keep_above) in edges {
        let coord = |p: (f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let inside = |p: (f64, f64)| (coord(p) >= at) == keep_above || coord(p) == at;
        let input = std::mem::take(&mut out);
        for (i, &p) in input.iter().enumerate() {
            let q = input[(i + 1) % input.len()];
            if inside(p) {
                out.push(p);
            }
            if inside(p) != inside(q) {
                let f = (at - coord(p)) / (coord(q) - coord(p));
                out.push((p.0 + f * (q.0 - p.0), p.1 + f * (q.1 - p.1)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The layout shared by every frame of one figure: title room, label areas, so that
/// the plotting area, and with it the scale, is the same in every frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StackLayout {
    title_px: u32,
    title_lines: usize,
    x_area: u32,
    y_area: u32,
}

/// Space around a stack chart, pixels.
const STACK_MARGIN: u32 = 12;

impl StackLayout {
    /// The layout for frames with these titles and views on `area`.
    pub(crate) fn new(area: &Canvas<'_>, titles: &[String], views: &[View]) -> Self {
        let measure = |s: &str, px: u32| {
            area.estimate_text_size(s, &TextStyle::from((FONT, px).into_font()))
                .map_or(0, |d| d.0)
        };
        let (w, _) = area.dim_in_pixel();
        let longest = titles
            .iter()
            .max_by_key(|t| measure(t, TITLE_PX))
            .cloned()
            .unwrap_or_default();
        let (lines, title_px) = fit_title(&longest, w.saturating_sub(24), TITLE_PX, measure);
        let widest_tick = views
            .iter()
            .flat_map(|v| Ticks::linear(v.y.start, v.y.end).labels)
            .map(|l| measure(&l, 14))
            .max()
            .unwrap_or(0);
        Self {
            title_px,
            title_lines: lines.len(),
            x_area: 50,
            y_area: widest_tick + 44,
        }
    }

    /// The pixels of a frame of `size` pixels left to its plotting area by the title,
    /// the label areas and the margins of [`draw_stack`].
    pub(crate) fn plot_px(&self, size: (u32, u32)) -> (u32, u32) {
        // As draw_title_reserving reserves the title's lines.
        let lines = u32::try_from(self.title_lines).unwrap_or(1);
        let title = 6 + self.title_px * 5 / 4 * lines + 4;
        self.plot_px_below_title((size.0, size.1.saturating_sub(title)))
    }

    /// The plotting area's pixels in the part of a frame below its title.
    fn plot_px_below_title(&self, (w, h): (u32, u32)) -> (u32, u32) {
        (
            w.saturating_sub(2 * STACK_MARGIN + self.y_area).max(10),
            h.saturating_sub(2 * STACK_MARGIN + self.x_area).max(10),
        )
    }

    /// The view widened to the plotting area's proportions (equal scales), about its
    /// centre; when it holds a floor, the added height goes above the floor rather than
    /// below (nothing is below a floor but the margin).
    pub(crate) fn stretched(
        view: &View,
        plot_px: (u32, u32),
        floor: Option<f64>,
    ) -> (Range<f64>, Range<f64>) {
        let (w, h) = (f64::from(plot_px.0), f64::from(plot_px.1));
        let scale = ((view.x.end - view.x.start) / w).max((view.y.end - view.y.start) / h);
        let cx = 0.5 * (view.x.start + view.x.end);
        let cy = 0.5 * (view.y.start + view.y.end);
        let x = cx - 0.5 * scale * w..cx + 0.5 * scale * w;
        let y = if floor.is_some_and(|f| view.y.contains(&f)) {
            view.y.start..view.y.start + scale * h
        } else {
            cy - 0.5 * scale * h..cy + 0.5 * scale * h
        };
        (x, y)
    }
}

/// Least pixels between the labelled ticks of a stack's axes: labels of 14 pixels with
/// room between them up the y axis, numbers like `-0.25` along the x axis.
const TICK_SPACING_PX: (f64, f64) = (60.0, 30.0);

/// The ticks of a stack's axes over `x` and `y` drawn in `plot_px` pixels: about six,
/// fewer on a short axis (a thumbnail of a column fallen flat), so that no two labels
/// touch ([`TICK_SPACING_PX`]).
pub(crate) fn stack_ticks(x: &Range<f64>, y: &Range<f64>, plot_px: (u32, u32)) -> (Ticks, Ticks) {
    let most = |px: u32, spacing: f64| (f64::from(px) / spacing).min(TARGET_TICKS);
    (
        Ticks::linear_about(x.start, x.end, most(plot_px.0, TICK_SPACING_PX.0)),
        Ticks::linear_about(y.start, y.end, most(plot_px.1, TICK_SPACING_PX.1)),
    )
}

/// Draws one frame of the stack onto a canvas: the floor as a line, the base in
/// [`BASE_COLOR`], the blocks as rotated rectangles in colour, clipped to the view; the
/// bodies out of view are named in the corner.
pub(crate) fn draw_stack(
    root: &Canvas<'_>,
    scene: &Scene,
    frame: &Frame,
    view: &View,
    title: &str,
    layout: &StackLayout,
) -> Result<()> {
    let area = draw_title_reserving(root, title, layout.title_px, layout.title_lines)?;
    let plot_px = layout.plot_px_below_title(area.dim_in_pixel());
    let (xr, yr) = StackLayout::stretched(view, plot_px, scene.floor().map(|f| f.y));
    let view = View {
        x: xr.clone(),
        y: yr.clone(),
    };
    let (xt, yt) = stack_ticks(&xr, &yr, plot_px);
    let mut chart = ChartBuilder::on(&area)
        .margin(STACK_MARGIN)
        .x_label_area_size(layout.x_area)
        .y_label_area_size(layout.y_area)
        .build_cartesian_2d(
            TickedRange::new(xr.clone(), xt),
            TickedRange::new(yr.clone(), yt),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(X_LABEL)
        .y_desc(Y_LABEL)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .bold_line_style(RGBColor(215, 215, 215))
        // No minor grid: cleaner pictures and a much smaller animation.
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    if let Some(f) = scene.floor().filter(|f| yr.contains(&f.y)) {
        chart
            .draw_series(LineSeries::new(
                vec![(xr.start, f.y), (xr.end, f.y)],
                BLACK.stroke_width(2),
            ))
            .map_err(err)?;
    }
    let mut hidden = Vec::new();
    for (k, poly) in frame.outlines(scene).into_iter().enumerate() {
        let shown = clip(&poly, &view);
        if shown.len() < 3 || !view.shows(&poly) {
            hidden.push(k);
            continue;
        }
        let mut closed = shown.clone();
        closed.push(shown[0]);
        chart
            .draw_series(std::iter::once(Polygon::new(
                shown,
                body_color(k).mix(0.75).filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(PathElement::new(
                closed,
                BLACK.stroke_width(1),
            )))
            .map_err(err)?;
    }
    if !hidden.is_empty() {
        let plot = chart.plotting_area().strip_coord_spec();
        let (_, ph) = plot.dim_in_pixel();
        #[allow(clippy::cast_possible_wrap)]
        plot.draw_text(
            &format!("out of view: {}", body_names(&hidden)),
            &(FONT, 14).into_font().color(&BLACK),
            (8, ph as i32 - 22),
        )
        .map_err(err)?;
    }
    Ok(())
}

/// "base, blocks 3, 4", "block 2": bodies by number (0: the base).
fn body_names(bodies: &[usize]) -> String {
    let blocks: Vec<String> = bodies
        .iter()
        .filter(|&&k| k > 0)
        .map(ToString::to_string)
        .collect();
    let mut parts = Vec::new();
    if bodies.contains(&0) {
        parts.push("base".to_owned());
    }
    match blocks.len() {
        0 => {}
        1 => parts.push(format!("block {}", blocks[0])),
        _ => parts.push(format!("blocks {}", blocks.join(", "))),
    }
    parts.join(", ")
}

/// Draws the stack at time t with coordinates q: the base in [`BASE_COLOR`] (black in
/// Figure 4.4), the blocks in colour, the floor as a line; equal scales on both axes.
///
/// # Errors
/// Non-finite coordinates or an unwritable file.
pub fn plot_stack(path: &Path, scene: &Scene, q: &[f64], t: f64, title: &str) -> Result<()> {
    let frame = Frame::from_coordinates(scene, q, t);
    if !frame.is_finite() {
        return Err(NON_FINITE);
    }
    let views = frame_views(scene, &[&frame]);
    with_png(path, (800, picture_height(800, &views)), |root| {
        let layout = StackLayout::new(root, &[title.to_owned()], &views);
        draw_stack(root, scene, &frame, &views[0], title, &layout)
    })
}

/// Draws frames into one PNG each, framed together ([`frame_views`]: one common view
/// unless the bodies travel far) (Figure 4.4 style snapshots).
///
/// # Errors
/// A non-finite frame or an unwritable file.
pub fn plot_snapshots(scene: &Scene, shots: &[(PathBuf, String, &Frame)]) -> Result<()> {
    if shots.iter().any(|s| !s.2.is_finite()) {
        return Err(NON_FINITE);
    }
    let frames: Vec<&Frame> = shots.iter().map(|s| s.2).collect();
    let views = frame_views(scene, &frames);
    let titles: Vec<String> = shots.iter().map(|s| s.1.clone()).collect();
    for ((path, title, frame), view) in shots.iter().zip(&views) {
        with_png(path, (800, picture_height(800, &views)), |root| {
            let layout = StackLayout::new(root, &titles, &views);
            draw_stack(root, scene, frame, view, title, &layout)
        })?;
    }
    Ok(())
}

/// Delay between animation frames (ms).
const ANIMATION_FRAME_MS: u32 = 80;

/// Writes an animated GIF of `frames`, every body of every frame in one view
/// ([`animation_view`]), atomically. Each frame's title is `title` and its time, fitted to the width.
///
/// # Errors
/// No finite frame, or an unwritable file.
pub fn write_animation(path: &Path, scene: &Scene, frames: &[Frame], title: &str) -> Result<()> {
    let good: Vec<&Frame> = frames.iter().filter(|f| f.is_finite()).collect();
    if good.is_empty() {
        return Err(FigureError::Data("no frame to animate"));
    }
    let views = vec![animation_view(scene, &good); good.len()];
    let titles: Vec<String> = good
        .iter()
        .map(|f| extend_headline(title, &format!(", t = {:.2}", f.t)))
        .collect();
    let size = (480, picture_height(480, &views));
    // The layout only measures text: a scratch canvas of the frames' size serves.
    let mut scratch = vec![0; size.0 as usize * size.1 as usize * 3];
    let layout = StackLayout::new(
        &BitMapBackend::with_buffer(&mut scratch, size).into_drawing_area(),
        &titles,
        &views,
    );
    write_gif(path, size, ANIMATION_FRAME_MS, good.len(), |i, root| {
        draw_stack(root, scene, good[i], &views[i], &titles[i], &layout)
    })
}

/// The top block's angle and height against time (Figures 4.5 (b), (c)).
///
/// # Errors
/// An unwritable file.
pub fn plot_top_block(path: &Path, top: &[TopSample], title: &str) -> Result<()> {
    let angle = LinePlot::new(
        extend_headline(title, ": top block angle"),
        "t [time unit]",
        "θ [rad]",
    )
    .with(Series::line(
        "",
        top.iter().map(|p| (p.t, p.theta)).collect(),
    ));
    let height = LinePlot::new(
        extend_headline(title, ": top block height"),
        "t [time unit]",
        "y [length unit]",
    )
    .with(Series::line("", top.iter().map(|p| (p.t, p.y)).collect()));
    with_png(path, (1400, 550), |root| {
        let (left, right) = root.split_horizontally(700);
        angle.draw(&left)?;
        height.draw(&right)
    })
}

/// File name of the snapshot at requested time t, e.g. `snapshot_t6.4.png`.
#[must_use]
pub fn snapshot_name(t: f64) -> String {
    // Six decimals at most: `snapshot_t7.853982.png`, not all seventeen digits.
    format!("snapshot_t{}.png", (t * 1e6).round() / 1e6)
}

/// What [`draw_run`] drew, and what it left out and why.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DrawnRun {
    /// The files written, relative names.
    pub files: Vec<String>,
    /// One line per picture left out, e.g. "no animation.gif: no state was computed".
    pub notes: Vec<String>,
}

/// The pictures of one run in `dir`: a snapshot per requested time (one common view;
/// a run that stopped earlier shows its last state and says so), the animation when
/// `animate`, and the top block's angle and height. A picture with nothing to draw (a
/// run that could not start has no state at all; a state that is not finite cannot be
/// drawn) is left out with a note instead.
///
/// # Errors
/// An unwritable file.
pub fn draw_run(
    dir: &Path,
    scene: &Scene,
    recording: &Recording,
    title: &str,
    animate: bool,
) -> Result<DrawnRun> {
    let mut out = DrawnRun::default();
    let why = |what: &str| {
        if recording.last.is_none() {
            format!("no {what}: no state was computed (the run did not start)")
        } else {
            format!("no {what}: no finite state to draw")
        }
    };
    let mut shots: Vec<(PathBuf, String, &Frame)> = Vec::new();
    for (ts, f) in &recording.snapshots {
        let name = snapshot_name(*ts);
        if !f.is_finite() {
            out.notes
                .push(format!("no {name}: the state at t = {} is not finite", f.t));
            continue;
        }
        let note = if f.t < ts - 0.5 * scene.solver.dt {
            format!(" (run ended before t = {ts})")
        } else {
            String::new()
        };
        let shot_title = extend_headline(title, &format!(", t = {:.2}{note}", f.t));
        shots.push((dir.join(&name), shot_title, f));
        out.files.push(name);
    }
    if recording.snapshots.is_empty() && recording.last.is_none() {
        out.notes.push(why("snapshots"));
    }
    plot_snapshots(scene, &shots)?;
    if animate {
        if recording.frames.iter().any(Frame::is_finite) {
            write_animation(&dir.join("animation.gif"), scene, &recording.frames, title)?;
            out.files.push("animation.gif".to_owned());
        } else {
            out.notes.push(why("animation.gif"));
        }
    }
    if recording.top.is_empty() {
        out.notes.push(why("top_block.png"));
    } else {
        plot_top_block(&dir.join("top_block.png"), &recording.top, title)?;
        out.files.push("top_block.png".to_owned());
    }
    Ok(out)
}

/// What a frequency sweep holds fixed (ω is the swept parameter): what its figure's
/// title says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrequencySweep {
    /// Number of free blocks.
    pub blocks: usize,
    /// Base amplitude A, length units.
    pub amplitude: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Base periods simulated per run (when there is no `t_max`).
    pub periods: f64,
    /// Steps per base period N (Δt = 2π/(Nω)).
    pub steps_per_period: f64,
    /// The horizon in time units, the same at every ω, when the sweep has one.
    pub t_max: Option<f64>,
    /// The prox parameter of the runs.
    pub prox: Prox,
    /// The branch rule when the sweep explores each run's motions (`--branches`).
    pub rule: Option<BranchRule>,
}

impl FrequencySweep {
    /// The fixed parameters of shaken columns like `s` (its ω is not used), with the
    /// default prox and no exploration.
    #[must_use]
    pub fn of(s: &Shaking) -> Self {
        Self {
            blocks: s.blocks,
            amplitude: s.amplitude,
            mu: s.mu,
            periods: s.periods,
            steps_per_period: s.steps_per_period,
            t_max: None,
            prox: SolverParams::default().prox,
            rule: None,
        }
    }

    /// How a run that does not fail is described: "no failure by t = 40", or "no failure
    /// within 10 periods (t = 20π/ω)" whose horizon shrinks as ω grows.
    #[must_use]
    pub fn survival(&self) -> String {
        match self.t_max {
            Some(t) => format!("no failure by t = {t}"),
            None => format!(
                "no failure within {} periods (t = {}·2π/ω)",
                self.periods, self.periods
            ),
        }
    }

    /// Whether these are the parameters of Figure 4.6 (four blocks, A = 0.2, μ = 0.2,
    /// Δt = 2π/(100ω), the defaults of [`Shaking`]); the number of periods only bounds
    /// each run.
    #[must_use]
    pub fn is_figure_4_6(&self) -> bool {
        let thesis = Shaking::default();
        self.blocks == thesis.blocks
            && self.amplitude == thesis.amplitude
            && self.mu == thesis.mu
            && self.steps_per_period == thesis.steps_per_period
    }

    /// The figure's title, from the parameters: e.g. "Failure time of a shaken column,
    /// 4 blocks, A = 0.2, μ = 0.2, 10 periods (cf. Figure 4.6)", or "…, t ≤ 40 (…)" with a
    /// horizon in time units, "cf. Figure 4.6" only when [`Self::is_figure_4_6`]; under
    /// it the caption: the rule when exploring, Δt = 2π/(Nω) and the prox.
    #[must_use]
    pub fn title(&self) -> String {
        let blocks = plural(self.blocks, "block");
        let horizon = self.t_max.map_or_else(
            || format!("{} periods", self.periods),
            |t| format!("t ≤ {t}"),
        );
        let mut t = format!(
            "Failure time of a shaken column, {blocks}, A = {}, μ = {}, {horizon}",
            self.amplitude, self.mu
        );
        if self.is_figure_4_6() {
            t.push_str(" (cf. Figure 4.6)");
        }
        let numerics = Numerics {
            rule: self.rule,
            step: Step::PerPeriod(self.steps_per_period),
            prox: self.prox,
        };
        numerics.under(&t)
    }
}

/// "1 block", "4 blocks".
fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The title of a scene sweep's panel: `what` against the swept `key`, with why the
/// panel is `empty` when it is, and the runs' caption under it.
#[must_use]
pub fn scene_sweep_title(
    what: &str,
    key: &str,
    empty: Option<&str>,
    numerics: &Numerics,
) -> String {
    let headline = match empty {
        None => format!("{what} against {key}"),
        Some(why) => format!("{what} against {key} ({why})"),
    };
    numerics.under(&headline)
}

/// The inverse time to failure 1/T of a shaken column against the frequency ω
/// (Figure 4.6 with its parameters), 0 where the column survived: a marker per run,
/// failed and surviving runs told apart; with [`DENSE_POINTS`](crate::plot::DENSE_POINTS)
/// runs or more, one curve through all of them with its markers. Runs that stopped
/// before failing or surviving have no value and no marker.
///
/// # Errors
/// An unwritable file.
pub fn plot_frequency_sweep(
    path: &Path,
    rows: &[FrequencyRow],
    sweep: &FrequencySweep,
) -> Result<()> {
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.inv_failure_time.map(|v| (r.omega, v)))
        .collect();
    let mut plot = LinePlot::new(sweep.title(), "ω [rad / time unit]", "1/T [1 / time unit]");
    let survived = sweep.survival();
    let dense = Series::computed("", points.clone());
    if dense.line {
        let mut sorted = points;
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        plot = plot.with(Series::line_and_markers(
            format!("1/T (T: first loss of support; 0: {survived})"),
            sorted,
        ));
    } else {
        let failed: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.1 > 0.0).collect();
        let kept: Vec<(f64, f64)> = points.into_iter().filter(|p| p.1 <= 0.0).collect();
        if !failed.is_empty() {
            plot = plot.with(Series::markers("1/T, T: first loss of support", failed));
        }
        if !kept.is_empty() {
            plot = plot.with(Series::markers(
                format!("{survived}, drawn at 1/T = 0"),
                kept,
            ));
        }
    }
    // Motions that survive the horizon count as 1/T = 0, the band reaches down to it.
    let bands = rows.iter().filter(|r| r.branches > 1).filter_map(|r| {
        let (lo, hi) = (r.failure_time_min?, r.failure_time_max?);
        let bottom = if r.failed_branches < r.branches {
            0.0
        } else {
            1.0 / hi
        };
        Some((r.omega, bottom, 1.0 / lo))
    });
    plot = with_bands(plot, bands, "1/T over the explored motions");
    let judged: Vec<JudgedPoint> = rows.iter().filter_map(judged_frequency).collect();
    plot = with_verdicts(
        plot,
        &judged,
        "1/T over Δt/2^k and the ensemble",
        "failure time",
    );
    plot.save(path, (1000, 620))
}

/// A frequency row's study as its figure draws it: 1/T at the finest level (0 when it
/// stood), the band in 1/T reaching down to 0 when some level stood.
fn judged_frequency(r: &FrequencyRow) -> Option<JudgedPoint> {
    let c = r.convergence.as_ref()?;
    let inverse = |t: f64| if t > 0.0 { 1.0 / t } else { 0.0 };
    let stood = c.failure_times.iter().any(Option::is_none);
    let band = c.spread.map(|[lo, hi]| {
        let bottom = if stood { 0.0 } else { inverse(hi) };
        (bottom, inverse(lo))
    });
    Some(JudgedPoint {
        x: r.omega,
        y: c.finest.map_or(0.0, inverse),
        band,
        verdict: c.failure_verdict?,
    })
}

/// `plot` with a vertical bar from `lo` to `hi` at each `x` of `bands`, labelled once.
pub(crate) fn with_bands(
    mut plot: LinePlot,
    bands: impl Iterator<Item = (f64, f64, f64)>,
    label: &str,
) -> LinePlot {
    let style = Style::color(GUIDE_COLOR).width(4);
    for (i, (x, lo, hi)) in bands.enumerate() {
        let name = if i == 0 { label } else { "" };
        plot = plot.with(Series::line(name, vec![(x, lo), (x, hi)]).styled(style));
    }
    plot
}

/// What a slide sweep holds fixed (v₀ is the swept parameter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlideSweep {
    /// Number of free blocks on the base.
    pub blocks: usize,
    /// Time at which the top block's angle is read.
    pub t_end: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// The runs' Δt, prox and (when exploring) branch rule.
    pub numerics: Numerics,
}

impl SlideSweep {
    /// Whether these are the parameters of Figure 4.7: four blocks (five bodies with
    /// the base), μ = 0.2, angle read at t = 3.
    #[must_use]
    pub fn is_figure_4_7(&self) -> bool {
        self.blocks == 4 && self.t_end == 3.0 && self.mu == 0.2
    }

    /// The figure's title, e.g. "Top block angle at t = 3 on a pulled base, 4 blocks
    /// (cf. Figure 4.7)", "cf." only for [`Self::is_figure_4_7`]; under it the caption
    /// of [`Self::numerics`].
    #[must_use]
    pub fn title(&self) -> String {
        let mut t = format!(
            "Top block angle at t = {} on a pulled base, {}, μ = {}",
            self.t_end,
            plural(self.blocks, "block"),
            self.mu
        );
        if self.is_figure_4_7() {
            t.push_str(" (cf. Figure 4.7)");
        }
        self.numerics.under(&t)
    }
}

/// The top block's angle at `t_end` against the base speed v₀ (Figure 4.7 with its
/// parameters): a marker per run in the colour and shape of its regime, runs that
/// stopped early apart (at the angle they had when they stopped); with
/// [`DENSE_POINTS`](crate::plot::DENSE_POINTS) runs or more that reached `t_end`, a grey
/// line joins them under the markers.
///
/// # Errors
/// An unwritable file.
pub fn plot_slide_sweep(path: &Path, rows: &[SlideRow], sweep: &SlideSweep) -> Result<()> {
    let mut plot = LinePlot::new(
        sweep.title(),
        "v0 [length / time unit]",
        "θ of the top block [rad]",
    );
    let mut reached: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.error.is_none())
        .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
        .collect();
    if reached.len() >= crate::plot::DENSE_POINTS {
        reached.sort_by(|a, b| a.0.total_cmp(&b.0));
        plot = plot.with(
            Series::line(format!("runs that reached t = {}", sweep.t_end), reached)
                .styled(Style::color(GUIDE_COLOR).width(1)),
        );
    }
    for regime in [
        SlideRegime::RidesAlong,
        SlideRegime::Topples,
        SlideRegime::Drops,
    ] {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.regime == Some(regime))
            .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
            .collect();
        if !pts.is_empty() {
            plot = plot.with(Series::markers(regime.name(), pts));
        }
    }
    let stopped: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.error.is_some())
        .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
        .collect();
    if !stopped.is_empty() {
        plot = plot.with(Series::markers(
            "stopped early (angle at the stop)",
            stopped,
        ));
    }
    let bands = rows
        .iter()
        .filter(|r| r.branches > 1)
        .filter_map(|r| Some((r.v0, r.top_angle_min?, r.top_angle_max?)));
    plot = with_bands(
        plot,
        bands,
        "θ over the explored motions (smallest to largest)",
    );
    let judged: Vec<JudgedPoint> = rows
        .iter()
        .filter_map(|r| {
            let c = r.convergence.as_ref()?;
            Some(JudgedPoint {
                x: r.v0,
                y: c.finest?,
                band: c.spread.map(|[lo, hi]| (lo, hi)),
                verdict: c.outcome_verdict?,
            })
        })
        .collect();
    plot = with_verdicts(plot, &judged, "θ over Δt/2^k and the ensemble", "outcome");
    plot.save(path, (1000, 620))
}

/// Most lines the picture of a scene sweep draws (one colour each, [`PALETTE`]); a sweep
/// with more combinations of its other keys is left without a picture.
pub const SCENE_SWEEP_MAX_LINES: usize = 8;

/// One line of a scene sweep's picture: its label and its rows, in order.
pub type SweepLine<'a> = (String, Vec<&'a SceneRow>);

/// The rows of a scene sweep as the lines of its picture: the key along x (the last
/// swept key that takes more than one value, else the last key) and one line per
/// combination of the other keys that take more than one value, labelled with their
/// values (`contact.mu = 0.1`), in order of first appearance; one unlabelled line when
/// only one key varies. `None` when no key is swept or there is no row.
#[must_use]
pub fn scene_sweep_lines(rows: &[SceneRow]) -> Option<(usize, Vec<SweepLine<'_>>)> {
    let n = rows.first()?.set.len();
    let varies = |i: usize| {
        rows.iter()
            .any(|r| r.set.get(i).map(|s| s.value) != rows[0].set.get(i).map(|s| s.value))
    };
    let x = (0..n).rev().find(|&i| varies(i)).or(n.checked_sub(1))?;
    let mut lines: Vec<SweepLine<'_>> = Vec::new();
    for row in rows {
        let label = row
            .set
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != x && varies(i))
            .map(|(_, s)| format!("{} = {}", s.key, s.value))
            .collect::<Vec<_>>()
            .join(", ");
        match lines.iter_mut().find(|(l, _)| *l == label) {
            Some((_, members)) => members.push(row),
            None => lines.push((label, vec![row])),
        }
    }
    Some((x, lines))
}

/// 1/T of a scene sweep's run, as in the frequency sweep's plot: 1/T for a run whose
/// column lost its support at T > 0, 0 for a run that reached its end without failing,
/// nothing for a run that stopped early without failing (nothing is known).
#[must_use]
pub fn inverse_failure_time(row: &SceneRow) -> Option<f64> {
    match (row.failure_time, &row.error) {
        (Some(t), _) if t > 0.0 => Some(1.0 / t),
        (None, None) if row.t_final.is_some() => Some(0.0),
        _ => None,
    }
}

/// The picture of a scene sweep: the inverse failure time 1/T ([`inverse_failure_time`]:
/// 0 for the runs that did not fail, as in the frequency sweep's plot) and the
/// top block's angle at the end of each run (at the stop, for runs that stopped early)
/// against one swept key, one line of markers per combination of the other keys
/// ([`scene_sweep_lines`]). Left out with a note when no key is swept, there is no row,
/// or the other keys have more than [`SCENE_SWEEP_MAX_LINES`] combinations.
///
/// # Errors
/// An unwritable file.
pub fn plot_scene_sweep(path: &Path, rows: &[SceneRow], numerics: &Numerics) -> Result<DrawnRun> {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut out = DrawnRun::default();
    let Some((x, lines)) = scene_sweep_lines(rows) else {
        out.notes
            .push(format!("no {name}: no row with a swept key to draw"));
        return Ok(out);
    };
    let key = rows[0].set[x].key.clone();
    if lines.len() > SCENE_SWEEP_MAX_LINES {
        out.notes.push(format!(
            "no {name}: the keys other than {key} have {} combinations, more than the {SCENE_SWEEP_MAX_LINES} lines one picture shows (plot the CSV)",
            lines.len()
        ));
        return Ok(out);
    }
    let panel = |what: &str, empty: &str, y_label: &str, y: fn(&SceneRow) -> Option<f64>| {
        let empty = (!rows.iter().any(|r| y(r).is_some())).then_some(empty);
        let title = scene_sweep_title(what, &key, empty, numerics);
        lines.iter().fold(
            LinePlot::new(title, key.as_str(), y_label),
            |plot, (label, members)| {
                let points = members
                    .iter()
                    .filter_map(|r| Some((r.set.get(x)?.value, y(r)?)))
                    .collect();
                plot.with(Series::line_and_markers(label.as_str(), points))
            },
        )
    };
    let failure = panel(
        "1/T (T: first loss of support; 0: no failure by the run's end)",
        "no run failed or reached its end",
        "1/T [1 / time unit]",
        inverse_failure_time,
    );
    let angle = panel(
        "top block's angle at the end",
        "no run computed a state",
        "theta of the top block at t_final (rad)",
        |r| r.top_theta,
    );
    with_png(path, (900, 1000), |root| {
        let panels = root.split_evenly((2, 1));
        failure.draw(&panels[0])?;
        angle.draw(&panels[1])
    })?;
    out.files.push(name);
    Ok(out)
}

#[cfg(test)]
mod scene_sweep_tests {
    use super::*;
    use blockstack::studies::scene_sweep::{cartesian_product, Override};

    fn rows(overrides: &[&str]) -> Vec<SceneRow> {
        let o: Vec<Override> = overrides.iter().map(|s| s.parse().unwrap()).collect();
        cartesian_product(&o)
            .into_iter()
            .enumerate()
            .map(|(k, set)| SceneRow {
                set,
                failure_time: (k % 2 == 0).then_some(1.0 + k as f64),
                opening_time: None,
                t_final: Some(2.0),
                steps: 10,
                failed_steps: 0,
                branch_points: 0,
                fallback_steps: 0,
                unshifted_steps: 0,
                linear_solves: 0,
                min_gap: None,
                max_penetration: None,
                top_x: Some(0.0),
                top_y: Some(1.0),
                top_theta: Some(0.1 * k as f64),
                error: None,
                wall_time_s: 0.0,
                convergence: None,
            })
            .collect()
    }

    #[test]
    fn scene_sweep_lines_follow_the_other_keys() {
        let one = rows(&["contact.mu=0.1:0.3:0.1"]);
        let (x, lines) = scene_sweep_lines(&one).unwrap();
        assert_eq!((x, lines.len()), (0, 1));
        assert_eq!((lines[0].0.as_str(), lines[0].1.len()), ("", 3));
        let three = rows(&[
            "contact.mu=0.1,0.2",
            "base.amplitude=0.1",
            "base.omega=1,2,3",
        ]);
        let (x, lines) = scene_sweep_lines(&three).unwrap();
        assert_eq!(x, 2);
        let labels: Vec<&str> = lines.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels, ["contact.mu = 0.1", "contact.mu = 0.2"]);
        assert!(lines.iter().all(|(_, m)| m.len() == 3));
        // A last key with one value is not the x axis.
        let fixed_last = rows(&["base.omega=1,2,3", "solver.periods=3"]);
        let (x, lines) = scene_sweep_lines(&fixed_last).unwrap();
        assert_eq!((x, lines.len()), (0, 1));
        let (x, _) = scene_sweep_lines(&rows(&["a.x=1", "b.y=2"])).unwrap();
        assert_eq!(x, 1);
        assert!(scene_sweep_lines(&rows(&[])).is_none(), "no key");
        assert!(scene_sweep_lines(&[]).is_none());
    }

    #[test]
    fn runs_without_failure_are_drawn_at_zero() {
        let mut r = rows(&["a.x=1,2"]);
        assert_eq!(r[0].failure_time, Some(1.0));
        assert_eq!(inverse_failure_time(&r[0]), Some(1.0));
        // Reached its end without failing: 1/T = 0, as in the frequency sweep's plot.
        assert_eq!(r[1].failure_time, None);
        assert_eq!(inverse_failure_time(&r[1]), Some(0.0));
        // Stopped early without failing, or never started: nothing is known.
        r[1].error = Some("stopped".to_owned());
        assert_eq!(inverse_failure_time(&r[1]), None);
        r[1].error = None;
        r[1].t_final = None;
        assert_eq!(inverse_failure_time(&r[1]), None);
        // A failure at t = 0 has no finite 1/T.
        r[0].failure_time = Some(0.0);
        assert_eq!(inverse_failure_time(&r[0]), None);
    }

    #[test]
    fn scene_sweep_picture_or_a_note() {
        let dir =
            std::env::temp_dir().join(format!("rollstack-scene-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sweep_scene.png");
        let numerics = Numerics::run(0.01, Prox::Scaled(1.0));
        let drawn = plot_scene_sweep(&path, &rows(&["a.x=1,2", "b.y=0:1:0.5"]), &numerics).unwrap();
        assert_eq!(drawn.files, ["sweep_scene.png"]);
        assert_eq!(&std::fs::read(&path).unwrap()[1..4], b"PNG");
        let many = plot_scene_sweep(
            &dir.join("many.png"),
            &rows(&["a.x=1:9:1", "b.y=1,2"]),
            &numerics,
        )
        .unwrap();
        assert!(
            many.files.is_empty() && many.notes[0].contains("9 combinations"),
            "{many:?}"
        );
        let fixed = plot_scene_sweep(&dir.join("fixed.png"), &rows(&["a.x=1"]), &numerics).unwrap();
        assert_eq!(fixed.files, ["fixed.png"]);
        let none = plot_scene_sweep(&dir.join("none.png"), &[], &numerics).unwrap();
        assert!(none.files.is_empty() && none.notes.len() == 1);
        assert!(!dir.join("many.png").exists() && !dir.join("none.png").exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::scenarios::{lire, shaking_column, sliding_column, Perturbation};
    use blockstack::Pose;

    /// The box of every body of a frame.
    fn extent(scene: &Scene, f: &Frame) -> Bounds {
        Bounds::of(f.outlines(scene).into_iter().flatten())
    }

    fn inside(view: &View, b: &Bounds) -> bool {
        view.x.start <= b.x0 && b.x1 <= view.x.end && view.y.start <= b.y0 && b.y1 <= view.y.end
    }

    /// Frames of a scene's bodies moved by `motion(t, k, pose)` (k = 0: the base).
    fn moved(scene: &Scene, motion: impl Fn(f64, usize, Pose) -> Pose) -> Vec<Frame> {
        let start = Frame::from_coordinates(scene, &scene.initial_coordinates(), 0.0);
        (0..=100)
            .map(|i| {
                let t = 0.1 * f64::from(i);
                Frame {
                    t,
                    base: motion(t, 0, start.base),
                    blocks: (1..)
                        .zip(&start.blocks)
                        .map(|(k, p)| motion(t, k, *p))
                        .collect(),
                }
            })
            .collect()
    }

    /// The frames of a tower whose blocks slide off the table and fall, 50 length units
    /// in 10 time units, turning; the table (body 0) stays.
    fn falling_off_the_table(scene: &Scene) -> Vec<Frame> {
        moved(scene, |t, k, p| {
            if k == 0 {
                p
            } else {
                Pose::new(p.x + 0.2 * t, p.y - 0.5 * t * t, p.theta + 0.3 * t)
            }
        })
    }

    #[test]
    fn a_tower_falling_off_its_table_stays_large_in_a_fixed_view() {
        // The Lire tower without a floor: the blocks slide off and fall for ever, 50
        // length units in 10 time units; the table stays.
        let scene = lire(4, Perturbation::Bottom).unwrap();
        let frames = falling_off_the_table(&scene);
        let refs: Vec<&Frame> = frames.iter().collect();
        let views = frame_views(&scene, &refs);
        assert_eq!(views.len(), frames.len());
        assert!(views.iter().all(|v| v == &views[0]), "one camera");
        let tower = extent(&scene, &frames[0]);
        assert!(inside(&views[0], &tower));
        // All positions together are 50 high; the view stays within a few tower sizes,
        // so a block 0.2 high keeps 20 pixels and more of a 480-pixel animation.
        let all = frames
            .iter()
            .fold(Bounds::EMPTY, |a, f| a.union(extent(&scene, f)));
        assert!(all.y1 - all.y0 > 45.0);
        let height = views[0].y.end - views[0].y.start;
        assert!(height <= 3.0 * tower.size(), "{height}");
        assert!(480.0 * 0.2 / height >= 20.0);
    }

    #[test]
    fn an_animation_keeps_every_block_in_frame() {
        // The tower falling off its table: snapshots frame the table, the animation
        // keeps every block of every frame in its one view, with a margin.
        let scene = lire(4, Perturbation::Bottom).unwrap();
        let frames = falling_off_the_table(&scene);
        let refs: Vec<&Frame> = frames.iter().collect();
        let view = animation_view(&scene, &refs);
        let all = frames
            .iter()
            .fold(Bounds::EMPTY, |a, f| a.union(extent(&scene, f)));
        assert!(inside(&view, &all));
        let margin = VIEW_MARGIN * all.size();
        assert!((all.y0 - view.y.start - margin).abs() < 1e-9);
        assert!((view.y.end - all.y1 - margin).abs() < 1e-9);
    }

    #[test]
    fn a_shaken_column_gets_one_view_that_holds_it_always() {
        let scene = shaking_column(&blockstack::scenarios::Shaking::default()).unwrap();
        let frames = moved(&scene, |t, k, p| {
            let dx = 0.2 * (2.0 * t).sin();
            Pose::new(p.x + dx, p.y, p.theta + 0.05 * (k as f64) * (3.0 * t).sin())
        });
        let refs: Vec<&Frame> = frames.iter().collect();
        let views = frame_views(&scene, &refs);
        assert!(views.iter().all(|v| v == &views[0]));
        assert!(frames.iter().all(|f| inside(&views[0], &extent(&scene, f))));
        // Framed on the bodies: the column fills most of the view's height.
        let column = extent(&scene, &frames[0]);
        let height = views[0].y.end - views[0].y.start;
        assert!((column.y1 - column.y0) / height > 0.6);
    }

    #[test]
    fn a_column_pulled_far_is_followed() {
        // Base and blocks travel 30 length units together: a fixed view of all of it
        // would make the blocks specks; the camera follows them instead.
        let scene = sliding_column(&blockstack::scenarios::Sliding {
            v0: 3.0,
            t_end: 10.0,
            ..Default::default()
        })
        .unwrap();
        let frames = moved(&scene, |t, _, p| Pose::new(p.x + 3.0 * t, p.y, p.theta));
        let refs: Vec<&Frame> = frames.iter().collect();
        let views = frame_views(&scene, &refs);
        assert_ne!(views[0], views[100]);
        let size = extent(&scene, &frames[0]).size();
        for (v, f) in views.iter().zip(&frames) {
            assert!(inside(v, &extent(&scene, f)));
            assert!(v.x.end - v.x.start <= 1.5 * size);
        }
    }

    #[test]
    fn clipping_keeps_the_part_in_view() {
        let view = View {
            x: 0.0..1.0,
            y: 0.0..1.0,
        };
        let square = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)];
        assert_eq!(clip(&square, &view), square.to_vec());
        let half_out = [(0.5, 0.5), (1.5, 0.5), (1.5, 0.8), (0.5, 0.8)];
        let c = clip(&half_out, &view);
        assert!(c.iter().all(|p| p.0 <= 1.0 && p.0 >= 0.5));
        assert!(c.contains(&(1.0, 0.5)) && c.contains(&(1.0, 0.8)));
        let out = [(2.0, 2.0), (3.0, 2.0), (3.0, 3.0), (2.0, 3.0)];
        assert!(clip(&out, &view).is_empty());
    }

    #[test]
    fn bodies_out_of_view_are_named() {
        assert_eq!(body_names(&[3, 4]), "blocks 3, 4");
        assert_eq!(body_names(&[0, 2]), "base, block 2");
    }

    #[test]
    fn no_block_has_the_base_colour() {
        assert_eq!(body_color(0), BASE_COLOR);
        for k in 1..=40 {
            assert_ne!(body_color(k), BASE_COLOR);
            assert_ne!(body_color(k), BLACK);
        }
        // Neighbours never share a colour, and the first twelve blocks are all different.
        let first: Vec<RGBColor> = (1..=12).map(body_color).collect();
        assert!((0..12).all(|i| !first[i + 1..].contains(&first[i])));
    }

    #[test]
    fn sweep_titles_name_their_parameters() {
        let thesis = FrequencySweep::of(&Shaking::default());
        assert_eq!(
            thesis.title(),
            "Failure time of a shaken column, 4 blocks, A = 0.2, μ = 0.2, 10 periods (cf. Figure 4.6)\nΔt = 2π/(100ω), prox scaled (α = 1)"
        );
        let mine = FrequencySweep {
            blocks: 1,
            mu: 0.5,
            steps_per_period: 50.0,
            prox: Prox::Constant(0.3),
            rule: Some(BranchRule::Converged),
            ..thesis
        };
        assert_eq!(
            mine.title(),
            "Failure time of a shaken column, 1 block, A = 0.2, μ = 0.5, 10 periods\nconverged rule (the thesis's count), Δt = 2π/(50ω), prox r = 0.3"
        );
        assert!(!mine.is_figure_4_6());
        let horizon = FrequencySweep {
            t_max: Some(40.0),
            ..thesis
        };
        assert_eq!(
            horizon.title(),
            "Failure time of a shaken column, 4 blocks, A = 0.2, μ = 0.2, t ≤ 40 (cf. Figure 4.6)\nΔt = 2π/(100ω), prox scaled (α = 1)"
        );
        assert_eq!(horizon.survival(), "no failure by t = 40");
        assert_eq!(
            thesis.survival(),
            "no failure within 10 periods (t = 10·2π/ω)"
        );
        let slide = SlideSweep {
            blocks: 4,
            t_end: 3.0,
            mu: 0.2,
            numerics: Numerics::run(0.01, Prox::Scaled(1.0)).with_rule(BranchRule::SelfConsistent),
        };
        assert_eq!(
            slide.title(),
            "Top block angle at t = 3 on a pulled base, 4 blocks, μ = 0.2 (cf. Figure 4.7)\nself-consistent rule, Δt = 0.01, prox scaled (α = 1)"
        );
        let other = SlideSweep {
            t_end: 2.5,
            ..slide
        };
        assert!(!other.title().contains("Figure"));
        let panel = scene_sweep_title(
            "1/T",
            "base.omega",
            Some("no run failed"),
            &Numerics::of_steps(&[0.01, 0.005], Prox::Scaled(1.0)),
        );
        assert_eq!(
            panel,
            "1/T against base.omega (no run failed)\nΔt = 0.01 … 0.005, prox scaled (α = 1)"
        );
    }
}
