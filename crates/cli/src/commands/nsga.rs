//! `rollstack nsga ball|work-precision`: the nonsmooth generalized-α solver core on its
//! benchmark systems (Capobianco et al. 2021; thesis §4.2). The numbers, their text and
//! the cells of the CSV files come from [`nsga::studies`]; this module reads the flags
//! and writes the files (docs/cli.md).

use crate::commands::blocks::TIME_BOUND_S;
use crate::output::{ensure_dir, print_json, require_finite, write_csv, write_run_json};
use anyhow::{bail, Result};
use clap::{Args, Subcommand, ValueEnum};
use figures::nsga::{plot_ball, plot_work_precision};
use nsga::studies::ball::{ball_report, BallRun, BallSample, Scheme, MAX_BALL_STEPS};
use nsga::studies::work_precision::{
    work_precision, work_precision_point, WorkPrecisionRow, WorkPrecisionSystem,
    EVENTS_REFERENCE_FACTOR,
};
use nsga::systems::ball::BallCase;
use nsga::Prox;
use std::path::{Path, PathBuf};

/// Arguments of `rollstack nsga`.
#[derive(Debug, Args)]
pub struct NsgaArgs {
    /// Which computation.
    #[command(subcommand)]
    pub command: NsgaCommand,
}

/// The subcommands of `rollstack nsga`.
#[derive(Debug, Subcommand)]
pub enum NsgaCommand {
    /// The rotating bouncing ball of the paper's first example (cases 1–4).
    Ball(BallArgs),
    /// Error against a closed form vs. wall time, NSGA (several ρ∞) and Moreau–Jean.
    WorkPrecision(WorkPrecisionArgs),
}

/// Time-stepping scheme on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SchemeArg {
    /// Nonsmooth generalized-α.
    Nsga,
    /// Moreau–Jean midpoint.
    Moreau,
}

impl From<SystemArg> for WorkPrecisionSystem {
    fn from(s: SystemArg) -> Self {
        match s {
            SystemArg::Ball => Self::Ball,
            SystemArg::Oscillator => Self::Oscillator,
            SystemArg::Incline => Self::Incline,
        }
    }
}

impl From<SchemeArg> for Scheme {
    fn from(s: SchemeArg) -> Self {
        match s {
            SchemeArg::Nsga => Scheme::Nsga,
            SchemeArg::Moreau => Scheme::Moreau,
        }
    }
}

/// Arguments of `rollstack nsga ball`.
#[derive(Debug, Args)]
pub struct BallArgs {
    /// Case 1 (e_N = 0.5, ω0 = 0), 2 (e_N = 0, ω0 = 50 rad/s), 3 (e_N = 0, ω0 = 10 rad/s)
    /// or 4 (e_N = 0.5, ω0 = 50 rad/s, x0 = −0.5 m, ẋ0 = 1 m/s).
    #[arg(long, allow_hyphen_values = true)]
    pub case: u8,
    /// Time step Δt in s.
    #[arg(long, value_parser = input::text::parse_finite, default_value_t = 2e-3, allow_hyphen_values = true)]
    pub dt: f64,
    /// Scheme.
    #[arg(long, value_enum, default_value_t = SchemeArg::Nsga)]
    pub scheme: SchemeArg,
    /// Spectral radius at infinity ρ∞ in [0, 1] (NSGA only).
    #[arg(long, value_parser = input::text::parse_finite, default_value_t = 0.5, allow_hyphen_values = true)]
    pub rho_inf: f64,
    /// Constant prox parameter r in kg (the thesis uses 0.3); default: scaled per
    /// constraint, r = 1/(wᵀM⁻¹w).
    // `--prox-r`, its old name, is a hidden alias (docs/cli.md "One name per concept").
    #[arg(long, alias = "prox-r", value_parser = input::text::parse_finite, allow_hyphen_values = true)]
    pub prox_constant: Option<f64>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write the trajectory (CSV), a plot (PNG) and run.json into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `rollstack nsga work-precision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    /// The benchmark: ball (case 2, error of x(1.5 s) in m), oscillator (ω = 2π rad/s,
    /// phase-plane error √(Δx² + (Δẋ/ω)²) at 1 s in m) or incline (turning at 0.5 rad/s, μ = 0.3, error of x(1.5 s) in m).
    #[arg(long, value_enum)]
    pub system: SystemArg,
    /// Directory for work_precision.csv, work_precision.png and run.json (without it,
    /// nothing is written).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Time steps Δt in s (comma-separated, each in (0, 0.1]); the same default for
    /// every system.
    #[arg(
        long,
        default_value = "0.008,0.004,0.002,0.001,0.0005,0.00025",
        allow_hyphen_values = true
    )]
    pub dts: String,
    /// Values of ρ∞ for NSGA (comma-separated).
    #[arg(long, default_value = "0,0.5,0.8,1", allow_hyphen_values = true)]
    pub rho_inf: String,
    /// Repetitions per point (1 to 1000); the fastest wall time is kept.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=1000), allow_hyphen_values = true)]
    pub repeat: u16,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Run even when the study is estimated to take longer than ten minutes.
    #[arg(long)]
    pub force: bool,
}

/// Work-precision benchmark systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SystemArg {
    /// Bouncing ball, case 2.
    Ball,
    /// Linear oscillator.
    Oscillator,
    /// Block on a turning incline.
    Incline,
}

/// Runs `rollstack nsga`.
///
/// # Errors
/// Bad input, a solver failure or an unwritable output directory.
pub fn run(args: &NsgaArgs) -> Result<()> {
    match &args.command {
        NsgaCommand::Ball(a) => ball(a),
        NsgaCommand::WorkPrecision(a) => work_precision_command(a),
    }
}

fn ball(a: &BallArgs) -> Result<()> {
    let dt = require_finite("--dt", a.dt)?;
    if dt <= 0.0 || dt > 0.1 {
        bail!("--dt must be in (0, 0.1] s, got {}", input::Short(dt));
    }
    if !(0.0..=1.0).contains(&a.rho_inf) {
        bail!(
            "--rho-inf must be in [0, 1], got {}",
            input::Short(a.rho_inf)
        );
    }
    let prox = match a.prox_constant {
        Some(r) if !(r.is_finite() && r > 0.0) => {
            bail!("--prox-constant must be positive, got {}", input::Short(r))
        }
        Some(r) => Prox::Constant(r),
        None => Prox::Scaled(1.0),
    };
    check_ball_case(a.case, dt)?;
    let (out, r) =
        ball_report(a.case, a.scheme.into(), dt, a.rho_inf, prox).map_err(|e| match e {
            nsga::StepError::InvalidInput(m) => anyhow::anyhow!(m),
            e => e.into(),
        })?;
    if let Some(dir) = &a.out {
        write_ball_files(dir, &r, a)?;
        write_run_json(
            dir,
            "nsga ball",
            &serde_json::json!({"case": a.case, "dt": dt, "scheme": out.scheme.name(),
            "rho_inf": a.rho_inf, "prox_constant": a.prox_constant}),
            &serde_json::json!({"wall_time_s": r.wall_time_s}),
        )?;
    }
    if a.json {
        print_json(&out)?;
    } else {
        println!("{out}");
    }
    Ok(())
}

/// Refuses a `--case` that does not exist and a `--dt` too small for its time span,
/// naming the flags (the library names its case and dt).
///
/// # Errors
/// A case other than 1–4; more than [`MAX_BALL_STEPS`] steps.
fn check_ball_case(case: u8, dt: f64) -> Result<()> {
    let c = BallCase::new(case)
        .map_err(|_| anyhow::anyhow!("--case {case} does not exist: give 1, 2, 3 or 4"))?;
    #[allow(clippy::cast_precision_loss)]
    let most = MAX_BALL_STEPS as f64;
    let steps = c.t_end / dt;
    anyhow::ensure!(
        steps <= most,
        "--dt {} s needs {steps:.1e} steps to reach t = {} s, more than the {most:.0e} \
         allowed: give --dt ≥ {:.1e} s",
        input::Short(dt),
        c.t_end,
        c.t_end / most
    );
    Ok(())
}

fn write_ball_files(dir: &Path, r: &BallRun, a: &BallArgs) -> Result<()> {
    ensure_dir(dir)?;
    write_csv(
        &dir.join("trajectory.csv"),
        &BallSample::CSV_HEADER,
        r.samples.iter().map(BallSample::csv_cells),
    )?;
    let radius = BallCase::new(a.case).map_or(0.1, |c| c.ball.radius);
    plot_ball(
        &dir.join("trajectory.png"),
        &format!("Bouncing ball, case {}", a.case),
        r,
        radius,
    )?;
    Ok(())
}

fn work_precision_command(a: &WorkPrecisionArgs) -> Result<()> {
    let system: WorkPrecisionSystem = a.system.into();
    let dts = input::text::parse_number_list(&a.dts).map_err(|e| anyhow::anyhow!("--dts: {e}"))?;
    if dts.iter().any(|&d| !(d > 0.0 && d <= 0.1)) {
        bail!("every --dts value must be in (0, 0.1] s");
    }
    let rhos = input::text::parse_number_list(&a.rho_inf)
        .map_err(|e| anyhow::anyhow!("--rho-inf: {e}"))?;
    if rhos.iter().any(|r| !(0.0..=1.0).contains(r)) {
        bail!("every --rho-inf value must be in [0, 1]");
    }
    let repeat = usize::from(a.repeat);
    if !a.force {
        check_time_bound(system, &dts, rhos.len() + 1, repeat)?;
    }
    let busy = crate::progress::busy("nsga work-precision: solving", !a.json);
    let study = work_precision(system, &dts, &rhos, repeat)?;
    let csv = a.out.as_ref().map(|dir| dir.join("work_precision.csv"));
    if let Some(dir) = &a.out {
        busy.set_message("nsga work-precision: writing the files");
        ensure_dir(dir)?;
        write_csv(
            &dir.join("work_precision.csv"),
            &WorkPrecisionRow::CSV_HEADER,
            study.rows.iter().map(WorkPrecisionRow::csv_cells),
        )?;
        plot_work_precision(
            &dir.join("work_precision.png"),
            &format!("Work-precision: {}", system.name()),
            &study,
        )?;
        write_run_json(
            dir,
            "nsga work-precision",
            &serde_json::json!({"system": system.name(), "dts": dts, "rho_inf": rhos, "repeat": repeat}),
            &serde_json::json!({"total_wall_time_s": study.rows.iter().map(|r| r.wall_time_s).sum::<f64>()}),
        )?;
    }
    busy.finish_and_clear();
    if a.json {
        print_json(
            &serde_json::json!({"rows": study.rows, "orders": study.orders,
            "reference_dt": study.reference_dt, "reference_events": study.reference_events,
            "csv": csv}),
        )?;
    } else {
        for r in &study.rows {
            println!("{r}");
        }
        for o in &study.orders {
            println!("{o}");
        }
        println!(
            "(orders fitted where the runs follow the {} contact events of a run with Δt = {:.2e} s)",
            study.reference_events, study.reference_dt
        );
        if let Some(csv) = &csv {
            println!("wrote {}", csv.display());
        }
    }
    Ok(())
}

/// The smallest Δt of the run [`check_time_bound`] times, s: at most 1500 steps.
const SMALLEST_TIMED_DT: f64 = 1e-3;

/// Refuses a work-precision study estimated to take more than [`TIME_BOUND_S`]: one run
/// at the largest Δt (or at [`SMALLEST_TIMED_DT`], whichever is larger, so that the
/// timed run is short) is timed, and a run at Δt costs its time × Δt_timed/Δt (steps go
/// as 1/Δt), for each of `schemes` (the ρ∞ values and Moreau–Jean) `repeat` times, plus
/// the reference run of the contact events at the smallest Δt over
/// [`EVENTS_REFERENCE_FACTOR`].
///
/// # Errors
/// When the estimate is over the bound, or the timed run fails.
fn check_time_bound(
    system: WorkPrecisionSystem,
    dts: &[f64],
    schemes: usize,
    repeat: usize,
) -> Result<()> {
    let Some(largest) = dts.iter().copied().reduce(f64::max) else {
        return Ok(());
    };
    let timed = largest.max(SMALLEST_TIMED_DT);
    let (_, seconds) = work_precision_point(system, Scheme::Nsga, 0.5, timed)?;
    #[allow(clippy::cast_precision_loss)]
    let runs = (schemes * repeat) as f64;
    let smallest = dts.iter().copied().fold(largest, f64::min);
    let reference = seconds * timed * EVENTS_REFERENCE_FACTOR / smallest;
    let total = reference + runs * dts.iter().map(|dt| seconds * timed / dt).sum::<f64>();
    anyhow::ensure!(
        total <= TIME_BOUND_S,
        "{} run(s) would take about {total:.1e} s (one at Δt = {timed} s took {seconds:.1e} \
         s, and a run's steps go as 1/Δt), more than {TIME_BOUND_S} s: take larger --dts, \
         fewer --rho-inf values or a smaller --repeat, or pass --force",
        schemes * repeat * dts.len()
    );
    Ok(())
}
