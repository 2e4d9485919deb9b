//! Every continuation of a block stack's run (§4.4, Figure 4.5): nsga's exploration
//! ([`mod@nsga::explore`]) driven over a scene, with the stack's contact states at each fork,
//! the outcomes a user reads (which blocks fell, in what order, which reached the floor),
//! and the test of each fork against refinement ([`crate::fork_check`]).
//!
//! A branch is stepped by the loop that steps a plain run ([`StackWalker`], which
//! [`crate::simulate`] drives too: corner contacts kept current, the same fallback
//! policy), and records the same events. Its
//! trajectory can be streamed to `branch_<id>.csv` in a directory, so no trajectory is
//! held in memory; what each branch keeps is its [`BranchSummary`]: final poses, events,
//! and the top block's (t, y, θ) sampled for the figure.

pub mod thesis;

use crate::contact_laws::{self, breaks_text, violation_text, ContactCheck, Tolerances};
use crate::contact_states::{differing_interfaces, interface_states, InterfaceState};
use crate::coordinates::Pose;
use crate::events::{EventKind, FailureEvent};
use crate::fork_check::{check_fork, ForkEvidence, ForkLabel, History, DEFAULT_WINDOW};
use crate::record::{
    finite_text, number_text, optional_text, trajectory_header_of, write_trajectory_row,
};
use crate::scene::Scene;
use crate::simulation::{
    check_failure, final_poses, step_count, stepper_options, BlockPose, Recorder, RunOptions,
    RunSummary, StepRecord, TimedPenetration,
};
use crate::stepping::CornerStepping;
use crate::system::StackSystem;
use crate::BlockError;
use nsga::explore::{explore, forkable, BranchEnd, Exploration, ExploreOptions, Walker};
use nsga::{BranchPoint, State, StepError, Stepper};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// One sample of the top block for the figure: (t, y, θ).
pub type TopSample = [f64; 3];

/// What a branch leaves: its end state and what happened on the way (ancestors'
/// events included, since a child starts with its parent's record).
#[derive(Debug, Clone, serde::Serialize)]
pub struct BranchSummary {
    /// Poses at the branch's last state, bottom to top.
    pub final_poses: Vec<BlockPose>,
    /// First time a block lost its support (§4.4), on this branch or before it.
    pub failure_time: Option<f64>,
    /// Failure events from t = 0 to the branch's end, in time order.
    pub events: Vec<FailureEvent>,
    /// Steps taken by the last resort on this branch.
    pub fallback_steps: usize,
    /// Steps taken without the friction percussions' half-step shift on this branch
    /// (`nsga::StepStats::unshifted`, docs/method.md §8.2, `Stage::Unshifted`).
    #[serde(default)]
    pub unshifted_steps: usize,
    /// The deepest penetration from t = 0 to the branch's end.
    pub deepest: TimedPenetration,
    /// The top block's (t, y, θ), every `sample_every` steps and at both ends.
    #[serde(skip)]
    pub top: Vec<TopSample>,
    /// Why the trajectory file stopped, if it did.
    pub trajectory_error: Option<String>,
    /// The forks this branch met, their candidates checked against the contact laws
    /// (and against refinement with [`WalkSettings::classify`]).
    pub fork_checks: Vec<CheckedFork>,
    /// The branch's last state, kept only for [`StackWalker::restarted`] walkers.
    #[serde(skip)]
    pub end_state: Option<State>,
}

/// A fork's candidates checked against the contact laws, and its evidence, with the
/// step number at its start.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CheckedFork {
    /// Step number k at the start of the forking step.
    pub k: u64,
    /// Each candidate's own step against the contact laws ([`crate::contact_laws`]).
    pub candidates: Vec<ContactCheck>,
    /// The evidence and label ([`crate::fork_check`]), with
    /// [`WalkSettings::classify`].
    pub evidence: Option<ForkEvidence>,
}

/// How a branch is walked beyond stepping.
#[derive(Debug, Clone, Copy, Default)]
pub struct WalkSettings<'a> {
    /// Sample the top block every this many steps (at least 1).
    pub sample_every: u64,
    /// Write each branch's trajectory into `branch_<id>.csv` in this directory.
    pub trajectories: Option<&'a Path>,
    /// Check every fork against refinement ([`crate::fork_check`]).
    pub classify: bool,
    /// Coarse steps of the refinement's window (None: [`DEFAULT_WINDOW`]).
    pub classify_window: Option<u64>,
    /// Counts the branches that ended (a progress display reads it from another thread).
    pub finished: Option<&'a AtomicUsize>,
    /// End each branch at the first loss of support (§4.4), as a sweep of failure times.
    pub stop_at_failure: bool,
}

/// Walks one branch of a scene (see the module docs): the one run loop of the crate.
/// [`crate::simulation::simulate_until`] drives it over a plain run, [`explore_scene`] over every
/// branch; either way a step is taken, counted into the run's [`RunSummary`] and
/// recorded here.
#[derive(Debug)]
pub struct StackWalker<'a> {
    scene: &'a Scene,
    stepper: Stepper<StackSystem>,
    corners: CornerStepping,
    rec: Recorder<'a>,
    horizon: u64,
    /// The run's statistics so far; the counts of last-resort and unshifted steps are
    /// this branch's own (a fork starts them again).
    summary: RunSummary,
    /// Energy of the last recorded state (+∞ before the first).
    energy: f64,
    /// Newton iterations of the last step, and of every step.
    iterations: usize,
    total_iterations: usize,
    /// Seconds spent in the consistent start and in the steps.
    solver_time: f64,
    /// Whether the summary lists the branch points met.
    record_branches: bool,
    sample_every: u64,
    top: Vec<TopSample>,
    trajectories: Option<&'a Path>,
    csv: Option<BufWriter<File>>,
    trajectory_error: Option<String>,
    classify: bool,
    /// The states at the start of the last steps, for the refinement's window.
    history: History,
    keep_end_state: bool,
    checks: Vec<CheckedFork>,
    finished: Option<&'a AtomicUsize>,
    stop_at_failure: bool,
}

/// A consistent start that failed, with the seconds it took.
pub(crate) type FailedStart = (StepError, f64);

impl<'a> StackWalker<'a> {
    /// A walker at the scene's initial state, to `steps` steps of its Δt.
    ///
    /// # Errors
    /// Bad run options; [`BlockError::Scene`] when the consistent start fails.
    pub fn new(
        scene: &'a Scene,
        options: &RunOptions,
        steps: u64,
        settings: WalkSettings<'a>,
    ) -> Result<Self, BlockError> {
        // Forks are found where a first attempt fails: the low-rank updates, which make
        // more first attempts converge, would pass some of them unnoticed.
        let mut opts = stepper_options(scene, options)?;
        opts.linear.low_rank_updates = false;
        Self::start(scene, opts, steps, settings, false)
            .map_err(|(e, _)| BlockError::Scene(format!("consistent start failed: {e}")))
    }

    /// A walker at the scene's initial state with nsga's `options`, to `steps` steps;
    /// `record_branches`: list the branch points met in the summary.
    ///
    /// # Errors
    /// The consistent start's failure.
    pub(crate) fn start(
        scene: &'a Scene,
        options: nsga::Options,
        steps: u64,
        settings: WalkSettings<'a>,
        record_branches: bool,
    ) -> Result<Self, FailedStart> {
        let clock = Instant::now();
        let started = CornerStepping::start_scene(scene, options);
        let solver_time = clock.elapsed().as_secs_f64();
        let (corners, stepper) = started.map_err(|e| (e, solver_time))?;
        let rec = Recorder::new(scene, &scene.initial_coordinates());
        let mut summary = RunSummary::before_the_run(scene, &rec);
        summary.start_failure = stepper.start_failure().map(str::to_owned);
        Ok(Self {
            scene,
            stepper,
            corners,
            rec,
            horizon: steps,
            summary,
            energy: f64::INFINITY,
            iterations: 0,
            total_iterations: 0,
            solver_time,
            record_branches,
            sample_every: settings.sample_every.max(1),
            top: Vec::new(),
            trajectories: settings.trajectories,
            csv: None,
            trajectory_error: None,
            classify: settings.classify,
            history: History::new(settings.classify_window.unwrap_or(DEFAULT_WINDOW)),
            keep_end_state: false,
            checks: Vec::new(),
            finished: settings.finished,
            stop_at_failure: settings.stop_at_failure,
        })
    }

    /// Stops the steps from here on when `interrupt` asks ([`nsga::Interrupt`]): a step
    /// in progress ends with [`StepError::Interrupted`].
    pub(crate) fn set_interrupt(&mut self, interrupt: nsga::Interrupt) {
        self.stepper.set_interrupt(interrupt);
    }

    /// The stepper's options.
    #[must_use]
    pub fn options(&self) -> &nsga::Options {
        self.stepper.options()
    }

    /// The scene walked.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        self.scene
    }

    /// Deeper interpenetration than this is warned about ([`RunSummary::penetration_tol`]).
    #[must_use]
    pub fn penetration_tol(&self) -> f64 {
        self.summary.penetration_tol
    }

    /// The contact laws at `st`, a state at the end of a step of this walker's stepper.
    fn contact_check(&self, st: &State) -> ContactCheck {
        let tol = Tolerances::new(self.scene, self.options().dt);
        let (system, layout) = (self.stepper.system(), self.stepper.layout());
        contact_laws::check(system, layout, st, self.scene.n_interfaces(), &tol)
    }

    /// A walker that takes this branch again from `before` (a state of it, at the start
    /// of a step) with other `options`, to step number `horizon`: it records nothing,
    /// checks no fork, and keeps its end state. None when `before` does not fit the
    /// contacts the stepper now has (a contact was added within the step).
    #[must_use]
    pub fn restarted(&self, before: &State, options: nsga::Options, horizon: u64) -> Option<Self> {
        let layout = self.stepper.layout();
        if before.p_n.len() != layout.n_normal() || before.p_f.len() != layout.n_friction() {
            return None;
        }
        let mut stepper = self.stepper.branch_from(before.clone());
        stepper.set_options(options).ok()?;
        Some(Self {
            horizon,
            sample_every: u64::MAX,
            trajectories: None,
            classify: false,
            keep_end_state: true,
            finished: None,
            stop_at_failure: false,
            ..self.branch(stepper)
        })
    }

    /// This walker continuing with `stepper` as a new branch: the past it records
    /// carried over, the branch's own counts, samples and files not.
    fn branch(&self, stepper: Stepper<StackSystem>) -> Self {
        Self {
            scene: self.scene,
            stepper,
            corners: self.corners.for_branch(),
            rec: self.rec.clone(),
            horizon: self.horizon,
            summary: RunSummary {
                fallback_steps: 0,
                unshifted_steps: 0,
                ..self.summary.clone()
            },
            energy: self.energy,
            iterations: self.iterations,
            total_iterations: self.total_iterations,
            solver_time: self.solver_time,
            record_branches: self.record_branches,
            sample_every: self.sample_every,
            top: Vec::new(),
            trajectories: self.trajectories,
            csv: None,
            trajectory_error: None,
            classify: self.classify,
            history: self.history.clone(),
            keep_end_state: self.keep_end_state,
            checks: Vec::new(),
            finished: self.finished,
            stop_at_failure: self.stop_at_failure,
        }
    }

    /// Records the current state: its record, the failure events, and the statistics of
    /// the states (smallest gap, energy increase, failure and opening times).
    pub(crate) fn record_state(&mut self) -> StepRecord {
        let st = self.stepper.state();
        let t = st.t;
        let found = self.corners.found_at(st.k);
        let r = self.rec.record(t, st, self.iterations, found);
        let s = &mut self.summary;
        s.min_gap = s.min_gap.min(r.min_gap);
        s.max_energy_increase = s.max_energy_increase.max(r.energy - self.energy);
        self.energy = r.energy;
        check_failure(&self.rec, t, s);
        r
    }

    /// The run's summary, up to the current state.
    pub(crate) fn into_summary(self) -> RunSummary {
        let mut s = self.summary;
        s.linear_solves = self.stepper.linear_solves();
        s.linear_solves_by_stage = self.stepper.solves_by_stage();
        s.newton_work = self.stepper.newton_work();
        let stats = self.stepper.run_stats();
        s.resting_steps = stats.resting_steps;
        s.held_island_steps = stats.held_island_steps;
        s.island_wakes = stats.island_wakes;
        s.corner_contacts = self.corners.most_contacts;
        s.redone_steps = self.corners.redone_steps;
        s.deepest = self.rec.deepest;
        s.events = self.rec.watch.into_events();
        s.final_poses = final_poses(self.scene, &self.stepper.state().q);
        if s.steps > 0 {
            s.newton_iterations_mean = self.total_iterations as f64 / s.steps as f64;
        }
        if !s.max_energy_increase.is_finite() {
            s.max_energy_increase = 0.0;
        }
        s.wall_time_s = self.solver_time;
        s
    }

    fn sample(&mut self) {
        let st = self.stepper.state();
        let n = self.scene.n_blocks();
        if n > 0 {
            let p = Pose::from_slice(&st.q[3 * (n - 1)..3 * n]);
            self.top.push([st.t, p.y, p.theta]);
        }
    }

    fn write_row(&mut self, rec: &crate::simulation::StepRecord) {
        if self.csv.is_none() {
            return;
        }
        let st = self.stepper.state();
        let laws = law_cells(&self.contact_check(st), st, self.scene.n_interfaces());
        if let Some(csv) = self.csv.as_mut() {
            if let Err(e) = write_branch_row(csv, rec, &laws) {
                self.trajectory_error = Some(e.to_string());
                self.csv = None;
            }
        }
    }
}

impl Walker for StackWalker<'_> {
    type Outcome = BranchSummary;

    fn begin(&mut self, id: usize) {
        self.top.clear();
        self.csv = None;
        let Some(dir) = self.trajectories else {
            return;
        };
        let path = trajectory_path(dir, id);
        let opened = File::create(&path).and_then(|f| {
            let mut w = BufWriter::new(f);
            writeln!(w, "{}", branch_header(self.scene).join(","))?;
            Ok(w)
        });
        match opened {
            Ok(w) => self.csv = Some(w),
            Err(e) => self.trajectory_error = Some(format!("{}: {e}", path.display())),
        }
    }

    fn step(&mut self) -> Result<Option<BranchPoint>, StepError> {
        if self.classify {
            self.history.push(self.stepper.state());
        }
        let clock = Instant::now();
        let stepped =
            self.corners
                .step(self.scene, &mut self.stepper, self.summary.penetration_tol);
        self.solver_time += clock.elapsed().as_secs_f64();
        if let Err(e) = stepped {
            // A step the caller stopped did not fail.
            if !matches!(e, StepError::Interrupted { .. }) {
                self.summary.failed_steps += 1;
            }
            return Err(e);
        }
        let stats = self.stepper.last_step().expect("a step was taken");
        self.iterations = stats.iterations;
        self.total_iterations += stats.iterations;
        self.summary.count_step(stats, self.record_branches);
        let point = forkable(stats);
        if let Some(p) = &point {
            let candidates: Vec<ContactCheck> = p
                .candidates
                .iter()
                .map(|(_, st)| self.contact_check(st))
                .collect();
            let evidence = self
                .classify
                .then(|| check_fork(self, &self.history, p, &candidates));
            self.checks.push(CheckedFork {
                k: self.stepper.state().k - 1,
                candidates,
                evidence,
            });
        }
        Ok(point)
    }

    fn observe(&mut self) {
        let rec = self.record_state();
        self.write_row(&rec);
        if self.top.is_empty() || self.stepper.state().k.is_multiple_of(self.sample_every) {
            self.sample();
        }
    }

    fn state(&self) -> &State {
        self.stepper.state()
    }

    fn done(&self) -> bool {
        self.stepper.state().k >= self.horizon
            || (self.stop_at_failure && self.summary.failure_time.is_some())
    }

    fn fork(&self, candidate: State) -> Self {
        self.branch(self.stepper.branch_from(candidate))
    }

    fn park(&mut self) {
        self.stepper.release_buffers();
    }

    fn finish(&mut self, end: &BranchEnd) -> BranchSummary {
        // A forked branch's last state is the fork's start, already sampled or not.
        if *end != BranchEnd::Forked
            && self.top.last().map(|s| s[0]) != Some(self.stepper.state().t)
        {
            self.sample();
        }
        if let Some(n) = self.finished {
            n.fetch_add(1, Ordering::Relaxed);
        }
        if let Some(mut csv) = self.csv.take() {
            if let Err(e) = csv.flush() {
                self.trajectory_error = Some(e.to_string());
            }
        }
        BranchSummary {
            final_poses: final_poses(self.scene, &self.stepper.state().q),
            failure_time: self.summary.failure_time,
            events: self.rec.watch.events().to_vec(),
            fallback_steps: self.summary.fallback_steps,
            unshifted_steps: self.summary.unshifted_steps,
            deepest: self.rec.deepest,
            top: std::mem::take(&mut self.top),
            trajectory_error: self.trajectory_error.take(),
            fork_checks: std::mem::take(&mut self.checks),
            end_state: self.keep_end_state.then(|| self.stepper.state().clone()),
        }
    }
}

/// The columns a branch's trajectory adds to a run's ([`trajectory_header_of`]), per
/// interface k (bottom to top): the step's normal impulses `pn{k}a`, `pn{k}b` (left and
/// right corner), friction impulse `pf{k}` and state `state{k}`
/// ([`contact_laws::interface_state`]); then the worst violation of each contact law at
/// the step over every contact ([`contact_laws::Violations`]).
pub const LAW_COLUMNS: [&str; 4] = [
    "gap_violation",
    "normal_violation",
    "cone_violation",
    "complementarity_violation",
];

/// The header of `branch_<id>.csv` for `scene`: its trajectory's
/// ([`trajectory_header_of`]), then the impulses and states of each interface
/// ([`Scene::n_interfaces`]) and [`LAW_COLUMNS`].
#[must_use]
pub fn branch_header(scene: &Scene) -> Vec<String> {
    let mut h = trajectory_header_of(scene);
    for k in 1..=scene.n_interfaces() {
        h.extend([
            format!("pn{k}a"),
            format!("pn{k}b"),
            format!("pf{k}"),
            format!("state{k}"),
        ]);
    }
    h.extend(LAW_COLUMNS.iter().map(|c| (*c).to_owned()));
    h
}

/// The cells [`branch_header`] adds for the state `st` checked in `check`, `n` interfaces.
fn law_cells(check: &ContactCheck, st: &State, n: usize) -> Vec<String> {
    let mut cells = Vec::with_capacity(4 * n + LAW_COLUMNS.len());
    for (k, state) in check.states.iter().enumerate().take(n) {
        cells.extend([
            finite_text(st.p_n[2 * k]),
            finite_text(st.p_n[2 * k + 1]),
            finite_text(st.p_f[k]),
            state.clone(),
        ]);
    }
    cells.extend(
        check
            .violations
            .by_law()
            .iter()
            .map(|(_, v)| finite_text(*v)),
    );
    cells
}

/// One row of `branch_<id>.csv`: the run's trajectory row, then `laws`.
fn write_branch_row<W: Write>(
    out: &mut W,
    rec: &crate::simulation::StepRecord,
    laws: &[String],
) -> Result<(), crate::record::TrajectoryError> {
    let mut row = Vec::new();
    write_trajectory_row(&mut row, rec)?;
    row.pop(); // its newline
    out.write_all(&row)?;
    writeln!(out, ",{}", laws.join(","))?;
    Ok(())
}

/// The trajectory file of branch `id` in `dir`.
#[must_use]
pub fn trajectory_path(dir: &Path, id: usize) -> PathBuf {
    dir.join(format!("branch_{id:05}.csv"))
}

/// What a user reads from a motion's end: which blocks fell, in the order they fell, and
/// which reached the floor. A block *fell* when it lost its support or tipped past its
/// tipping angle ([`crate::events`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct Outcome {
    /// The blocks that fell (1-based), in the order of their first such event.
    pub fell: Vec<usize>,
    /// The blocks that touched the floor (1-based, ascending).
    pub on_floor: Vec<usize>,
}

impl Outcome {
    /// The outcome of a motion with these events.
    #[must_use]
    pub fn of(events: &[FailureEvent]) -> Self {
        let mut fell = Vec::new();
        let mut on_floor = Vec::new();
        for e in events {
            let Some(k) = e.block else { continue };
            match e.kind {
                EventKind::SupportLost | EventKind::Tipped if !fell.contains(&k) => fell.push(k),
                EventKind::TouchedFloor if !on_floor.contains(&k) => on_floor.push(k),
                _ => {}
            }
        }
        on_floor.sort_unstable();
        Self { fell, on_floor }
    }

    /// "column standing", or e.g. "blocks 5, 4 fell in that order; 5 on the floor".
    #[must_use]
    pub fn label(&self) -> String {
        let list = |v: &[usize]| {
            v.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        if self.fell.is_empty() {
            return "column standing".into();
        }
        let mut s = match self.fell.len() {
            1 => format!("block {} fell", self.fell[0]),
            _ => format!("blocks {} fell in that order", list(&self.fell)),
        };
        if !self.on_floor.is_empty() {
            s.push_str(&format!("; {} on the floor", list(&self.on_floor)));
        }
        s
    }
}

/// A fork as the stack sees it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ForkRecord {
    /// The branch that met it.
    pub branch: usize,
    /// Time and step number at the start of the forking step.
    pub t: f64,
    /// Step number k at its start.
    pub k: u64,
    /// Fixed-set re-solves tried.
    pub tried: usize,
    /// Distinct candidates.
    pub distinct: usize,
    /// Self-consistent ones among them.
    pub consistent: usize,
    /// Whether its candidates were followed.
    pub followed: bool,
    /// Child branches (empty when not followed).
    pub children: Vec<usize>,
    /// Interfaces (1-based) whose contact states differ between the candidates.
    pub differing_interfaces: Vec<usize>,
    /// Each candidate's interface states (App. H), bottom to top.
    pub states: Vec<Vec<InterfaceState>>,
    /// Whether the corner contacts beyond the stack's interfaces (blocks that fell onto
    /// others or the floor) differ between the candidates.
    pub corner_contacts_differ: bool,
    /// The largest distance between two candidates' (q, u), relative to 1 + ‖q‖ + ‖u‖.
    pub spread: f64,
    /// Each candidate's own step against the contact laws (in the order of `states`).
    pub candidates: Vec<ContactCheck>,
    /// The check against refinement, when it was made.
    pub evidence: Option<ForkEvidence>,
}

impl ForkRecord {
    /// How many of its candidates' own steps break a contact law.
    #[must_use]
    pub fn breaking_laws(&self) -> usize {
        self.candidates
            .iter()
            .filter(|c| !c.broken.is_empty())
            .count()
    }

    /// `real`, `artefact`, `undecided`, or `unchecked`.
    #[must_use]
    pub fn label(&self) -> &'static str {
        self.evidence
            .as_ref()
            .map_or("unchecked", |e| e.label.name())
    }
}

/// The forks of an exploration, in branch order then time, for a scene of `n_interfaces`
/// interfaces ([`Scene::n_interfaces`]; a column: its blocks).
#[must_use]
pub fn fork_records(tree: &Exploration<BranchSummary>, n_interfaces: usize) -> Vec<ForkRecord> {
    tree.forks()
        .map(|(b, f)| {
            let sets = f.candidate_sets();
            let checked = b.outcome.fork_checks.iter().find(|c| c.k == f.k);
            ForkRecord {
                branch: b.id,
                t: f.t,
                k: f.k,
                tried: f.tried,
                distinct: f.sets.len(),
                consistent: f.consistent.iter().filter(|&&c| c).count(),
                followed: f.followed,
                children: f.children.clone(),
                differing_interfaces: differing_interfaces(&sets, n_interfaces),
                states: sets
                    .iter()
                    .map(|s| interface_states(s, n_interfaces))
                    .collect(),
                corner_contacts_differ: sets.iter().any(|s| {
                    let (a, b) = (sets[0], *s);
                    a.a[2 * n_interfaces..] != b.a[2 * n_interfaces..]
                        || a.c[2 * n_interfaces..] != b.c[2 * n_interfaces..]
                        || a.d[n_interfaces..] != b.d[n_interfaces..]
                }),
                spread: f.spread,
                candidates: checked.map(|c| c.candidates.clone()).unwrap_or_default(),
                evidence: checked.and_then(|c| c.evidence.clone()),
            }
        })
        .collect()
}

/// The motions found, grouped by [`Outcome`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct OutcomeGroup {
    /// The outcome.
    pub outcome: Outcome,
    /// Its label.
    pub label: String,
    /// The leaves (branch ids) that end in it.
    pub branches: Vec<usize>,
    /// Smallest, median and largest failure time over them (None when none failed).
    pub failure_time: Option<[f64; 3]>,
}

/// The leaves of `tree` grouped by outcome, most frequent first (ties: outcome order).
#[must_use]
pub fn outcome_groups(tree: &Exploration<BranchSummary>) -> Vec<OutcomeGroup> {
    let mut groups: Vec<OutcomeGroup> = Vec::new();
    for leaf in tree.leaves() {
        let outcome = Outcome::of(&leaf.outcome.events);
        match groups.iter_mut().find(|g| g.outcome == outcome) {
            Some(g) => g.branches.push(leaf.id),
            None => groups.push(OutcomeGroup {
                label: outcome.label(),
                outcome,
                branches: vec![leaf.id],
                failure_time: None,
            }),
        }
    }
    for g in &mut groups {
        let times: Vec<f64> = g
            .branches
            .iter()
            .filter_map(|&id| tree.branches[id].outcome.failure_time)
            .collect();
        g.failure_time = spread_of(times);
    }
    groups.sort_by(|a, b| {
        b.branches
            .len()
            .cmp(&a.branches.len())
            .then_with(|| a.outcome.cmp(&b.outcome))
    });
    groups
}

/// Smallest, median and largest of `v` (None when empty).
#[must_use]
pub fn spread_of(mut v: Vec<f64>) -> Option<[f64; 3]> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    Some([v[0], median, v[n - 1]])
}

/// Explores every continuation of `scene` to its end time (or `options.t_end`): each
/// branch is a [`StackWalker`], and every branch point the stepper meets (its candidates
/// those of `options.branch_rule`) is a fork.
///
/// # Errors
/// Bad run options; a failed consistent start.
pub fn explore_scene(
    scene: &Scene,
    options: &RunOptions,
    explore_options: &ExploreOptions,
    settings: WalkSettings<'_>,
) -> Result<Exploration<BranchSummary>, BlockError> {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    input::positive("t_end", t_end)?;
    let steps = step_count(t_end, scene.solver.dt) as u64;
    let root = StackWalker::new(scene, options, steps, settings)?;
    Ok(explore(root, explore_options))
}

/// How many forks got each label.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct LabelCounts {
    /// Real bifurcations.
    pub real: usize,
    /// Solver artefacts.
    pub artefact: usize,
    /// Undecided.
    pub undecided: usize,
    /// Not checked (`classify` off).
    pub unchecked: usize,
}

/// The headline numbers of an exploration (`rollstack blocks explore --json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct ExplorationReport {
    /// Branches (the root included).
    pub branches: usize,
    /// Branches that did not fork: the motions found.
    pub leaves: usize,
    /// Forks met, followed or not.
    pub forks: usize,
    /// Forks whose candidates were followed.
    pub forks_followed: usize,
    /// Candidates over all forks.
    pub candidates: usize,
    /// Candidates whose own step breaks a contact law ([`crate::contact_laws`]).
    pub candidates_breaking_laws: usize,
    /// Branches that start with a step breaking a contact law: the followed candidates
    /// that break one.
    pub branches_breaking_laws: usize,
    /// Distinct outcomes among the leaves.
    pub distinct_outcomes: usize,
    /// Labels of the forks.
    pub labels: LabelCounts,
    /// Whether the branch cap kept a fork from being followed.
    pub branch_cap_reached: bool,
    /// Whether the depth cap kept a fork from being followed.
    pub depth_cap_reached: bool,
    /// Whether the wall-time cap stopped running branches.
    pub wall_cap_reached: bool,
    /// Leaves that ended on a failed step.
    pub failed_leaves: usize,
    /// Steps simulated over all branches (the shared past counted once).
    pub steps: u64,
    /// Steps taken by the last resort over all branches.
    pub fallback_steps: usize,
    /// Steps taken without the friction percussions' half-step shift over all branches.
    pub unshifted_steps: usize,
    /// The deepest penetration between two bodies over all branches.
    pub max_penetration: f64,
    /// Wall time of the exploration, s.
    pub wall_time_s: f64,
    /// The outcomes, most frequent first.
    pub outcomes: Vec<OutcomeGroup>,
}

impl ExplorationReport {
    /// The report of `tree` (with its `forks` and outcome `groups`).
    #[must_use]
    pub fn new(
        tree: &Exploration<BranchSummary>,
        forks: &[ForkRecord],
        groups: Vec<OutcomeGroup>,
    ) -> Self {
        let mut labels = LabelCounts::default();
        for f in forks {
            match f.evidence.as_ref().map(|e| e.label) {
                Some(ForkLabel::Real) => labels.real += 1,
                Some(ForkLabel::Artefact) => labels.artefact += 1,
                Some(ForkLabel::Undecided) => labels.undecided += 1,
                None => labels.unchecked += 1,
            }
        }
        Self {
            branches: tree.branches.len(),
            leaves: tree.leaves().count(),
            forks: forks.len(),
            forks_followed: forks.iter().filter(|f| f.followed).count(),
            candidates: forks.iter().map(|f| f.distinct).sum(),
            candidates_breaking_laws: forks.iter().map(ForkRecord::breaking_laws).sum(),
            branches_breaking_laws: forks
                .iter()
                .filter(|f| f.followed)
                .map(ForkRecord::breaking_laws)
                .sum(),
            distinct_outcomes: groups.len(),
            labels,
            branch_cap_reached: tree.branch_cap_reached,
            depth_cap_reached: tree.depth_cap_reached,
            wall_cap_reached: tree.wall_cap_reached,
            failed_leaves: tree
                .leaves()
                .filter(|b| matches!(b.end, BranchEnd::Failed(_)))
                .count(),
            steps: tree.branches.iter().map(nsga::explore::Branch::steps).sum(),
            fallback_steps: tree.branches.iter().map(|b| b.outcome.fallback_steps).sum(),
            unshifted_steps: tree
                .branches
                .iter()
                .map(|b| b.outcome.unshifted_steps)
                .sum(),
            max_penetration: tree
                .branches
                .iter()
                .map(|b| b.outcome.deepest.depth())
                .fold(0.0, f64::max),
            wall_time_s: tree.wall_time.as_secs_f64(),
            outcomes: groups,
        }
    }
}

/// Columns of `branches.csv`.
pub const BRANCH_COLUMNS: [&str; 13] = [
    "id",
    "parent",
    "candidate",
    "depth",
    "t_start",
    "t_end",
    "steps",
    "end",
    "forks_passed",
    "failure_time",
    "fallback_steps",
    "unshifted_steps",
    "outcome",
];

/// One row of `branches.csv` ([`BRANCH_COLUMNS`]); the outcome only for leaves.
#[must_use]
pub fn branch_cells(b: &nsga::explore::Branch<BranchSummary>) -> Vec<String> {
    let passed = b.forks.iter().filter(|f| !f.followed).count();
    let outcome = if b.end == BranchEnd::Forked {
        String::new()
    } else {
        Outcome::of(&b.outcome.events).label()
    };
    vec![
        b.id.to_string(),
        b.parent.map_or(String::new(), |p| p.0.to_string()),
        b.parent.map_or(String::new(), |p| p.1.to_string()),
        b.depth.to_string(),
        number_text(b.start.0),
        number_text(b.end_at.0),
        b.steps().to_string(),
        b.end.name().to_owned(),
        passed.to_string(),
        optional_text(b.outcome.failure_time),
        b.outcome.fallback_steps.to_string(),
        b.outcome.unshifted_steps.to_string(),
        outcome,
    ]
}

/// Columns of `forks.csv`.
pub const FORK_COLUMNS: [&str; 23] = [
    "branch",
    "t",
    "k",
    "tried",
    "distinct",
    "consistent",
    "followed",
    "children",
    "differing_interfaces",
    "corner_contacts_differ",
    "spread",
    "label",
    "refined_dt2",
    "refined_dt4",
    "other_prox",
    "refined_converged_dt2",
    "refined_converged_dt4",
    "window",
    "stepped_back",
    "candidate_states",
    "breaks",
    "violation",
    "why",
];

impl ForkRecord {
    /// One row of `forks.csv` ([`FORK_COLUMNS`]); lists are separated by spaces.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let count = |c: Option<usize>| c.map_or(String::new(), |c| c.to_string());
        let e = self.evidence.as_ref();
        vec![
            self.branch.to_string(),
            number_text(self.t),
            self.k.to_string(),
            self.tried.to_string(),
            self.distinct.to_string(),
            self.consistent.to_string(),
            self.followed.to_string(),
            space_list(&self.children),
            space_list(&self.differing_interfaces),
            self.corner_contacts_differ.to_string(),
            number_text(self.spread),
            self.label().to_owned(),
            count(e.and_then(|e| e.refined[0])),
            count(e.and_then(|e| e.refined[1])),
            count(e.and_then(|e| e.other_prox)),
            count(e.and_then(|e| e.refined_converged[0])),
            count(e.and_then(|e| e.refined_converged[1])),
            e.map_or(String::new(), |e| e.window.to_string()),
            e.and_then(|e| e.stepped_back)
                .map_or(String::new(), |b| b.to_string()),
            self.per_candidate(|c| c.states.join("|")),
            self.per_candidate(|c| breaks_text(&c.broken)),
            self.per_candidate(|c| violation_text(&c.broken)),
            e.map_or(String::new(), |e| e.why.clone()),
        ]
    }

    /// One cell with a word per candidate, separated by spaces.
    fn per_candidate(&self, word: impl Fn(&ContactCheck) -> String) -> String {
        self.candidates
            .iter()
            .map(word)
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// Columns of `outcomes.csv`.
pub const OUTCOME_COLUMNS: [&str; 7] = [
    "outcome",
    "leaves",
    "fell",
    "on_floor",
    "failure_time_min",
    "failure_time_median",
    "failure_time_max",
];

impl OutcomeGroup {
    /// One row of `outcomes.csv` ([`OUTCOME_COLUMNS`]).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let t = |i: usize| optional_text(self.failure_time.map(|f| f[i]));
        vec![
            self.label.clone(),
            self.branches.len().to_string(),
            space_list(&self.outcome.fell),
            space_list(&self.outcome.on_floor),
            t(0),
            t(1),
            t(2),
        ]
    }
}

/// A row value over the motions of an exploration: how many leaves, and the smallest,
/// median and largest value over those that have one (Figures 4.6–4.7 as bands).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LeafSpread {
    /// Leaves explored (1 for a plain run).
    pub branches: usize,
    /// Leaves that have a value.
    pub valued: usize,
    /// Smallest, median and largest value, None when no leaf has one.
    pub spread: Option<[f64; 3]>,
}

/// The spread of a sweep row's value over the motions of its run: with
/// [`RunOptions::spread_branches`] > 1, `scene` explored to that many branches (breadth
/// first, the run options' branch rule), `value` of each leaf; otherwise the plain run's
/// value `plain` alone. `stop_at_failure` ends each branch at its first loss of support.
///
/// # Errors
/// Bad run options; a failed consistent start.
pub fn leaf_spread(
    scene: &Scene,
    options: &RunOptions,
    stop_at_failure: bool,
    plain: Option<f64>,
    value: impl Fn(&nsga::explore::Branch<BranchSummary>) -> Option<f64>,
) -> Result<LeafSpread, BlockError> {
    if options.spread_branches <= 1 {
        return Ok(LeafSpread {
            branches: 1,
            valued: usize::from(plain.is_some()),
            spread: plain.map(|v| [v; 3]),
        });
    }
    let explore_options = ExploreOptions {
        max_branches: options.spread_branches,
        ..ExploreOptions::default()
    };
    let settings = WalkSettings {
        sample_every: u64::MAX,
        stop_at_failure,
        ..WalkSettings::default()
    };
    let tree = explore_scene(scene, options, &explore_options, settings)?;
    let values: Vec<f64> = tree.leaves().filter_map(&value).collect();
    Ok(LeafSpread {
        branches: tree.leaves().count(),
        valued: values.len(),
        spread: spread_of(values),
    })
}

/// Numbers separated by spaces: a list in one CSV cell.
fn space_list(v: &[usize]) -> String {
    v.iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(" ")
}
