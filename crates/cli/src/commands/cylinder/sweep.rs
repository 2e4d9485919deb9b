//! `rollstack cylinder sweep pair`: Figure 3.14, the transport of two touching
//! cylinders at each inclination ([`cylinders::studies::pair`]), in parallel, rows in
//! input order, sharded like the block sweeps (the plumbing of
//! [`crate::commands::blocks::sweep::SweepRun`]).

use crate::commands::blocks::sweep::{SweepOutputArgs, SweepRun};
use crate::output::{ensure_dir, write_csv};
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use cylinders::studies::pair::{pair_sweep_row, PairSettings, PairSweepRow};
use cylinders::transport::SpinProfile;
use figures::cylinders::plot_pair_sweep;
use input::text::{parse_finite, parse_values};

/// The sweeps of `rollstack cylinder sweep`.
#[derive(Debug, Subcommand)]
pub enum CylinderSweepCommand {
    /// Figure 3.14: N/mg, F3/mg and the force between the cylinders against ϑ, with the
    /// smooth-floor statics (3.3.10).
    Pair(PairSweepArgs),
}

/// Arguments of `rollstack cylinder sweep pair`.
#[derive(Debug, Args)]
pub struct PairSweepArgs {
    /// Inclinations ϑ, rad, as A:B:STEP, one value or a comma list, each in
    /// (arctan(2r/h), π/2) (Figure 3.14: (arctan(2r/h), π/4)).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: String,
    /// Time step Δt, s.
    #[arg(long, default_value_t = 2e-3, value_parser = parse_finite, allow_hyphen_values = true)]
    pub dt: f64,
    /// Number of steps per run.
    #[arg(long, default_value_t = 2000)]
    pub steps: usize,
    /// Prescribed spin φ̇10 of cylinder I, rad/s.
    #[arg(long, default_value_t = -6.0 * std::f64::consts::PI, value_parser = parse_finite, allow_hyphen_values = true)]
    pub spin: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// Runs `rollstack cylinder sweep ...`.
///
/// # Errors
/// Bad input, an unwritable directory; [`shards::RowsFailed`] after the files.
pub fn run(command: &CylinderSweepCommand) -> Result<()> {
    match command {
        CylinderSweepCommand::Pair(a) => sweep_pair(a),
    }
}

fn sweep_pair(a: &PairSweepArgs) -> Result<()> {
    let all = parse_values(&a.theta).map_err(|e| anyhow::anyhow!("--theta: {e}"))?;
    let settings = |theta| PairSettings {
        dt: a.dt,
        steps: a.steps,
        spin: SpinProfile::constant(a.spin),
        ..PairSettings::thesis(theta)
    };
    for &theta in &all {
        settings(theta)
            .system()
            .with_context(|| format!("--theta {theta}"))?;
    }
    let inputs =
        serde_json::json!({"theta": a.theta, "dt": a.dt, "steps": a.steps, "spin": a.spin});
    let sweep = SweepRun::of_command(
        "cylinder sweep pair".into(),
        "pair",
        &a.output,
        inputs,
        all.len(),
    )?;
    let thetas = sweep.run.select(&all);
    let rows = sweep.rows(&thetas, |&theta| pair_sweep_row(&settings(theta)))?;
    if let Some(dir) = &a.output.out {
        ensure_dir(dir)?;
        let csv = rows.iter().map(PairSweepRow::csv_cells);
        write_csv(&dir.join("sweep_pair.csv"), &PairSweepRow::CSV_HEADER, csv)?;
        let c = PairSettings::thesis(0.5).cylinder;
        plot_pair_sweep(&dir.join("fig3_14.png"), &rows, c.radius() / c.height())?;
    }
    let worst = rows
        .iter()
        .filter(|r| r.error.is_none())
        .map(|r| r.static_error)
        .fold(0.0, f64::max);
    let extra = serde_json::Map::from_iter([("max_static_error".into(), worst.into())]);
    sweep.finish(
        &["sweep_pair.csv", "fig3_14.png"],
        extra,
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        ToString::to_string,
    )
}
