//! `rollstack blocks work-precision`: speed against error for block stacks, NSGA beside
//! Moreau–Jean ([`blockstack::studies::work_precision`]).

use super::{check_time_bound, run_cost, RunOptions};
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use blockstack::studies::work_precision::{
    stack_work_precision, StackBenchmark, StackWorkPrecisionRow,
};
use clap::Args;
use figures::nsga::plot_stack_work_precision;
use input::text::{parse_finite, parse_number_list};
use std::path::PathBuf;

/// Arguments of `rollstack blocks work-precision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    /// The scene: `block` (one block sliding and rocking on a shaken base, to t = 2),
    /// `column` (three blocks, the bottom one sliding, then sticking while a corner above
    /// it lifts, to t = 0.8) or `lire` (the Lire collapse, to t = 5, before its first
    /// fork).
    #[arg(long, default_value = "block", value_parser = ["block", "column", "lire"])]
    pub system: String,
    /// Time steps Δt (comma-separated).
    #[arg(
        long,
        default_value = "1e-2,5e-3,2e-3,1e-3,5e-4",
        allow_hyphen_values = true
    )]
    pub dts: String,
    /// The reference run takes Δt = min(dts)/FACTOR.
    #[arg(long, default_value_t = 16.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub reference_factor: f64,
    /// Repetitions per point (1 to 1000); the fastest solver time is kept.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=1000), allow_hyphen_values = true)]
    pub repeat: u16,
    /// Run even when the reference is estimated to take longer than ten minutes.
    #[arg(long)]
    pub force: bool,
    /// Directory for work_precision.csv, work_precision.png and run.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `rollstack blocks work-precision`.
///
/// # Errors
/// Bad input, a failed reference run or an unwritable directory.
pub fn run(a: &WorkPrecisionArgs) -> Result<()> {
    let bench = StackBenchmark::ALL
        .into_iter()
        .find(|b| b.name() == a.system)
        .context("--system")?;
    let dts = parse_number_list(&a.dts)
        .map_err(anyhow::Error::msg)
        .context("--dts")?;
    // Checked here so that the error names the flag, not the scene's dt.
    for &dt in &dts {
        input::positive("--dts", dt)?;
    }
    anyhow::ensure!(
        a.reference_factor >= 1.0,
        "--reference-factor must be at least 1"
    );
    let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
    let reference_dt = smallest / a.reference_factor;
    anyhow::ensure!(
        reference_dt > 0.0,
        "the smallest --dts {} over --reference-factor {} gives a reference Δt of 0 in \
         double precision: take larger --dts or a smaller --reference-factor",
        input::Short(smallest),
        input::Short(a.reference_factor)
    );
    let reference = bench.scene(reference_dt)?;
    let options = RunOptions::default();
    check_time_bound(
        &[run_cost(&reference, &options)],
        Some((&reference, &options)),
        a.force,
        "take a smaller --reference-factor or larger --dts",
    )?;
    let repeat = usize::from(a.repeat);
    let study = stack_work_precision(bench, &dts, a.reference_factor, repeat)?;
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let csv = study.rows.iter().map(StackWorkPrecisionRow::csv_cells);
        write_csv(
            &dir.join("work_precision.csv"),
            &StackWorkPrecisionRow::CSV_HEADER,
            csv,
        )?;
        plot_stack_work_precision(&dir.join("work_precision.png"), &study)?;
        let inputs = serde_json::json!({"system": a.system, "dts": dts,
            "reference_factor": a.reference_factor, "repeat": repeat});
        let solver_s: f64 = study.rows.iter().map(|r| r.wall_time_s).sum();
        let timings = serde_json::json!({"solver_s": solver_s + study.reference_wall_time_s});
        write_run_json(dir, "blocks work-precision", &inputs, &timings)?;
    }
    if a.json {
        return print_json(&study);
    }
    for r in &study.rows {
        println!("{r}");
    }
    println!("observed order, NSGA: {}", study.orders.nsga);
    println!("observed order, Moreau-Jean: {}", study.orders.moreau);
    println!(
        "(reference Δt = {:.2e}, {} contact events; orders fitted over the smallest Δt whose \
         runs follow them)",
        study.reference_dt, study.reference_events
    );
    Ok(())
}
