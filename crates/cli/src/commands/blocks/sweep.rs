//! `rollstack blocks sweep frequency|slide`: Figures 4.6 and 4.7, one row per parameter
//! value from `blockstack::studies`, run in parallel and written in input order.

use super::SolverArgs;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use crate::sweep::{par_map_ordered, Shard};
use anyhow::Result;
use blockstack::scenarios::Shaking;
use blockstack::studies::shaking::{frequency_row, FrequencyRow};
use blockstack::studies::slide::{slide_row, SlideRegime, SlideRow};
use clap::{Args, Subcommand};
use figures::blocks::{plot_frequency_sweep, plot_slide_sweep, FrequencySweep, SlideSweep};
use input::text::parse_finite;
use input::text::parse_range;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The sweeps of §4.4–4.5.
#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// Failure time T of a shaken column against the base frequency ω (Figure 4.6: four
    /// blocks w = 0.2, h = 0.4 on a base w = 1, h = 0.1, μ = 0.2, Δt = 2π/(100ω)).
    Frequency(FrequencyArgs),
    /// Angle of the top block at t_end against the speed v0 of the pulled base (Figure 4.7:
    /// base and blocks w = 0.2, h = 0.4, μ = 0.2, t_end = 3).
    Slide(SlideArgs),
}

/// Options shared by the sweeps.
#[derive(Debug, Clone, Args)]
pub struct SweepOutputArgs {
    /// Run only part K of N of the values (a contiguous block, so the parts' CSV rows
    /// concatenate in input order).
    #[arg(long, default_value = "1/1")]
    pub shard: Shard,
    /// Directory for the CSV, the PNG and run.json (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Also print the rows as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rollstack blocks sweep frequency`.
#[derive(Debug, Args)]
pub struct FrequencyArgs {
    /// Base angular frequencies ω (rad per time unit), as A:B:STEP or one value.
    #[arg(long, allow_hyphen_values = true)]
    pub omega: String,
    /// Number of base periods simulated per run (the run stops at the failure).
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub periods: f64,
    /// Base amplitude A (length units; the thesis's "A = w²" is ambiguous).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Number of free blocks on the base.
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    /// Steps per base period N: Δt = 2π/(Nω) (Figure 4.6: 100; ERRATA 21).
    #[arg(long, default_value_t = 100.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub steps_per_period: f64,
    /// Friction coefficient μ at every contact (dimensionless).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// Arguments of `rollstack blocks sweep slide`.
#[derive(Debug, Args)]
pub struct SlideArgs {
    /// Base speeds v0 (length per time unit), as A:B:STEP or one value.
    #[arg(long, allow_hyphen_values = true)]
    pub v0: String,
    /// Time at which the top block's angle is read (Figure 4.7: 3; ERRATA 21).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Number of free blocks on the base (Figure 4.7: 4, the thesis's "five" with the base).
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

fn sweep_values(text: &str, name: &str, shard: Shard) -> Result<Vec<f64>> {
    let all = parse_range(text).map_err(|e| anyhow::anyhow!("--{name}: {e}"))?;
    Ok(shard.select(&all).into_iter().map(|(_, v)| v).collect())
}

/// Runs `rollstack blocks sweep frequency`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn sweep_frequency(args: &FrequencyArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    anyhow::ensure!(args.periods > 0.0, "--periods must be positive");
    anyhow::ensure!(
        args.steps_per_period > 0.0,
        "--steps-per-period must be positive"
    );
    anyhow::ensure!(args.mu >= 0.0, "--mu must not be negative");
    let options = args.solver.run_options(None, true)?;
    let omegas = sweep_values(&args.omega, "omega", args.output.shard)?;
    let column = |omega| Shaking {
        blocks: args.blocks,
        amplitude: args.amplitude,
        omega,
        periods: args.periods,
        steps_per_period: args.steps_per_period,
        mu: args.mu,
    };
    let rows = par_map_ordered(&omegas, "omega", |&omega| {
        frequency_row(&column(omega), &options)
    });
    let dir = &args.output.out;
    ensure_dir(dir)?;
    write_frequency_files(dir, &rows, &FrequencySweep::of(&column(1.0)))?;
    finish_sweep(
        "frequency",
        &args.output,
        &args.solver,
        serde_json::json!({
            "omega": args.omega, "periods": args.periods, "amplitude": args.amplitude,
            "blocks": args.blocks, "steps_per_period": args.steps_per_period, "mu": args.mu,
        }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        |r| {
            format!(
                "omega = {:.4}: T = {}, steps {}{}",
                r.omega,
                r.failure_time
                    .map_or_else(|| "none".to_owned(), |t| format!("{t:.4}")),
                r.steps,
                error_suffix(r.error.as_ref())
            )
        },
    )
}

/// What every sweep does once its rows are written: `run.json` (inputs, version,
/// timings), then either `{"rows": [...]}` on stdout or one line per row.
///
/// # Errors
/// An unwritable directory.
fn finish_sweep<R: Serialize>(
    name: &str,
    output: &SweepOutputArgs,
    solver: &SolverArgs,
    mut inputs: serde_json::Value,
    rows: &[R],
    solver_seconds: f64,
    start: Instant,
    line: impl Fn(&R) -> String,
) -> Result<()> {
    inputs["shard"] = format!("{}/{}", output.shard.index, output.shard.count).into();
    inputs["prox_constant"] = serde_json::json!(solver.prox_constant);
    inputs["explore_branches"] = solver.explore_branches.into();
    write_run_json(
        &output.out,
        &format!("blocks sweep {name}"),
        &inputs,
        &serde_json::json!({
            "total_s": start.elapsed().as_secs_f64(),
            "solver_s": solver_seconds,
        }),
    )?;
    if output.json {
        return print_json(&serde_json::json!({ "rows": rows }));
    }
    for r in rows {
        println!("{}", line(r));
    }
    println!(
        "wrote sweep_{name}.csv and sweep_{name}.png into {}",
        output.out.display()
    );
    Ok(())
}

/// `, error: …` after a sweep row's line, or nothing.
fn error_suffix(error: Option<&String>) -> String {
    error.map_or_else(String::new, |e| format!(", error: {e}"))
}

/// Writes `sweep_frequency.csv` and `sweep_frequency.png` (Figure 4.6 with the
/// parameters of `sweep`, which the title names).
///
/// # Errors
/// An unwritable directory.
pub fn write_frequency_files(
    dir: &Path,
    rows: &[FrequencyRow],
    sweep: &FrequencySweep,
) -> Result<()> {
    write_csv(
        &dir.join("sweep_frequency.csv"),
        &FrequencyRow::CSV_HEADER,
        rows.iter().map(FrequencyRow::csv_cells),
    )?;
    plot_frequency_sweep(&dir.join("sweep_frequency.png"), rows, sweep)?;
    Ok(())
}

/// Runs `rollstack blocks sweep slide`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn sweep_slide(args: &SlideArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    let options = args.solver.run_options(Some(args.t_end), false)?;
    let speeds = sweep_values(&args.v0, "v0", args.output.shard)?;
    let rows = par_map_ordered(&speeds, "v0", |&v| {
        slide_row(args.blocks, v, args.t_end, &options)
    });
    let dir = &args.output.out;
    ensure_dir(dir)?;
    let sweep = SlideSweep {
        blocks: args.blocks,
        t_end: args.t_end,
    };
    write_slide_files(dir, &rows, &sweep)?;
    finish_sweep(
        "slide",
        &args.output,
        &args.solver,
        serde_json::json!({ "v0": args.v0, "t_end": args.t_end, "blocks": args.blocks }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        |r| {
            format!(
                "v0 = {:.4}: top angle {} at t = {:.3}, {}{}",
                r.v0,
                r.top_angle
                    .map_or_else(|| "-".to_owned(), |a| format!("{a:.4} rad")),
                r.t_final,
                r.regime.map_or("-", SlideRegime::name),
                error_suffix(r.error.as_ref())
            )
        },
    )
}

/// Writes `sweep_slide.csv` and `sweep_slide.png` (Figure 4.7 with the parameters of
/// `sweep`, which the title names).
///
/// # Errors
/// An unwritable directory.
pub fn write_slide_files(dir: &Path, rows: &[SlideRow], sweep: &SlideSweep) -> Result<()> {
    write_csv(
        &dir.join("sweep_slide.csv"),
        &SlideRow::CSV_HEADER,
        rows.iter().map(SlideRow::csv_cells),
    )?;
    plot_slide_sweep(&dir.join("sweep_slide.png"), rows, sweep)?;
    Ok(())
}
