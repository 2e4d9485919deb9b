//! `rollstack blocks converge`: a scene at Δt/2^k and under tiny perturbations, with a
//! verdict on its failure time and on its outcome
//! ([`blockstack::studies::convergence`]): the runs in parallel, a table on stdout or
//! JSON, and with `--out` a CSV per run, `runs.csv`, `separation.csv` and the plot of
//! the failure time against Δt.

use super::check_time_bound;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json_with};
use crate::sweep::par_map_ordered;
use anyhow::{Context, Result};
use blockstack::record::{trajectory_header_of, write_trajectory_row, TrajectoryError};
use blockstack::simulation::{RunOptions, StepRecord};
use blockstack::studies::convergence::{
    separation_rows, ConvergenceReport, ConvergenceRun, Job, Reference, Settings, Study,
    DEFAULT_ENSEMBLE, DEFAULT_LEVELS,
};
use blockstack::Prox;
use clap::Args;
use figures::convergence::plot_convergence;
use input::text::parse_finite;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Arguments of `rollstack blocks converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// The scene: a TOML file (keys: docs/scenes.md) or the name of a built-in scene, as
    /// in `blocks run`.
    pub scene: PathBuf,
    /// K: the scene is run at Δt/2^k for k = 0…K (1 to 8; each level doubles the steps).
    #[arg(long, default_value_t = DEFAULT_LEVELS as u8, value_name = "K",
          value_parser = clap::value_parser!(u8).range(1..=8), allow_hyphen_values = true)]
    pub levels: u8,
    /// Perturbed runs per magnitude (1e-10, 1e-7, 1e-4) at the finest Δt, alternately of
    /// the initial x and of the base's frequency (0 to 20; 0: no ensemble).
    #[arg(long, default_value_t = DEFAULT_ENSEMBLE as u8, value_name = "N",
          value_parser = clap::value_parser!(u8).range(0..=20), allow_hyphen_values = true)]
    pub ensemble: u8,
    /// End time of every run (model time units; overrides the scene's solver.t_end).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Run even when the runs are estimated to take longer than ten minutes, and let
    /// each run go on when it is projected past ten minutes as it runs (its watchdog).
    #[arg(long)]
    pub force: bool,
    /// Directory for runs.csv, one trajectory CSV per run (level{k}.csv,
    /// member{k}.csv), separation.csv, converge.png and run.json (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout (otherwise the table and the verdicts).
    #[arg(long)]
    pub json: bool,
}

/// `--convergence K` and `--ensemble N` of `blocks run`, `blocks shake` and the sweeps:
/// the study of `blocks converge` on each run.
#[derive(Debug, Clone, Args)]
pub struct ConvergenceArgs {
    /// Also run the scene (each row of a sweep) at Δt/2^k for k = 0…K (1 to 8) and judge
    /// its failure time and outcome as `blocks converge` does: converged (to what
    /// tolerance, or to a Richardson limit), chaotic, non-unique or not converged.
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u8).range(1..=8),
          allow_hyphen_values = true)]
    pub convergence: Option<u8>,
    /// With --convergence: perturbed runs per magnitude (1e-10, 1e-7, 1e-4) at the finest
    /// Δt (0 to 20). Default 2 for `blocks run` and `shake`, 0 for the sweeps: a member
    /// costs as much as the finest level, and without members a verdict is never
    /// chaotic.
    #[arg(long, value_name = "N", requires = "convergence",
          value_parser = clap::value_parser!(u8).range(0..=20), allow_hyphen_values = true)]
    pub ensemble: Option<u8>,
}

impl ConvergenceArgs {
    /// The study's settings, `default_ensemble` members per magnitude unless
    /// `--ensemble` is given; None without `--convergence`.
    #[must_use]
    pub fn settings(&self, default_ensemble: usize) -> Option<Settings> {
        self.convergence.map(|k| Settings {
            levels: usize::from(k),
            ensemble: self.ensemble.map_or(default_ensemble, usize::from),
        })
    }

    /// Adds `convergence` and `ensemble` to a sweep's identity `inputs` when
    /// `--convergence` is given, and nothing otherwise: a sweep without it keeps the
    /// identity, and so the row log, of a sweep from before the flag.
    pub fn identify(&self, inputs: &mut serde_json::Value, default_ensemble: usize) {
        if let Some(s) = self.settings(default_ensemble) {
            inputs["convergence"] = s.levels.into();
            inputs["ensemble"] = s.ensemble.into();
        }
    }
}

/// The study of `scene` with `options` and `settings` for `blocks run` and `shake`: refused
/// when estimated past ten minutes unless `force`, its runs in parallel.
///
/// # Errors
/// As [`Study::new`] (settings named `--convergence`, `--ensemble`), a study over the
/// time bound, or a run that could not start.
pub fn verdicts(
    scene: &blockstack::Scene,
    options: &RunOptions,
    settings: Settings,
    force: bool,
) -> Result<ConvergenceReport> {
    let study = Study::new(scene, options, settings, ["--convergence", "--ensemble"])?;
    check_time_bound(
        &study.costs(),
        Some(study.probe()),
        force,
        "take a smaller --convergence or --ensemble, shorten the run",
    )?;
    let levels = run_all(&study, study.levels(), None, None, "convergence levels")?;
    let reference = study.reference(&levels).cloned();
    let members = run_all(
        &study,
        study.members(),
        reference.as_ref(),
        None,
        "ensemble",
    )?;
    Ok(study.report(levels, members))
}

/// Runs `rollstack blocks converge`.
///
/// # Errors
/// A bad scene or flag (before any run), or an unwritable output directory.
pub fn run(a: &ConvergeArgs) -> Result<()> {
    let loaded = super::scenes::load_scene(&a.scene)?;
    if let Some(t) = a.t_end {
        input::positive("--t-end", t)?;
    }
    let options = RunOptions {
        t_end: a.t_end,
        time_bound: input::watchdog::time_bound(a.force),
        ..RunOptions::default()
    };
    let settings = Settings {
        levels: usize::from(a.levels),
        ensemble: usize::from(a.ensemble),
    };
    let study = Study::new(
        &loaded.scene,
        &options,
        settings,
        ["--levels", "--ensemble"],
    )?;
    check_time_bound(
        &study.costs(),
        Some(study.probe()),
        a.force,
        "take fewer --levels or a smaller --ensemble, shorten --t-end",
    )?;
    super::simulate::print_warnings(&loaded.scene);
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
    }
    let dir = a.out.as_deref();
    let levels = run_all(&study, study.levels(), None, dir, "levels")?;
    let reference = study.reference(&levels).cloned();
    let members = run_all(&study, study.members(), reference.as_ref(), dir, "ensemble")?;
    let report = study.report(levels, members);
    for r in report.runs.iter().filter(|r| r.error.is_some()) {
        eprintln!(
            "warning: {} stopped at t = {:.4}: {}",
            r.label,
            r.t_final,
            r.error.as_deref().unwrap_or_default()
        );
    }
    let mut files = Vec::new();
    let mut notes = Vec::new();
    if let Some(dir) = dir {
        let prox = loaded.scene.solver.prox;
        write_outputs(dir, &report, a, prox, &mut files, &mut notes)?;
    }
    if a.json {
        let mut value = serde_json::to_value(&report)?;
        value["files"] = serde_json::to_value(&files)?;
        value["notes"] = serde_json::to_value(&notes)?;
        return print_json(&value);
    }
    println!("{report}");
    for n in &notes {
        println!("note: {n}");
    }
    if let Some(dir) = dir {
        println!("wrote {} files into {}", files.len(), dir.display());
    }
    Ok(())
}

/// Runs `jobs` in parallel with a progress bar, each trajectory streamed into
/// `dir/<label>.csv` when `dir` is given.
fn run_all(
    study: &Study,
    jobs: &[Job],
    reference: Option<&Reference>,
    dir: Option<&Path>,
    message: &str,
) -> Result<Vec<ConvergenceRun>> {
    par_map_ordered(jobs, message, |job| {
        let path = dir.map(|d| d.join(format!("{}.csv", job.label())));
        let mut csv = path
            .as_deref()
            .map(|p| Trajectory::create(p, &job.scene))
            .transpose()?;
        let run = study.run(job, reference, |r| {
            if let Some(csv) = &mut csv {
                csv.write(r);
            }
        })?;
        if let (Some(csv), Some(path)) = (csv, &path) {
            csv.finish(path)?;
        }
        Ok(run)
    })
    .into_iter()
    .collect()
}

/// A run's trajectory CSV (the columns of `blocks run`'s `trajectory.csv`), written as
/// it runs; the first failure to write stops the writing and is reported at the end.
struct Trajectory {
    out: BufWriter<File>,
    error: Option<TrajectoryError>,
}

impl Trajectory {
    fn create(path: &Path, scene: &blockstack::Scene) -> Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot write {}", path.display()))?;
        let mut out = BufWriter::new(file);
        writeln!(out, "{}", trajectory_header_of(scene).join(","))
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(Self { out, error: None })
    }

    fn write(&mut self, record: &StepRecord) {
        if self.error.is_none() {
            self.error = write_trajectory_row(&mut self.out, record).err();
        }
    }

    fn finish(mut self, path: &Path) -> Result<()> {
        let flushed = self.out.flush();
        match (self.error, flushed) {
            // A non-finite state ends the file at the last finite row, as in `blocks run`.
            (None | Some(TrajectoryError::NonFinite(_)), Ok(())) => Ok(()),
            (Some(TrajectoryError::Io(e)), _) | (_, Err(e)) => {
                Err(anyhow::Error::new(e).context(format!("cannot write {}", path.display())))
            }
        }
    }
}

/// Writes runs.csv, separation.csv, converge.png (its title naming `prox`, the scene's
/// prox choice) and run.json into `dir` (the trajectories are written already), adding
/// their names to `files` after the trajectories'.
fn write_outputs(
    dir: &Path,
    report: &ConvergenceReport,
    a: &ConvergeArgs,
    prox: Prox,
    files: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Result<()> {
    files.extend(report.runs.iter().map(|r| format!("{}.csv", r.label)));
    let n = report
        .runs
        .first()
        .map_or(0, |r| r.observed.final_poses.len());
    let header = ConvergenceRun::csv_header(n);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(
        &dir.join("runs.csv"),
        &header,
        report.runs.iter().map(ConvergenceRun::csv_cells),
    )?;
    files.push("runs.csv".to_owned());
    let members: Vec<ConvergenceRun> = report.runs.iter().skip(report.dts.len()).cloned().collect();
    if !members.is_empty() {
        let (header, rows) = separation_rows(&members);
        let header: Vec<&str> = header.iter().map(String::as_str).collect();
        write_csv(&dir.join("separation.csv"), &header, rows)?;
        files.push("separation.csv".to_owned());
    }
    let scene = a
        .scene
        .file_stem()
        .map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned());
    let drawn = plot_convergence(&dir.join("converge.png"), report, &scene, prox)?;
    files.extend(drawn.files);
    notes.extend(drawn.notes);
    files.push("run.json".to_owned());
    let inputs = serde_json::json!({
        "scene": a.scene.display().to_string(),
        "levels": a.levels,
        "ensemble": a.ensemble,
        "t_end": report.t_end,
        "force": a.force,
    });
    let solver_s: f64 = report.runs.iter().map(|r| r.wall_time_s).sum();
    let extra = serde_json::json!({ "notes": notes });
    write_run_json_with(
        dir,
        "blocks converge",
        &inputs,
        &serde_json::json!({ "solver_s": solver_s }),
        extra.as_object().expect("an object"),
    )
}
