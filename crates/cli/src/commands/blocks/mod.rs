//! `rollstack blocks`: the stack of blocks on a driven base (Ch. 4, App. G–I).
//!
//! - `run SCENE` ([`simulate`]), `lire` ([`lire`]) and `shake` ([`shake`]): one
//!   simulation (§4.3–4.5) with the JSON of docs/cli.md, a trajectory CSV written
//!   progressively (ERRATA 25), branch points, snapshots of the stack, an animation and
//!   plots of the top block ([`figures::blocks::draw_run`]);
//! - `scenes [NAME]` ([`scenes`]): the built-in scenes, listed or printed as TOML;
//! - `sweep frequency` (Figure 4.6) and `sweep slide` (Figure 4.7) ([`sweep`]), and
//!   `sweep scene` ([`sweep_scene`]: any scene over any of its numeric keys): many runs in
//!   parallel, one CSV row per parameter value (or combination) in input order;
//! - `painleve` ([`painleve`]): Painlevé's paradoxes for one block (App. I);
//! - `work-precision` ([`work_precision`]): speed against error, NSGA and Moreau–Jean;
//! - `explore` ([`explore`]): every continuation of a run, its forks labelled real or
//!   artefact, and Figure 4.5;
//! - `fragility` ([`fragility`]): a scene under every record of a directory at every
//!   intensity level, and lognormal fragility curves against PGA and PGV;
//! - `converge` ([`converge`]): a scene at Δt/2^k and under tiny perturbations, with a
//!   verdict on its failure time and its outcome (converged, chaotic, non-unique).
//!
//! Every number comes from `blockstack`: its simulation, its recorder and its studies.

pub mod converge;
pub mod explore;
pub mod fragility;
pub mod lire;
pub mod painleve;
pub mod scenes;
pub mod shake;
pub mod simulate;
pub mod sweep;
pub mod sweep_scene;
pub mod units;
pub mod work_precision;

use anyhow::Result;
use blockstack::simulation::{Prox, RunOptions};
use blockstack::time_guard::Guard;
pub use blockstack::time_guard::{run_cost, RunCost, TIME_BOUND_S};
use blockstack::Scene;
use clap::{Args, Subcommand};
use figures::numerics::Numerics;
use input::text::parse_finite;
use std::path::PathBuf;

use simulate::OutputPlan;

/// Arguments of `rollstack blocks`.
#[derive(Debug, Args)]
pub struct BlocksArgs {
    /// Which analysis or simulation to run.
    #[command(subcommand)]
    pub command: BlocksCommand,
}

/// The subcommands of `rollstack blocks`.
#[derive(Debug, Subcommand)]
pub enum BlocksCommand {
    /// Simulates a scene from t = 0 to t_end: a TOML file (every key with its unit and
    /// default: docs/scenes.md) or a built-in scene's name (`rollstack blocks scenes`).
    Run(simulate::RunArgs),
    /// Lists the built-in scenes, or prints one (`rollstack blocks scenes NAME`) as TOML
    /// to save, edit and run.
    Scenes(scenes::ScenesArgs),
    /// Shakes a column of blocks w = 0.2, h = 0.4 on a base w = 1, h = 0.1 moving as
    /// x = A sin(ωt) (§4.4), with the outputs of `blocks run`; Δt and t_end count in base
    /// periods.
    Shake(shake::ShakeArgs),
    /// The Leaning Tower of Lire (§4.3, Figure 4.4): blocks w = 1, h = 0.2, μ = 0.3 in the
    /// harmonic maximum-overhang configuration (ERRATA 16) on a fixed table, with nothing
    /// below it as in the thesis (`--floor`: a floor at the table's bottom).
    Lire(lire::LireArgs),
    /// Parameter sweeps: failure time against the shaking frequency (Figure 4.6), top
    /// block angle against the speed of the pulled base (Figure 4.7), and any scene over
    /// any of its numeric keys.
    #[command(subcommand)]
    Sweep(sweep::SweepCommand),
    /// Painlevé's paradoxes for one block on a rough plane (App. I): least friction
    /// coefficient, admissible angles, sign regions of b, line-contact forces.
    Painleve(painleve::PainleveArgs),
    /// Every continuation of a scene's run (§4.4, Figure 4.5): at each fork (a step with
    /// several solutions) every candidate is followed as a branch; the tree, the forks
    /// (optionally checked against refinement: real or artefact), the outcomes and
    /// Figure 4.5.
    Explore(explore::ExploreArgs),
    /// Speed against error for block stacks: the error at the end time against a run
    /// with a much smaller step, and the largest penetration, against solver time, NSGA
    /// beside Moreau–Jean, with the observed orders.
    WorkPrecision(work_precision::WorkPrecisionArgs),
    /// Whether a scene's answer can be trusted: its runs at Δt/2^k, k = 0…K, and tiny
    /// perturbations of its initial state and base, with a verdict on the failure time
    /// and on the outcome (converged, chaotic, non-unique or not converged).
    Converge(converge::ConvergeArgs),
    /// Fragility curves from recorded ground motions: every record (`*.AT2`, `*.csv`) of
    /// a directory played on the scene's base at every level of `--scales`, whether a
    /// block overturned and whether the stack failed, and lognormal curves fitted to
    /// them against PGA and PGV with their 95 % bands (docs/fragility.md).
    Fragility(fragility::FragilityArgs),
}

/// Runs `rollstack blocks`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn run(args: &BlocksArgs) -> Result<()> {
    match &args.command {
        BlocksCommand::Run(a) => simulate::run_scene_file(a),
        BlocksCommand::Scenes(a) => scenes::run(a),
        BlocksCommand::Shake(a) => shake::run_shake(a),
        BlocksCommand::Lire(a) => lire::run_lire(a),
        BlocksCommand::Sweep(sweep::SweepCommand::Frequency(a)) => sweep::sweep_frequency(a),
        BlocksCommand::Sweep(sweep::SweepCommand::Slide(a)) => sweep::sweep_slide(a),
        BlocksCommand::Sweep(sweep::SweepCommand::Scene(a)) => sweep_scene::sweep_scene(a),
        BlocksCommand::Painleve(a) => painleve::run(a),
        BlocksCommand::WorkPrecision(a) => work_precision::run(a),
        BlocksCommand::Explore(a) => explore::run(a),
        BlocksCommand::Converge(a) => converge::run(a),
        BlocksCommand::Fragility(a) => fragility::run(a),
    }
}

/// Solver overrides shared by `run`, `lire` and the sweeps.
#[derive(Debug, Clone, Args)]
pub struct SolverArgs {
    /// Use one constant prox parameter r > 0 for every contact (the thesis: 0.3; model
    /// units of mass) instead of the scene's choice (default: scaled per
    /// constraint, r_k = 1/(w_kᵀM⁻¹w_k), docs/method.md §4).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub prox_constant: Option<f64>,
    /// Record branch points: the steps whose contact states alternated and that
    /// re-solves with each set seen held fixed resolved (docs/method.md §8), counted in
    /// the summary and listed in branch_points.csv. Only the record: those re-solves are
    /// part of every run, so `--explore-branches false` leaves the motion as it is.
    #[arg(long, default_value_t = RunOptions::default().explore_branches, action = clap::ArgAction::Set, value_name = "BOOL")]
    pub explore_branches: bool,
    /// Take a step that nothing else resolves by the last resort, a Moreau–Jean step
    /// whose contact problem Lemke's method solves (docs/method.md §8), and go on; with
    /// `false` such a step ends the run.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set, value_name = "BOOL")]
    pub last_resort: bool,
    /// Where a Newton iterate's index sets differ from those of the kept factors in a
    /// few rows, update the kept factors for those rows instead of factorizing anew
    /// (docs/method.md §7); with `false` every change of sets is factorized, as in the
    /// paper. Branch exploration (`blocks explore`) never updates.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set, value_name = "BOOL")]
    pub low_rank_updates: bool,
    /// Run even when the runs are estimated to take longer than ten minutes, and let
    /// `run`, `shake`, `lire` and the sweeps' rows go on when they are projected past
    /// ten minutes as they run (their watchdog).
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub tuning: crate::commands::tuning::TuningArgs,
}

impl SolverArgs {
    /// The library's run options for an end time override.
    ///
    /// # Errors
    /// A non-positive end time or prox constant.
    pub fn run_options(&self, t_end: Option<f64>, stop_at_failure: bool) -> Result<RunOptions> {
        if let Some(t) = t_end {
            input::positive("--t-end", t)?;
        }
        if let Some(r) = self.prox_constant {
            input::positive("--prox-constant", r)?;
        }
        // Each assignment checked here, so that its error names the flag.
        self.tuning.apply(&mut ::nsga::Options::default())?;
        Ok(RunOptions {
            t_end,
            prox: self.prox_constant.map(Prox::Constant),
            explore_branches: self.explore_branches,
            stop_at_failure,
            skip_last_resort: !self.last_resort,
            skip_low_rank_updates: !self.low_rank_updates,
            tuning: self.tuning.assignments.clone(),
            time_bound: input::watchdog::time_bound(self.force),
            ..RunOptions::default()
        })
    }

    /// Refuses, before any output, runs whose estimated wall time exceeds
    /// [`TIME_BOUND_S`], unless `--force` ([`check_time_bound`]).
    ///
    /// # Errors
    /// When the estimate is over the bound and `--force` was not given.
    pub fn check_cost(
        &self,
        costs: &[RunCost],
        probe: Option<(&Scene, &RunOptions)>,
    ) -> Result<()> {
        check_time_bound(
            costs,
            probe,
            self.force,
            "shorten --t-end or --periods, take fewer values",
        )
    }

    /// [`Self::check_cost`] of one run.
    ///
    /// # Errors
    /// When the estimate is over the bound and `--force` was not given.
    pub fn check_run(&self, scene: &Scene, options: &RunOptions) -> Result<()> {
        self.check_cost(&[run_cost(scene, options)], Some((scene, options)))
    }
}

/// Refuses `costs` whose estimated wall time, shared out over the threads, exceeds
/// [`TIME_BOUND_S`], unless `force`: at the typical cost per block and step first
/// (nothing run), then at the cost measured on the first steps of `probe` (the
/// costliest run), nothing written either way ([`blockstack::time_guard`]); `advice`
/// says what to change.
///
/// # Errors
/// When an estimate is over the bound and `force` is false.
pub fn check_time_bound(
    costs: &[RunCost],
    probe: Option<(&Scene, &RunOptions)>,
    force: bool,
    advice: &str,
) -> Result<()> {
    if force {
        return Ok(());
    }
    let guard = Guard {
        costs,
        threads: rayon::current_num_threads(),
        probe,
    };
    guard
        .check()
        .map_err(|estimate| anyhow::anyhow!("{estimate}: {advice}, or pass --force"))
}

/// The caption of the figures of runs of `scene` with `options`: its Δt, the prox the
/// runs use, and the branch rule when they explore (a sweep's `--branches` above 1), since
/// the rule changes what an exploration records but not a plain run's motion.
#[must_use]
pub fn figure_numerics(scene: &Scene, options: &RunOptions) -> Numerics {
    let numerics = Numerics::run(scene.solver.dt, options.prox.unwrap_or(scene.solver.prox));
    if options.spread_branches > 1 {
        numerics.with_rule(options.branch_rule)
    } else {
        numerics
    }
}

/// Output options of `run`, `shake` and `lire`.
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// Directory for trajectory.csv, branch_points.csv, snapshots (PNG), the animation
    /// (GIF), plots of the top block and run.json (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Times (model time units) of the PNG snapshots of the stack, comma-separated; the
    /// nearest computed step is drawn (default: lire 0,5,6.4; run and shake 0, t_end/2,
    /// t_end).
    #[arg(long, value_delimiter = ',', value_parser = parse_finite, allow_hyphen_values = true)]
    pub snapshots: Option<Vec<f64>>,
    /// Largest number of animation frames (one every 10th step or sparser); 0: no GIF.
    #[arg(long, default_value_t = 120, allow_hyphen_values = true)]
    pub max_frames: usize,
}

impl OutputArgs {
    /// The output plan of a run: `default_snapshots` unless `--snapshots` was given;
    /// `force`: `--force`, no watchdog.
    #[must_use]
    pub fn plan(&self, default_snapshots: Vec<f64>, title: String, force: bool) -> OutputPlan {
        OutputPlan {
            dir: self.out.clone(),
            snapshots: self.snapshots.clone().unwrap_or(default_snapshots),
            max_frames: self.max_frames,
            title,
            defaults: blockstack::scene_info::Defaults::default(),
            progress: !self.json,
            force,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::scenarios::{lire, Perturbation};
    use nsga::BranchRule;

    #[test]
    fn run_figures_name_their_step_and_prox_and_explored_ones_their_rule() {
        let scene = lire(4, Perturbation::Bottom).unwrap();
        let plain = figure_numerics(&scene, &RunOptions::default());
        assert_eq!(plain.caption(), "Δt = 0.01, prox scaled (α = 1)");
        assert_eq!(
            plain.under("Lire tower"),
            "Lire tower\nΔt = 0.01, prox scaled (α = 1)"
        );
        // A sweep that explores its runs (`--branches 30`) draws what the rule records.
        let explored = RunOptions {
            prox: Some(Prox::Constant(0.3)),
            spread_branches: 30,
            branch_rule: BranchRule::Converged,
            ..RunOptions::default()
        };
        assert_eq!(
            figure_numerics(&scene, &explored).caption(),
            "converged rule (the thesis's count), Δt = 0.01, prox r = 0.3"
        );
        // `blocks explore` always names its rule.
        let tree =
            figure_numerics(&scene, &RunOptions::default()).with_rule(BranchRule::SelfConsistent);
        assert_eq!(
            tree.caption(),
            "self-consistent rule, Δt = 0.01, prox scaled (α = 1)"
        );
    }
}
