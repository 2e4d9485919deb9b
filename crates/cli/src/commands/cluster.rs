//! `rollstack merge` and `rollstack slurm`: a sweep run as shards on many machines and
//! joined again. The checks, the calibration and the scripts are the `shards` crate's;
//! this module parses, runs the sweep's own code over the merged rows, and prints.

use crate::commands::blocks::fragility::{FragilityArgs, RECORDS_COPY};
use crate::commands::blocks::sweep::{OnlyChecked, SweepCommand, SweepOutputArgs};
use crate::commands::blocks::sweep_scene::SCENE_COPY;
use crate::commands::blocks::{BlocksArgs, BlocksCommand, SolverArgs};
use crate::commands::cylinder::sweep::CylinderSweepCommand;
use crate::commands::cylinder::{CylinderArgs, CylinderCommand};
use crate::output::write_atomic;
use crate::{Cli, Command};
use anyhow::{Context, Result};
use clap::{Args, Parser};
use shards::slurm::{Job, Request};
use shards::{RowLog, ShardChoice};
use std::path::PathBuf;

/// Arguments of `rollstack merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The output directories of the shards, in any order.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Directory for the joined sweep: the files a single run of the sweep writes.
    #[arg(long)]
    pub out: PathBuf,
    /// Also print the rows as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rollstack slurm`.
#[derive(Debug, Args)]
pub struct SlurmArgs {
    /// Tasks of the job array: the sweep's shards.
    #[arg(long, allow_hyphen_values = true)]
    pub tasks: usize,
    /// Cores per task; the sweep runs its rows on that many threads.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub cpus_per_task: usize,
    /// Time limit of each task, minutes.
    #[arg(long, allow_hyphen_values = true)]
    pub time: Option<u64>,
    /// Memory of each task and of the merge job, MiB.
    #[arg(long, allow_hyphen_values = true)]
    pub mem: Option<u64>,
    /// Slurm partition of the jobs.
    #[arg(long)]
    pub partition: Option<String>,
    /// The sweep, as it would be run on one machine, with its `--out`.
    #[arg(required = true, trailing_var_arg = true, allow_hyphen_values = true)]
    pub sweep: Vec<String>,
}

/// A sweep command line (without the program name), parsed, and the sweep's name.
fn parse_sweep(argv: &[String]) -> Result<(Cli, &'static str)> {
    let line = argv.join(" ");
    let words = ["rollstack"]
        .into_iter()
        .chain(argv.iter().map(String::as_str));
    let mut cli = Cli::try_parse_from(words)
        .map_err(|e| anyhow::anyhow!("`{line}` is not a sweep command line: {}", e.kind()))?;
    let name = sweep_output(&mut cli.command).map(|(name, _)| name);
    let name = name.with_context(|| format!("`{line}` is not a sweep"))?;
    Ok((cli, name))
}

/// The sweep of blocks a parsed command line runs, or `None` for another command.
fn blocks_sweep(command: &mut Command) -> Option<&mut SweepCommand> {
    match command {
        Command::Blocks(BlocksArgs {
            command: BlocksCommand::Sweep(sweep),
        }) => Some(sweep),
        _ => None,
    }
}

/// Whether a parsed command line runs a fragility study (a sweep of its own kind).
fn is_fragility(command: &Command) -> bool {
    matches!(
        command,
        Command::Blocks(BlocksArgs {
            command: BlocksCommand::Fragility(_),
        })
    )
}

/// The fragility study a parsed command line runs, or `None` for another command.
fn fragility(command: &mut Command) -> Option<&mut FragilityArgs> {
    match command {
        Command::Blocks(BlocksArgs {
            command: BlocksCommand::Fragility(a),
        }) => Some(a),
        _ => None,
    }
}

/// The scene file a parsed sweep reads, or `None` for a sweep that reads no file.
fn scene_of(command: &mut Command) -> Option<&mut PathBuf> {
    if is_fragility(command) {
        return fragility(command).map(|a| &mut a.scene);
    }
    match blocks_sweep(command)? {
        SweepCommand::Scene(a) => Some(&mut a.scene),
        _ => None,
    }
}

/// The solver options of a parsed sweep of blocks, or `None` for another command.
fn solver_of(command: &mut Command) -> Option<&mut SolverArgs> {
    if is_fragility(command) {
        return fragility(command).map(|a| &mut a.solver);
    }
    Some(match blocks_sweep(command)? {
        SweepCommand::Frequency(a) => &mut a.solver,
        SweepCommand::Slide(a) => &mut a.solver,
        SweepCommand::Scene(a) => &mut a.solver,
    })
}

/// The name and output options of a parsed sweep, or `None` for another command.
fn sweep_output(command: &mut Command) -> Option<(&'static str, &mut SweepOutputArgs)> {
    if let Command::Cylinder(CylinderArgs {
        command: CylinderCommand::Sweep(sweep),
    }) = command
    {
        return Some(match sweep {
            CylinderSweepCommand::Pair(a) => ("pair", &mut a.output),
            CylinderSweepCommand::Push(a) => ("push", &mut a.output),
        });
    }
    if is_fragility(command) {
        return fragility(command).map(|a| ("fragility", &mut a.output));
    }
    Some(match blocks_sweep(command)? {
        SweepCommand::Frequency(a) => ("frequency", &mut a.output),
        SweepCommand::Slide(a) => ("slide", &mut a.output),
        SweepCommand::Scene(a) => ("scene", &mut a.output),
    })
}

/// Runs `rollstack merge`: checks the shards, writes their rows as the row log of
/// `--out` and the copies of the files they read (the scene) there, and runs the sweep
/// of their manifests there on those copies, which then computes nothing and writes
/// exactly what one run writes, from any working directory.
///
/// # Errors
/// Shards that do not join ([`shards::merge`]), a version other than this one, an
/// unwritable `--out`, or the sweep's [`shards::RowsFailed`].
pub fn merge(args: &MergeArgs) -> Result<()> {
    let merged = shards::merge(&args.dirs, env!("CARGO_PKG_VERSION"))?;
    let (mut cli, _) = parse_sweep(&merged.argv)?;
    RowLog::write_all(&args.out, &merged.sweep, &merged.rows)?;
    for (name, bytes) in &merged.files {
        let path = args.out.join(name);
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder)
                .with_context(|| format!("cannot create directory {}", folder.display()))?;
        }
        write_atomic(&path, bytes)?;
    }
    if let Some(study) = fragility(&mut cli.command) {
        study.records = args.out.join(RECORDS_COPY);
    }
    if let Some(scene) =
        scene_of(&mut cli.command).filter(|_| merged.files.contains_key(SCENE_COPY))
    {
        *scene = args.out.join(SCENE_COPY);
    }
    let (_, output) = sweep_output(&mut cli.command).context("not a sweep")?;
    output.out = Some(args.out.clone());
    output.shard = ShardChoice::default();
    output.json = args.json;
    output.argv.clone_from(&merged.argv);
    output.complete = true;
    crate::run(cli)
}

/// Checks every value of the sweep `argv` (of all its shards) without running a row or
/// writing a file: with `--time` and `--mem` given, no calibration run checks them. The
/// time bound of one machine is not checked: the tasks' time is `--time`.
///
/// # Errors
/// The sweep's own error for a value it refuses.
fn check_sweep(argv: &[String]) -> Result<()> {
    let (sweep, _) = shards::slurm::split_out(argv).map_err(anyhow::Error::msg)?;
    let (mut cli, _) = parse_sweep(&sweep)?;
    if let Some(solver) = solver_of(&mut cli.command) {
        solver.force = true;
    }
    let (_, output) = sweep_output(&mut cli.command).context("not a sweep")?;
    output.check_only = true;
    match crate::run(cli) {
        Err(e) if !e.is::<OnlyChecked>() => Err(e),
        _ => Ok(()),
    }
}

/// Runs `rollstack slurm`: the requests and every value of the sweep checked, a
/// calibration run of the sweep's last row (unless `--time` and `--mem` are both given),
/// then the batch scripts in `OUT/slurm`.
///
/// # Errors
/// A bad request ([`Request::check`]), a command line that is not a sweep with `--out`,
/// a value the sweep refuses, a failed calibration, or an unwritable directory.
pub fn slurm(args: &SlurmArgs) -> Result<()> {
    let (_, name) = parse_sweep(&args.sweep)?;
    let request = Request {
        name: name.to_owned(),
        tasks: args.tasks,
        cpus_per_task: args.cpus_per_task,
        minutes: args.time,
        mem_mib: args.mem,
        partition: args.partition.clone(),
        sweep: args.sweep.clone(),
        binary: std::env::current_exe().context("cannot find the rollstack binary")?,
        workdir: std::env::current_dir()?,
    };
    request.check()?;
    check_sweep(&args.sweep)?;
    let (job, calibration) = Job::plan(request)?;
    let submit = job.write()?;
    print!("{}", job.summary(calibration.as_ref(), &submit));
    Ok(())
}
