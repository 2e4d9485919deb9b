//! `rollstack cylinder work-precision`: speed against error for the transport of two
//! touching cylinders spun up (§3.6), NSGA beside Moreau–Jean
//! ([`cylinders::studies::work_precision`]).

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use clap::Args;
use cylinders::studies::work_precision::{
    pair_work_precision, study_cost_settings, study_settings, PairWorkPrecisionRow, MAX_DT, T_END_S,
};
use figures::cylinders::plot_pair_work_precision;
use input::text::{parse_finite, parse_number_list, RotationAngle};
use std::path::PathBuf;

/// Arguments of `rollstack cylinder work-precision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    /// Inclination ϑ of both cylinders, in (arctan(2r/h), π/2), rad (`30deg` accepted);
    /// by default that of the tour's `cylinder pair --theta 30deg`, so that the study
    /// measures the run the tour shows.
    #[arg(long, default_value = "30deg", allow_hyphen_values = true)]
    pub theta: RotationAngle,
    /// Time steps Δt in s (comma-separated, each in (0, 0.1]).
    #[arg(
        long,
        default_value = "8e-3,4e-3,2e-3,1e-3",
        allow_hyphen_values = true
    )]
    pub dts: String,
    /// The reference run takes Δt = min(dts)/FACTOR (at least 1).
    #[arg(long, default_value_t = 4.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub reference_factor: f64,
    /// Repetitions per point (1 to 1000); the fastest solver time is kept.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=1000), allow_hyphen_values = true)]
    pub repeat: u16,
    /// Run even when the study is estimated to take longer than ten minutes.
    #[arg(long)]
    pub force: bool,
    /// Directory for work_precision.csv, work_precision.png and run.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `rollstack cylinder work-precision`.
///
/// # Errors
/// Bad input, a failed reference run or an unwritable directory.
pub fn run(a: &WorkPrecisionArgs) -> Result<()> {
    let theta = a.theta.0;
    let dts = parse_number_list(&a.dts)
        .map_err(anyhow::Error::msg)
        .context("--dts")?;
    // Checked here so that the errors name the flags, not the library's Δt and factor.
    for &dt in &dts {
        input::positive("--dts", dt)?;
        input::in_range("--dts", dt, 0.0..=MAX_DT, "(0, 0.1] s")?;
    }
    anyhow::ensure!(
        a.reference_factor >= 1.0,
        "--reference-factor must be at least 1, got {}",
        input::Short(a.reference_factor)
    );
    let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
    anyhow::ensure!(
        smallest / a.reference_factor > 0.0,
        "the smallest --dts {} over --reference-factor {} gives a reference Δt of 0 in \
         double precision: take larger --dts or a smaller --reference-factor",
        input::Short(smallest),
        input::Short(a.reference_factor)
    );
    super::check_theta(theta, &study_settings(theta, smallest).cylinder)?;
    let repeat = usize::from(a.repeat);
    check_time_bound(theta, &dts, a.reference_factor, repeat, a.force)?;
    let busy = crate::progress::busy("cylinder work-precision: solving", !a.json);
    let study = pair_work_precision(theta, &dts, a.reference_factor, repeat)?;
    if let Some(dir) = &a.out {
        busy.set_message("cylinder work-precision: writing the files");
        ensure_dir(dir)?;
        write_csv(
            &dir.join("work_precision.csv"),
            &PairWorkPrecisionRow::CSV_HEADER,
            study.rows.iter().map(PairWorkPrecisionRow::csv_cells),
        )?;
        plot_pair_work_precision(&dir.join("work_precision.png"), &study)?;
        let inputs = serde_json::json!({"theta": theta, "dts": dts,
            "reference_factor": a.reference_factor, "repeat": repeat});
        let solver_s: f64 = study.rows.iter().map(|r| r.wall_time_s).sum();
        let timings = serde_json::json!({"solver_s": solver_s + study.reference_wall_time_s});
        write_run_json(dir, "cylinder work-precision", &inputs, &timings)?;
    }
    busy.finish_and_clear();
    if a.json {
        return print_json(&study);
    }
    for r in &study.rows {
        println!("{r}");
    }
    println!("observed order, NSGA: {}", study.orders.nsga);
    println!("observed order, Moreau-Jean: {}", study.orders.moreau);
    println!(
        "(error at t = {T_END_S} s against Δt = {:.2e} s, {} contact events; orders fitted \
         over the smallest Δt whose runs follow them; (3.3.10): N/mg = {:.10})",
        study.reference_dt, study.reference_events, study.n_over_mg_static
    );
    Ok(())
}

/// Refuses a study estimated to take more than
/// [`TIME_BOUND_S`](crate::commands::blocks::TIME_BOUND_S), unless `force`: all its
/// steps at the cost of a step of the reference run, measured on its first steps
/// ([`study_cost_settings`], [`super::guard::check_time_bound`]).
///
/// # Errors
/// When the estimate is over the bound.
fn check_time_bound(
    theta: f64,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
    force: bool,
) -> Result<()> {
    let settings = study_cost_settings(theta, dts, reference_factor, repeat);
    super::guard::check_time_bound(
        &settings,
        1,
        1,
        force,
        "take larger --dts, a smaller --reference-factor or --repeat",
    )
}
