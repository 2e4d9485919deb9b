//! Pictures of the stack: snapshots (Figure 4.4), the animation, and the top block's
//! angle and height (Figure 4.5 (b), (c)), and the sweeps' plots. The frames come from
//! [`blockstack::record`].

use crate::plot::{with_png, LinePlot, Series, FONT, PALETTE};
use crate::{err, file, write_error, FigureError, Result};
use blockstack::record::{Frame, Recording, TopSample};
use blockstack::studies::scene_sweep::SceneRow;
use blockstack::studies::shaking::FrequencyRow;
use blockstack::studies::slide::{SlideRegime, SlideRow};
use blockstack::Scene;
use plotters::prelude::*;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The refusal to draw a frame whose coordinates are not all finite.
const NON_FINITE: FigureError =
    FigureError::Data("cannot draw a stack with non-finite coordinates");

/// A square window onto the plane of the stack: x and y ranges of equal length.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Horizontal range.
    pub x: Range<f64>,
    /// Vertical range.
    pub y: Range<f64>,
}

/// A square view that holds every body of every frame and the floor, with a margin.
fn view_of(scene: &Scene, frames: &[&Frame]) -> View {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for f in frames.iter().filter(|f| f.is_finite()) {
        for &(x, y) in f.outlines(scene).iter().flatten() {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    if let Some(f) = scene.floor() {
        y0 = y0.min(f.y);
    }
    let half = 0.55 * (x1 - x0).max(y1 - y0);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    View {
        x: cx - half..cx + half,
        y: cy - half..cy + half,
    }
}

/// Draws one frame of the stack onto a canvas: the floor as a line, the base black (as
/// in Figure 4.4), the blocks as rotated rectangles in colour.
fn draw_stack<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    scene: &Scene,
    frame: &Frame,
    view: &View,
    title: &str,
) -> Result<()> {
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(view.x.clone(), view.y.clone())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("x")
        .y_desc("y")
        .label_style((FONT, 14))
        // No minor grid: cleaner pictures and a much smaller animation.
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    if let Some(f) = scene.floor() {
        chart
            .draw_series(LineSeries::new(
                vec![(view.x.start, f.y), (view.x.end, f.y)],
                BLACK.stroke_width(2),
            ))
            .map_err(err)?;
    }
    for (k, poly) in frame.outlines(scene).into_iter().enumerate() {
        let color = if k == 0 {
            BLACK
        } else {
            PALETTE[(k - 1) % PALETTE.len()]
        };
        let mut closed = poly.to_vec();
        closed.push(poly[0]);
        chart
            .draw_series(std::iter::once(Polygon::new(
                poly.to_vec(),
                color.mix(0.6).filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(PathElement::new(
                closed,
                BLACK.stroke_width(1),
            )))
            .map_err(err)?;
    }
    Ok(())
}

/// Draws the stack at time t with coordinates q: the base black (as in Figure 4.4), the
/// blocks in colour, the floor as a line; equal scales on both axes.
///
/// # Errors
/// Non-finite coordinates or an unwritable file.
pub fn plot_stack(path: &Path, scene: &Scene, q: &[f64], t: f64, title: &str) -> Result<()> {
    let frame = Frame::from_coordinates(scene, q, t);
    if !frame.is_finite() {
        return Err(NON_FINITE);
    }
    let view = view_of(scene, &[&frame]);
    with_png(path, (800, 800), |root| {
        draw_stack(root, scene, &frame, &view, title)
    })
}

/// Draws frames into one PNG each with a common view (Figure 4.4 style snapshots).
///
/// # Errors
/// A non-finite frame or an unwritable file.
pub fn plot_snapshots(scene: &Scene, shots: &[(PathBuf, String, &Frame)]) -> Result<()> {
    let frames: Vec<&Frame> = shots.iter().map(|s| s.2).collect();
    let view = view_of(scene, &frames);
    for (path, title, frame) in shots {
        if !frame.is_finite() {
            return Err(NON_FINITE);
        }
        with_png(path, (800, 800), |root| {
            draw_stack(root, scene, frame, &view, title)
        })?;
    }
    Ok(())
}

/// Delay between animation frames (ms).
const ANIMATION_FRAME_MS: u32 = 80;

/// Writes an animated GIF of `frames` (one common view), atomically.
///
/// # Errors
/// No finite frame, or an unwritable file.
pub fn write_animation(path: &Path, scene: &Scene, frames: &[Frame], title: &str) -> Result<()> {
    let good: Vec<&Frame> = frames.iter().filter(|f| f.is_finite()).collect();
    if good.is_empty() {
        return Err(FigureError::Data("no frame to animate"));
    }
    let view = view_of(scene, &good);
    crate::plot::register_font();
    let tmp = file::temp_sibling(path);
    {
        let root = BitMapBackend::gif(&tmp, (480, 480), ANIMATION_FRAME_MS)
            .map_err(|e| write_error(path, e))?
            .into_drawing_area();
        for f in good {
            root.fill(&WHITE).map_err(err)?;
            draw_stack(&root, scene, f, &view, &format!("{title}, t = {:.2}", f.t))?;
            root.present().map_err(|e| write_error(path, e))?;
        }
    }
    file::commit_temp(path).map_err(|e| write_error(path, e))
}

/// The top block's angle and height against time (Figures 4.5 (b), (c)).
///
/// # Errors
/// An unwritable file.
pub fn plot_top_block(path: &Path, top: &[TopSample], title: &str) -> Result<()> {
    let angle = LinePlot::new(format!("{title}: top block angle"), "t", "theta (rad)").with(
        Series::line("", top.iter().map(|p| (p.t, p.theta)).collect()),
    );
    let height = LinePlot::new(format!("{title}: top block height"), "t", "y")
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
        shots.push((dir.join(&name), format!("{title}, t = {:.2}{note}", f.t), f));
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

/// Figure 4.6: the inverse time to failure 1/T of a shaken column against the
/// frequency ω (0 where the column survived).
///
/// # Errors
/// An unwritable file.
pub fn plot_frequency_sweep(path: &Path, rows: &[FrequencyRow]) -> Result<()> {
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.inv_failure_time.map(|v| (r.omega, v)))
        .collect();
    LinePlot::new(
        "Figure 4.6: onset of failure of a shaken column",
        "omega (rad per time unit)",
        "1/T (failure: loss of support)",
    )
    .with(Series::line("", points.clone()))
    .with(Series::markers("1/T (0: survived)", points))
    .save(path, (900, 600))
}

/// Figure 4.7: the top block's angle at `t_end` against the base speed v₀, with each
/// run's regime marked and runs that stopped early shown apart.
///
/// # Errors
/// An unwritable file.
pub fn plot_slide_sweep(path: &Path, rows: &[SlideRow], t_end: f64) -> Result<()> {
    // The curve joins the runs that reached t_end; runs that stopped early are shown
    // apart, at the angle they had when they stopped.
    let mut plot = LinePlot::new(
        format!("Figure 4.7: top block angle at t = {t_end} against base speed"),
        "v0 (length per time unit)",
        "theta of the top block (rad)",
    )
    .with(Series::line(
        "",
        rows.iter()
            .filter(|r| r.error.is_none())
            .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
            .collect(),
    ));
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
    plot.save(path, (900, 600))
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

/// The picture of a scene sweep: the failure time (runs with a loss of support) and the
/// top block's angle at the end of each run (at the stop, for runs that stopped early)
/// against one swept key, one line of markers per combination of the other keys
/// ([`scene_sweep_lines`]). Left out with a note when no key is swept, there is no row,
/// or the other keys have more than [`SCENE_SWEEP_MAX_LINES`] combinations.
///
/// # Errors
/// An unwritable file.
pub fn plot_scene_sweep(path: &Path, rows: &[SceneRow]) -> Result<DrawnRun> {
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
    let panel = |title: &str, empty: &str, y_label: &str, y: fn(&SceneRow) -> Option<f64>| {
        let title = if rows.iter().any(|r| y(r).is_some()) {
            format!("{title} against {key}")
        } else {
            format!("{title} against {key} ({empty})")
        };
        lines.iter().fold(
            LinePlot::new(title, key.as_str(), y_label),
            |plot, (label, members)| {
                let points = members
                    .iter()
                    .filter_map(|r| Some((r.set.get(x)?.value, y(r)?)))
                    .collect();
                plot.with(Series::joined_markers(label.as_str(), points))
            },
        )
    };
    let failure = panel(
        "failure time",
        "no run lost its support",
        "failure time (loss of support)",
        |r| r.failure_time,
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
mod tests {
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
                min_gap: None,
                top_x: Some(0.0),
                top_y: Some(1.0),
                top_theta: Some(0.1 * k as f64),
                error: None,
                wall_time_s: 0.0,
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
    fn scene_sweep_picture_or_a_note() {
        let dir =
            std::env::temp_dir().join(format!("rollstack-scene-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sweep_scene.png");
        let drawn = plot_scene_sweep(&path, &rows(&["a.x=1,2", "b.y=0:1:0.5"])).unwrap();
        assert_eq!(drawn.files, ["sweep_scene.png"]);
        assert_eq!(&std::fs::read(&path).unwrap()[1..4], b"PNG");
        let many =
            plot_scene_sweep(&dir.join("many.png"), &rows(&["a.x=1:9:1", "b.y=1,2"])).unwrap();
        assert!(
            many.files.is_empty() && many.notes[0].contains("9 combinations"),
            "{many:?}"
        );
        let fixed = plot_scene_sweep(&dir.join("fixed.png"), &rows(&["a.x=1"])).unwrap();
        assert_eq!(fixed.files, ["fixed.png"]);
        let none = plot_scene_sweep(&dir.join("none.png"), &[]).unwrap();
        assert!(none.files.is_empty() && none.notes.len() == 1);
        assert!(!dir.join("many.png").exists() && !dir.join("none.png").exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
