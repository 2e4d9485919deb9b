//! `rollstack blocks sweep scene`: a scene run once per combination of the values of its
//! `--set` keys, with the rows of `blockstack::studies::scene_sweep`, run in parallel and
//! written in input order through the plumbing of the other sweeps ([`super::sweep`]).

use super::converge::ConvergenceArgs;
use super::sweep::{check_judged_before_any_run, write_judged_csv, SweepOutputArgs, SweepRun};
use super::SolverArgs;
use crate::output::ensure_dir;
use anyhow::{Context, Result};
use blockstack::simulation::RunOptions;
use blockstack::studies::convergence::row::{RowConvergence, SWEEP_ENSEMBLE};
use blockstack::studies::scene_sweep::{Override, SceneSweep, SetValue};
use blockstack::SolverParams;
use clap::Args;
use figures::blocks::plot_scene_sweep;
use figures::numerics::Numerics;
use input::text::parse_finite;
use shards::InputFile;
use std::path::PathBuf;

/// The name of the copy of the scene a sweep keeps in its `--out` (the scene counts by
/// its content: an edited scene is another sweep, and `merge` reads this copy).
pub const SCENE_COPY: &str = "scene.toml";

/// Arguments of `rollstack blocks sweep scene`.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The scene: a TOML file (keys: docs/scenes.md) or the name of a built-in scene, as
    /// in `blocks run`.
    pub scene: PathBuf,
    /// A scene key and its values, KEY=VALUES: `contact.mu=0.1:0.5:0.1`,
    /// `base.omega=2,4,8`, `blocks.0.width=0.25` (`[[blocks]]` entry 0), `blocks.width=0.3`
    /// (every entry). Repeat for a cartesian product; the first varies slowest.
    #[arg(long = "set", required = true, value_name = "KEY=VALUES", allow_hyphen_values = true,
          value_parser = check_override)]
    pub set: Vec<String>,
    /// End time of every run (model time units; overrides the scene's solver.t_end).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Stop each run at its first loss of support (the failure time is then its last
    /// state).
    #[arg(long)]
    pub stop_at_failure: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub convergence: ConvergenceArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// Runs `rollstack blocks sweep scene`.
///
/// # Errors
/// An unreadable scene, an unknown key (before any run), bad options, or an unwritable
/// output directory, or a value the scene refuses (all before any run). A run the
/// solver stops is the error of its row.
pub fn sweep_scene(args: &SceneArgs) -> Result<()> {
    let (text, what) = super::scenes::scene_text(&args.scene)?;
    let overrides = args
        .set
        .iter()
        .map(|s| s.parse::<Override>().map_err(anyhow::Error::msg))
        .collect::<Result<Vec<_>>>()?;
    let sweep = SceneSweep::new(&text, overrides)
        .with_context(|| what.clone())?
        .in_dir(super::scenes::scene_dir(&args.scene));
    let options = args
        .output
        .watched(args.solver.run_options(args.t_end, args.stop_at_failure)?);
    let mut inputs = serde_json::json!({
        "set": args.set,
        "t_end": args.t_end,
        "stop_at_failure": args.stop_at_failure,
    });
    args.convergence.identify(&mut inputs, SWEEP_ENSEMBLE);
    let settings = args.convergence.settings(SWEEP_ENSEMBLE);
    let all = sweep.points();
    let scene = InputFile {
        copy: SCENE_COPY.into(),
        source: what,
        bytes: text.as_bytes().to_vec(),
    };
    let run = SweepRun::new("scene", &args.output, &args.solver, inputs, all.len())?.reading(
        "scene",
        &args.scene.display().to_string(),
        scene,
    );
    let points = run.run.select(&all);
    check_judged_before_any_run(
        &points,
        &args.solver,
        &args.output,
        &options,
        settings,
        |(_, point)| {
            let set: Vec<String> = point
                .iter()
                .map(|s| format!("{}={}", s.key, input::Short(s.value)))
                .collect();
            let loaded = sweep
                .scene(point)
                .with_context(|| format!("--set {}", set.join(" --set ")))?;
            Ok(loaded.scene)
        },
    )?;
    let rows = run.rows(&points, |p| sweep.row_judged(p, &options, settings))?;
    let mut files = Vec::new();
    let mut notes = Vec::new();
    if let Some(dir) = &args.output.out {
        ensure_dir(dir)?;
        write_judged_csv(
            &dir.join("sweep_scene.csv"),
            sweep.csv_header(),
            &rows,
            settings,
            |r| (r.csv_cells(), r.convergence.as_ref()),
        )?;
        let numerics = sweep_numerics(&sweep, &points, &options)?;
        let drawn = plot_scene_sweep(&dir.join("sweep_scene.png"), &rows, &numerics)?;
        files.push("sweep_scene.csv".to_owned());
        files.extend(drawn.files);
        files.push(SCENE_COPY.to_owned());
        notes = drawn.notes;
    }
    let files: Vec<&str> = files.iter().map(String::as_str).collect();
    let mut extra = serde_json::Map::new();
    extra.insert("notes".into(), serde_json::to_value(&notes)?);
    run.finish(
        &files,
        extra,
        &rows,
        rows.iter()
            .map(|r| r.wall_time_s + RowConvergence::seconds(r.convergence.as_ref()))
            .sum(),
        ToString::to_string,
    )
}

/// The caption of the sweep's figure: the runs' Δt (one, or the range when a swept key
/// moves it, as ω at fixed steps per period does) and the prox of the first point's scene
/// unless `--prox-constant` sets it.
fn sweep_numerics(
    sweep: &SceneSweep,
    points: &[(usize, Vec<SetValue>)],
    options: &RunOptions,
) -> Result<Numerics> {
    let scenes = points
        .iter()
        .map(|(_, point)| sweep.scene(point).map(|l| l.scene))
        .collect::<Result<Vec<_>, _>>()?;
    let dts: Vec<f64> = scenes.iter().map(|s| s.solver.dt).collect();
    let scene_prox = scenes
        .first()
        .map_or(SolverParams::default().prox, |s| s.solver.prox);
    Ok(Numerics::of_steps(&dts, options.prox.unwrap_or(scene_prox)))
}

/// Checks the syntax of one `--set KEY=VALUES` (keys are checked against the scene
/// later), keeping the text as typed for `run.json`.
fn check_override(text: &str) -> Result<String, String> {
    text.parse::<Override>().map(|_| text.to_owned())
}
