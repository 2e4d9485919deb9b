//! Figure 4.5: the motions an exploration found ([`blockstack::exploration`]): the
//! distinct final states side by side, the top block's height and angle against time
//! for every branch, and the tree of branches over time.

use crate::blocks::{draw_stack, frame_views, StackLayout};
use crate::plot::{with_png, LinePlot, Series, Style, PALETTE};
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
            format!("{title}: top block {name}{more}"),
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
    let tree_plot = tree_lines(tree, &colour, drawn, &format!("{title}: branches{more}"));
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

/// The final states side by side, framed together.
fn draw_final_states(
    area: &crate::plot::Canvas<'_>,
    scene: &Scene,
    frames: &[(String, Frame)],
) -> Result<()> {
    if frames.is_empty() {
        return Ok(());
    }
    let refs: Vec<&Frame> = frames.iter().map(|(_, f)| f).collect();
    let views = frame_views(scene, &refs);
    let titles: Vec<String> = frames.iter().map(|(t, _)| t.clone()).collect();
    let (w, _) = area.dim_in_pixel();
    let width = w / u32::try_from(frames.len()).unwrap_or(1).max(1);
    let mut rest = area.clone();
    for (i, ((label, frame), view)) in frames.iter().zip(&views).enumerate() {
        let (cell, right) = if i + 1 < frames.len() {
            rest.split_horizontally(width)
        } else {
            (rest.clone(), rest.clone())
        };
        let layout = StackLayout::new(&cell, &titles, &views);
        draw_stack(&cell, scene, frame, view, label, &layout)?;
        rest = right;
    }
    Ok(())
}
