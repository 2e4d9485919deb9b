//! Figure 4.5: the motions an exploration found ([`blockstack::exploration`]): the
//! distinct final states side by side, the top block's height and angle against time
//! for every branch, and the tree of branches over time.

use crate::blocks::{draw_stack, frame_views, StackLayout, View};
use crate::numerics::extend_headline;
use crate::plot::{with_png, Canvas, LinePlot, Series, Style, PALETTE};
use crate::{FigureError, Result};
use blockstack::exploration::{BranchSummary, OutcomeGroup};
use blockstack::record::Frame;
use blockstack::Scene;
use nsga::explore::Exploration;
use std::path::Path;

/// Most final states drawn side by side (one per outcome, the most frequent first).
pub const MAX_FINAL_STATES: usize = 4;

/// Most branches whose curves are drawn (the first ones by id); the rest are counted in
/// the title.
pub const MAX_DRAWN_BRANCHES: usize = 400;

/// The colour of outcome group `g` (groups beyond the palette share its last colour).
fn group_color(g: usize) -> Style {
    Style::color(PALETTE[g.min(PALETTE.len() - 1)]).width(1)
}

/// Draws Figure 4.5 of an exploration of `scene` into `path`: (a) one final state per
/// outcome (at most [`MAX_FINAL_STATES`]), (b) y and (c) θ of the top block against t for
/// every branch, coloured by outcome, (d) the tree: each branch a horizontal line over
/// its time span, joined to its parent at the fork.
///
/// # Errors
/// No branch, non-finite final states, or an unwritable file.
pub fn plot_exploration(
    path: &Path,
    scene: &Scene,
    tree: &Exploration<BranchSummary>,
    groups: &[OutcomeGroup],
    title: &str,
) -> Result<()> {
    if tree.branches.is_empty() {
        return Err(FigureError::Data("an exploration without branches"));
    }
    let group_of = |id: usize| groups.iter().position(|g| g.branches.contains(&id));
    // Every branch takes the colour of the outcome its first leaf descendant reaches.
    let colour: Vec<usize> = (0..tree.branches.len())
        .map(|id| group_of(first_leaf(tree, id)).unwrap_or(0))
        .collect();
    let frames: Vec<(String, Frame)> = groups
        .iter()
        .take(MAX_FINAL_STATES)
        .map(|g| {
            let leaf = &tree.branches[g.branches[0]];
            let q: Vec<f64> = leaf
                .outcome
                .final_poses
                .iter()
                .flat_map(|p| [p.x, p.y, p.theta])
                .collect();
            let label = format!("{} × {}", g.branches.len(), g.label);
            (label, Frame::from_coordinates(scene, &q, leaf.end_at.0))
        })
        .collect();
    if frames.iter().any(|(_, f)| !f.is_finite()) {
        return Err(FigureError::Data("cannot draw a non-finite final state"));
    }
    let drawn = tree.branches.len().min(MAX_DRAWN_BRANCHES);
    let more = if drawn < tree.branches.len() {
        format!(" (first {drawn} of {} branches)", tree.branches.len())
    } else {
        String::new()
    };
    let curves = |index: usize, name: &str, unit: &str| {
        let mut plot = LinePlot::new(
            extend_headline(title, &format!(": top block {name}{more}")),
            "t [time unit]",
            unit,
        );
        let mut labelled = vec![false; groups.len().max(1)];
        for b in tree.branches.iter().take(drawn) {
            let mut pts: Vec<(f64, f64)> = Vec::with_capacity(b.outcome.top.len() + 1);
            if let Some((parent, _)) = b.parent {
                if let Some(last) = tree.branches[parent].outcome.top.last() {
                    pts.push((last[0], last[index]));
                }
            }
            pts.extend(b.outcome.top.iter().map(|s| (s[0], s[index])));
            let g = colour[b.id];
            let label = if labelled[g] || groups.is_empty() {
                String::new()
            } else {
                labelled[g] = true;
                groups[g].label.clone()
            };
            plot = plot.with(Series::line(label, pts).styled(group_color(g)));
        }
        plot
    };
    let height = curves(1, "height", "y [length unit]");
    let angle = curves(2, "angle", "θ [rad]");
    let tree_plot = tree_lines(
        tree,
        &colour,
        drawn,
        &extend_headline(title, &format!(": branches{more}")),
    );
    with_png(path, (1400, 1100), |root| {
        let (top, bottom) = root.split_vertically(550);
        let (states, tree_area) = top.split_horizontally(700);
        let (left, right) = bottom.split_horizontally(700);
        draw_final_states(&states, scene, &frames)?;
        tree_plot.draw(&tree_area)?;
        height.draw(&left)?;
        angle.draw(&right)
    })
}

/// The first leaf below branch `id` (following first children).
fn first_leaf(tree: &Exploration<BranchSummary>, mut id: usize) -> usize {
    while let Some(f) = tree.branches[id].followed_fork() {
        match f.children.first() {
            Some(&c) => id = c,
            None => break,
        }
    }
    id
}

/// The tree over time: leaves on consecutive rows in depth-first order, a forked branch
/// at the mean row of its children, each joined to its parent at the fork.
fn tree_lines(
    tree: &Exploration<BranchSummary>,
    colour: &[usize],
    drawn: usize,
    title: &str,
) -> LinePlot {
    let n = tree.branches.len();
    let mut row = vec![0.0; n];
    let mut next = 0.0;
    // Children have larger ids than their parent: a post-order walk from the root.
    fn place(tree: &Exploration<BranchSummary>, id: usize, row: &mut [f64], next: &mut f64) {
        match tree.branches[id].followed_fork() {
            Some(f) if !f.children.is_empty() => {
                for &c in &f.children {
                    place(tree, c, row, next);
                }
                row[id] = f.children.iter().map(|&c| row[c]).sum::<f64>() / f.children.len() as f64;
            }
            _ => {
                row[id] = *next;
                *next += 1.0;
            }
        }
    }
    place(tree, 0, &mut row, &mut next);
    let mut plot = LinePlot::new(title, "t [time unit]", "branch (leaves in tree order)");
    for b in tree.branches.iter().take(drawn) {
        let mut pts = Vec::with_capacity(3);
        if let Some((parent, _)) = b.parent {
            pts.push((b.start.0, row[parent]));
        }
        pts.push((b.start.0, row[b.id]));
        pts.push((b.end_at.0, row[b.id]));
        plot = plot.with(Series::line("", pts).styled(group_color(colour[b.id])));
    }
    plot
}

/// The final states, each framed on its own bodies ([`thumbnails`]).
fn draw_final_states(area: &Canvas<'_>, scene: &Scene, frames: &[(String, Frame)]) -> Result<()> {
    if frames.is_empty() {
        return Ok(());
    }
    let refs: Vec<&Frame> = frames.iter().map(|(_, f)| f).collect();
    let titles: Vec<String> = frames.iter().map(|(t, _)| t.clone()).collect();
    let thumbs = thumbnails(area, scene, &refs, &titles);
    for (((label, frame), cell), view) in frames.iter().zip(&thumbs.cells).zip(&thumbs.views) {
        draw_stack(cell, scene, frame, view, label, &thumbs.layout)?;
    }
    Ok(())
}

/// Where the final states are drawn: a cell each, its view, and their common layout.
struct Thumbnails<'a> {
    cells: Vec<Canvas<'a>>,
    views: Vec<View>,
    layout: StackLayout,
}

/// The thumbnails of `frames` on `area`. Each is framed on its own bodies (outcomes
/// differ: a standing column is 1.7 high and 1 wide, a column fallen on the floor 0.4 high
/// and 6 wide, and one view for both would make one of them specks), on the grid of rows
/// and columns that draws the smallest of them largest (fallen columns one above the
/// other, standing ones side by side), and each cell is cut down to its view's
/// proportions, so that the axes span the bodies and their margin only rather than
/// stretching to the cell at equal scales.
fn thumbnails<'a>(
    area: &Canvas<'a>,
    scene: &Scene,
    frames: &[&Frame],
    titles: &[String],
) -> Thumbnails<'a> {
    let views: Vec<View> = frames
        .iter()
        .flat_map(|f| frame_views(scene, &[f]))
        .collect();
    let grid = |rows: usize| {
        let cells = area.split_evenly((rows, frames.len().div_ceil(rows)));
        let layout = StackLayout::new(&cells[0], titles, &views);
        let plot = layout.plot_px(cells[0].dim_in_pixel());
        let smallest = views
            .iter()
            .map(|v| scale(v, plot))
            .fold(f64::INFINITY, f64::min);
        (smallest, cells, layout)
    };
    let (_, cells, layout) = (1..=frames.len().max(1))
        .map(grid)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .expect("at least one row");
    let cells = cells
        .iter()
        .zip(&views)
        .map(|(cell, view)| fitted(cell, view, &layout))
        .collect();
    Thumbnails {
        cells,
        views,
        layout,
    }
}

/// Pixels per length unit of `view` drawn at equal scales in `plot` pixels.
fn scale(view: &View, plot: (u32, u32)) -> f64 {
    let (w, h) = (view.x.end - view.x.start, view.y.end - view.y.start);
    (f64::from(plot.0) / w).min(f64::from(plot.1) / h)
}

/// `cell` less the plotting area's pixels that `view`, drawn at equal scales, leaves
/// empty, split evenly on both sides.
fn fitted<'a>(cell: &Canvas<'a>, view: &View, layout: &StackLayout) -> Canvas<'a> {
    let plot = layout.plot_px(cell.dim_in_pixel());
    let s = scale(view, plot);
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let spare = |px: u32, units: f64| px.saturating_sub((s * units).ceil() as u32) / 2;
    let (sx, sy) = (
        spare(plot.0, view.x.end - view.x.start),
        spare(plot.1, view.y.end - view.y.start),
    );
    cell.margin(sy, sy, sx, sx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::stack_ticks;
    use blockstack::scenarios::{shaking_column, Shaking};
    use blockstack::Pose;
    use plotters::prelude::*;

    /// The box of a frame's bodies: (x0, x1, y0, y1).
    fn bodies(scene: &Scene, f: &Frame) -> [f64; 4] {
        f.outlines(scene).into_iter().flatten().fold(
            [f64::MAX, f64::MIN, f64::MAX, f64::MIN],
            |[x0, x1, y0, y1], (x, y)| [x0.min(x), x1.max(x), y0.min(y), y1.max(y)],
        )
    }

    #[test]
    fn each_final_state_is_framed_on_its_own_blocks_in_its_own_cell() {
        // A shaken column's outcomes: standing (1.7 high, the base 1 wide), and fallen,
        // its four blocks lying on the floor from x = -3 to 3. In one view of both at
        // equal scales, the thumbnails spanned 30 units for blocks 0.2 high.
        crate::plot::register_font();
        let scene = shaking_column(&Shaking::default()).unwrap();
        let floor = scene.floor().unwrap().y;
        let standing = Frame::from_coordinates(&scene, &scene.initial_coordinates(), 9.0);
        let fallen = Frame {
            blocks: (0..4)
                .map(|k| {
                    let x = -3.0 + 2.0 * f64::from(k);
                    Pose::new(x, floor + 0.1, std::f64::consts::FRAC_PI_2)
                })
                .collect(),
            ..standing.clone()
        };
        let frames = [&standing, &fallen];
        let titles = vec!["3 × column standing".to_owned(), "7 × ".repeat(20)];
        let mut pixels = vec![0u8; 700 * 550 * 3];
        let area = BitMapBackend::with_buffer(&mut pixels, (700, 550)).into_drawing_area();
        let thumbs = thumbnails(&area, &scene, &frames, &titles);
        for ((frame, cell), view) in frames.iter().zip(&thumbs.cells).zip(&thumbs.views) {
            let plot = thumbs.layout.plot_px(cell.dim_in_pixel());
            let (x, y) = StackLayout::stretched(view, plot, Some(floor));
            let [x0, x1, y0, y1] = bodies(&scene, frame);
            // The drawn ranges hold the bodies ...
            assert!(x.start <= x0 && x1 <= x.end && y.start <= y0 && y1 <= y.end);
            // ... and are the bodies' box with its margin, not a stretch of it: at most
            // the bodies' larger side again around them, and each range within 10 % of
            // the view's.
            let size = (x1 - x0).max(y1 - y0);
            assert!(x.end - x.start <= (x1 - x0) + size, "{x:?} for {x0}..{x1}");
            assert!(y.end - y.start <= (y1 - y0) + size, "{y:?} for {y0}..{y1}");
            assert!(
                x.end - x.start <= 1.1 * (view.x.end - view.x.start),
                "{x:?} {view:?}"
            );
            assert!(
                y.end - y.start <= 1.1 * (view.y.end - view.y.start),
                "{y:?} {view:?}"
            );
            // The tick labels up the short axis stay apart: 14 pixels high, at least 30
            // pixels between their centres (and along x, 60).
            let (xt, yt) = stack_ticks(&x, &y, plot);
            for (ticks, range, px, least) in [(&xt, &x, plot.0, 60.0), (&yt, &y, plot.1, 30.0)] {
                let per_unit = f64::from(px) / (range.end - range.start);
                for pair in ticks.major.windows(2) {
                    let apart = (pair[1] - pair[0]) * per_unit;
                    assert!(apart >= least, "{:?} in {px} px", ticks.labels);
                }
            }
        }
        // One above the other (the fallen column is wide), in cells that do not overlap,
        // so neither do their titles and axis labels.
        let rect = |c: &Canvas<'_>| {
            let ((x, y), (w, h)) = (c.get_base_pixel(), c.dim_in_pixel());
            #[allow(clippy::cast_possible_wrap)]
            (x, y, x + w as i32, y + h as i32)
        };
        let (a, b) = (rect(&thumbs.cells[0]), rect(&thumbs.cells[1]));
        assert!(a.3 <= b.1, "{a:?} above {b:?}");
    }
}
