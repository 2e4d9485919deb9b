//! `rollstack blocks painleve`: Painlevé's paradoxes for one block (App. I, ERRATA 18):
//! the report of `blockstack::studies::painleve`, the b-sign grid and Figure I.2.

use crate::angles::parse_finite;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use crate::plot::{err, with_png, LinePlot, Series, FONT, PALETTE};
use anyhow::{Context, Result};
use blockstack::painleve::{admissible_range, b_grid, critical_mu, least_friction};
use blockstack::studies::painleve::{painleve_report, PainleveReport};
use clap::Args;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack blocks painleve`.
#[derive(Debug, Args)]
pub struct PainleveArgs {
    /// Aspect ratio w/h of the block (dimensionless, > 0).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub aspect: f64,
    /// Friction coefficient μ_d (dimensionless, ≥ 0) of the line-contact LCP (I.2.10).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    /// Largest μ_d of the b-sign grid (dimensionless).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_max: f64,
    /// Grid nodes per axis of the b-sign grid (angle and μ_d).
    #[arg(long, default_value_t = 121)]
    pub grid: usize,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Directory for the b-sign grid (CSV), Figure I.2 (PNG) and run.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rollstack blocks painleve`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn run(args: &PainleveArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(
        args.grid >= 2,
        "--grid must be at least 2, got {}",
        args.grid
    );
    let report = painleve_report(args.aspect, args.mu)?;
    let (theta_min, theta_max) = (report.theta_min, report.theta_max);
    let least = least_friction(args.aspect)?;
    if let Some(dir) = &args.out {
        write_painleve_files(dir, args.aspect, args.mu_max, args.grid, &report)?;
        write_run_json(
            dir,
            "blocks painleve",
            &serde_json::json!({"aspect": args.aspect, "mu": args.mu, "mu_max": args.mu_max, "grid": args.grid}),
            &serde_json::json!({"wall_time_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if args.json {
        print_json(&report)?;
    } else {
        println!(
            "w/h = {}: admissible angles ({:.3}°, {:.3}°) (I.1.3)",
            args.aspect,
            theta_min.to_degrees(),
            theta_max.to_degrees()
        );
        println!(
            "least friction coefficient for a paradox: μ_d = {:.6} at ϑ = {:.3}° (sgn ẋ_P = {:+})",
            least.mu,
            least.theta.to_degrees(),
            least.slip_sign
        );
        for (name, sols) in [
            ("right", &report.line_contact.sliding_right),
            ("left", &report.line_contact.sliding_left),
        ] {
            for s in sols {
                println!(
                    "line contact, μ_d = {}, sliding {name}: n_R = {:.6}, n_L = {:.6} (I.2.10)",
                    args.mu, s.n_right, s.n_left
                );
            }
        }
    }
    Ok(())
}

/// Writes `painleve_b_grid.csv` (b on a (ϑ, μ_d) grid of `grid` × `grid` nodes up to
/// `mu_max`) and `painleve.png` (Figure I.2) into `dir`.
///
/// # Errors
/// Bad parameters or an unwritable directory.
pub fn write_painleve_files(
    dir: &Path,
    aspect: f64,
    mu_max: f64,
    grid: usize,
    report: &PainleveReport,
) -> Result<()> {
    // Everything that can fail on bad input comes before the first file is written.
    let samples = b_grid(aspect, mu_max, grid, grid)?;
    ensure_dir(dir)?;
    let rows = samples.iter().map(|s| {
        vec![
            format!("{}", s.theta),
            format!("{}", s.theta.to_degrees()),
            format!("{}", s.mu),
            format!("{}", s.b_plus),
            format!("{}", s.b_minus),
            format!("{}", u8::from(s.admissible)),
        ]
    });
    write_csv(
        &dir.join("painleve_b_grid.csv"),
        &[
            "theta_rad",
            "theta_deg",
            "mu_d",
            "b_slip_positive",
            "b_slip_negative",
            "admissible",
        ],
        rows,
    )?;
    // Panel (a): admissible angles against the aspect ratio w/h.
    let aspects: Vec<f64> = (1..=200).map(|i| 0.025 * f64::from(i)).collect();
    let mut lo = Vec::new();
    let mut hi = Vec::new();
    for &r in &aspects {
        let (a, b) = admissible_range(r)?;
        lo.push((r, a.to_degrees()));
        hi.push((r, b.to_degrees()));
    }
    let panel_a = LinePlot::new("(a) admissible angles (I.1.3)", "aspect w/h", "angle (deg)")
        .with(Series::line("theta_max = atan(w/h)", hi))
        .with(Series::line("theta_min = -atan(h/w)", lo))
        .with(Series::markers(
            format!("w/h = {aspect}"),
            vec![
                (aspect, report.theta_min.to_degrees()),
                (aspect, report.theta_max.to_degrees()),
            ],
        ));
    with_png(&dir.join("painleve.png"), (1400, 600), |root| {
        let (left, right) = root.split_horizontally(560);
        panel_a.draw(&left)?;
        draw_b_regions(&right, mu_max, grid, report, &samples)
    })
    .context("cannot draw the Painlevé figure")
}

/// Panel (b) of Figure I.2: where b ≤ 0 in the (ϑ, μ_d) plane, per slip direction, with
/// the loci b = 0, the admissible range and the points i, ii of least μ_d.
fn draw_b_regions(
    root: &crate::plot::Canvas<'_>,
    mu_max: f64,
    n_grid: usize,
    report: &PainleveReport,
    grid: &[blockstack::painleve::BSample],
) -> Result<()> {
    let mut chart = ChartBuilder::on(root)
        .caption("(b) Painlevé region b <= 0 (I.1.8, ERRATA 18)", (FONT, 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(-90.0..90.0, 0.0..mu_max)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("theta (deg)")
        .y_desc("mu_d")
        .label_style((FONT, 14))
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
    for th in [report.theta_min, report.theta_max] {
        let d = th.to_degrees();
        chart
            .draw_series(LineSeries::new(
                vec![(d, 0.0), (d, mu_max)],
                BLACK.stroke_width(1),
            ))
            .map_err(err)?;
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
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}
