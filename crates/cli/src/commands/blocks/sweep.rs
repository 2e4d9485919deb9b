//! `rollstack blocks sweep frequency|slide`: Figures 4.6 and 4.7, one row per parameter
//! value from `blockstack::studies`, run in parallel and written in input order. Every
//! value is checked before any run: one the model refuses is an error of the command; a
//! run the solver stops is the error of its row. And the
//! plumbing every sweep shares ([`sweep_values`], [`finish_sweep`]), which
//! `sweep scene` ([`super::sweep_scene`]) uses too.

use super::{run_cost, SolverArgs};
use crate::output::{ensure_dir, print_json, write_csv, write_run_json_with};
use crate::sweep::{par_map_ordered, Shard};
use anyhow::{Context, Result};
use blockstack::scenarios::{shaking_column, sliding_column, Shaking, Sliding};
use blockstack::simulation::RunOptions;
use blockstack::studies::shaking::{frequency_row, FrequencyRow};
use blockstack::studies::slide::{slide_row, SlideRow};
use blockstack::Scene;
use clap::{Args, Subcommand};
use figures::blocks::{plot_frequency_sweep, plot_slide_sweep, FrequencySweep, SlideSweep};
use input::text::parse_finite;
use input::text::parse_values;
use serde::Serialize;
use std::path::PathBuf;
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
    /// Any scene over any of its numbers: each `--set KEY=VALUES` sets a scene key
    /// (`contact.mu`, `base.omega`, `blocks.0.width`) to a range or list of values, one run
    /// per combination (the first `--set` varies slowest).
    Scene(super::sweep_scene::SceneArgs),
}

/// Options shared by the sweeps.
#[derive(Debug, Clone, Args)]
pub struct SweepOutputArgs {
    /// Run only part K of N of the values (a contiguous block, so the parts' CSV rows
    /// concatenate in input order).
    #[arg(long, default_value = "1/1")]
    pub shard: Shard,
    /// Directory for the CSV, the PNG and run.json (created if missing); without it,
    /// nothing is written.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also print the rows as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rollstack blocks sweep frequency`.
#[derive(Debug, Args)]
pub struct FrequencyArgs {
    /// Base angular frequencies ω (rad per time unit), as A:B:STEP, one value or a comma
    /// list of them.
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
    /// Base speeds v0 (length per time unit), as A:B:STEP, one value or a comma list of
    /// them.
    #[arg(long, allow_hyphen_values = true)]
    pub v0: String,
    /// Time at which the top block's angle is read (Figure 4.7: 3; ERRATA 21).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Number of free blocks on the base (Figure 4.7: 4, the thesis's "five" with the base).
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    /// Friction coefficient μ at every contact (dimensionless; Figure 4.7: 0.2).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// The values of `--{name}` this shard runs: `A:B:STEP`, numbers and comma lists of them
/// ([`parse_values`]).
///
/// # Errors
/// Text that is not such a list.
pub fn sweep_values(text: &str, name: &str, shard: Shard) -> Result<Vec<f64>> {
    let all = parse_values(text).map_err(|e| anyhow::anyhow!("--{name}: {e}"))?;
    Ok(shard.select(&all).into_iter().map(|(_, v)| v).collect())
}

/// What every sweep checks before any run: the scene of each of its `points` (a value
/// the model refuses is the sweep's error, naming it), and the estimated time of them
/// all ([`SolverArgs::check_cost`]).
///
/// # Errors
/// The first refused point, or a sweep over the time bound.
pub fn check_before_any_run<P>(
    points: &[P],
    solver: &SolverArgs,
    options: &RunOptions,
    scene: impl Fn(&P) -> Result<Scene>,
) -> Result<()> {
    let costs = points
        .iter()
        .map(|p| Ok(run_cost(&scene(p)?, options)))
        .collect::<Result<Vec<_>>>()?;
    solver.check_cost(&costs)
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
    check_before_any_run(&omegas, &args.solver, &options, |&omega| {
        shaking_column(&column(omega)).with_context(|| format!("--omega {omega}"))
    })?;
    let rows = par_map_ordered(&omegas, "omega", |&omega| {
        frequency_row(&column(omega), &options)
    });
    if let Some(dir) = &args.output.out {
        ensure_dir(dir)?;
        let csv = rows.iter().map(FrequencyRow::csv_cells);
        write_csv(
            &dir.join("sweep_frequency.csv"),
            &FrequencyRow::CSV_HEADER,
            csv,
        )?;
        let sweep = FrequencySweep::of(&column(1.0));
        plot_frequency_sweep(&dir.join("sweep_frequency.png"), &rows, &sweep)?;
    }
    finish_sweep(
        "frequency",
        &args.output,
        &args.solver,
        &["sweep_frequency.csv", "sweep_frequency.png"],
        &serde_json::Map::new(),
        serde_json::json!({
            "omega": args.omega, "periods": args.periods, "amplitude": args.amplitude,
            "blocks": args.blocks, "steps_per_period": args.steps_per_period, "mu": args.mu,
        }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        ToString::to_string,
    )
}

/// What every sweep does once its rows are written: `run.json` (inputs, version,
/// timings, and the keys of `extra`) when there is an output directory, then either
/// `{"rows": [...]}` (with the keys of `extra`) on stdout or one line per row, the notes
/// and the files written.
///
/// # Errors
/// An unwritable directory.
pub fn finish_sweep<R: Serialize>(
    name: &str,
    output: &SweepOutputArgs,
    solver: &SolverArgs,
    files: &[&str],
    extra: &serde_json::Map<String, serde_json::Value>,
    mut inputs: serde_json::Value,
    rows: &[R],
    solver_seconds: f64,
    start: Instant,
    line: impl Fn(&R) -> String,
) -> Result<()> {
    inputs["shard"] = format!("{}/{}", output.shard.index, output.shard.count).into();
    inputs["prox_constant"] = serde_json::json!(solver.prox_constant);
    inputs["explore_branches"] = solver.explore_branches.into();
    inputs["last_resort"] = solver.last_resort.into();
    if let Some(dir) = &output.out {
        write_run_json_with(
            dir,
            &format!("blocks sweep {name}"),
            &inputs,
            &serde_json::json!({
                "total_s": start.elapsed().as_secs_f64(),
                "solver_s": solver_seconds,
            }),
            extra,
        )?;
    }
    if output.json {
        let mut object = serde_json::Map::new();
        object.insert("rows".into(), serde_json::to_value(rows)?);
        object.extend(extra.clone());
        return print_json(&object);
    }
    for r in rows {
        println!("{}", line(r));
    }
    let notes = extra.get("notes").and_then(serde_json::Value::as_array);
    for n in notes
        .into_iter()
        .flatten()
        .filter_map(serde_json::Value::as_str)
    {
        println!("note: {n}");
    }
    if let Some(dir) = &output.out {
        println!(
            "wrote {} and run.json into {}",
            files.join(", "),
            dir.display()
        );
    }
    Ok(())
}

/// Runs `rollstack blocks sweep slide`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn sweep_slide(args: &SlideArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    anyhow::ensure!(args.mu >= 0.0, "--mu must not be negative");
    let options = args.solver.run_options(Some(args.t_end), false)?;
    let speeds = sweep_values(&args.v0, "v0", args.output.shard)?;
    let column = |v0| Sliding {
        blocks: args.blocks,
        v0,
        t_end: args.t_end,
        mu: args.mu,
    };
    check_before_any_run(&speeds, &args.solver, &options, |&v0| {
        sliding_column(&column(v0)).with_context(|| format!("--v0 {v0}"))
    })?;
    let rows = par_map_ordered(&speeds, "v0", |&v0| slide_row(&column(v0), &options));
    if let Some(dir) = &args.output.out {
        ensure_dir(dir)?;
        let csv = rows.iter().map(SlideRow::csv_cells);
        write_csv(&dir.join("sweep_slide.csv"), &SlideRow::CSV_HEADER, csv)?;
        let sweep = SlideSweep {
            blocks: args.blocks,
            t_end: args.t_end,
            mu: args.mu,
        };
        plot_slide_sweep(&dir.join("sweep_slide.png"), &rows, &sweep)?;
    }
    finish_sweep(
        "slide",
        &args.output,
        &args.solver,
        &["sweep_slide.csv", "sweep_slide.png"],
        &serde_json::Map::new(),
        serde_json::json!({
            "v0": args.v0, "t_end": args.t_end, "blocks": args.blocks, "mu": args.mu,
        }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        ToString::to_string,
    )
}
