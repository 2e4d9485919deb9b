//! `rollstack blocks sweep frequency|slide`: Figures 4.6 and 4.7, one row per parameter
//! value from `blockstack::studies`, run in parallel and written in input order. Every
//! value is checked before any run: one the model refuses is an error of the command; a
//! run the solver stops is the error of its row. And the
//! plumbing every sweep shares ([`check_before_any_run`], [`SweepRun`]: shard, row log,
//! manifest, outputs and exit status), which
//! `sweep scene` ([`super::sweep_scene`]) uses too.

use super::converge::ConvergenceArgs;
use super::units::{omega_of_hz, UnitArgs};
use super::{run_cost, RunCost, SolverArgs};
use crate::output::{ensure_dir, print_json, write_csv, write_run_json_with};
use crate::sweep::{par_map_ordered, ShardChoice};
use anyhow::{Context, Result};
use blockstack::scenarios::{shaking_column_in, sliding_column_in, Shaking, Sliding};
use blockstack::simulation::{RunOptions, STOPPED_BY_WATCHDOG};
use blockstack::studies::convergence::row::{RowConvergence, SWEEP_ENSEMBLE};
use blockstack::studies::convergence::{Settings, Study};
use blockstack::studies::shaking::{frequency_row_judged, periods_for_horizon, FrequencyRow};
use blockstack::studies::slide::{slide_row_judged, SlideRow};
use blockstack::Scene;
use clap::{Args, Subcommand};
use figures::blocks::{plot_frequency_sweep, plot_slide_sweep, FrequencySweep, SlideSweep};
use input::text::parse_finite;
use input::text::parse_values;
use serde::{de::DeserializeOwned, Serialize};
use shards::{keep_inputs, resume_rows, InputFile, RowsFailed, Run, SweepId};
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
    /// concatenate in input order), or `auto`: the task of a Slurm job array,
    /// SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT. A K/N given here wins over the
    /// job array's variables, which only `auto` reads.
    #[arg(long, default_value = "1/1", allow_hyphen_values = true)]
    pub shard: ShardChoice,
    /// Directory for the CSV, the PNG, run.json, manifest.json and the row log rows.log
    /// (created if missing); the same command with the same `--out` resumes a killed
    /// sweep, computing only the rows the log lacks. Without it, nothing is written.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also print the rows as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// The command line recorded in the manifest (set by `merge`; else this process's).
    #[arg(skip)]
    pub argv: Vec<String>,
    /// Every row must come from the row log (set by `merge`).
    #[arg(skip)]
    pub complete: bool,
    /// Check every value, then stop with [`OnlyChecked`] before any row (set by
    /// `slurm`, which has no calibration run to check them when given `--time` and
    /// `--mem`).
    #[arg(skip)]
    pub check_only: bool,
}

impl SweepOutputArgs {
    /// Whether the time guard applies: not to a merge (its rows are computed already)
    /// nor to a task of a Slurm job array (`--shard auto`: Slurm's `--time` bounds it,
    /// and its rows per task are the user's choice).
    #[must_use]
    pub fn time_guarded(&self) -> bool {
        !self.complete && !matches!(self.shard, ShardChoice::Auto)
    }

    /// `options` whose rows are watched ([`RunOptions::time_bound`]) only where the
    /// sweep is [`Self::time_guarded`].
    #[must_use]
    pub fn watched(&self, options: RunOptions) -> RunOptions {
        RunOptions {
            time_bound: options.time_bound.filter(|_| self.time_guarded()),
            ..options
        }
    }
}

/// Whether `row`'s `error` says the watchdog stopped its run
/// ([`blockstack::RunError::Stopped`]).
fn stopped_by_watchdog(row: &impl Serialize) -> bool {
    serde_json::to_value(row).is_ok_and(|v| {
        v["error"]
            .as_str()
            .is_some_and(|e| e.starts_with(STOPPED_BY_WATCHDOG))
    })
}

/// How a sweep run with [`SweepOutputArgs::check_only`] ends once its values are
/// checked: no row was computed and nothing was written.
#[derive(Debug, thiserror::Error)]
#[error("every value of the sweep was checked; no row was run")]
pub struct OnlyChecked;

/// `inputs` with the solver options that change a sweep's rows, which join its
/// identity (every sweep of blocks: `blocks sweep …`, `blocks fragility`).
#[must_use]
pub fn with_solver_inputs(mut inputs: serde_json::Value, solver: &SolverArgs) -> serde_json::Value {
    inputs["prox_constant"] = serde_json::json!(solver.prox_constant);
    inputs["explore_branches"] = solver.explore_branches.into();
    inputs["last_resort"] = solver.last_resort.into();
    inputs["low_rank_updates"] = solver.low_rank_updates.into();
    inputs
}

/// One sweep being run ([`shards::Run`]: the sweep, the shard of `--shard`, the size),
/// with its output options and the files it reads.
#[derive(Debug)]
pub struct SweepRun<'a> {
    name: &'static str,
    output: &'a SweepOutputArgs,
    /// The sweep and this run's shard of it.
    pub run: Run,
    files: Vec<InputFile>,
    /// Inputs of `run.json` that are not part of the sweep's identity: the paths of
    /// the files, which count by their content.
    named: serde_json::Map<String, serde_json::Value>,
    start: Instant,
}

impl<'a> SweepRun<'a> {
    /// The sweep `blocks sweep {name}` of `total` rows with `inputs` and the solver's.
    ///
    /// # Errors
    /// `--shard auto` outside a job array.
    pub fn new(
        name: &'static str,
        output: &'a SweepOutputArgs,
        solver: &SolverArgs,
        inputs: serde_json::Value,
        total: usize,
    ) -> Result<Self> {
        let inputs = with_solver_inputs(inputs, solver);
        Self::of_command(format!("blocks sweep {name}"), name, output, inputs, total)
    }

    /// The sweep `command` (`cylinder sweep pair`) of `total` rows with `inputs`, for a
    /// sweep of another family that shares this plumbing.
    ///
    /// # Errors
    /// `--shard auto` outside a job array.
    pub fn of_command(
        command: String,
        name: &'static str,
        output: &'a SweepOutputArgs,
        inputs: serde_json::Value,
        total: usize,
    ) -> Result<Self> {
        let version = env!("CARGO_PKG_VERSION");
        let id = SweepId::new(command, inputs, version);
        let shard = output.shard.resolve(|v| std::env::var(v).ok())?;
        let (run, start) = (Run { id, shard, total }, Instant::now());
        Ok(Self {
            name,
            output,
            run,
            files: Vec::new(),
            named: serde_json::Map::new(),
            start,
        })
    }

    /// This sweep reading `file`, which `run.json` names as `given` under `key`: its
    /// content, not its path, joins the sweep's identity, and `--out` keeps a copy
    /// ([`shards::keep_inputs`]), so that rows of an edited file are never resumed
    /// with the old rows, and `merge` reads the copy.
    #[must_use]
    pub fn reading(mut self, key: &str, given: &str, file: InputFile) -> Self {
        self.run.id = self.run.id.with_file(&file.copy, &file.bytes);
        self.named.insert(key.into(), given.into());
        self.files.push(file);
        self
    }

    /// The rows of `points` in order, in parallel, resumed from the row log of `--out`
    /// ([`shards::resume_rows`]) after the files read are kept there.
    ///
    /// # Errors
    /// [`OnlyChecked`] when only checking; a file read that differs from the one the
    /// rows of `--out` were computed from; an unusable row log, or a lacking row in a
    /// merge.
    pub fn rows<P: Sync, R: Serialize + DeserializeOwned + Send>(
        &self,
        points: &[(usize, P)],
        f: impl Fn(&P) -> R + Sync + Send,
    ) -> Result<Vec<R>> {
        anyhow::ensure!(!self.output.check_only, OnlyChecked);
        let (out, id) = (self.output.out.as_deref(), &self.run.id);
        if let Some(dir) = out {
            keep_inputs(dir, id, &self.files)?;
        }
        let rows = resume_rows(out, id, self.output.complete, points, |lacking, record| {
            let reused = points.len() - lacking.len();
            // A merge reads every row back by design; only a resumed run says so.
            if let (Some(dir), false, true) = (out, self.output.complete, reused > 0) {
                crate::progress::resumed(dir, reused, points.len());
            }
            par_map_ordered(lacking, self.name, |(i, p)| {
                let row = f(p);
                // A row the watchdog stopped is not logged: a rerun (with --force)
                // computes it rather than resuming its error.
                if stopped_by_watchdog(&row) {
                    return Ok(row);
                }
                record(*i, &row).map(|()| row)
            })
        })?;
        Ok(rows)
    }

    /// What every sweep does once its rows are written: `run.json` (inputs, version,
    /// timings, `failed_rows` and the keys of `extra`) and `manifest.json` when there is
    /// an output directory, then either `{"rows": [...]}` (with the same keys) on stdout
    /// or one line per row, the notes and the files written.
    ///
    /// # Errors
    /// An unwritable directory; [`RowsFailed`] when a row failed, after everything.
    pub fn finish<R: Serialize>(
        &self,
        files: &[&str],
        mut extra: serde_json::Map<String, serde_json::Value>,
        rows: &[R],
        solver_seconds: f64,
        line: impl Fn(&R) -> String,
    ) -> Result<()> {
        let values: Vec<_> = rows
            .iter()
            .map(serde_json::to_value)
            .collect::<Result<_, _>>()?;
        let mut argv = self.output.argv.clone();
        argv.is_empty()
            .then(|| argv.extend(std::env::args().skip(1)));
        let out = self.output.out.as_deref();
        let csv = files.first().copied().unwrap_or_default();
        let failed = self.run.finish(out, argv, csv, &values)?;
        extra.insert("failed_rows".into(), failed.into());
        let mut inputs = self.named.clone();
        if let Some(identity) = self.run.id.inputs.as_object() {
            inputs.extend(identity.clone());
        }
        inputs.insert("shard".into(), self.run.shard.to_string().into());
        if let Some(dir) = out {
            let timings = serde_json::json!({
                "total_s": self.start.elapsed().as_secs_f64(),
                "solver_s": solver_seconds,
            });
            write_run_json_with(dir, &self.run.id.command, &inputs, &timings, &extra)?;
        }
        if self.output.json {
            let mut object = serde_json::Map::from_iter([("rows".into(), values.into())]);
            object.extend(extra);
            print_json(&object)?;
        } else {
            rows.iter().for_each(|r| println!("{}", line(r)));
            let notes = extra.get("notes").and_then(serde_json::Value::as_array);
            for n in notes.into_iter().flatten().filter_map(|n| n.as_str()) {
                println!("note: {n}");
            }
            if let Some(dir) = &self.output.out {
                let (files, dir) = (files.join(", "), dir.display());
                println!("wrote {files}, run.json and manifest.json into {dir}");
            }
        }
        let rows = rows.len();
        anyhow::ensure!(failed == 0, RowsFailed { failed, rows });
        Ok(())
    }
}

/// The spread of a sweep's value over the motions of each run (Figures 4.6–4.7 as
/// bands).
#[derive(Debug, Clone, Args)]
pub struct SpreadArgs {
    /// Explore up to this many branches of each run (`blocks explore`) and report the
    /// smallest, median and largest value over the motions found, drawn as a band; 1:
    /// the plain run only.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub branches: usize,
    /// Which solutions of a cycling step are a fork's candidates when exploring:
    /// `self-consistent` or `converged` (the thesis's count). The plain run of each row
    /// is the same under either rule.
    #[arg(long, value_enum, default_value = "self-consistent")]
    pub branch_rule: super::explore::RuleArg,
}

impl SpreadArgs {
    /// `options` with this spread.
    fn apply(&self, options: RunOptions) -> Result<RunOptions> {
        anyhow::ensure!(self.branches >= 1, "--branches must be at least 1");
        Ok(RunOptions {
            spread_branches: self.branches,
            branch_rule: self.branch_rule.rule(),
            ..options
        })
    }
}

/// Arguments of `rollstack blocks sweep frequency`.
#[derive(Debug, Args)]
#[command(group = clap::ArgGroup::new("frequency").required(true).args(["omega", "hz"]))]
pub struct FrequencyArgs {
    /// Base angular frequencies ω (rad per time unit), as A:B:STEP, one value or a comma
    /// list of them; each value may be a multiple of π (`2pi:6pi:pi`).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: Option<String>,
    /// Base frequencies f in cycles per time unit (Hz with lengths in metres and
    /// --gravity 9.81), as A:B:STEP, one value or a comma list, instead of --omega:
    /// ω = 2πf.
    #[arg(long, allow_hyphen_values = true)]
    pub hz: Option<String>,
    /// Number of base periods simulated per run (the run stops at the failure). A fast
    /// base then gets less time than a slow one: prefer --t-max.
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub periods: f64,
    /// Horizon in time units, the same at every ω, instead of --periods: each run lasts
    /// t_max unless the column fails first ("no failure by t_max" is its own outcome).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, conflicts_with = "periods")]
    pub t_max: Option<f64>,
    /// Base amplitude A (length units; the thesis's "A = w²" is ambiguous).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Number of free blocks on the base.
    #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
    pub blocks: usize,
    /// Steps per base period N: Δt = 2π/(Nω) (Figure 4.6: 100; ERRATA 21).
    #[arg(long, default_value_t = 100.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub steps_per_period: f64,
    /// Friction coefficient μ at every contact (dimensionless).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub units: UnitArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub spread: SpreadArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub convergence: ConvergenceArgs,
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
    #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
    pub blocks: usize,
    /// Friction coefficient μ at every contact (dimensionless; Figure 4.7: 0.2).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub units: UnitArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub spread: SpreadArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub convergence: ConvergenceArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// What every sweep checks before any run: the scene of each of its `points` (a value
/// the model refuses is the sweep's error, naming it), and, where `output` is
/// [`SweepOutputArgs::time_guarded`], the estimated time of them all
/// ([`SolverArgs::check_cost`], calibrated on the costliest).
///
/// # Errors
/// The first refused point, or a sweep over the time bound.
pub fn check_before_any_run<P>(
    points: &[P],
    solver: &SolverArgs,
    output: &SweepOutputArgs,
    options: &RunOptions,
    scene: impl Fn(&P) -> Result<Scene>,
) -> Result<()> {
    check_judged_before_any_run(points, solver, output, options, None, scene)
}

/// [`check_before_any_run`] for rows that each run the convergence study of `settings`
/// (`--convergence K`) too: its runs count in the estimate.
///
/// # Errors
/// As [`check_before_any_run`], and settings out of range, named.
pub fn check_judged_before_any_run<P>(
    points: &[P],
    solver: &SolverArgs,
    output: &SweepOutputArgs,
    options: &RunOptions,
    settings: Option<Settings>,
    scene: impl Fn(&P) -> Result<Scene>,
) -> Result<()> {
    let mut costs = Vec::with_capacity(points.len());
    let mut costliest: Option<Scene> = None;
    let mut studies = Vec::new();
    for p in points {
        let s = scene(p)?;
        let cost = run_cost(&s, options);
        if let Some(settings) = settings {
            let study = Study::new(&s, options, settings, ["--convergence", "--ensemble"])?;
            studies.extend(study.costs());
        }
        if costs
            .iter()
            .all(|c: &RunCost| c.block_steps() < cost.block_steps())
        {
            costliest = Some(s);
        }
        costs.push(cost);
    }
    costs.extend(studies);
    if !output.time_guarded() {
        return Ok(());
    }
    solver.check_cost(&costs, costliest.as_ref().map(|s| (s, options)))
}

/// Writes a sweep's CSV at `path`: `header` and each row's cells (`cells`: its own and
/// its convergence), with the columns [`RowConvergence`] adds when `settings` asks
/// (`--convergence`); without it the file is the sweep's as before the flag.
///
/// # Errors
/// An unwritable file.
pub fn write_judged_csv<R>(
    path: &std::path::Path,
    mut header: Vec<String>,
    rows: &[R],
    settings: Option<Settings>,
    cells: impl Fn(&R) -> (Vec<String>, Option<&RowConvergence>),
) -> Result<()> {
    let asked = settings.is_some();
    RowConvergence::extend_header(&mut header, asked);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows = rows.iter().map(|r| {
        let (mut own, convergence) = cells(r);
        RowConvergence::extend_cells(&mut own, convergence, asked);
        own
    });
    write_csv(path, &header, rows)
}

/// The angular frequencies ω of `--omega`, or of `--hz` as 2πf, and how to name one of
/// them in an error in the flag and unit the user typed.
fn base_frequencies(args: &FrequencyArgs) -> Result<(Vec<f64>, impl Fn(f64) -> String)> {
    let (flag, text, per_omega) = match (&args.omega, &args.hz) {
        (Some(omega), _) => ("--omega", omega, 1.0),
        (None, Some(hz)) => ("--hz", hz, omega_of_hz(1.0)),
        (None, None) => anyhow::bail!("give --omega or --hz"),
    };
    let values = parse_values(text).map_err(|e| anyhow::anyhow!("{flag}: {e}"))?;
    let omegas = values
        .into_iter()
        .map(|v| Ok(input::positive(flag, v)? * per_omega))
        .collect::<Result<_>>()?;
    Ok((omegas, move |omega: f64| {
        format!("{flag} {}", input::Short(omega / per_omega))
    }))
}

/// Runs `rollstack blocks sweep frequency`.
///
/// # Errors
/// Bad input or an unwritable output directory; [`RowsFailed`] after the files.
pub fn sweep_frequency(args: &FrequencyArgs) -> Result<()> {
    blockstack::scene::check_block_count("--blocks", args.blocks)?;
    anyhow::ensure!(args.periods > 0.0, "--periods must be positive");
    anyhow::ensure!(
        args.t_max.is_none_or(|t| t > 0.0),
        "--t-max must be positive"
    );
    anyhow::ensure!(
        args.steps_per_period > 0.0,
        "--steps-per-period must be positive"
    );
    anyhow::ensure!(args.mu >= 0.0, "--mu must not be negative");
    let options = args
        .output
        .watched(args.spread.apply(args.solver.run_options(None, true)?)?);
    let units = args.units.units()?;
    let (all, typed) = base_frequencies(args)?;
    let mut inputs = serde_json::json!({
        "omega": args.omega, "hz": args.hz, "width": units.width, "height": units.height,
        "gravity": units.gravity, "periods": args.t_max.is_none().then_some(args.periods),
        "t_max": args.t_max, "amplitude": args.amplitude,
        "blocks": args.blocks, "steps_per_period": args.steps_per_period, "mu": args.mu,
        "branches": args.spread.branches,
        "branch_rule": args.spread.branch_rule.rule().name(),
    });
    args.convergence.identify(&mut inputs, SWEEP_ENSEMBLE);
    let settings = args.convergence.settings(SWEEP_ENSEMBLE);
    let sweep = SweepRun::new("frequency", &args.output, &args.solver, inputs, all.len())?;
    let omegas = sweep.run.select(&all);
    let column = |omega| Shaking {
        blocks: args.blocks,
        amplitude: args.amplitude,
        omega,
        periods: args
            .t_max
            .map_or(args.periods, |t| periods_for_horizon(t, omega)),
        steps_per_period: args.steps_per_period,
        mu: args.mu,
        start_with_base: false,
    };
    // Every ω of the sweep, not only this shard's: each shard refuses what the whole
    // sweep would.
    let span = args.t_max.map(|t| ("--t-max", t));
    for &omega in &all {
        super::shake::check_stepping(&column(omega), &typed(omega), span)?;
    }
    check_judged_before_any_run(
        &omegas,
        &args.solver,
        &args.output,
        &options,
        settings,
        |&(_, omega)| shaking_column_in(&column(omega), &units).with_context(|| typed(omega)),
    )?;
    let rows = sweep.rows(&omegas, |&omega| {
        frequency_row_judged(&column(omega), &units, &options, settings)
    })?;
    if let Some(dir) = &args.output.out {
        ensure_dir(dir)?;
        let header = FrequencyRow::CSV_HEADER.map(str::to_owned).to_vec();
        write_judged_csv(
            &dir.join("sweep_frequency.csv"),
            header,
            &rows,
            settings,
            |r| (r.csv_cells(), r.convergence.as_ref()),
        )?;
        // The figure's fixed parameters from the sweep's first column, whose step was
        // checked (a column at ω = 1 may have none: Δt = 2π/N overflows for a tiny N).
        let first = column(all.first().copied().unwrap_or(1.0));
        let numerics = super::figure_numerics(&shaking_column_in(&first, &units)?, &options);
        let plot = FrequencySweep {
            t_max: args.t_max,
            prox: numerics.prox,
            rule: numerics.rule,
            ..FrequencySweep::of(&first)
        };
        plot_frequency_sweep(&dir.join("sweep_frequency.png"), &rows, &plot)?;
    }
    sweep.finish(
        &["sweep_frequency.csv", "sweep_frequency.png"],
        serde_json::Map::new(),
        &rows,
        rows.iter()
            .map(|r| r.wall_time_s + RowConvergence::seconds(r.convergence.as_ref()))
            .sum(),
        ToString::to_string,
    )
}

/// Runs `rollstack blocks sweep slide`.
///
/// # Errors
/// Bad input or an unwritable output directory; [`RowsFailed`] after the files.
pub fn sweep_slide(args: &SlideArgs) -> Result<()> {
    blockstack::scene::check_block_count("--blocks", args.blocks)?;
    anyhow::ensure!(args.mu >= 0.0, "--mu must not be negative");
    let options = args
        .spread
        .apply(args.solver.run_options(Some(args.t_end), false)?)?;
    let options = args.output.watched(options);
    let units = args.units.units()?;
    let all = parse_values(&args.v0).map_err(|e| anyhow::anyhow!("--v0: {e}"))?;
    let mut inputs = serde_json::json!({
        "v0": args.v0, "t_end": args.t_end, "blocks": args.blocks, "mu": args.mu,
        "width": units.width, "height": units.height, "gravity": units.gravity,
        "branches": args.spread.branches,
        "branch_rule": args.spread.branch_rule.rule().name(),
    });
    args.convergence.identify(&mut inputs, SWEEP_ENSEMBLE);
    let settings = args.convergence.settings(SWEEP_ENSEMBLE);
    let sweep = SweepRun::new("slide", &args.output, &args.solver, inputs, all.len())?;
    let speeds = sweep.run.select(&all);
    let column = |v0| Sliding {
        blocks: args.blocks,
        v0,
        t_end: args.t_end,
        mu: args.mu,
    };
    check_judged_before_any_run(
        &speeds,
        &args.solver,
        &args.output,
        &options,
        settings,
        |&(_, v0)| {
            sliding_column_in(&column(v0), &units)
                .with_context(|| format!("--v0 {}", input::Short(v0)))
        },
    )?;
    let rows = sweep.rows(&speeds, |&v0| {
        slide_row_judged(&column(v0), &units, &options, settings)
    })?;
    if let Some(dir) = &args.output.out {
        ensure_dir(dir)?;
        let header = SlideRow::CSV_HEADER.map(str::to_owned).to_vec();
        write_judged_csv(&dir.join("sweep_slide.csv"), header, &rows, settings, |r| {
            (r.csv_cells(), r.convergence.as_ref())
        })?;
        let first = speeds.first().map_or(1.0, |&(_, v0)| v0);
        let plot = SlideSweep {
            blocks: args.blocks,
            t_end: args.t_end,
            mu: args.mu,
            numerics: super::figure_numerics(&sliding_column_in(&column(first), &units)?, &options),
        };
        plot_slide_sweep(&dir.join("sweep_slide.png"), &rows, &plot)?;
    }
    sweep.finish(
        &["sweep_slide.csv", "sweep_slide.png"],
        serde_json::Map::new(),
        &rows,
        rows.iter()
            .map(|r| r.wall_time_s + RowConvergence::seconds(r.convergence.as_ref()))
            .sum(),
        ToString::to_string,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::time_guard::TIME_BOUND_S;
    use serde_json::{json, Value};
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_row_the_watchdog_stopped_is_not_resumed_and_forced_sweeps_are_not_watched() {
        let dir = std::env::temp_dir().join(format!("rollstack-watched-{}", std::process::id()));
        let output = SweepOutputArgs {
            shard: ShardChoice::default(),
            out: Some(dir.clone()),
            json: false,
            argv: vec!["test".into()],
            complete: false,
            check_only: false,
        };
        let sweep = SweepRun::of_command("test".into(), "test", &output, json!({}), 2).unwrap();
        let points = [(0, false), (1, true)];
        let computed = AtomicUsize::new(0);
        let row = |&stopped: &bool| {
            computed.fetch_add(1, Ordering::Relaxed);
            let error = stopped.then(|| format!("{STOPPED_BY_WATCHDOG}: projected"));
            json!({ "error": error })
        };
        let rows: Vec<Value> = sweep.rows(&points, row).unwrap();
        assert!(rows[1]["error"]
            .as_str()
            .unwrap()
            .starts_with(STOPPED_BY_WATCHDOG));
        // Rerun: the finished row is resumed, the stopped one computed again.
        let again: Vec<Value> = sweep.rows(&points, row).unwrap();
        assert_eq!((again, computed.load(Ordering::Relaxed)), (rows, 3));
        std::fs::remove_dir_all(&dir).unwrap();
        // Rows are watched only where the time guard applies.
        let bounded = RunOptions {
            time_bound: Some(TIME_BOUND_S),
            ..RunOptions::default()
        };
        assert_eq!(
            output.watched(bounded.clone()).time_bound,
            Some(TIME_BOUND_S)
        );
        let task = SweepOutputArgs {
            shard: ShardChoice::Auto,
            ..output
        };
        assert_eq!(task.watched(bounded).time_bound, None);
    }
}
