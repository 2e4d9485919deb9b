//! The figures of `rollstack sphere` and the tour: Figures 2.1, 2.5, 2.6–2.9 and the
//! integrator study, drawn from the data of [`holonomy::studies`].

use crate::plot::{with_png, LinePlot, Series, FONT, PALETTE};
use crate::{err, Result};
use holonomy::rectangle::holonomy_angle;
use holonomy::studies::level_sets::{level_set_branches, FIGURE_2_5_LEVELS_DEG};
use holonomy::studies::plan::RectangleReport;
use holonomy::studies::roll::{StudyPath, StudyRow};
use holonomy::{Integrator, Trajectory};
use plotters::prelude::*;
use std::f64::consts::TAU;
use std::path::Path;

/// Figure 2.1: top view of the traces of the centre C (i) and the marked point X (ii).
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
        .with(Series::line("i: centre C", c))
        .with(Series::line("ii: material point X", x))
        .with(Series::markers("X at t0 (A) and t1 (B)", ends));
    plot.equal_aspect = true;
    plot.save(path, (800, 800))
}

/// The corners of a rectangle's path as plot points.
fn outline(r: &RectangleReport) -> Vec<(f64, f64)> {
    r.waypoints.iter().map(|w| (w[0], w[1])).collect()
}

/// Draws rectangles (the centre's path) in one frame, numbered, with the start S (the
/// direction of travel is in the legend).
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangles(path: &Path, title: &str, rects: &[RectangleReport]) -> Result<()> {
    let mut plot = LinePlot::new(title, "E1 [R]", "E2 [R]");
    plot.equal_aspect = true;
    for (i, r) in rects.iter().enumerate() {
        plot = plot.with(Series::line(
            format!(
                "{}: ϑ={:.3}, φ1={:.3}, φ2={:.3}, {}",
                i + 1,
                r.theta,
                r.phi1,
                r.phi2,
                r.direction.as_str()
            ),
            outline(r),
        ));
    }
    plot = plot.with(Series::markers("S", vec![(0.0, 0.0)]));
    plot.save(path, (900, 900))
}

/// Figure 2.6: each rectangle in its own panel (at most six), same scale.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangle_panels(path: &Path, rects: &[RectangleReport]) -> Result<()> {
    let rects = &rects[..rects.len().min(6)];
    let n = rects.len().max(1);
    #[allow(clippy::cast_possible_truncation)]
    let cols = n.min(3) as u32;
    #[allow(clippy::cast_possible_truncation)]
    let rows_n = n.div_ceil(3) as u32;
    with_png(path, (420 * cols, 440 * rows_n), |root| {
        let areas = root.split_evenly((rows_n as usize, cols as usize));
        for (r, area) in rects.iter().zip(areas.iter()) {
            let mut plot = LinePlot::new(
                format!(
                    "ϑ={:.4} φ1={:.4} φ2={:.4} {}",
                    r.theta,
                    r.phi1,
                    r.phi2,
                    r.direction.as_str()
                ),
                "A1 [R]",
                "A2 [R]",
            )
            .with(Series::line("", outline(r)))
            .with(Series::markers("", vec![(0.0, 0.0)]));
            plot.equal_aspect = true;
            plot.draw(area)?;
        }
        Ok(())
    })
}

/// Figure 2.5: the level sets of ψ(ϑ, φ2) over [0, 2π]² ([`level_set_branches`],
/// (2.4.11) with the factor 2 of ERRATA item 1). A marked point shows `mark` if given.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_level_sets(path: &Path, mark: Option<(f64, f64)>) -> Result<()> {
    with_png(path, (820, 800), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Level sets of ψ(ϑ, φ2), (2.4.11) corrected (Figure 2.5)",
                (FONT, 22),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..TAU, 0.0..TAU)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("ϑ [rad]")
            .y_desc("φ2 [rad]")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()
            .map_err(err)?;
        for (i, deg) in FIGURE_2_5_LEVELS_DEG.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            for branch in level_set_branches(deg.to_radians(), 400) {
                let points = branch.into_iter().map(|[t, p]| (t, p));
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))
                    .map_err(err)?;
            }
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!("ψ = {deg}°"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
        }
        if let Some((t, p)) = mark {
            // The rectangle's place in the window [0, 2π]² (ψ has period 2π in both).
            let (t, p) = (t.rem_euclid(TAU), p.rem_euclid(TAU));
            chart
                .draw_series(std::iter::once(Circle::new((t, p), 5, BLACK.filled())))
                .map_err(err)?
                .label(format!(
                    "this rectangle: ψ = {:.2}°",
                    holonomy_angle(t, p).to_degrees()
                ))
                .legend(|(x, y)| Circle::new((x + 9, y), 4, BLACK.filled()));
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}

/// The integrator study: error of the final orientation against wall time, log–log.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_study(path: &Path, rows: &[StudyRow]) -> Result<()> {
    let mut plot = LinePlot::new(
        "Rolling integrators: error of the final orientation vs wall time",
        "log10 of the wall time [s]",
        "log10 of the error [rad] (floored at 1e-17)",
    );
    for shape in [StudyPath::Rectangle, StudyPath::Circle] {
        for integrator in [Integrator::Exact, Integrator::Rk4] {
            let pts = rows
                .iter()
                .filter(|r| r.path == shape && r.integrator == integrator)
                .map(|r| (r.wall_time_s.log10(), r.error.max(1e-17).log10()))
                .collect();
            plot = plot.with(Series::line(
                format!("{}, {}", integrator.as_str(), shape.as_str()),
                pts,
            ));
        }
    }
    plot.save(path, (900, 600))
}
