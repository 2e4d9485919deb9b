//! `rollstack cylinder sweep pair|push`: Figure 3.14 and the slip onset under a push,
//! the transport of two touching cylinders at each inclination
//! ([`cylinders::studies::pair`]), in parallel, rows in input order, sharded like the
//! block sweeps (the plumbing of [`crate::commands::blocks::sweep::SweepRun`]).

use crate::commands::blocks::sweep::{SweepOutputArgs, SweepRun};
use crate::output::{ensure_dir, write_csv};
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use cylinders::studies::pair::{pair_sweep_row, push_row, PairSettings, PairSweepRow, PushRow};
use cylinders::transport::SpinProfile;
use figures::cylinders::{plot_minimum_force, plot_pair_sweep, plot_push_sweep};
use input::text::{parse_finite, parse_value, parse_values};

/// The sweeps of `rollstack cylinder sweep`.
#[derive(Debug, Subcommand)]
pub enum CylinderSweepCommand {
    /// Figure 3.14: N/mg, F3/mg and the force between the cylinders against ϑ, with the
    /// smooth-floor statics (3.3.10).
    Pair(PairSweepArgs),
    /// The push at which a rim starts to slip against ϑ: pushes P along e′2 at each top
    /// with floor friction μ_s, against the static bounds μ_s N₋ of (3.3.8)₋ (P > 0) and
    /// −μ_s N₊ of (3.3.8)₊ (P < 0).
    Push(PushSweepArgs),
}

/// Arguments of `rollstack cylinder sweep push`.
#[derive(Debug, Args)]
pub struct PushSweepArgs {
    /// Inclinations ϑ, rad (`30deg`, `pi/6` accepted), as A:B:STEP, one value or a comma
    /// list, each in (arctan(2r/h), π/2).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: String,
    /// Pushes P/mg tried at each ϑ, moving away from 0 (increasing for pushes along
    /// +e′2, decreasing for −e′2), as A:B:STEP or a list (the first that makes a rim slip
    /// is the onset).
    #[arg(long, default_value = "0:0.5:0.01", allow_hyphen_values = true)]
    pub push: String,
    /// Floor friction coefficient μ_s (Figures 3.3–3.8: 0.2, as `--mu` of `cylinder
    /// statics` and `support`).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_floor: f64,
    /// Time step Δt, s.
    #[arg(long, default_value_t = 2e-3, value_parser = parse_finite, allow_hyphen_values = true)]
    pub dt: f64,
    /// Number of steps per run (fewer than the 2000 of `pair`: the push reaches its value
    /// after 0.05 s and a rim slips, or not, soon after).
    #[arg(long, default_value_t = 100, allow_hyphen_values = true)]
    pub steps: usize,
    /// Run even when the runs are estimated to take longer than ten minutes, and let
    /// each run go on when it is projected past ten minutes (its watchdog).
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// Arguments of `rollstack cylinder sweep pair`.
#[derive(Debug, Args)]
pub struct PairSweepArgs {
    /// Inclinations ϑ, rad (`30deg`, `pi/6` accepted), as A:B:STEP (`10deg:40deg:10deg`),
    /// one value or a comma list, each in (arctan(2r/h), π/2) (Figure 3.14:
    /// (arctan(2r/h), π/4)).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: String,
    /// Time step Δt, s.
    #[arg(long, default_value_t = 2e-3, value_parser = parse_finite, allow_hyphen_values = true)]
    pub dt: f64,
    /// Number of steps per run.
    #[arg(long, default_value_t = 2000, allow_hyphen_values = true)]
    pub steps: usize,
    /// Run even when the runs are estimated to take longer than ten minutes, and let
    /// each run go on when it is projected past ten minutes (its watchdog).
    #[arg(long)]
    pub force: bool,
    /// Prescribed spin φ̇10 of cylinder I, rad/s (the thesis: −6π, written `-6pi`).
    #[arg(long, default_value_t = -6.0 * std::f64::consts::PI, value_parser = parse_value, allow_hyphen_values = true)]
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
        CylinderSweepCommand::Push(a) => sweep_push(a),
    }
}

fn sweep_pair(a: &PairSweepArgs) -> Result<()> {
    let all = parse_values(&a.theta).map_err(|e| anyhow::anyhow!("--theta: {e}"))?;
    let settings = |theta| PairSettings {
        dt: a.dt,
        steps: a.steps,
        spin: SpinProfile::constant(a.spin),
        time_bound: super::guard::time_bound(a.force || !a.output.time_guarded()),
        ..PairSettings::thesis(theta)
    };
    super::check_steps(a.dt, a.steps)?;
    for &theta in &all {
        let s = settings(theta);
        super::check_theta(theta, &s.cylinder)?;
        s.system()
            .with_context(|| format!("--theta {}", input::Short(theta)))?;
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
    if let Some(&(_, theta)) = thetas.first() {
        let force = a.force || !a.output.time_guarded();
        super::guard::check_time_bound(
            &settings(theta),
            thetas.len(),
            1,
            force,
            super::guard::FEWER_STEPS,
        )?;
    }
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

fn sweep_push(a: &PushSweepArgs) -> Result<()> {
    let all = parse_values(&a.theta).map_err(|e| anyhow::anyhow!("--theta: {e}"))?;
    let pushes = parse_values(&a.push).map_err(|e| anyhow::anyhow!("--push: {e}"))?;
    let away = |w: &[f64]| (w[0] >= 0.0 && w[1] > w[0]) || (w[0] <= 0.0 && w[1] < w[0]);
    anyhow::ensure!(
        pushes.windows(2).all(away),
        "--push must move away from 0: increasing from 0 or more, or decreasing from 0 or less"
    );
    let settings = |theta| PairSettings {
        dt: a.dt,
        steps: a.steps,
        mu_floor: a.mu_floor,
        time_bound: super::guard::time_bound(a.force || !a.output.time_guarded()),
        ..PairSettings::thesis(theta)
    };
    super::check_steps(a.dt, a.steps)?;
    // Checked here so that the error names the flag, not the library's μ_s.
    input::non_negative("--mu-floor", a.mu_floor)?;
    for &theta in &all {
        let s = settings(theta);
        super::check_theta(theta, &s.cylinder)?;
        s.system()
            .with_context(|| format!("--theta {}", input::Short(theta)))?;
    }
    let inputs = serde_json::json!({
        "theta": a.theta, "push": a.push, "mu_floor": a.mu_floor, "dt": a.dt, "steps": a.steps,
    });
    let sweep = SweepRun::of_command(
        "cylinder sweep push".into(),
        "push",
        &a.output,
        inputs,
        all.len(),
    )?;
    let thetas = sweep.run.select(&all);
    if let Some(&(_, theta)) = thetas.first() {
        // Every push of a row may be run, one after another: a bound.
        let force = a.force || !a.output.time_guarded();
        super::guard::check_time_bound(
            &settings(theta),
            thetas.len(),
            pushes.len(),
            force,
            super::guard::FEWER_STEPS,
        )?;
    }
    let rows = sweep.rows(&thetas, |&theta| {
        push_row(&settings(theta), &pushes).unwrap_or_else(|e| PushRow {
            error: Some(e.to_string()),
            ..PushRow::failed(theta, a.mu_floor)
        })
    })?;
    if let Some(dir) = &a.output.out {
        ensure_dir(dir)?;
        let csv = rows.iter().map(PushRow::csv_cells);
        write_csv(&dir.join("sweep_push.csv"), &PushRow::CSV_HEADER, csv)?;
        let c = PairSettings::thesis(0.5).cylinder;
        plot_push_sweep(
            &dir.join("sweep_push.png"),
            &rows,
            c.radius() / c.height(),
            a.mu_floor,
            pushes
                .last()
                .map_or(1.0, |p| if *p < 0.0 { -1.0 } else { 1.0 }),
        )?;
        plot_minimum_force(&dir.join("sweep_push_minimum.png"), &rows, &c, a.mu_floor)?;
    }
    let agreeing = rows.iter().filter(|r| r.agrees).count();
    let minimum = rows
        .iter()
        .filter(|r| r.minimum_force.as_ref().is_some_and(|m| m.agrees))
        .count();
    let extra = serde_json::Map::from_iter([
        ("agreeing_rows".into(), agreeing.into()),
        ("minimum_force_agreeing_rows".into(), minimum.into()),
    ]);
    sweep.finish(
        &["sweep_push.csv", "sweep_push.png", "sweep_push_minimum.png"],
        extra,
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        ToString::to_string,
    )
}
