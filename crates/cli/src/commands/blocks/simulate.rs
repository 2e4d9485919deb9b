//! `rollstack blocks run`: one simulation, its JSON report, and its files (trajectory
//! written progressively, branch points, snapshots, animation, top block). `lire`,
//! `shake` run through [`simulate_with_output`] and [`finish_command`] too.

use super::converge::{verdicts, ConvergenceArgs};
use super::{OutputArgs, SolverArgs};
use crate::output::{
    commit_temp, discard_temp, ensure_dir, print_json, temp_sibling, write_csv, write_run_json_with,
};
use crate::progress::RunProgress;
use anyhow::{Context, Result};
use blockstack::record::{RecordPlan, Recorder, Recording, TrajectoryError};
use blockstack::simulation::{self as library, RunOptions, RunReport, RunSummary, RunWarning};
use blockstack::studies::convergence::{ConvergenceReport, DEFAULT_ENSEMBLE};
use blockstack::time_guard::{Clock, Watchdog};
use blockstack::{Defaults, Scene};
use clap::Args;
use figures::blocks::draw_run;
use figures::numerics::Numerics;
use input::text::parse_finite;
use serde::Serialize;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack blocks run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene: a TOML file (keys: docs/scenes.md) or the name of a built-in scene
    /// (`rollstack blocks scenes` lists them); an existing file wins over a name.
    pub scene: PathBuf,
    /// End time (model time units; overrides the scene's solver.t_end).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: OutputArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub convergence: ConvergenceArgs,
}

/// The JSON of `rollstack blocks run`, `lire` and `shake`: the library's report, the
/// files written and the pictures left out.
#[derive(Debug, Serialize)]
pub struct SimulationJson<'a> {
    /// The run's report.
    #[serde(flatten)]
    pub report: &'a RunReport,
    /// Files written into --out (relative names).
    pub files: &'a [String],
    /// Pictures left out and why (a run that did not start has nothing to draw).
    pub notes: &'a [String],
    /// With `--convergence K`: the study of `blocks converge` on the scene.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub convergence: Option<&'a ConvergenceReport>,
}

/// Everything one simulation produced, for the commands.
#[derive(Debug)]
pub struct SimulationOutput {
    /// The JSON report.
    pub report: RunReport,
    /// Files written into the output directory (relative names).
    pub files: Vec<String>,
    /// What the recorder kept: snapshots, animation frames, top block, last state.
    pub recording: Recording,
    /// Pictures left out and why.
    pub notes: Vec<String>,
    /// A failure while writing output (the run itself went on, run.json was written).
    pub write_error: Option<String>,
    /// With `--convergence K`: the study of `blocks converge` on the scene
    /// ([`with_convergence`]).
    pub convergence: Option<ConvergenceReport>,
}

/// What to write besides the JSON.
#[derive(Debug, Clone, Default)]
pub struct OutputPlan {
    /// Output directory, if any.
    pub dir: Option<PathBuf>,
    /// Snapshot times.
    pub snapshots: Vec<f64>,
    /// Largest number of GIF frames (0: none).
    pub max_frames: usize,
    /// A short name of the run for plot titles.
    pub title: String,
    /// The scene-file keys that took their defaults (empty for scenes built in code).
    pub defaults: Defaults,
    /// Draw a progress bar over model time on stderr when it is a terminal (not with
    /// `--json`).
    pub progress: bool,
    /// `--force`: no time guard refuses the run up front (the watchdog's bound is
    /// [`RunOptions::time_bound`]).
    pub force: bool,
}

/// Runs one scene, writing the trajectory progressively and, afterwards, the branch
/// points, snapshots, animation, top-block plots and run.json into `plan.dir`; the
/// library's [`Watchdog`] stops the run when it is projected past
/// [`RunOptions::time_bound`].
///
/// # Errors
/// A bad scene or options, or an output directory that cannot be created or a run.json
/// that cannot be written. A run that cannot start, stops mid-run or is stopped by the
/// watchdog is not an Err: it is in the report's `error`, with run.json and the files up
/// to then; a picture with nothing to draw is left out with a note; another failure to
/// write a file is in `write_error`.
pub fn simulate_with_output(
    scene: &Scene,
    options: &RunOptions,
    plan: &OutputPlan,
    command: &str,
    inputs: &serde_json::Value,
) -> Result<SimulationOutput> {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let watchdog = Watchdog::for_run(options.time_bound, 0.0, t_end);
    simulate_watched(scene, options, plan, command, inputs, watchdog)
}

/// [`simulate_with_output`] watched by `watchdog`.
fn simulate_watched(
    scene: &Scene,
    options: &RunOptions,
    plan: &OutputPlan,
    command: &str,
    inputs: &serde_json::Value,
    watchdog: Watchdog<impl Clock>,
) -> Result<SimulationOutput> {
    let start = Instant::now();
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let csv_path = plan.dir.as_ref().map(|d| d.join("trajectory.csv"));
    let writer = match &csv_path {
        Some(path) => {
            ensure_dir(path.parent().unwrap_or(Path::new(".")))?;
            let tmp = temp_sibling(path);
            let file =
                File::create(&tmp).with_context(|| format!("cannot write {}", tmp.display()))?;
            Some(BufWriter::new(file))
        }
        None => None,
    };
    let record_plan = RecordPlan {
        snapshots: plan.snapshots.clone(),
        max_frames: plan.max_frames,
    };
    let mut recorder = Recorder::new(scene, t_end, &record_plan, writer)?;
    let progress = RunProgress::new(command, t_end, plan.progress);
    let result = library::simulate_watched(scene, options, watchdog, |r| {
        progress.at(r.t);
        recorder.on_step(r);
        ControlFlow::Continue(())
    });
    progress.finish();
    let (recording, writer, write_error) = recorder.finish();
    let io_failed = matches!(write_error, Some(TrajectoryError::Io(_)));
    // Keep what was computed even when the run is refused or stops (ERRATA 25).
    let finished = writer
        .zip(csv_path.as_ref())
        .map(|(w, path)| finish_trajectory(w, path, io_failed));
    let summary = result.context("cannot simulate the scene")?;
    let mut write_error = match (write_error, &csv_path) {
        (Some(TrajectoryError::Io(e)), Some(path)) => {
            Some(format!("cannot write {}: {e}", path.display()))
        }
        (e, _) => e.map(|e| e.to_string()),
    };
    if let Some(Err(e)) = finished {
        write_error.get_or_insert(format!("{e:#}"));
    }
    let t_final = recording.last.as_ref().map_or(0.0, |f| f.t);
    // A run the watchdog stopped says so in its error, naming --force.
    let report = RunReport::new(&summary, scene, options, &plan.defaults, t_final);
    let (mut files, mut notes) = (Vec::new(), Vec::new());
    if let Some(dir) = &plan.dir {
        files.push("trajectory.csv".to_owned());
        let numerics = super::figure_numerics(scene, options);
        match write_run_files(
            dir, scene, plan, &numerics, &summary, &recording, &mut files,
        ) {
            Ok(n) => notes = n,
            Err(e) => {
                write_error.get_or_insert(format!("{e:#}"));
            }
        }
        files.push("run.json".to_owned());
        let extra = serde_json::json!({
            "scene": report.scene,
            "warnings": report.warnings,
            "notes": notes,
            "error": report.summary.error,
        });
        write_run_json_with(
            dir,
            command,
            inputs,
            &serde_json::json!({
                "solver_s": summary.wall_time_s,
                "total_s": start.elapsed().as_secs_f64(),
                "steps": summary.steps,
                "write_error": write_error,
            }),
            extra.as_object().expect("an object"),
        )?;
    }
    Ok(SimulationOutput {
        report,
        files,
        recording,
        notes,
        write_error,
        convergence: None,
    })
}

/// `out` with the study of `convergence` (`--convergence K`, `--ensemble N`) on the scene
/// it ran, when asked.
///
/// # Errors
/// As [`super::converge::verdicts`].
pub fn with_convergence(
    mut out: SimulationOutput,
    convergence: &ConvergenceArgs,
    scene: &Scene,
    options: &RunOptions,
    force: bool,
) -> Result<SimulationOutput> {
    if let Some(settings) = convergence.settings(DEFAULT_ENSEMBLE) {
        out.convergence = Some(verdicts(scene, options, settings, force)?);
    }
    Ok(out)
}

/// Flushes the trajectory written progressively into the temporary sibling of `path`
/// and renames it into place; after a failed write (`failed`: a full disk) or flush,
/// the temporary is removed instead, and an error names `path`.
fn finish_trajectory(mut w: BufWriter<File>, path: &Path, failed: bool) -> Result<()> {
    let flushed = w.flush();
    drop(w);
    if let Err(e) = flushed {
        discard_temp(path);
        return Err(anyhow::Error::new(e).context(format!("cannot write {}", path.display())));
    }
    if failed {
        discard_temp(path);
        return Ok(());
    }
    commit_temp(path)
}

/// Writes branch_points.csv, the snapshots, the animation and the top block's plot into
/// `dir`, adding each file's name to `files`; returns the notes of the pictures left out.
/// The pictures' titles carry `numerics` as their caption.
fn write_run_files(
    dir: &Path,
    scene: &Scene,
    plan: &OutputPlan,
    numerics: &Numerics,
    summary: &RunSummary,
    recording: &Recording,
    files: &mut Vec<String>,
) -> Result<Vec<String>> {
    let rows = summary.branch_points.iter().map(|b| {
        [
            b.t.to_string(),
            b.candidates.to_string(),
            b.distinct.to_string(),
        ]
    });
    write_csv(
        &dir.join("branch_points.csv"),
        &["t", "candidates", "distinct"],
        rows,
    )?;
    files.push("branch_points.csv".to_owned());
    let title = numerics.under(&plan.title);
    let drawn = draw_run(dir, scene, recording, &title, plan.max_frames > 0)?;
    files.extend(drawn.files);
    Ok(drawn.notes)
}

/// Prints the scene's warnings on stderr, one `warning: …` line each.
pub fn print_warnings(scene: &Scene) {
    for w in scene.warnings() {
        eprintln!("warning: {w}");
    }
}

/// Prints the report (JSON or text) and turns a run that stopped early or output that
/// could not be written into a non-zero exit after the output is out.
pub fn finish_command(out: &SimulationOutput, json: bool, dir: Option<&Path>) -> Result<()> {
    let r = &out.report;
    // The scene's own warnings were printed before the run.
    for w in &r.warnings {
        if !matches!(w, RunWarning::Scene(_)) {
            eprintln!("warning: {w}");
        }
    }
    if json {
        print_json(&SimulationJson {
            report: r,
            files: &out.files,
            notes: &out.notes,
            convergence: out.convergence.as_ref(),
        })?;
    } else {
        let text = r.to_string();
        match &out.convergence {
            Some(c) => {
                let lines = format!(
                    "convergence over Δt/2^k, k = 0…{}, {} member(s) per perturbation size (the finest level's failure time):\n{}",
                    c.settings.levels,
                    c.settings.ensemble,
                    c.verdict_lines()
                );
                println!("{}", after_failure_line(&text, &lines));
            }
            None => println!("{text}"),
        }
        for n in &out.notes {
            println!("note: {n}");
        }
        if let Some(dir) = dir {
            println!("wrote {} files into {}", out.files.len(), dir.display());
        }
    }
    if let Some(e) = &r.summary.error {
        let (what, kept) = if out.recording.last.is_none() {
            ("the simulation could not start".to_owned(), "run.json is")
        } else {
            (
                format!(
                    "the simulation stopped at t = {:.6} after {} steps",
                    r.t_final, r.summary.steps
                ),
                "results up to then are",
            )
        };
        let place = dir.map_or_else(String::new, |d| format!(" ({kept} in {})", d.display()));
        anyhow::bail!("{what}: {e}{place}");
    }
    if let Some(e) = &out.write_error {
        anyhow::bail!("{e}");
    }
    Ok(())
}

/// `report` ([`RunReport`]'s text) with `lines` inserted after its failure line
/// (`failure (loss of support) at …`), or at its end should it have none.
fn after_failure_line(report: &str, lines: &str) -> String {
    let mut out: Vec<&str> = report.lines().collect();
    let at = out
        .iter()
        .position(|l| l.starts_with("failure (loss of support)"))
        .map_or(out.len(), |i| i + 1);
    out.insert(at, lines);
    out.join("\n")
}

/// Runs `rollstack blocks run`.
///
/// # Errors
/// A bad scene, bad options, a run that stopped early, or unwritable output.
pub fn run_scene_file(args: &RunArgs) -> Result<()> {
    let loaded = super::scenes::load_scene(&args.scene)?;
    let scene = &loaded.scene;
    let options = args.solver.run_options(args.t_end, false)?;
    args.solver.check_run(scene, &options)?;
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let title = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned());
    let mut plan = args.output.plan(
        vec![0.0, 0.5 * t_end, t_end],
        title.unwrap_or_else(|| "scene".into()),
        args.solver.force,
    );
    plan.defaults = loaded.defaults.clone();
    let inputs = serde_json::json!({
        "scene": args.scene.display().to_string(),
        "t_end": t_end,
        "prox_constant": args.solver.prox_constant,
        "explore_branches": args.solver.explore_branches,
        "last_resort": args.solver.last_resort,
        "low_rank_updates": args.solver.low_rank_updates,
        "snapshots": plan.snapshots,
    });
    print_warnings(scene);
    let out = simulate_with_output(scene, &options, &plan, "blocks run", &inputs)?;
    let out = with_convergence(out, &args.convergence, scene, &options, args.solver.force)?;
    finish_command(&out, args.output.json, plan.dir.as_deref())
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::scenarios::{shaking_column, Shaking};
    use blockstack::time_guard::{TIME_BOUND_S, WATCHDOG_GRACE_S};
    use input::watchdog::TickingClock;

    #[test]
    fn the_watchdog_stops_a_run_projected_past_the_bound_and_says_so() {
        // 1000 steps at a second each: projected at 1.0e3 s once the grace time is over.
        let scene = shaking_column(&Shaking::default()).unwrap();
        let options = RunOptions::default();
        let dir = std::env::temp_dir().join(format!("rollstack-watchdog-{}", std::process::id()));
        let plan = OutputPlan {
            dir: Some(dir.clone()),
            title: "watched".into(),
            ..OutputPlan::default()
        };
        let t_end = scene.solver.t_end;
        let watchdog = Watchdog::new(TickingClock::default(), 0.0, t_end, TIME_BOUND_S);
        let inputs = serde_json::json!({});
        let out = simulate_watched(&scene, &options, &plan, "test", &inputs, watchdog).unwrap();
        // Each step is checked: the first check past the grace time stops the run,
        // after the step it follows.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let steps = WATCHDOG_GRACE_S as usize;
        assert_eq!(out.report.summary.steps, steps);
        let error = out.report.summary.error.clone().unwrap().to_string();
        assert!(error.contains("projected to take about 1.0e3 s"), "{error}");
        assert!(
            error.contains("more than 600 s") && error.contains("--force"),
            "{error}"
        );
        // The files hold the run up to there, and run.json says why it stopped.
        let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
        assert_eq!(
            csv.lines().count(),
            1 + 1 + steps,
            "header, t = 0, the steps"
        );
        let json = std::fs::read_to_string(dir.join("run.json")).unwrap();
        assert!(json.contains("projected to take about"), "{json}");
        let said = finish_command(&out, false, Some(&dir))
            .unwrap_err()
            .to_string();
        assert!(said.starts_with("the simulation stopped at t = "), "{said}");
        assert!(
            said.contains("--force") && said.contains("results up to then"),
            "{said}"
        );
        assert!(!said.contains('\n'), "{said}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
