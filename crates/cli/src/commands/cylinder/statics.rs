//! `rollstack cylinder statics`: the support-force curves of Figures 3.3, 3.4, 3.5, 3.7
//! and 3.8 as CSV and PNG ([`cylinders::studies::statics`]).

use crate::output::{ensure_dir, write_csv, write_run_json};
use anyhow::Result;
use clap::Args;
use cylinders::studies::statics::{
    statics_figures, MinimumForceRow, NormalForceCurves, NormalForceRow, StaticsFigures, MAX_POINTS,
};
use figures::cylinders::plot_statics;
use input::text::parse_finite;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack cylinder statics`.
#[derive(Debug, Args)]
pub struct StaticsArgs {
    /// Aspect ratio r/h of Figures 3.3, 3.5, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Friction coefficient μ of Figures 3.3, 3.4, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Number of inclinations sampled in (0, 90°).
    #[arg(long, default_value_t = 721, allow_hyphen_values = true)]
    pub points: usize,
    /// Write fig3_3.csv … fig3_8.csv, their PNGs and run.json here (without it, the
    /// curves are computed and nothing is written).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub(super) fn run(a: &StaticsArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(
        (3..=MAX_POINTS).contains(&a.points),
        "--points must lie in [3, {MAX_POINTS}], got {}",
        a.points
    );
    // Checked here so that the errors name the flags, not the library's r/h and μ.
    input::non_negative("--r-over-h", a.r_over_h)?;
    input::non_negative("--mu", a.mu)?;
    let fig = statics_figures(a.r_over_h, a.mu, a.points)?;
    println!(
        "computed Figures 3.3, 3.4, 3.5, 3.7 and 3.8 at {} inclinations (r/h = {}, μ = {}); \
         point D at ϑ = {:.4}°",
        fig.minimum_force.len(),
        fig.r_over_h,
        fig.mu,
        fig.self_balancing_theta.to_degrees()
    );
    let Some(dir) = &a.out else {
        println!("give --out DIR to write their CSV and PNG files");
        return Ok(());
    };
    ensure_dir(dir)?;
    write_statics(dir, &fig)?;
    write_run_json(
        dir,
        "cylinder statics",
        &serde_json::json!({"r_over_h": a.r_over_h, "mu": a.mu, "points": a.points}),
        &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
    )?;
    println!(
        "wrote fig3_3 … fig3_8 (CSV, PNG) and run.json into {}",
        dir.display()
    );
    Ok(())
}

/// Writes the five statics figures (CSV and PNG) into `dir`.
///
/// # Errors
/// A file that cannot be written.
fn write_statics(dir: &Path, fig: &StaticsFigures) -> Result<()> {
    write_csv(
        &dir.join("fig3_3.csv"),
        &NormalForceRow::CSV_HEADER,
        fig.figure_3_3.rows.iter().map(NormalForceRow::csv_cells),
    )?;
    for (name, family) in [("fig3_4", &fig.figure_3_4), ("fig3_5", &fig.figure_3_5)] {
        write_csv(
            &dir.join(format!("{name}.csv")),
            &NormalForceCurves::CSV_HEADER,
            family.iter().flat_map(NormalForceCurves::csv_rows),
        )?;
    }
    write_csv(
        &dir.join("fig3_7_fig3_8.csv"),
        &MinimumForceRow::CSV_HEADER,
        fig.minimum_force.iter().map(MinimumForceRow::csv_cells),
    )?;
    Ok(plot_statics(dir, fig)?)
}
