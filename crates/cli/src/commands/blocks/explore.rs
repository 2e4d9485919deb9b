//! `rollstack blocks explore`: every continuation of a scene's run (§4.4, Figure 4.5):
//! the tree of `blockstack::exploration`, its forks checked against refinement, the
//! outcomes, and Figure 4.5.

use super::scenes::{load_scene, scene_dir, scene_text};
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use blockstack::exploration::thesis;
use blockstack::exploration::{
    branch_cells, explore_scene, fork_records, outcome_groups, ExplorationReport, ForkRecord,
    OutcomeGroup, WalkSettings, BRANCH_COLUMNS, FORK_COLUMNS, OUTCOME_COLUMNS,
};
use blockstack::fork_check::DEFAULT_WINDOW;
use blockstack::scene_file::{LoadedScene, SceneFile};
use blockstack::simulation::{Prox, RunOptions};
use blockstack::time_guard::wall_limit;
use clap::{Args, ValueEnum};
use figures::exploration::plot_exploration;
use input::text::parse_finite;
use nsga::explore::{ExploreOptions, Strategy};
use nsga::BranchRule;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// How the tree grows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StrategyArg {
    /// One generation at a time, its branches in parallel.
    Breadth,
    /// Depth first, one branch at a time.
    Depth,
}

/// Which fixed-set solutions of a cycling step are its continuations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RuleArg {
    /// Solutions whose own contact states are the ones they were solved with.
    SelfConsistent,
    /// Every converged fixed-set solve, as the thesis counts branches.
    Converged,
}

impl RuleArg {
    /// nsga's rule.
    #[must_use]
    pub fn rule(self) -> BranchRule {
        match self {
            Self::SelfConsistent => BranchRule::SelfConsistent,
            Self::Converged => BranchRule::Converged,
        }
    }
}

/// A set of settings that `--preset` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PresetArg {
    /// The thesis's algorithm and model, as its code runs them (docs/exploration.md).
    Thesis,
}

impl PresetArg {
    /// The name `--preset` takes.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Thesis => "thesis",
        }
    }
}

/// Arguments of `rollstack blocks explore`.
#[derive(Debug, Args)]
pub struct ExploreArgs {
    /// The scene: a TOML file (keys: docs/scenes.md) or a built-in scene's name
    /// (`abundance`: Figure 4.5 as the thesis states it; `abundance-author`: with the
    /// author's scripts' settings).
    pub scene: PathBuf,
    /// Directory for branches.csv, forks.csv, outcomes.csv, trajectories/, abundance.png
    /// and run.json (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// End time (model time units; overrides the scene's solver.t_end).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Breadth first (a generation at a time, in parallel) or depth first.
    #[arg(long, value_enum, default_value = "breadth")]
    pub strategy: StrategyArg,
    /// Most branches, the root included; a fork whose candidates do not all fit is
    /// passed (its branch goes on with the chosen candidate).
    #[arg(long, default_value_t = 1000, allow_hyphen_values = true)]
    pub max_branches: usize,
    /// Most followed forks from the root to a branch (default: no limit).
    #[arg(long, allow_hyphen_values = true)]
    pub max_depth: Option<usize>,
    /// Wall time (s) after which running branches stop where they are.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub max_wall: Option<f64>,
    /// Which fixed-set solutions are a fork's candidates: `self-consistent` (solutions
    /// of the step's equations) or `converged` (the thesis's count). A branch that does
    /// not follow a fork goes on as the plain run does, under either rule.
    #[arg(long, value_enum, default_value = "self-consistent")]
    pub branch_rule: RuleArg,
    /// Also re-solve every converged step with the touching contacts' states fixed (every
    /// combination for at most 3 touching contacts, else one flipped at a time): finds
    /// non-uniqueness that Newton does not reveal by cycling; up to 64 solves per step.
    /// Without it the probe runs only where Painlevé's indeterminacy is possible (App. I's
    /// b ≤ 0 at a touching sliding contact), and finds sliding contact, jam and lift-off.
    #[arg(long)]
    pub probe_flips: bool,
    /// Check each fork: its candidates against the contact laws, and a window of steps
    /// from the fork's start again with Δt/2 and Δt/4 under both branch rules and with
    /// the other prox choice; label it real, artefact or undecided with a reason
    /// (docs/exploration.md).
    #[arg(long)]
    pub classify: bool,
    /// Coarse steps of the window --classify takes again (at least 1).
    #[arg(long, default_value_t = DEFAULT_WINDOW, allow_hyphen_values = true)]
    pub classify_window: u64,
    /// `thesis`: the thesis's algorithm as its code runs it: a branch point wherever
    /// Newton has not converged in 20 iterations, every converged fixed-set solve a
    /// branch, a finite-difference Jacobian (eps = 1e-6), no line search, r = 0.3, rho_inf
    /// retried by steps of 0.05 on a singular matrix, each branch stopped at the onset of
    /// failure; and its model: no floor, a base 0.2 high, contacts between neighbouring
    /// blocks only (docs/exploration.md, "The thesis's algorithm").
    #[arg(long, value_enum, conflicts_with_all = ["branch_rule", "prox_constant", "probe_flips"])]
    pub preset: Option<PresetArg>,
    /// Use one constant prox parameter r > 0 (the thesis: 0.3) instead of the scene's.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub prox_constant: Option<f64>,
    /// Write each branch's trajectory to trajectories/branch_NNNNN.csv (NNNNN: the branch id) (with --out).
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set, value_name = "BOOL")]
    pub trajectories: bool,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Run even when the root branch alone is estimated to take longer than ten
    /// minutes.
    #[arg(long)]
    pub force: bool,
}

/// The JSON of `rollstack blocks explore`.
#[derive(Debug, Serialize)]
struct ExploreJson<'a> {
    #[serde(flatten)]
    report: &'a ExplorationReport,
    strategy: &'static str,
    branch_rule: &'static str,
    preset: Option<&'static str>,
    files: Vec<String>,
}

/// Samples of the top block per branch for the figure: about this many over the run.
const TOP_SAMPLES: f64 = 400.0;

/// Runs `rollstack blocks explore`.
///
/// # Errors
/// Bad input, a failed start, or an unwritable output directory.
pub fn run(args: &ExploreArgs) -> Result<()> {
    let loaded = match args.preset {
        None => load_scene(&args.scene)?,
        Some(PresetArg::Thesis) => load_as_in_the_thesis_code(&args.scene)?,
    };
    let scene = &loaded.scene;
    anyhow::ensure!(args.max_branches >= 1, "--max-branches must be at least 1");
    anyhow::ensure!(
        args.classify_window >= 1,
        "--classify-window must be at least 1"
    );
    if let Some(t) = args.t_end {
        input::positive("--t-end", t)?;
    }
    if let Some(r) = args.prox_constant {
        input::positive("--prox-constant", r)?;
    }
    if let Some(w) = args.max_wall {
        input::non_negative("--max-wall", w)?;
    }
    let strategy = match args.strategy {
        StrategyArg::Breadth => Strategy::Breadth,
        StrategyArg::Depth => Strategy::Depth,
    };
    let mut options = RunOptions {
        t_end: args.t_end,
        prox: args.prox_constant.map(Prox::Constant),
        branch_rule: args.branch_rule.rule(),
        probe_flips: args.probe_flips,
        ..RunOptions::default()
    };
    if args.preset == Some(PresetArg::Thesis) {
        options = thesis::run_options(options, scene.solver.rho_inf);
    }
    let rule = options.branch_rule;
    let explore_options = ExploreOptions {
        strategy,
        max_branches: args.max_branches,
        max_depth: args.max_depth.unwrap_or(usize::MAX),
        max_wall: args.max_wall.and_then(wall_limit),
    };
    super::check_time_bound(
        &[super::run_cost(scene, &options)],
        Some((scene, &options)),
        args.force,
        "shorten --t-end",
    )?;
    let traj_dir = match (&args.out, args.trajectories) {
        (Some(dir), true) => {
            let d = dir.join("trajectories");
            ensure_dir(&d)?;
            Some(d)
        }
        _ => None,
    };
    let t_end = args.t_end.unwrap_or(scene.solver.t_end);
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let sample_every = (t_end / scene.solver.dt / TOP_SAMPLES).ceil().max(1.0) as u64;
    let finished = AtomicUsize::new(0);
    let mut settings = WalkSettings {
        sample_every,
        trajectories: traj_dir.as_deref(),
        classify: args.classify,
        classify_window: Some(args.classify_window),
        finished: Some(&finished),
        stop_at_failure: false,
    };
    if args.preset == Some(PresetArg::Thesis) {
        settings = thesis::walk_settings(settings);
    }
    let bar = crate::progress::bar_when(args.max_branches as u64, "branches", !args.json);
    let done = AtomicBool::new(false);
    let tree = std::thread::scope(|s| {
        s.spawn(|| {
            while !done.load(Ordering::Relaxed) {
                bar.set_position(finished.load(Ordering::Relaxed) as u64);
                std::thread::sleep(Duration::from_millis(200));
            }
        });
        let tree = explore_scene(scene, &options, &explore_options, settings);
        done.store(true, Ordering::Relaxed);
        tree
    })?;
    bar.finish_and_clear();
    let forks = fork_records(&tree, scene.n_interfaces());
    let groups = outcome_groups(&tree);
    let report = ExplorationReport::new(&tree, &forks, groups.clone());
    let mut files = Vec::new();
    if let Some(dir) = &args.out {
        files = write_files(dir, args, &tree, &forks, &report)?;
        let title = args
            .scene
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
        let title = super::figure_numerics(scene, &options)
            .with_rule(rule)
            .under(&title);
        let png = dir.join("abundance.png");
        plot_exploration(&png, scene, &tree, &groups, &title)
            .with_context(|| format!("cannot draw {}", png.display()))?;
        files.push("abundance.png".into());
        if traj_dir.is_some() {
            files.push("trajectories/".into());
        }
    }
    if args.json {
        print_json(&ExploreJson {
            report: &report,
            strategy: strategy.name(),
            branch_rule: rule.name(),
            preset: args.preset.map(PresetArg::name),
            files,
        })
    } else {
        print_summary(&report, strategy, rule);
        Ok(())
    }
}

/// The scene `arg` as the thesis's code models it (no floor, a base 0.2 high, neighbour
/// contacts only: `SceneFile::as_in_the_thesis_code`).
fn load_as_in_the_thesis_code(arg: &Path) -> Result<LoadedScene> {
    let (text, what) = scene_text(arg)?;
    let file = SceneFile::parse(&text).with_context(|| what.clone())?;
    file.as_in_the_thesis_code()
        .build_at(&scene_dir(arg))
        .with_context(|| format!("{what} as the thesis's code models it (--preset thesis)"))
}

/// Writes branches.csv, forks.csv, outcomes.csv and run.json into `dir`.
fn write_files(
    dir: &Path,
    args: &ExploreArgs,
    tree: &nsga::explore::Exploration<blockstack::exploration::BranchSummary>,
    forks: &[ForkRecord],
    report: &ExplorationReport,
) -> Result<Vec<String>> {
    ensure_dir(dir)?;
    write_csv(
        &dir.join("branches.csv"),
        &BRANCH_COLUMNS,
        tree.branches.iter().map(branch_cells),
    )?;
    write_csv(
        &dir.join("forks.csv"),
        &FORK_COLUMNS,
        forks.iter().map(ForkRecord::csv_cells),
    )?;
    write_csv(
        &dir.join("outcomes.csv"),
        &OUTCOME_COLUMNS,
        report.outcomes.iter().map(OutcomeGroup::csv_cells),
    )?;
    write_run_json(
        dir,
        "blocks explore",
        &serde_json::json!({
            "scene": args.scene.display().to_string(),
            "t_end": args.t_end,
            "strategy": format!("{:?}", args.strategy).to_lowercase(),
            "max_branches": args.max_branches,
            "max_depth": args.max_depth,
            "max_wall": args.max_wall,
            "branch_rule": format!("{:?}", args.branch_rule),
            "preset": args.preset.map(PresetArg::name),
            "probe_flips": args.probe_flips,
            "classify": args.classify,
            "classify_window": args.classify_window,
            "prox_constant": args.prox_constant,
        }),
        &serde_json::json!({"wall_time_s": report.wall_time_s}),
    )?;
    Ok(vec![
        "branches.csv".into(),
        "forks.csv".into(),
        "outcomes.csv".into(),
        "run.json".into(),
    ])
}

fn print_summary(r: &ExplorationReport, strategy: Strategy, rule: BranchRule) {
    println!(
        "{} branches ({} leaves) from {} forks met, {} followed ({} first, {} rule), {} steps in {:.2} s",
        r.branches,
        r.leaves,
        r.forks,
        r.forks_followed,
        strategy.name(),
        rule.name(),
        r.steps,
        r.wall_time_s
    );
    let caps: Vec<&str> = [
        (r.branch_cap_reached, "--max-branches"),
        (r.depth_cap_reached, "--max-depth"),
        (r.wall_cap_reached, "--max-wall"),
    ]
    .iter()
    .filter(|c| c.0)
    .map(|c| c.1)
    .collect();
    if !caps.is_empty() {
        println!("caps reached: {}", caps.join(", "));
    }
    let l = r.labels;
    println!(
        "forks: {} real, {} artefact, {} undecided, {} unchecked",
        l.real, l.artefact, l.undecided, l.unchecked
    );
    println!(
        "{} of {} candidates break a contact law, {} of them followed as branches",
        r.candidates_breaking_laws, r.candidates, r.branches_breaking_laws
    );
    println!("{} distinct outcomes:", r.distinct_outcomes);
    for g in &r.outcomes {
        println!("  {:>5} × {}", g.branches.len(), g.label);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Cli;
    use clap::Parser;

    fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
        let mut all = vec!["rollstack", "blocks", "explore", "abundance-author"];
        all.extend_from_slice(args);
        Cli::try_parse_from(all)
    }

    #[test]
    fn the_thesis_preset_refuses_the_flags_it_sets() {
        assert!(parse(&["--preset", "thesis"]).is_ok());
        for flag in [
            &["--branch-rule", "converged"][..],
            &["--prox-constant", "0.3"],
            &["--probe-flips"],
        ] {
            let mut args = vec!["--preset", "thesis"];
            args.extend_from_slice(flag);
            let e = parse(&args).unwrap_err();
            assert_eq!(e.kind(), clap::error::ErrorKind::ArgumentConflict, "{e}");
            assert!(e.to_string().contains(flag[0]), "{e}");
        }
        let e = parse(&["--preset", "thesys"]).unwrap_err();
        assert!(e.to_string().contains("thesis"), "{e}");
    }

    #[test]
    fn the_thesis_preset_loads_the_authors_model() {
        let loaded = load_as_in_the_thesis_code(Path::new("abundance-author")).unwrap();
        assert!(loaded.scene.neighbours_only() && loaded.scene.floor().is_none());
        let e = load_as_in_the_thesis_code(Path::new("no-such-scene")).unwrap_err();
        assert!(format!("{e:#}").contains("no-such-scene"), "{e:#}");
    }
}
