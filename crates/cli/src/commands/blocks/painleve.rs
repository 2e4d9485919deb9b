//! `rollstack blocks painleve`: Painlevé's paradoxes for one block (App. I, ERRATA 18):
//! the report of `blockstack::studies::painleve`, the b-sign grid and Figure I.2.

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use blockstack::painleve::{b_grid, BSample, MAX_GRID_NODES};
use blockstack::studies::painleve::{corner_scan, painleve_report, CornerCase, PainleveReport};
use clap::Args;
use figures::painleve::plot_painleve;
use input::text::parse_finite;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack blocks painleve`.
#[derive(Debug, Args)]
pub struct PainleveArgs {
    /// Aspect ratio w/h of the block (dimensionless, > 0).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub aspect: f64,
    /// Friction coefficient μ_d (dimensionless, ≥ 0) of the line-contact LCP (I.2.10) and
    /// of the corner scan.
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    /// Largest μ_d of the b-sign grid (dimensionless).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_max: f64,
    /// Grid nodes per axis of the b-sign grid (angle and μ_d).
    #[arg(long, default_value_t = 121, allow_hyphen_values = true)]
    pub grid: usize,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Directory for the b-sign grid (CSV), Figure I.2 (PNG), the corner scan at --mu
    /// (CSV: each case's first-step solutions, sliding contact, jam, lift-off) and
    /// run.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rollstack blocks painleve`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn run(args: &PainleveArgs) -> Result<()> {
    let start = Instant::now();
    // Checked here so that each refusal names its flag, not the library's parameter.
    anyhow::ensure!(
        (2..=MAX_GRID_NODES).contains(&args.grid),
        "--grid must lie in [2, {MAX_GRID_NODES}], got {}",
        args.grid
    );
    input::positive("--aspect", args.aspect)?;
    friction("--mu", input::non_negative("--mu", args.mu)?)?;
    friction("--mu-max", input::positive("--mu-max", args.mu_max)?)?;
    let report = painleve_report(args.aspect, args.mu)?;
    if let Some(dir) = &args.out {
        write_painleve_files(dir, args.aspect, args.mu_max, args.grid, &report)?;
        write_csv(
            &dir.join("painleve_corner_scan.csv"),
            &CornerCase::CSV_HEADER,
            corner_scan(args.mu)?.iter().map(CornerCase::csv_cells),
        )?;
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
        println!("{}", report.summary(args.aspect));
    }
    Ok(())
}

/// Refuses a friction coefficient for which the term 3 μ sin ϑ cos ϑ of b (I.1.8)
/// overflows: b would be ±∞ in the grid and the corner scan.
///
/// # Errors
/// 3 μ not finite.
fn friction(flag: &str, mu: f64) -> Result<f64> {
    anyhow::ensure!(
        (3.0 * mu).is_finite(),
        "{flag} {mu:e} is too large: 3 μ sin ϑ cos ϑ in b (I.1.8) overflows"
    );
    Ok(mu)
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
    write_csv(
        &dir.join("painleve_b_grid.csv"),
        &BSample::CSV_HEADER,
        samples.iter().map(BSample::csv_cells),
    )?;
    plot_painleve(
        &dir.join("painleve.png"),
        aspect,
        mu_max,
        grid,
        report,
        &samples,
    )
    .context("cannot draw the Painlevé figure")
}
