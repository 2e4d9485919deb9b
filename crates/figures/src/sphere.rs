//! The figures of `rollstack sphere` and the tour: Figures 2.1, 2.5, 2.6–2.9 and the
//! integrator study, drawn from the data of [`holonomy::studies`].

use crate::plot::{
    draw_title, with_png, Legend, LinePlot, Series, Style, BASE_COLOR, PALETTE, TITLE_PX,
};
use crate::Result;
use holonomy::rectangle::holonomy_angle;
use holonomy::studies::level_sets::FIGURE_2_5_LEVELS_DEG;
use holonomy::studies::plan::RectangleReport;
use holonomy::studies::roll::{StudyPath, StudyRow};
use holonomy::{Integrator, Trajectory};
use std::f64::consts::{PI, TAU};
use std::ops::Range;
use std::path::Path;

/// Figure 2.1: top view of the traces of the centre C (i) and the marked point X (ii),
/// with arrows in the direction of travel.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_traces(path: &Path, traj: &Trajectory, title: &str) -> Result<()> {
    let c: Vec<(f64, f64)> = traj
        .samples
        .iter()
        .map(|s| (s.centre[0], s.centre[1]))
        .collect();
    let x: Vec<(f64, f64)> = traj
        .samples
        .iter()
        .map(|s| (s.marked_point[0], s.marked_point[1]))
        .collect();
    let ends = vec![x[0], *x.last().unwrap_or(&x[0])];
    let mut plot = LinePlot::new(title, "E1 [R]", "E2 [R]")
        .with(Series::line("i: centre C", c).with_arrows())
        .with(Series::line("ii: material point X", x))
        .with(Series::markers("X at t0 (A) and t1 (B)", ends));
    plot.equal_aspect = true;
    plot.save(path, (800, 800))
}

/// The corners of a rectangle's path as plot points.
fn outline(r: &RectangleReport) -> Vec<(f64, f64)> {
    r.waypoints.iter().map(|w| (w[0], w[1])).collect()
}

/// Draws rectangles (the centre's path) in one frame, numbered, with arrows in the
/// direction of travel and the start S.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangles(path: &Path, title: &str, rects: &[RectangleReport]) -> Result<()> {
    let mut plot = LinePlot::new(title, "E1 [R]", "E2 [R]");
    plot.equal_aspect = true;
    for (i, r) in rects.iter().enumerate() {
        plot = plot.with(
            Series::line(
                format!(
                    "{}: ϑ={:.3}, φ1={:.3}, φ2={:.3}, {}",
                    i + 1,
                    r.theta,
                    r.phi1,
                    r.phi2,
                    r.direction.as_str()
                ),
                outline(r),
            )
            .with_arrows(),
        );
    }
    plot =
        plot.with(Series::markers("S: start", vec![(0.0, 0.0)]).styled(Style::color(BASE_COLOR)));
    plot.save(path, (900, 900))
}

/// Size of one panel of [`plot_rectangle_panels`], pixels.
const PANEL: (u32, u32) = (400, 420);

/// Figure 2.6: every rectangle in its own panel (a grid of up to four columns), all to
/// one scale, each path with arrows in the direction of travel and its start S. The
/// rectangle `shortest` (an index into `rects`) is drawn thicker in another colour
/// (vermillion, the others blue), and its panel title says "shortest"; the start S is
/// a dark grey dot.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangle_panels(
    path: &Path,
    title: &str,
    rects: &[RectangleReport],
    shortest: Option<usize>,
) -> Result<()> {
    let n = rects.len().max(1);
    let cols = panel_columns(n);
    let rows_n = n.div_ceil(cols);
    // One scale: the box of all paths (they all start at S = 0), padded.
    let all: Vec<(f64, f64)> = rects.iter().flat_map(outline).collect();
    let bounds = common_bounds(&all);
    #[allow(clippy::cast_possible_truncation)]
    let (c, r) = (cols as u32, rows_n as u32);
    with_png(path, (PANEL.0 * c, PANEL.1 * r + 40), |root| {
        let area = draw_title(root, title, TITLE_PX)?;
        let panels = area.split_evenly((rows_n, cols));
        for (i, (rect, panel)) in rects.iter().zip(panels.iter()).enumerate() {
            let best = shortest == Some(i);
            let style = if best {
                Style::color(PALETTE[1]).width(4)
            } else {
                Style::color(PALETTE[0])
            };
            let mut plot = LinePlot::new(
                format!(
                    "{}{}: ϑ={:.3} φ1={:.3} φ2={:.3} {}, length {:.3} R",
                    if best { "shortest, no. " } else { "no. " },
                    i + 1,
                    rect.theta,
                    rect.phi1,
                    rect.phi2,
                    rect.direction.as_str(),
                    rect.path_length,
                ),
                "A1 [R]",
                "A2 [R]",
            )
            .with(Series::line("", outline(rect)).with_arrows().styled(style))
            .with(Series::markers("", vec![(0.0, 0.0)]).styled(Style::color(BASE_COLOR)));
            plot.equal_aspect = true;
            plot.bounds = Some(bounds.clone());
            plot.draw(panel)?;
        }
        Ok(())
    })
}

/// Columns of a grid of `n` panels: all in one row up to three, then four (twelve
/// rectangles: 4 × 3).
#[must_use]
pub fn panel_columns(n: usize) -> usize {
    match n {
        0..=3 => n.max(1),
        4 => 2,
        5..=9 => 3,
        _ => 4,
    }
}

/// The box of `points` padded by 8 % (a unit box around the origin when empty).
fn common_bounds(points: &[(f64, f64)]) -> (Range<f64>, Range<f64>) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for &(x, y) in points.iter().filter(|p| p.0.is_finite() && p.1.is_finite()) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let pad = 0.08 * (x1 - x0).max(y1 - y0).max(1e-9);
    (x0 - pad..x1 + pad, y0 - pad..y1 + pad)
}

/// Figure 2.5: the level sets of ψ(ϑ, φ2) over [0, 2π]², traced on a grid ([`holonomy_angle`],
/// (2.4.11) with the factor 2 of ERRATA item 1), one colour per level, the legend
/// beside the square. A marked point shows `mark` if given.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_level_sets(path: &Path, mark: Option<(f64, f64)>) -> Result<()> {
    // A rectangle outside the window is drawn at its sides modulo 2π: the title says so
    // (the legend beside the square has no room for it).
    let note = mark.map_or_else(String::new, |(t, p)| wrap_note(t, p));
    let mut plot = LinePlot::new(
        format!("Level sets of ψ(ϑ, φ2), (2.4.11) corrected (Figure 2.5){note}"),
        "ϑ [rad]",
        "φ2 [rad]",
    );
    plot.equal_aspect = true;
    plot.legend = Legend::Right;
    plot.bounds = Some((0.0..TAU, 0.0..TAU));
    for deg in FIGURE_2_5_LEVELS_DEG {
        let points = level_set_points(deg.to_radians(), LEVEL_SET_CELLS);
        plot = plot.with(Series::line(format!("ψ = {deg}°"), points));
    }
    if let Some((t, p)) = mark {
        // The rectangle's place in the window [0, 2π]² (ψ has period 2π in both).
        let (t, p) = (t.rem_euclid(TAU), p.rem_euclid(TAU));
        let psi = holonomy_angle(t, p);
        // Above 180° the chart's ψ is the rotation by 360° − ψ about the opposite axis,
        // the angle the reports print.
        let label = if psi > PI {
            format!(
                "this rectangle: ψ = {:.2}° (= {:.2}° about −s)",
                psi.to_degrees(),
                (TAU - psi).to_degrees()
            )
        } else {
            format!("this rectangle: ψ = {:.2}°", psi.to_degrees())
        };
        plot = plot.with(Series::markers(label, vec![(t, p)]).styled(Style::color(BASE_COLOR)));
    }
    plot.save(path, (1000, 760))
}

/// Grid cells along each side of [0, 2π]² in which Figure 2.5's level sets are traced.
const LEVEL_SET_CELLS: usize = 300;

/// The level set ψ(ϑ, φ2) = `psi` over [0, 2π]² as one series of segments broken by
/// NaN points, traced by marching squares on a grid of `cells` × `cells`: every cell
/// the curve crosses holds a piece of it, so the curve has no gap where it turns
/// vertical (branches solved as functions of one angle leave gaps there).
fn level_set_points(psi: f64, cells: usize) -> Vec<(f64, f64)> {
    #[allow(clippy::cast_precision_loss)]
    let at = |i: usize| TAU * i as f64 / cells as f64;
    let value: Vec<Vec<f64>> = (0..=cells)
        .map(|i| {
            (0..=cells)
                .map(|j| holonomy_angle(at(i), at(j)) - psi)
                .collect()
        })
        .collect();
    let mut points = Vec::new();
    for i in 0..cells {
        for j in 0..cells {
            // Corners counter-clockwise, and where ψ − psi changes sign on each edge.
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let crossings: Vec<(f64, f64)> = (0..4)
                .filter_map(|k| {
                    let (a, b) = (corners[k], corners[(k + 1) % 4]);
                    let (va, vb) = (value[a.0][a.1], value[b.0][b.1]);
                    ((va < 0.0) != (vb < 0.0)).then(|| {
                        let f = va / (va - vb);
                        (
                            at(a.0) + f * (at(b.0) - at(a.0)),
                            at(a.1) + f * (at(b.1) - at(a.1)),
                        )
                    })
                })
                .collect();
            // Two crossings: one segment; four (a saddle): two, paired along the edges.
            for pair in crossings.chunks_exact(2) {
                points.extend([pair[0], pair[1], (f64::NAN, f64::NAN)]);
            }
        }
    }
    points
}

/// `v` to four decimal places without trailing zeros (3π as 9.4248, 8 as 8), short
/// enough for a title.
fn four_places(v: f64) -> String {
    let text = format!("{v:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// What the title of Figure 2.5 adds when the marked rectangle lies outside the window
/// [0, 2π)² and is drawn at its sides modulo 2π: e.g. "; this rectangle's φ2 = 8 drawn
/// at 1.717 (mod 2π)"; empty inside the window.
fn wrap_note(theta: f64, phi2: f64) -> String {
    let moved: Vec<String> = [("ϑ", theta), ("φ2", phi2)]
        .into_iter()
        .filter(|&(_, v)| !(0.0..TAU).contains(&v))
        .map(|(name, v)| {
            format!(
                "{name} = {} drawn at {:.3}",
                four_places(v),
                v.rem_euclid(TAU)
            )
        })
        .collect();
    if moved.is_empty() {
        String::new()
    } else {
        format!("; this rectangle's {} (mod 2π)", moved.join(", "))
    }
}

/// The integrator study: error of the final orientation against wall time on log–log
/// axes, a marker per run.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_study(path: &Path, rows: &[StudyRow]) -> Result<()> {
    let mut plot = LinePlot::new(
        "Rolling integrators: error of the final orientation vs wall time",
        "wall time [s]",
        "error [rad] (floored at 1e-17)",
    );
    plot.log = (true, true);
    for shape in [StudyPath::Rectangle, StudyPath::Circle] {
        for integrator in [Integrator::Exact, Integrator::Rk4] {
            let pts = rows
                .iter()
                .filter(|r| r.path == shape && r.integrator == integrator)
                .map(|r| (r.wall_time_s, r.error.max(1e-17)))
                .collect();
            plot = plot.with(Series::line_and_markers(
                format!("{}, {}", integrator.as_str(), shape.as_str()),
                pts,
            ));
        }
    }
    plot.save(path, (900, 600))
}

#[cfg(test)]
mod tests {
    use super::*;
    use holonomy::studies::plan::plan_report;
    use nalgebra::{Rotation3, Vector3};

    #[test]
    fn level_sets_have_no_gap() {
        // ψ = 5°: sin²(ϑ/2) sin²(φ2/2) = sin²(ψ/4), so along the left side of the square
        // ϑ = 2 asin(sqrt(s / sin²(φ2/2))); every such point lies within a grid cell of
        // the drawn curve, where the curve turns vertical too (φ2 near π).
        let cells = 300;
        let psi = 5f64.to_radians();
        let drawn: Vec<(f64, f64)> = level_set_points(psi, cells)
            .into_iter()
            .filter(|p| p.0.is_finite())
            .collect();
        let s = (psi / 4.0).sin().powi(2);
        let h = TAU / f64::from(u32::try_from(cells).unwrap());
        for k in 1..200 {
            let phi2 = TAU * f64::from(k) / 200.0;
            let b = (phi2 / 2.0).sin().powi(2);
            if b < s {
                continue;
            }
            let theta = 2.0 * (s / b).sqrt().asin();
            let nearest = drawn
                .iter()
                .map(|p| (p.0 - theta).hypot(p.1 - phi2))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < h, "gap at φ2 = {phi2}: {nearest}");
        }
    }

    #[test]
    fn a_rectangle_outside_the_window_says_it_is_wrapped() {
        assert_eq!(wrap_note(3.0, 1.5), "");
        assert_eq!(
            wrap_note(3.0, 8.0),
            "; this rectangle's φ2 = 8 drawn at 1.717 (mod 2π)"
        );
        assert_eq!(
            wrap_note(-1.0, 7.0),
            "; this rectangle's ϑ = -1 drawn at 5.283, φ2 = 7 drawn at 0.717 (mod 2π)"
        );
        // 3π printed whole took 16 digits of the title (the tour's Figure 2.5).
        assert_eq!(
            wrap_note(1.0, 3.0 * std::f64::consts::PI),
            "; this rectangle's φ2 = 9.4248 drawn at 3.142 (mod 2π)"
        );
    }

    #[test]
    fn every_rectangle_gets_a_panel() {
        assert_eq!(panel_columns(1), 1);
        assert_eq!(panel_columns(3), 3);
        assert_eq!(panel_columns(6), 3);
        assert_eq!(panel_columns(12), 4);
        // 90° about A1: twelve rectangles, all drawn (4 × 3 panels), not the first six.
        let target = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let rep = plan_report(&target).unwrap();
        assert_eq!(rep.rectangles.len(), 12);
        let dir = std::env::temp_dir().join(format!("figures-panels-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("plan.png");
        plot_rectangle_panels(&path, "plan", &rep.rectangles, rep.shortest).unwrap();
        let png = std::fs::read(&path).unwrap();
        let dim = |at: usize| u32::from_be_bytes([png[at], png[at + 1], png[at + 2], png[at + 3]]);
        assert_eq!((dim(16), dim(20)), (4 * PANEL.0, 3 * PANEL.1 + 40));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
