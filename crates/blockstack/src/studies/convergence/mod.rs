//! Convergence as an answer (`rollstack blocks converge`): a scene run at Δt/2^k,
//! k = 0…K, and, at the finest Δt, an ensemble of tiny perturbations of its initial
//! positions and of its base's timing ([`perturb`]); a verdict on the failure time and
//! one on the outcome ([`verdict`]), and when nearby motions separate ([`separation`]).
//!
//! **The quantities.** The *failure time* is the first loss of support (§4.4, the
//! `failure_time` of every run and of Figure 4.6); the *outcome* is which blocks fell
//! (lost their support or tipped), in which order, which reached the floor
//! ([`Outcome`]), and where every block rests at the end (its final pose).
//!
//! **The rules**, tried in this order for each quantity, on the finest two levels
//! (Δt_{K−1} = 2Δt_K) and the ensemble at Δt_K together with the unperturbed run there:
//! 1. `non-unique`: some run (a level or a member) met a *fork*, a step with two or more
//!    distinct self-consistent solutions (a branch point whose candidates, under the
//!    self-consistent rule, differ: [`crate::RunSummary::branch_points`], the forks
//!    `blocks explore` follows), before the quantity was decided: before its failure
//!    time (anywhere if it never failed) for the failure time, anywhere for the
//!    outcome. Which motion the run shows is then a choice among several.
//! 2. `converged`: both levels fail, within [`verdict::FAILURE_TIME_STEPS`] steps of
//!    the coarser one (or both stand to the end); for the outcome, the same blocks fell
//!    in the same order and reached the floor, and no corner's final position differs by
//!    more than [`verdict::POSE_TOLERANCE`] of the smallest block dimension. The
//!    tolerance reported is the level difference (for a failure time at least the
//!    finest Δt, its resolution; none for a column that stands at both); with three
//!    levels or more that agree, the observed order log₂(d_{K−2,K−1}/d_{K−1,K}).
//!    A failure time is converged too by *Richardson's rule* when the three finest
//!    levels follow one motion (each fails, the same block falls first) and their
//!    failure times move one way at an observed order in
//!    [`verdict::RICHARDSON_ORDERS`]: the answer is the extrapolated limit, known to
//!    [`verdict::RICHARDSON_SAFETY`] times its distance from the finest level's value.
//! 3. `chaotic`: the levels disagree, and the spread of the members perturbed by at
//!    most [`verdict::SENSITIVE_MAGNITUDE`] (failure times max − min; the largest corner
//!    distance of a member's final poses from the unperturbed run's) is at least
//!    [`verdict::CHAOS_FRACTION`] of the levels' difference (|T_{K−1} − T_K|; the corner
//!    distance of their final poses), or those members and the unperturbed run disagree
//!    on the discrete answer (fail or stand; which blocks fell in which order, which
//!    reached the floor). The members at 10⁻⁴ show how smoothly the answer depends on
//!    the initial state: reported, not judged. The report gives the ensemble's spread,
//!    when the members' motions separate from the unperturbed one and the finite-time
//!    Lyapunov estimate ([`separation`]).
//! 4. `not converged`: none of these, or a run of the finest two levels stopped (an
//!    error, the watchdog) before deciding.
//!
//! The runs are independent: [`Study`] lists them ([`Study::levels`], then
//! [`Study::members`], which compare themselves step by step with the finest level's
//! run and so run after it) and runs one ([`Study::run`]); the caller runs them in
//! parallel and hands them back to [`Study::report`].

pub mod perturb;
pub mod row;
pub mod separation;
pub mod verdict;

use crate::error::BlockError;
use crate::exploration::Outcome;
use crate::record::{finite_text, number_text, optional_text};
use crate::scene::Scene;
use crate::simulation::{simulate_until, BlockPose, RunOptions, StepRecord};
use crate::time_guard::{run_cost, RunCost};
use perturb::{ensemble, Perturbation, MAGNITUDES};
use separation::{corner_distance, Separation, DISTANCE_FLOOR};
use std::fmt;
use std::ops::ControlFlow;
use verdict::{judge_failure, judge_outcome, Level, Member, Observed, Verdict, POSE_TOLERANCE};

/// The default K: runs at Δt, Δt/2 and Δt/4, three levels, enough for an observed order.
pub const DEFAULT_LEVELS: usize = 2;

/// The most halvings: Δt/2^8 takes 256 times the steps of the scene's run.
pub const MAX_LEVELS: usize = 8;

/// The default members per magnitude ([`MAGNITUDES`]): one of each kind of
/// perturbation where the base moves.
pub const DEFAULT_ENSEMBLE: usize = 2;

/// The most members per magnitude.
pub const MAX_ENSEMBLE: usize = 20;

/// How many runs a study makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Settings {
    /// K: the levels are Δt/2^k, k = 0…K (1 to [`MAX_LEVELS`]).
    pub levels: usize,
    /// Members per perturbation magnitude (0 to [`MAX_ENSEMBLE`]).
    pub ensemble: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            levels: DEFAULT_LEVELS,
            ensemble: DEFAULT_ENSEMBLE,
        }
    }
}

impl Settings {
    /// Checks K in [1, [`MAX_LEVELS`]] and the ensemble in [0, [`MAX_ENSEMBLE`]];
    /// `names`: what the user calls them (`--levels`, `levels`).
    ///
    /// # Errors
    /// The first out of range, named.
    pub fn validate(&self, names: [&str; 2]) -> Result<(), BlockError> {
        let check = |name: &str, v: usize, lo: usize, hi: usize, range: &'static str| {
            if (lo..=hi).contains(&v) {
                return Ok(());
            }
            #[allow(clippy::cast_precision_loss)]
            let value = v as f64;
            Err(BlockError::from(input::InputError::OutOfRange {
                name: name.to_owned(),
                range,
                value,
            }))
        };
        check(names[0], self.levels, 1, MAX_LEVELS, "[1, 8]")?;
        check(names[1], self.ensemble, 0, MAX_ENSEMBLE, "[0, 20]")
    }
}

/// What a run of the study is.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum JobKind {
    /// The scene at Δt/2^k.
    Level {
        /// k.
        k: usize,
    },
    /// A perturbed scene at the finest Δt.
    Member {
        /// The member's number (1-based).
        member: usize,
        /// Its perturbation.
        #[serde(flatten)]
        perturbation: Perturbation,
    },
}

/// One run of the study: its scene (Δt set, perturbed for a member) and what it is.
#[derive(Debug, Clone)]
pub struct Job {
    /// What it is.
    pub kind: JobKind,
    /// The scene it runs.
    pub scene: Scene,
}

impl Job {
    /// `level0`, `level1`, …, `member01`, …: the name of its trajectory file.
    #[must_use]
    pub fn label(&self) -> String {
        match self.kind {
            JobKind::Level { k } => format!("level{k}"),
            JobKind::Member { member, .. } => format!("member{member:02}"),
        }
    }
}

/// The finest level's configurations, step by step, that the members are compared with.
#[derive(Debug, Clone, Default)]
pub struct Reference {
    times: Vec<f64>,
    poses: Vec<BlockPose>,
    blocks: usize,
}

impl Reference {
    fn at(&self, i: usize) -> Option<(f64, &[BlockPose])> {
        let t = *self.times.get(i)?;
        Some((t, &self.poses[i * self.blocks..(i + 1) * self.blocks]))
    }
}

/// One run's result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ConvergenceRun {
    /// Its name ([`Job::label`]).
    pub label: String,
    /// What it is.
    #[serde(flatten)]
    pub kind: JobKind,
    /// Its Δt.
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Time reached.
    pub t_final: f64,
    /// What it shows.
    #[serde(flatten)]
    pub observed: Observed,
    /// Why it stopped before its end time, if it did.
    pub error: Option<String>,
    /// Solver seconds.
    pub wall_time_s: f64,
    /// A member: how it separated from the finest level's run.
    pub separation: Option<Separation>,
    /// A member: its distance from the finest level's run, (t, d) per step.
    #[serde(skip)]
    pub distance: Vec<(f64, f64)>,
    /// The finest level: its configurations, for the members.
    #[serde(skip)]
    pub reference: Option<Reference>,
}

impl ConvergenceRun {
    /// The columns of `runs.csv` before the final poses (`x{k}`, `y{k}`, `theta{k}` per
    /// block follow).
    pub const CSV_HEADER: [&'static str; 18] = [
        "label",
        "kind",
        "k",
        "member",
        "perturbed",
        "magnitude",
        "dt",
        "steps",
        "t_final",
        "failure_time",
        "fell",
        "on_floor",
        "forks",
        "separated_at",
        "lyapunov",
        "max_distance",
        "wall_time_s",
        "error",
    ];

    /// The header of `runs.csv` for `n` blocks.
    #[must_use]
    pub fn csv_header(n: usize) -> Vec<String> {
        let mut h: Vec<String> = Self::CSV_HEADER.iter().map(|c| (*c).to_owned()).collect();
        for k in 1..=n {
            h.extend([format!("x{k}"), format!("y{k}"), format!("theta{k}")]);
        }
        h
    }

    /// Its row of `runs.csv` (lists of blocks space-separated, empty cells for what does
    /// not apply).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let list = |v: &[usize]| {
            v.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(" ")
        };
        let (kind, k, member, perturbed, magnitude) = match self.kind {
            JobKind::Level { k } => ("level", k.to_string(), String::new(), "", None),
            JobKind::Member {
                member,
                perturbation: p,
            } => (
                "member",
                String::new(),
                member.to_string(),
                p.perturbed.name(),
                Some(p.magnitude),
            ),
        };
        let sep = self.separation.as_ref();
        let mut cells = vec![
            self.label.clone(),
            kind.to_owned(),
            k,
            member,
            perturbed.to_owned(),
            optional_text(magnitude),
            number_text(self.dt),
            self.steps.to_string(),
            number_text(self.t_final),
            optional_text(self.observed.failure_time),
            list(&self.observed.outcome.fell),
            list(&self.observed.outcome.on_floor),
            self.observed.forks.len().to_string(),
            optional_text(sep.and_then(|s| s.separated_at)),
            optional_text(sep.and_then(|s| s.lyapunov)),
            optional_text(sep.map(|s| s.max_distance)),
            number_text(self.wall_time_s),
            self.error.clone().unwrap_or_default(),
        ];
        for p in &self.observed.final_poses {
            cells.extend([p.x, p.y, p.theta].map(finite_text));
        }
        cells
    }
}

/// The members' distances from the unperturbed finest run as the rows of
/// `separation.csv`: `t`, then one column per member (`member01`, …), a row per step of
/// the finest run; empty where a member had stopped.
#[must_use]
pub fn separation_rows(members: &[ConvergenceRun]) -> (Vec<String>, Vec<Vec<String>>) {
    let mut header = vec!["t".to_owned()];
    header.extend(members.iter().map(|m| m.label.clone()));
    let steps = members.iter().map(|m| m.distance.len()).max().unwrap_or(0);
    let rows = (0..steps)
        .map(|i| {
            let t = members.iter().find_map(|m| m.distance.get(i)).map(|d| d.0);
            let mut row = vec![optional_text(t)];
            row.extend(
                members
                    .iter()
                    .map(|m| optional_text(m.distance.get(i).map(|d| d.1))),
            );
            row
        })
        .collect();
    (header, rows)
}

/// The ensemble's separation in brief: how many members separated, the earliest time,
/// and the range and median of their Lyapunov estimates.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EnsembleSeparation {
    /// Members compared.
    pub members: usize,
    /// Members whose motion separated from the unperturbed one.
    pub separated: usize,
    /// The earliest separation.
    pub earliest: Option<f64>,
    /// The median separation time of those that separated.
    pub median_time: Option<f64>,
    /// Members with a separating window long enough for a slope.
    pub with_slope: usize,
    /// Smallest, median and largest λ of those.
    pub lyapunov: Option<[f64; 3]>,
}

/// What `rollstack blocks converge` reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ConvergenceReport {
    /// K and members per magnitude.
    pub settings: Settings,
    /// The levels' Δt, coarsest first.
    pub dts: Vec<f64>,
    /// The perturbation magnitudes.
    pub magnitudes: Vec<f64>,
    /// End time of every run.
    pub t_end: f64,
    /// The pose tolerance (a length): agreement of final poses, and separation.
    pub pose_tolerance: f64,
    /// The verdict on the failure time.
    pub failure: Verdict,
    /// The verdict on the outcome.
    pub outcome: Verdict,
    /// When the members separated from the unperturbed finest run.
    pub separation: EnsembleSeparation,
    /// Every run, levels (coarsest first) then members.
    pub runs: Vec<ConvergenceRun>,
}

/// A convergence study of one scene (module docs).
#[derive(Debug, Clone)]
pub struct Study {
    options: RunOptions,
    settings: Settings,
    levels: Vec<Job>,
    members: Vec<Job>,
    radii: Vec<f64>,
    smallest: f64,
}

impl Study {
    /// The study of `scene` with `options` (t_end, prox, watchdog; branch points are
    /// always recorded, since forks decide `non-unique`).
    ///
    /// # Errors
    /// Settings out of range (named as in `names`, as [`Settings::validate`]), a t_end
    /// that is not positive, or a member's scene the checks refuse.
    pub fn new(
        scene: &Scene,
        options: &RunOptions,
        settings: Settings,
        names: [&str; 2],
    ) -> Result<Self, BlockError> {
        settings.validate(names)?;
        if let Some(t) = options.t_end {
            input::positive("t_end", t)?;
        }
        let options = RunOptions {
            explore_branches: true,
            branch_rule: nsga::BranchRule::SelfConsistent,
            ..options.clone()
        };
        let levels: Vec<Job> = (0..=settings.levels)
            .map(|k| {
                let mut scene = scene.clone();
                scene.solver.dt /= f64::from(1u32 << k);
                Job {
                    kind: JobKind::Level { k },
                    scene,
                }
            })
            .collect();
        let finest = &levels[settings.levels].scene;
        let members = ensemble(scene, settings.ensemble)
            .into_iter()
            .enumerate()
            .map(|(i, perturbation)| {
                Ok(Job {
                    kind: JobKind::Member {
                        member: i + 1,
                        perturbation,
                    },
                    scene: perturbation.apply(finest)?,
                })
            })
            .collect::<Result<Vec<_>, BlockError>>()?;
        Ok(Self {
            options,
            settings,
            levels,
            members,
            radii: scene
                .blocks()
                .iter()
                .map(|b| 0.5 * b.width().hypot(b.height()))
                .collect(),
            smallest: scene.smallest_block_dimension(),
        })
    }

    /// The runs at Δt/2^k, coarsest first.
    #[must_use]
    pub fn levels(&self) -> &[Job] {
        &self.levels
    }

    /// The ensemble's runs, at the finest Δt.
    #[must_use]
    pub fn members(&self) -> &[Job] {
        &self.members
    }

    /// The options every run takes.
    #[must_use]
    pub fn options(&self) -> &RunOptions {
        &self.options
    }

    /// The end time of every run.
    #[must_use]
    pub fn t_end(&self) -> f64 {
        self.options
            .t_end
            .unwrap_or(self.levels[0].scene.solver.t_end)
    }

    /// Every run's cost, for the time guard ([`crate::time_guard`]).
    #[must_use]
    pub fn costs(&self) -> Vec<RunCost> {
        self.levels
            .iter()
            .chain(&self.members)
            .map(|j| run_cost(&j.scene, &self.options))
            .collect()
    }

    /// The costliest run (the finest level), to calibrate the time guard on.
    #[must_use]
    pub fn probe(&self) -> (&Scene, &RunOptions) {
        (&self.levels[self.settings.levels].scene, &self.options)
    }

    /// The pose tolerance, a length ([`POSE_TOLERANCE`] of the smallest block dimension).
    #[must_use]
    pub fn pose_tolerance(&self) -> f64 {
        POSE_TOLERANCE * self.smallest
    }

    /// Runs `job`; a member is compared with `reference` (the finest level's run,
    /// [`Self::reference`]) step by step. `on_step` sees every state, as
    /// [`crate::simulate`]'s does.
    ///
    /// # Errors
    /// Bad run options (a run that stops is not an error: its `error` says why).
    pub fn run(
        &self,
        job: &Job,
        reference: Option<&Reference>,
        mut on_step: impl FnMut(&StepRecord),
    ) -> Result<ConvergenceRun, BlockError> {
        let n = job.scene.n_blocks();
        let finest = matches!(job.kind, JobKind::Level { k } if k == self.settings.levels);
        let mut kept = finest.then(|| Reference {
            blocks: n,
            ..Reference::default()
        });
        let mut distance = Vec::new();
        let mut t_final = 0.0;
        let summary = simulate_until(&job.scene, &self.options, |r| {
            on_step(r);
            t_final = r.t;
            if let Some(kept) = &mut kept {
                kept.times.push(r.t);
                kept.poses.extend_from_slice(&r.poses);
            }
            if let Some((t, poses)) = reference.and_then(|x| x.at(distance.len())) {
                // The same grid: a member at another Δt would compare other times.
                if (t - r.t).abs() <= 1e-9 * job.scene.solver.dt {
                    distance.push((r.t, corner_distance(&r.poses, poses, &self.radii)));
                }
            }
            ControlFlow::Continue(())
        })?;
        let separation = matches!(job.kind, JobKind::Member { .. }).then(|| {
            Separation::of(
                &distance,
                DISTANCE_FLOOR * self.smallest,
                self.pose_tolerance(),
            )
        });
        Ok(ConvergenceRun {
            label: job.label(),
            kind: job.kind,
            dt: job.scene.solver.dt,
            steps: summary.steps,
            t_final,
            observed: Observed {
                failure_time: summary.failure_time,
                outcome: Outcome::of(&summary.events),
                final_poses: summary.final_poses.clone(),
                forks: summary
                    .branch_points
                    .iter()
                    .filter(|b| b.distinct >= 2)
                    .map(|b| b.t)
                    .collect(),
                complete: summary.error.is_none(),
            },
            error: summary.error.as_ref().map(ToString::to_string),
            wall_time_s: summary.wall_time_s,
            separation,
            distance,
            reference: kept,
        })
    }

    /// The finest level's configurations among the levels' runs.
    #[must_use]
    pub fn reference<'r>(&self, levels: &'r [ConvergenceRun]) -> Option<&'r Reference> {
        levels.iter().find_map(|r| r.reference.as_ref())
    }

    /// The report of the levels' runs (coarsest first) and the members' runs.
    #[must_use]
    pub fn report(
        &self,
        levels: Vec<ConvergenceRun>,
        members: Vec<ConvergenceRun>,
    ) -> ConvergenceReport {
        let as_levels: Vec<Level> = levels
            .iter()
            .map(|r| Level {
                dt: r.dt,
                observed: r.observed.clone(),
            })
            .collect();
        let observed: Vec<Member> = members
            .iter()
            .filter_map(|r| match r.kind {
                JobKind::Member { perturbation, .. } => Some(Member {
                    magnitude: perturbation.magnitude,
                    observed: r.observed.clone(),
                }),
                JobKind::Level { .. } => None,
            })
            .collect();
        ConvergenceReport {
            settings: self.settings,
            dts: levels.iter().map(|r| r.dt).collect(),
            magnitudes: MAGNITUDES.to_vec(),
            t_end: self.t_end(),
            pose_tolerance: self.pose_tolerance(),
            failure: judge_failure(&as_levels, &observed),
            outcome: judge_outcome(&as_levels, &observed, &self.radii, self.smallest),
            separation: EnsembleSeparation::of(&members),
            runs: levels.into_iter().chain(members).collect(),
        }
    }
}

/// The study of `scene` with `options` and `settings`, its runs one after the other (the
/// CLI and Python run them in parallel through [`Study`]).
///
/// # Errors
/// As [`Study::new`] and [`Study::run`].
pub fn converge(
    scene: &Scene,
    options: &RunOptions,
    settings: Settings,
) -> Result<ConvergenceReport, BlockError> {
    let study = Study::new(scene, options, settings, ["levels", "ensemble"])?;
    let levels = study
        .levels()
        .iter()
        .map(|j| study.run(j, None, |_| {}))
        .collect::<Result<Vec<_>, _>>()?;
    let reference = study.reference(&levels).cloned();
    let members = study
        .members()
        .iter()
        .map(|j| study.run(j, reference.as_ref(), |_| {}))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(study.report(levels, members))
}

impl EnsembleSeparation {
    /// The brief of the members' separations.
    #[must_use]
    pub fn of(members: &[ConvergenceRun]) -> Self {
        let seps: Vec<&Separation> = members
            .iter()
            .filter_map(|m| m.separation.as_ref())
            .collect();
        let times: Vec<f64> = seps.iter().filter_map(|s| s.separated_at).collect();
        let slopes: Vec<f64> = seps.iter().filter_map(|s| s.lyapunov).collect();
        Self {
            members: seps.len(),
            separated: times.len(),
            earliest: times.iter().copied().reduce(f64::min),
            median_time: crate::exploration::spread_of(times).map(|s| s[1]),
            with_slope: slopes.len(),
            lyapunov: crate::exploration::spread_of(slopes),
        }
    }
}

/// A time or a number, or `-`.
fn cell(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.digits$}"))
}

/// A number in scientific notation, or `-`.
fn sci(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.1e}"))
}

impl fmt::Display for ConvergenceRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            JobKind::Level { k } => format!("Δt/{}", 1u32 << k),
            JobKind::Member {
                perturbation: p, ..
            } => {
                format!("{} {:.0e}", p.perturbed.label(), p.magnitude)
            }
        };
        let sep = self.separation.as_ref();
        write!(
            f,
            "{:<9} {:<20} {:>10.3e} {:>9} {:>9} {:>11} {:>7} {:>5}  {}",
            self.label,
            what,
            self.dt,
            cell(self.observed.failure_time, 4),
            cell(sep.and_then(|s| s.separated_at), 4),
            cell(sep.and_then(|s| s.lyapunov), 2),
            sci(sep.map(|s| s.max_distance)),
            self.observed.forks.len(),
            self.observed.outcome.label(),
        )?;
        if let Some(e) = &self.error {
            write!(f, " (stopped at t = {:.4}: {e})", self.t_final)?;
        }
        Ok(())
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.verdict)?;
        if let Some(tol) = self.tolerance {
            write!(f, " to {tol:.2e}")?;
        }
        if let Some(t) = self.extrapolated {
            write!(f, ", extrapolated {t:.4}")?;
        }
        write!(
            f,
            " (finest two levels differ by {}, threshold {:.2e}; order {}; ensemble spread {}, {} answer(s) over {} member(s) and the unperturbed run",
            sci(self.level_difference),
            self.threshold,
            cell(self.order, 2),
            sci(self.ensemble_spread),
            self.ensemble_answers,
            self.ensemble_members,
        )?;
        if !self.fork_times.is_empty() {
            let t: Vec<String> = self.fork_times.iter().map(|t| format!("{t:.4}")).collect();
            write!(f, "; forks at t = {}", t.join(", "))?;
        }
        write!(f, "): {}", self.why)
    }
}

impl fmt::Display for ConvergenceReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<9} {:<20} {:>10} {:>9} {:>9} {:>11} {:>7} {:>5}  outcome",
            "run", "step or perturbation", "dt", "failure", "separate", "lyapunov", "dist", "forks"
        )?;
        for r in &self.runs {
            writeln!(f, "{r}")?;
        }
        let s = &self.separation;
        writeln!(
            f,
            "separation: {} of {} members separated from the unperturbed run (corners {:.1e} apart), earliest at t = {}, median {}; Lyapunov estimate (1/time) over {} window(s): {}",
            s.separated,
            s.members,
            self.pose_tolerance,
            cell(s.earliest, 4),
            cell(s.median_time, 4),
            s.with_slope,
            s.lyapunov.map_or_else(
                || "-".to_owned(),
                |[lo, mid, hi]| format!("median {mid:.2} (from {lo:.2} to {hi:.2})")
            ),
        )?;
        write!(f, "{}", self.verdict_lines())
    }
}

impl ConvergenceReport {
    /// The two verdicts, a line each: `failure time 6.5950: converged to …` (the finest
    /// level's failure time) and `outcome: …`.
    #[must_use]
    pub fn verdict_lines(&self) -> String {
        let failure_time = self
            .runs
            .get(self.dts.len() - 1)
            .and_then(|r| r.observed.failure_time);
        format!(
            "failure time {}: {}\noutcome: {}",
            cell(failure_time, 4),
            self.failure,
            self.outcome
        )
    }
}
