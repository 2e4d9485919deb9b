//! Figure I.2: Painlevé's paradoxes for one block on a rough floor (App. I of the
//! thesis, ERRATA 18): (a) the admissible angles against the aspect ratio, (b) the
//! region b ≤ 0 in the (ϑ, μ_d) plane per slip direction.

use crate::axis::{TickedRange, Ticks};
use crate::plot::{draw_title, with_png, Canvas, LinePlot, Series, FONT, PALETTE, TITLE_PX};
use crate::{err, Result};
use blockstack::painleve::{admissible_range, critical_mu, BSample};
use blockstack::studies::painleve::PainleveReport;
use plotters::prelude::*;
use std::path::Path;

/// Draws Figure I.2 for a block of aspect ratio w/h = `aspect`, from the b-sign grid
/// `samples` (`n_grid` × `n_grid` nodes up to `mu_max`) and the report's admissible
/// range and points of least friction.
///
/// # Errors
/// An unwritable file.
pub fn plot_painleve(
    path: &Path,
    aspect: f64,
    mu_max: f64,
    n_grid: usize,
    report: &PainleveReport,
    samples: &[BSample],
) -> Result<()> {
    // Panel (a): admissible angles against the aspect ratio w/h.
    let aspects: Vec<f64> = (1..=200).map(|i| 0.025 * f64::from(i)).collect();
    let mut lo = Vec::new();
    let mut hi = Vec::new();
    for (r, (a, b)) in aspects
        .iter()
        .filter_map(|&r| Some((r, admissible_range(r).ok()?)))
    {
        lo.push((r, a.to_degrees()));
        hi.push((r, b.to_degrees()));
    }
    let panel_a = LinePlot::new(
        "(a) admissible angles (I.1.3)",
        "aspect w/h [dimensionless]",
        "angle ϑ [deg]",
    )
    .with(Series::line("ϑ_max = atan(w/h)", hi))
    .with(Series::line("ϑ_min = −atan(h/w)", lo))
    .with(Series::markers(
        format!("w/h = {aspect}"),
        vec![
            (aspect, report.theta_min.to_degrees()),
            (aspect, report.theta_max.to_degrees()),
        ],
    ));
    with_png(path, (1400, 600), |root| {
        let (left, right) = root.split_horizontally(560);
        panel_a.draw(&left)?;
        draw_b_regions(&right, mu_max, n_grid, report, samples)
    })
}

/// Panel (b) of Figure I.2: where b ≤ 0 in the (ϑ, μ_d) plane, per slip direction, with
/// the loci b = 0, the admissible range and the points i, ii of least μ_d.
fn draw_b_regions(
    root: &Canvas<'_>,
    mu_max: f64,
    n_grid: usize,
    report: &PainleveReport,
    grid: &[BSample],
) -> Result<()> {
    let area = draw_title(
        root,
        "(b) Painlevé region b ≤ 0 (I.1.8, ERRATA 18)",
        TITLE_PX,
    )?;
    let mut chart = ChartBuilder::on(&area)
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(64)
        .build_cartesian_2d(
            TickedRange::new(-90.0..90.0, Ticks::linear(-90.0, 90.0)),
            TickedRange::new(0.0..mu_max, Ticks::linear(0.0, mu_max)),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("ϑ [deg]")
        .y_desc("μ_d [dimensionless]")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .bold_line_style(RGBColor(200, 200, 200))
        .light_line_style(RGBColor(236, 236, 236))
        .draw()
        .map_err(err)?;
    let (dt, dm) = (180.0 / n_grid as f64, mu_max / (n_grid - 1) as f64);
    let cells = grid.iter().filter_map(|s| {
        let color = if s.b_plus <= 0.0 {
            PALETTE[0]
        } else if s.b_minus <= 0.0 {
            PALETTE[1]
        } else {
            return None;
        };
        let alpha = if s.admissible { 0.7 } else { 0.2 };
        let (t, m) = (s.theta.to_degrees(), s.mu);
        Some(Rectangle::new(
            [(t - 0.5 * dt, m - 0.5 * dm), (t + 0.5 * dt, m + 0.5 * dm)],
            color.mix(alpha).filled(),
        ))
    });
    chart.draw_series(cells).map_err(err)?;
    for (sign, color, label) in [
        (1.0, PALETTE[0], "b = 0, sgn(x_P') = +1"),
        (-1.0, PALETTE[1], "b = 0, sgn(x_P') = -1"),
    ] {
        let locus: Vec<(f64, f64)> = (1..1800)
            .map(|i| -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(i) / 1800.0)
            .filter_map(|th| critical_mu(th, sign).map(|m| (th.to_degrees(), m)))
            .filter(|p| p.1 <= mu_max)
            .collect();
        chart
            .draw_series(LineSeries::new(locus, color.stroke_width(2)))
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    for (i, th) in [report.theta_min, report.theta_max].into_iter().enumerate() {
        let d = th.to_degrees();
        let drawn = chart
            .draw_series(LineSeries::new(
                vec![(d, 0.0), (d, mu_max)],
                BLACK.stroke_width(1),
            ))
            .map_err(err)?;
        if i == 0 {
            drawn
                .label("ϑ_min, ϑ_max (I.1.3)")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        }
    }
    let points = [
        (
            report.mu_min_slip_positive.theta.to_degrees(),
            report.mu_min_slip_positive.mu,
            "i",
        ),
        (
            report.mu_min_slip_negative.theta.to_degrees(),
            report.mu_min_slip_negative.mu,
            "ii",
        ),
    ];
    chart
        .draw_series(points.iter().map(|&(t, m, name)| {
            EmptyElement::at((t, m))
                + Circle::new((0, 0), 5, BLACK.filled())
                + Text::new(name.to_string(), (8, -18), (FONT, 18))
        }))
        .map_err(err)?;
    // Lower right: the regions b ≤ 0 open upwards from their minima i, ii at
    // μ_d = 4/3 (tan ϑ = ±1/2), so the bottom of the plane is empty.
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}
