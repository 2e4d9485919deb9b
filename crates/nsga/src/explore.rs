//! Exploring every continuation of a run: the tree of branches that grows from its
//! branch points (docs/method.md §8.4, "Exploring the branches").
//!
//! A step whose Newton iterates cycle is re-solved with each visited index-set row fixed;
//! its distinct solutions that the [`BranchRule`](crate::BranchRule) keeps
//! ([`BranchPoint::candidates`], deduplicated by [`State::same_motion`]) are the step's
//! continuations. A plain run keeps one of them.
//! [`explore`] keeps them all: a **branch** runs from its first state until it forks,
//! fails or reaches its horizon; at a followed fork it ends, and every candidate starts a
//! child branch from the fork's end state (the common past is never simulated again).
//!
//! The exploration knows no physics: it drives a [`Walker`], which takes the steps,
//! records what it wants (a trajectory streamed to disk, a summary), says when its
//! horizon is reached and continues from a given state. [`StepperWalker`] walks a bare
//! [`Stepper`].
//!
//! # Strategies, caps, determinism
//!
//! - [`Strategy::Breadth`] advances the tree one generation at a time: every live branch
//!   runs to its next fork (or its end) in parallel on rayon, then the forks of the
//!   generation are followed in branch-id order.
//! - [`Strategy::Depth`] follows the first candidate of each fork to its end before its
//!   siblings, one branch at a time (memory: one walker per pending sibling).
//! - Caps end a run cleanly with what was found: at most [`ExploreOptions::max_branches`]
//!   branches (a fork whose candidates do not all fit is not followed), forks below
//!   [`ExploreOptions::max_depth`] not followed, and an optional wall-time limit (the
//!   branches running when it passes end where they are, [`BranchEnd::WallTime`]).
//!   A fork that is not followed is still recorded; its branch goes on with the candidate
//!   the system chose, as a plain run would.
//! - Ids are given in the order the forks are followed (breadth: generation, then parent
//!   id, then candidate order; depth: the order of the depth-first walk), so the tree and
//!   everything derived from it are the same whatever the number of rayon threads,
//!   unless the wall-time cap ends the run.

use crate::error::StepError;
use crate::report::BranchPoint;
use crate::sets::IndexSets;
use crate::state::State;
use crate::stepper::Stepper;
use crate::system::System;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// What the exploration drives along one branch.
pub trait Walker: Send + Sized {
    /// What a branch leaves behind when it ends (kept for every branch: keep it small).
    type Outcome: Send;

    /// Starts branch `id` (called once per branch, before its first [`Walker::observe`]).
    fn begin(&mut self, id: usize);
    /// Takes one step, without recording it. Returns the step's branch point when it has
    /// more than one candidate the exploration could follow (candidates that are states
    /// of the whole step, not of a substep).
    ///
    /// # Errors
    /// The step's error; the branch then ends ([`BranchEnd::Failed`]).
    fn step(&mut self) -> Result<Option<BranchPoint>, StepError>;
    /// Records the current state as a state of the current branch (after `begin`, and
    /// after each step the branch keeps).
    fn observe(&mut self);
    /// The current state.
    fn state(&self) -> &State;
    /// Whether the branch has reached its horizon.
    fn done(&self) -> bool;
    /// A walker that continues from `candidate`, a state of the branch point the last
    /// step returned.
    fn fork(&self, candidate: State) -> Self;
    /// Ends the current branch.
    fn finish(&mut self, end: &BranchEnd) -> Self::Outcome;
    /// Frees what the walker can rebuild (solver buffers) while it waits for the rest of
    /// its generation: a breadth-first tree holds one walker per live branch.
    fn park(&mut self) {}
}

/// How the tree is grown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// One generation at a time, the branches of a generation in parallel.
    #[default]
    Breadth,
    /// Depth first, one branch at a time.
    Depth,
}

impl Strategy {
    /// `breadth` or `depth`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Breadth => "breadth",
            Self::Depth => "depth",
        }
    }
}

/// Caps and strategy of an exploration.
#[derive(Debug, Clone, PartialEq)]
pub struct ExploreOptions {
    /// Breadth or depth first.
    pub strategy: Strategy,
    /// Most branches, the root included (≥ 1).
    pub max_branches: usize,
    /// Most followed forks on the way from the root to a branch.
    pub max_depth: usize,
    /// Wall time after which running branches stop (None: no limit).
    pub max_wall: Option<Duration>,
}

impl Default for ExploreOptions {
    fn default() -> Self {
        Self {
            strategy: Strategy::Breadth,
            max_branches: 1000,
            max_depth: usize::MAX,
            max_wall: None,
        }
    }
}

/// Why a branch ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BranchEnd {
    /// It reached its horizon.
    Horizon,
    /// It forked: its children continue it.
    Forked,
    /// A step failed; the message says why.
    Failed(String),
    /// The wall-time cap passed.
    WallTime,
}

impl BranchEnd {
    /// `horizon`, `forked`, `failed` or `wall_time`.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Horizon => "horizon",
            Self::Forked => "forked",
            Self::Failed(_) => "failed",
            Self::WallTime => "wall_time",
        }
    }
}

/// A branch point met by a branch: what is kept of it once it is decided (the candidate
/// states themselves live on in the child branches).
#[derive(Debug, Clone, PartialEq)]
pub struct Fork {
    /// Time t_n at the start of the forking step.
    pub t: f64,
    /// Step number at the start of the forking step.
    pub k: u64,
    /// The index sets each candidate was solved with.
    pub sets: Vec<IndexSets>,
    /// Whether each candidate is self-consistent ([`BranchPoint::consistent`]).
    pub consistent: Vec<bool>,
    /// Fixed-set re-solves tried.
    pub tried: usize,
    /// The candidate a plain run continues with.
    pub chosen: usize,
    /// The largest distance between two candidates ([`State::relative_distance`]).
    pub spread: f64,
    /// Whether its candidates were followed as child branches.
    pub followed: bool,
    /// The child branch of each candidate (empty when not followed).
    pub children: Vec<usize>,
}

impl Fork {
    /// The fork of `point`, met on the step that starts at (t, k).
    fn of((t, k): (f64, u64), point: &BranchPoint) -> Self {
        let c = &point.candidates;
        let mut spread: f64 = 0.0;
        for (i, (_, a)) in c.iter().enumerate() {
            for (_, b) in &c[i + 1..] {
                spread = spread.max(a.relative_distance(b));
            }
        }
        Self {
            t,
            k,
            sets: c.iter().map(|(s, _)| s.clone()).collect(),
            consistent: point.consistent.clone(),
            tried: point.tried,
            chosen: point.chosen,
            spread,
            followed: false,
            children: Vec::new(),
        }
    }

    /// The index sets of the candidates.
    #[must_use]
    pub fn candidate_sets(&self) -> Vec<&IndexSets> {
        self.sets.iter().collect()
    }
}

/// One branch of the tree.
#[derive(Debug, Clone)]
pub struct Branch<O> {
    /// Its id (0: the root).
    pub id: usize,
    /// The branch it forked from, with the index of its candidate there.
    pub parent: Option<(usize, usize)>,
    /// Followed forks between the root and it.
    pub depth: usize,
    /// Time and step number of its first state.
    pub start: (f64, u64),
    /// Time and step number of its last state.
    pub end_at: (f64, u64),
    /// The forks it met, in time order; only the last can be followed.
    pub forks: Vec<Fork>,
    /// Why it ended.
    pub end: BranchEnd,
    /// What its walker left.
    pub outcome: O,
}

impl<O> Branch<O> {
    /// Steps taken on this branch.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.end_at.1 - self.start.1
    }
    /// The followed fork at its end, if it forked.
    #[must_use]
    pub fn followed_fork(&self) -> Option<&Fork> {
        self.forks.last().filter(|f| f.followed)
    }
}

/// The tree an exploration grew.
#[derive(Debug, Clone)]
pub struct Exploration<O> {
    /// All branches, by id.
    pub branches: Vec<Branch<O>>,
    /// Whether a fork was not followed because of [`ExploreOptions::max_branches`].
    pub branch_cap_reached: bool,
    /// Whether a fork was not followed because of [`ExploreOptions::max_depth`].
    pub depth_cap_reached: bool,
    /// Whether the wall-time cap ended running branches.
    pub wall_cap_reached: bool,
    /// Wall time of the exploration.
    pub wall_time: Duration,
}

impl<O> Exploration<O> {
    /// The branches that did not fork: one per motion found.
    pub fn leaves(&self) -> impl Iterator<Item = &Branch<O>> {
        self.branches.iter().filter(|b| b.end != BranchEnd::Forked)
    }
    /// Every fork met, followed or not, with the branch that met it.
    pub fn forks(&self) -> impl Iterator<Item = (&Branch<O>, &Fork)> {
        self.branches
            .iter()
            .flat_map(|b| b.forks.iter().map(move |f| (b, f)))
    }
}

/// A branch while it runs.
struct Live<W> {
    walker: W,
    id: usize,
    parent: Option<(usize, usize)>,
    depth: usize,
    start: (f64, u64),
    forks: Vec<Fork>,
}

/// How a run of a live branch up to its next decision ended.
enum Stop {
    /// Horizon, failure or wall time: the branch is over.
    Over(BranchEnd),
    /// A fork that the scheduler may follow, with its candidates' states.
    Fork(Fork, Vec<State>),
}

/// Runs `live` until it ends or meets a fork it may follow (`may_fork`); forks it may
/// not follow are recorded and passed.
fn advance<W: Walker>(live: &mut Live<W>, may_fork: bool, deadline: Option<Instant>) -> Stop {
    loop {
        if live.walker.done() {
            return Stop::Over(BranchEnd::Horizon);
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            return Stop::Over(BranchEnd::WallTime);
        }
        let at = (live.walker.state().t, live.walker.state().k);
        match live.walker.step() {
            Err(e) => return Stop::Over(BranchEnd::Failed(e.to_string())),
            Ok(Some(point)) => {
                let fork = Fork::of(at, &point);
                if may_fork {
                    let states = point.candidates.into_iter().map(|(_, s)| s).collect();
                    return Stop::Fork(fork, states);
                }
                live.forks.push(fork);
                live.walker.observe();
            }
            Ok(None) => live.walker.observe(),
        }
    }
}

/// The tree's bookkeeping while it grows.
struct Tree<O> {
    done: Vec<Option<Branch<O>>>,
    options: ExploreOptions,
    branch_cap_reached: bool,
    depth_cap_reached: bool,
    wall_cap_reached: bool,
}

impl<O> Tree<O> {
    /// Whether a branch of `depth` may still stop at a fork to follow it.
    fn may_fork(&self, depth: usize) -> bool {
        depth < self.options.max_depth && self.done.len() + 2 <= self.options.max_branches
    }

    /// Notes which cap made a branch of `depth` pass a fork.
    fn passed_fork(&mut self, depth: usize) {
        if depth >= self.options.max_depth {
            self.depth_cap_reached = true;
        } else {
            self.branch_cap_reached = true;
        }
    }

    /// Notes the caps behind the forks `live` passed while it ran (`known` forks before).
    fn note_passed<W>(&mut self, live: &Live<W>, known: usize) {
        if live.forks.len() > known {
            self.passed_fork(live.depth);
        }
    }

    /// Ends `live` with `end`.
    fn close<W: Walker<Outcome = O>>(&mut self, mut live: Live<W>, end: BranchEnd) {
        if end == BranchEnd::WallTime {
            self.wall_cap_reached = true;
        }
        let outcome = live.walker.finish(&end);
        // A forked branch ends where its fork's step starts: the step is its children's.
        let end_at = match (&end, live.forks.last()) {
            (BranchEnd::Forked, Some(f)) => (f.t, f.k),
            _ => (live.walker.state().t, live.walker.state().k),
        };
        self.done[live.id] = Some(Branch {
            id: live.id,
            parent: live.parent,
            depth: live.depth,
            start: live.start,
            end_at,
            forks: live.forks,
            end,
            outcome,
        });
    }

    /// Decides a fork met by `live`: its children (to run), or `live` itself going on
    /// with the chosen candidate when a cap forbids following it.
    fn decide<W: Walker<Outcome = O>>(
        &mut self,
        mut live: Live<W>,
        mut fork: Fork,
        states: Vec<State>,
    ) -> Vec<Live<W>> {
        let n = states.len();
        let fits = self.done.len() + n <= self.options.max_branches;
        if live.depth >= self.options.max_depth || !fits {
            self.passed_fork(live.depth);
            live.forks.push(fork);
            live.walker.observe();
            return vec![live];
        }
        let mut children = Vec::with_capacity(n);
        for (i, state) in states.into_iter().enumerate() {
            let id = self.done.len();
            self.done.push(None);
            let start = (state.t, state.k);
            let mut walker = live.walker.fork(state);
            walker.begin(id);
            walker.observe();
            fork.children.push(id);
            children.push(Live {
                walker,
                id,
                parent: Some((live.id, i)),
                depth: live.depth + 1,
                start,
                forks: Vec::new(),
            });
        }
        fork.followed = true;
        live.forks.push(fork);
        self.close(live, BranchEnd::Forked);
        children
    }
}

/// Explores every continuation of `root` from its current state (see the module docs).
#[must_use]
pub fn explore<W: Walker>(mut root: W, options: &ExploreOptions) -> Exploration<W::Outcome> {
    let clock = Instant::now();
    let deadline = options.max_wall.map(|w| clock + w);
    root.begin(0);
    root.observe();
    let st = root.state();
    let live = Live {
        id: 0,
        parent: None,
        depth: 0,
        start: (st.t, st.k),
        forks: Vec::new(),
        walker: root,
    };
    let mut tree = Tree {
        done: vec![None],
        options: ExploreOptions {
            max_branches: options.max_branches.max(1),
            ..options.clone()
        },
        branch_cap_reached: false,
        depth_cap_reached: false,
        wall_cap_reached: false,
    };
    match options.strategy {
        Strategy::Breadth => breadth(&mut tree, live, deadline),
        Strategy::Depth => depth_first(&mut tree, live, deadline),
    }
    Exploration {
        branches: tree
            .done
            .into_iter()
            .map(|b| b.expect("every branch ends"))
            .collect(),
        branch_cap_reached: tree.branch_cap_reached,
        depth_cap_reached: tree.depth_cap_reached,
        wall_cap_reached: tree.wall_cap_reached,
        wall_time: clock.elapsed(),
    }
}

/// Generation by generation: the live branches run in parallel to their next decision,
/// then their forks are decided in id order.
fn breadth<W: Walker>(tree: &mut Tree<W::Outcome>, root: Live<W>, deadline: Option<Instant>) {
    let mut generation = vec![root];
    while !generation.is_empty() {
        let may: Vec<bool> = generation.iter().map(|l| tree.may_fork(l.depth)).collect();
        let stops: Vec<(Live<W>, usize, Stop)> = generation
            .into_par_iter()
            .zip(may)
            .map(|(mut live, may_fork)| {
                let known = live.forks.len();
                let stop = advance(&mut live, may_fork, deadline);
                live.walker.park();
                (live, known, stop)
            })
            .collect();
        let mut next = Vec::new();
        for (live, known, stop) in stops {
            tree.note_passed(&live, known);
            match stop {
                Stop::Over(end) => tree.close(live, end),
                Stop::Fork(fork, states) => next.extend(tree.decide(live, fork, states)),
            }
        }
        next.sort_by_key(|l| l.id);
        generation = next;
    }
}

/// Depth first: the first candidate of each fork is run to its end before its siblings.
fn depth_first<W: Walker>(tree: &mut Tree<W::Outcome>, root: Live<W>, deadline: Option<Instant>) {
    let mut stack = vec![root];
    while let Some(mut live) = stack.pop() {
        let (may_fork, known) = (tree.may_fork(live.depth), live.forks.len());
        let stop = advance(&mut live, may_fork, deadline);
        tree.note_passed(&live, known);
        match stop {
            Stop::Over(end) => tree.close(live, end),
            Stop::Fork(fork, states) => {
                let mut next = tree.decide(live, fork, states);
                next.reverse();
                stack.extend(next);
            }
        }
    }
}

/// A [`Walker`] over a bare [`Stepper`], up to a number of steps; its outcome is the
/// final state.
#[derive(Debug)]
pub struct StepperWalker<S: System> {
    /// The stepper.
    pub stepper: Stepper<S>,
    /// Step number k at which branches end.
    pub horizon: u64,
}

impl<S: System + Clone + Send> Walker for StepperWalker<S> {
    type Outcome = State;

    fn begin(&mut self, _id: usize) {}
    fn step(&mut self) -> Result<Option<BranchPoint>, StepError> {
        let stats = self.stepper.step()?;
        Ok(forkable(stats))
    }
    fn observe(&mut self) {}
    fn state(&self) -> &State {
        self.stepper.state()
    }
    fn done(&self) -> bool {
        self.stepper.state().k >= self.horizon
    }
    fn fork(&self, candidate: State) -> Self {
        Self {
            stepper: self.stepper.branch_from(candidate),
            horizon: self.horizon,
        }
    }
    fn finish(&mut self, _end: &BranchEnd) -> State {
        self.stepper.state().clone()
    }
    fn park(&mut self) {
        self.stepper.release_buffers();
    }
}

/// The branch point of an accepted step when an exploration can follow it: more than one
/// candidate, and candidates that are states of the whole step (a step taken as
/// substeps forks within a substep, whose candidates end mid-step).
#[must_use]
pub fn forkable(stats: &crate::report::StepStats) -> Option<BranchPoint> {
    stats
        .branch
        .as_ref()
        .filter(|b| b.candidates.len() > 1 && stats.substeps == 1)
        .cloned()
}
