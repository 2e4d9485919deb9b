//! Running a scene with the nonsmooth generalized-α stepper (§4.2–4.5): records per
//! step, the failure times of §4.4, energy, branch points, and a summary.
//!
//! - **Start** (§4.3): nsga's consistent start (docs/method.md §5) solves the
//!   acceleration-level contact problem of the contacts closed at t = 0 (each may stay
//!   closed or separate, stick or slide), so a resting column starts with its static
//!   contact forces and no first-step impulse.
//! - **Failure** (§4.4, Figure 4.6): `failure_time` is the first time any block has lost
//!   its support on the block beneath ((G.2.4) corrected, ERRATA 23); `opening_time` the
//!   first time any interface is open along its whole edge (both gaps above
//!   [`OPEN_GAP_TOL`] times the block height) or unsupported.
//! - **Energy**: kinetic plus potential energy of the free blocks; with a fixed base,
//!   e_N = e_F = 0 and Coulomb friction it must never increase ([`RunSummary`]'s
//!   `max_energy_increase`).
//! - **A step that does not converge** goes through nsga's fallback policy
//!   ([`nsga::Stepper::step`], docs/method.md §8), configured here by
//!   [`stepper_options`]: no retries with other ρ∞ (they did not pay); when the index
//!   sets alternate, re-solves with each distinct set
//!   fixed, continuing with the first self-consistent candidate (a branch point,
//!   ERRATA 22), recorded with the number of sets tried and of distinct converged
//!   states; then the step as two half steps with this same policy (up to
//!   [`MAX_HALVINGS`] times); with branch exploration on, finally re-solves that accept
//!   friction laws sitting exactly on their stick–slip bound
//!   ([`nsga::PolicyOptions::boundary_resolves`]).
//! - **Redundant contacts**: a toppled column resting on the table edge and on the floor
//!   with several corners touches at more points than it has degrees of freedom; nsga's
//!   regularized Newton update ([`nsga::LinearOptions::regularization`]) carries it.
//! - **Errors**: a step that fails after every fallback ends the run; the summary up to
//!   it carries the typed error ([`RunError`], with the state it failed at), it is not
//!   an `Err`.

use crate::coordinates::Pose;
use crate::error::BlockError;
use crate::events::{EventKind, EventWatch, FailureEvent};
use crate::overlap::{deepest_penetration, Penetration};
use crate::scene::Scene;
use crate::scene_info::{Defaults, SceneReport, SceneWarning};
use crate::stack::StackContacts;
use crate::stepping::CornerStepping;
use crate::system::StackSystem;
use nsga::{
    LinearOptions, NewtonOptions, Options, PolicyOptions, SolverChoice, StepError, Stepper,
};
use std::ops::ControlFlow;
use std::time::Instant;

pub use crate::time_guard::{run_cost, RunCost, SECONDS_PER_BLOCK_STEP, TIME_BOUND_S};
pub use nsga::Prox;

/// The errors of [`simulate`]: bad scenes or options.
pub type BlockstackError = BlockError;

/// Relative tolerance (of the block height) above which a gap counts as open when
/// deciding that an interface has opened completely.
pub const OPEN_GAP_TOL: f64 = 1e-6;

/// Relative tolerance (of the smallest block height) above which a penetration between
/// two bodies is reported as a warning: the stack's own contacts close to the Newton
/// tolerance, many orders below it, so a deeper one is a body passing through another.
pub const PENETRATION_TOL: f64 = 1e-6;

/// Unknowns up to which the Newton matrix is factorized by [`nsga::MarkowitzLu`] (dense
/// storage, sparse elimination); above, by faer's sparse LU.
///
/// Measured on the Lire collapse on a floor (124 unknowns, fewer while the floor contacts
/// are open and pruned): the whole run is about twice as fast with dense LU as with
/// faer's sparse LU, and Markowitz LU, which skips the zeros that make up most of these
/// matrices, is faster again (`cargo run --release -p blockstack --example lire_nearby
/// 60 --floor`, paired
/// runs: median solver time 105–114 ms against 126–127 ms with dense LU). Blocks piled on
/// the floor make matrices of 200 to 400 unknowns, on which Markowitz LU is still about
/// twice as fast as faer's sparse LU, and finds many of the singular ones (redundant
/// contacts) by their structure, where faer's took longer than a regular factorization:
/// up to 384 unknowns (its largest size) instead of 200, the 36 columns of 10 to 20
/// blocks collapsing into piles (docs/method.md §7, "Crossovers") take 14.0 s of solver
/// time instead of 20.0 s. Above it, the banded matrix of a tall column needs the sparse
/// solver. Both small solvers detect the singular matrices of redundant contacts by their
/// pivots (see `nsga::LinearOptions::regularization`).
pub const SMALL_LU_UP_TO: usize = 384;

/// How often a step that fails after every retry and re-solve may be halved (a
/// failing step is then taken as 2, 4, … up to 2^MAX_HALVINGS substeps).
///
/// The Lire collapse on a floor (`scenarios::lire_on_floor`) needs it where the column
/// lands with several corners at once (t = 7.41): Newton cycles through 7 index sets,
/// none self-consistent, and the two half steps go through (`cargo test -p blockstack
/// --test simulation`).
///
/// Some landings need far finer substeps: over the Lire collapse on a floor and its
/// neighbours (`cargo run --release -p blockstack --example lire_nearby 100 --floor`),
/// 4 halvings left 3 of the first 60 runs stopped with an error (neighbours 11, 29 and
/// 59, at t = 6.03, 7.52 and 6.21), 7 halvings left neighbour 59, which needs 9; with 10 all 100 run through.
/// A failure at one instant costs a bounded amount of work per level (only the half
/// that contains it is split again), not 2^level substeps.
pub const MAX_HALVINGS: usize = 10;

/// Halvings allowed in the line search of each Newton update (`nsga::NewtonOptions::line_search`).
/// Measured on the Lire collapse on a floor and 29 neighbours (`cargo run --release -p
/// blockstack --example lire_nearby 30 --floor`): with 3, failed steps fall from 6.5 to
/// 3.3 per run and linear solves by 5 %; more halvings change nothing. The held-sets
/// attempt of columns with many contacts ([`MAX_OPENINGS_PER_UPDATE`]) takes its updates
/// whole regardless (docs/method.md §8.2, stage 1).
pub const LINE_SEARCH_HALVINGS: usize = 3;

/// Openings per Newton update in nsga's held-sets attempt
/// (`nsga::NewtonOptions::max_openings_per_update`), the first attempt at each step of a
/// column with more contacts than [`MAX_NEWTON_ITERATIONS`]. With one opening per
/// update, a 300-block column moving with its base tips as one body: to t = 0.5 it
/// takes 13 linear solves instead of 5393.
pub const MAX_OPENINGS_PER_UPDATE: usize = 1;

/// Newton iterations per attempt before nsga gives it up.
pub const MAX_NEWTON_ITERATIONS: usize = 40;

/// Choices of a run that are not part of the scene.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// End time; overrides the scene's `solver.t_end`.
    pub t_end: Option<f64>,
    /// Prox parameter; overrides the scene's choice.
    pub prox: Option<Prox>,
    /// Record branch points (re-solve with fixed sets when Newton cycles).
    pub explore_branches: bool,
    /// Which fixed-set solutions count as a branch point's candidates (default: the
    /// self-consistent ones; [`nsga::BranchRule::Converged`] is the thesis's count).
    pub branch_rule: nsga::BranchRule,
    /// Probe every converged step for other solutions by flipping one touching contact
    /// ([`nsga::PolicyOptions::probe_flips`]; costly, for exploring).
    pub probe_flips: bool,
    /// For the sweeps' rows: explore up to this many branches of each run
    /// ([`crate::exploration`]) and report the spread of the row's value over them
    /// (0 or 1: the plain run only).
    pub spread_branches: usize,
    /// Stop as soon as `failure_time` is known (sweeps).
    pub stop_at_failure: bool,
    /// Leave out the last resort ([`nsga::PolicyOptions::last_resort`]): a step nothing else
    /// resolves then ends the run (to see what the generalized-α scheme alone does).
    pub skip_last_resort: bool,
    /// Factorize the Newton matrix whenever the index sets differ from those of its kept
    /// factors, as the paper does, instead of updating the kept factors for the changed
    /// rows ([`nsga::LinearOptions::low_rank_updates`]). The exploration of branches
    /// ([`crate::exploration`]) always does: it finds forks where a first attempt fails,
    /// and the updates converge through some of them unnoticed.
    pub skip_low_rank_updates: bool,
    /// Start every step's Newton iteration from the last solution, never from the
    /// extrapolated one ([`nsga::NewtonOptions::predict_start`]): the paper's start, to compare
    /// with.
    pub skip_predicted_start: bool,
    /// nsga options set by name after all of the above, each `NAME=VALUE`
    /// ([`nsga::Options::set`]: `tuning.stall_iterations=4`, `policy.max_halvings=0`):
    /// to measure what one constant or one stage of the step's policy is worth
    /// (`scripts/reference_workload.py --variant`).
    pub tuning: Vec<String>,
    /// A flag another thread may set to end the run after its current step, as a
    /// `ControlFlow::Break` of [`simulate_until`] would (a sweep that is interrupted
    /// stops every run it has started this way).
    pub cancel: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

/// The pose of one block.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BlockPose {
    /// Centre of mass x.
    pub x: f64,
    /// Centre of mass y.
    pub y: f64,
    /// Angle θ (rad).
    pub theta: f64,
}

impl From<Pose> for BlockPose {
    fn from(p: Pose) -> Self {
        Self {
            x: p.x,
            y: p.y,
            theta: p.theta,
        }
    }
}

/// The contact forces λ of interface k/k+1 (bottom to top, base/block 1 first).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct InterfaceForce {
    /// Normal forces of the left and right gaps.
    pub normal: [f64; 2],
    /// Friction force of the interface's law.
    pub friction: f64,
}

/// The state after one step (or the initial state).
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepRecord {
    /// Time t.
    pub t: f64,
    /// Free blocks, bottom to top (not the base).
    pub poses: Vec<BlockPose>,
    /// The prescribed base at t.
    pub base: BlockPose,
    /// Velocities of the free blocks [ẋ, ẏ, θ̇], bottom to top.
    pub velocities: Vec<[f64; 3]>,
    /// One per interface (n of them), bottom to top.
    pub forces: Vec<InterfaceForce>,
    /// The left and right gaps of each interface (G.2.2), bottom to top; NaN where the
    /// upper block has lost its support and the gaps mean nothing (G.2.4, ERRATA 23).
    pub gaps: Vec<[f64; 2]>,
    /// Smallest gap among the contacts that can close (+∞ if none can).
    pub min_gap: f64,
    /// Newton iterations of the step (0 for the initial state).
    pub iterations: usize,
    /// Kinetic plus potential energy of the free blocks.
    pub energy: f64,
}

/// A step resolved by fixed-set re-solves (docs/method.md §8).
#[derive(Debug, Clone, serde::Serialize)]
pub struct BranchRecord {
    /// Time at the start of the step.
    pub t: f64,
    /// Fixed-set re-solves tried (distinct index sets seen by the failed Newton run).
    pub candidates: usize,
    /// Distinct converged states among them.
    pub distinct: usize,
}

/// What a run did.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: usize,
    /// First time any block lost its support on the block beneath (§4.4).
    pub failure_time: Option<f64>,
    /// First time any interface opened completely.
    pub opening_time: Option<f64>,
    /// Poses at the end, bottom to top.
    pub final_poses: Vec<BlockPose>,
    /// Smallest gap over the run.
    pub min_gap: f64,
    /// Mean Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver time only (no I/O, no callback time), seconds.
    pub wall_time_s: f64,
    /// Steps whose first Newton attempt did not converge.
    pub failed_steps: usize,
    /// Steps resolved by fixed-set re-solves.
    pub branch_points: Vec<BranchRecord>,
    /// Steps that went through only as substeps (halved Δt, [`MAX_HALVINGS`]).
    pub split_steps: usize,
    /// Steps taken by the last resort after every other attempt failed: a Moreau–Jean
    /// step whose contact problem Lemke's method solves (docs/method.md §8).
    pub fallback_steps: usize,
    /// The largest complementarity residual of those steps (0 when none).
    pub fallback_residual: f64,
    /// Steps taken without the friction percussions' half-step shift, where the
    /// paper's step had no self-consistent index sets
    /// ([`nsga::PolicyOptions::retry_without_friction_shift`]).
    pub unshifted_steps: usize,
    /// Why the consistent start failed, where the run started without it and took its
    /// first step by the last resort ([`nsga::Stepper::start_failure`]); `None` after a
    /// consistent start.
    pub start_failure: Option<String>,
    /// Linear solves of the Newton iterations, in every attempt (failed ones, retries,
    /// fixed-set re-solves and substeps included): the run's work, independent of the
    /// machine ([`nsga::Stepper::linear_solves`]).
    pub linear_solves: u64,
    /// The same by the stage of the step's policy that made them (first attempt, ρ∞
    /// retries, branch trials, unshifted, boundary, other;
    /// [`nsga::Stepper::solves_by_stage`]).
    pub linear_solves_by_stage: nsga::SolvesByStage,
    /// The Newton work by kind, why exact updates were made, and the seconds of each
    /// kind ([`nsga::Stepper::newton_work`]).
    pub newton_work: nsga::NewtonWork,
    /// Largest increase of the energy between two steps (unforced runs: ≤ ~0).
    pub max_energy_increase: f64,
    /// The deepest penetration between any two bodies over the run (base, blocks,
    /// floor), with its time: the overlap check of every recorded state.
    pub deepest: TimedPenetration,
    /// [`PENETRATION_TOL`] times the smallest block height: deeper is warned about.
    pub penetration_tol: f64,
    /// Failure events in the order they happened ([`crate::events`]).
    pub events: Vec<FailureEvent>,
    /// The most corner contacts between bodies beyond the stack's neighbours
    /// ([`crate::pairs`]) the broad phase kept at once (0 while the column stands).
    pub corner_contacts: usize,
    /// Steps taken again because a contact was missed by the broad phase
    /// ([`crate::stepping`]).
    pub redone_steps: usize,
    /// Why the run stopped before its end time: the step that finally failed (or the
    /// start), with the last good state; the summary covers the run up to it.
    pub error: Option<RunError>,
}

/// A penetration and when it was measured.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TimedPenetration {
    /// Time of the state.
    pub t: f64,
    /// The pair and its depth (its keys inline in JSON).
    #[serde(flatten)]
    pub penetration: Penetration,
}

impl TimedPenetration {
    /// The depth, 0 when the bodies are apart or only touch.
    #[must_use]
    pub fn depth(&self) -> f64 {
        self.penetration.depth.max(0.0)
    }
}

/// Why a run stopped before its end time. It serializes as its message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// No consistent initial accelerations and forces exist (docs/method.md §5), or the
    /// stepper refused the initial state.
    #[error("{}", start_message(.0))]
    Start(StepError),
    /// A step failed after every fallback of nsga's policy; the error carries the last
    /// good state ([`StepError::state`]).
    #[error("{0}")]
    Step(StepError),
}

/// The message of a failed start: nsga's own when it already says "consistent start".
fn start_message(e: &StepError) -> String {
    match e {
        StepError::Start { .. } => e.to_string(),
        other => format!("consistent start failed: {other}"),
    }
}

impl RunError {
    /// The step error.
    #[must_use]
    pub fn step_error(&self) -> &StepError {
        match self {
            Self::Start(e) | Self::Step(e) => e,
        }
    }
}

impl serde::Serialize for RunError {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// nsga's options for a scene.
///
/// # Errors
/// Bad run options (t_end, prox).
pub fn stepper_options(scene: &Scene, options: &RunOptions) -> Result<Options, BlockstackError> {
    let s = &scene.solver;
    let mut opts = Options {
        dt: s.dt,
        rho_inf: s.rho_inf,
        prox: options.prox.unwrap_or(s.prox),
        tol: s.tol,
        newton: NewtonOptions {
            max_iter: MAX_NEWTON_ITERATIONS,
            max_iter_per_contact: 1,
            prune_open_contacts: true,
            predict_start: !options.skip_predicted_start,
            line_search: LINE_SEARCH_HALVINGS,
            max_openings_per_update: MAX_OPENINGS_PER_UPDATE,
        },
        linear: LinearOptions {
            // Markowitz LU for the small scenes of the thesis, faer's sparse LU for tall
            // columns (the Newton matrix of a chain is banded).
            solver: SolverChoice::Markowitz(SMALL_LU_UP_TO),
            reuse_factorization: true,
            low_rank_updates: !options.skip_low_rank_updates,
            ..LinearOptions::default()
        },
        policy: PolicyOptions {
            explore_branches: options.explore_branches,
            branch_rule: options.branch_rule,
            probe_flips: options.probe_flips,
            retry_without_friction_shift: true,
            // No ρ∞ retries (thesis §4.2): they paid less than 1 % on the reference
            // workload (docs/method.md §8.3, "The stages measured").
            rho_inf_retries: Vec::new(),
            max_halvings: MAX_HALVINGS,
            boundary_resolves: options.explore_branches,
            last_resort: !options.skip_last_resort,
            ..PolicyOptions::default()
        },
        ..Options::default()
    };
    for assignment in &options.tuning {
        opts.set(assignment)
            .map_err(|e| BlockError::Scene(format!("solver options: {e}")))?;
    }
    opts.validate()
        .map_err(|e| BlockError::Scene(format!("solver options: {e}")))?;
    Ok(opts)
}

/// Number of steps to reach t_end with the scene's Δt (a final partial step is taken
/// whole).
pub(crate) fn step_count(t_end: f64, dt: f64) -> usize {
    let n = t_end / dt;
    // Round-off: 10/0.01 = 1000.0000000000001 is 1000 steps.
    let rounded = n.round();
    let steps = if (n - rounded).abs() < 1e-9 * n.max(1.0) {
        rounded
    } else {
        n.ceil()
    };
    // A count of steps: t_end / dt is positive and finite here.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let steps = steps as usize;
    steps
}

/// What is recorded of one state.
#[derive(Debug, Clone)]
pub(crate) struct Recorder<'a> {
    scene: &'a Scene,
    pub(crate) contacts: StackContacts<f64>,
    pub(crate) open_tol: f64,
    pub(crate) watch: EventWatch,
    /// The deepest penetration of the states recorded so far (the initial one before).
    pub(crate) deepest: TimedPenetration,
}

impl<'a> Recorder<'a> {
    /// A recorder for a run of `scene` from coordinates `q0` at t = 0.
    pub(crate) fn new(scene: &'a Scene, q0: &[f64]) -> Self {
        let height = scene.smallest_block_height();
        Self {
            scene,
            contacts: StackContacts::default(),
            open_tol: OPEN_GAP_TOL * height,
            watch: EventWatch::new(scene, OPEN_GAP_TOL * height),
            deepest: TimedPenetration {
                t: 0.0,
                penetration: deepest_penetration(scene, 0.0, q0),
            },
        }
    }

    pub(crate) fn record(&mut self, t: f64, st: &nsga::State, iterations: usize) -> StepRecord {
        let n = self.scene.n_blocks();
        self.scene
            .contacts_into(t, &st.q, &st.u, &mut self.contacts);
        let poses = (0..n)
            .map(|k| Pose::from_slice(&st.q[3 * k..3 * k + 3]).into())
            .collect();
        self.watch.observe(self.scene, t, &st.q, &self.contacts);
        let p = deepest_penetration(self.scene, t, &st.q);
        if p.depth > self.deepest.penetration.depth {
            self.deepest = TimedPenetration { t, penetration: p };
        }
        let forces = (0..n)
            .map(|k| InterfaceForce {
                normal: [st.lambda_n[2 * k], st.lambda_n[2 * k + 1]],
                friction: st.lambda_f[k],
            })
            .collect();
        let velocities = (0..n)
            .map(|k| [st.u[3 * k], st.u[3 * k + 1], st.u[3 * k + 2]])
            .collect();
        let gaps = self
            .contacts
            .interfaces
            .iter()
            .map(|i| {
                if i.is_supported() {
                    [i.left.row.value, i.right.row.value]
                } else {
                    [f64::NAN; 2]
                }
            })
            .collect();
        StepRecord {
            t,
            poses,
            velocities,
            base: self.scene.base().state(t).pose.into(),
            forces,
            gaps,
            min_gap: self.contacts.min_gap().unwrap_or(f64::INFINITY),
            iterations,
            energy: self.scene.energy(&st.q, &st.u),
        }
    }
}

/// Runs a scene from t = 0 to t_end; `on_step` is called once with the initial state and
/// once per step (so a caller can write rows progressively, ERRATA 25). A step that fails
/// after all retries ends the run with `summary.error` set (not an `Err`).
///
/// # Errors
/// Only bad scenes or options (t_end ≤ 0, a prox parameter out of range).
pub fn simulate(
    scene: &Scene,
    options: &RunOptions,
    mut on_step: impl FnMut(&StepRecord),
) -> Result<RunSummary, BlockstackError> {
    simulate_until(scene, options, |r| {
        on_step(r);
        ControlFlow::Continue(())
    })
}

/// [`simulate`] with a caller that may stop the run: when `on_step` returns
/// `ControlFlow::Break`, no further step is taken and the summary covers the run up to
/// that record (its `error` stays `None`). The Python bindings stop on Ctrl-C this way.
///
/// # Errors
/// Only bad scenes or options, as [`simulate`].
pub fn simulate_until(
    scene: &Scene,
    options: &RunOptions,
    mut on_step: impl FnMut(&StepRecord) -> ControlFlow<()>,
) -> Result<RunSummary, BlockstackError> {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    input::positive("t_end", t_end)?;
    let opts = stepper_options(scene, options)?;
    let dt = opts.dt;
    let steps_wanted = step_count(t_end, dt);
    let q0 = scene.initial_coordinates();
    let u0 = scene.initial_velocities();
    let height = scene.smallest_block_height();
    let mut rec = Recorder::new(scene, &q0);
    let mut summary = RunSummary {
        steps: 0,
        failure_time: None,
        opening_time: None,
        final_poses: Vec::new(),
        min_gap: f64::INFINITY,
        newton_iterations_mean: 0.0,
        wall_time_s: 0.0,
        failed_steps: 0,
        branch_points: Vec::new(),
        split_steps: 0,
        fallback_steps: 0,
        fallback_residual: 0.0,
        unshifted_steps: 0,
        start_failure: None,
        linear_solves: 0,
        linear_solves_by_stage: nsga::SolvesByStage::default(),
        newton_work: nsga::NewtonWork::default(),
        max_energy_increase: f64::NEG_INFINITY,
        deepest: rec.deepest,
        penetration_tol: PENETRATION_TOL * height,
        events: Vec::new(),
        corner_contacts: 0,
        redone_steps: 0,
        error: None,
    };
    let clock = Instant::now();
    let mut system = StackSystem::new(scene.clone());
    let mut corners = CornerStepping::default();
    corners.start(&mut system, &q0, &u0, dt);
    let started = Stepper::new(system, 0.0, &q0, &u0, opts);
    let mut solver_time = clock.elapsed().as_secs_f64();
    let mut stepper = match started {
        Ok(s) => {
            summary.start_failure = s.start_failure().map(str::to_owned);
            s
        }
        Err(e) => {
            summary.error = Some(RunError::Start(e));
            summary.final_poses = (0..scene.n_blocks())
                .map(|k| Pose::from_slice(&q0[3 * k..]).into())
                .collect();
            summary.max_energy_increase = 0.0;
            summary.wall_time_s = solver_time;
            return Ok(summary);
        }
    };
    let first = rec.record(0.0, stepper.state(), 0);
    let mut energy = first.energy;
    summary.min_gap = first.min_gap;
    check_failure(&rec, 0.0, &mut summary);
    let mut stop = on_step(&first).is_break();
    let mut iterations = 0usize;
    for _ in 0..steps_wanted {
        let cancelled = options
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed));
        if stop || cancelled || (options.stop_at_failure && summary.failure_time.is_some()) {
            break;
        }
        let clock = Instant::now();
        let result = corners
            .step(scene, &mut stepper, summary.penetration_tol)
            .map(|()| accepted(stepper.last_step().expect("a step was taken")));
        solver_time += clock.elapsed().as_secs_f64();
        let (t, its, retries, branch) = match result {
            Ok(r) => r,
            Err(e) => {
                summary.failed_steps += 1;
                summary.error = Some(RunError::Step(e));
                break;
            }
        };
        summary.steps += 1;
        iterations += its;
        if retries > 0 {
            summary.failed_steps += 1;
        }
        summary.branch_points.extend(branch);
        if stepper.last_step().is_some_and(|s| s.substeps > 1) {
            summary.split_steps += 1;
        }
        if stepper.last_step().is_some_and(|s| s.unshifted) {
            summary.unshifted_steps += 1;
        }
        if let Some(last) = stepper.last_step().and_then(|s| s.last_resort.as_ref()) {
            summary.fallback_steps += 1;
            summary.fallback_residual = summary.fallback_residual.max(last.residual);
        }
        let r = rec.record(t, stepper.state(), its);
        summary.min_gap = summary.min_gap.min(r.min_gap);
        summary.max_energy_increase = summary.max_energy_increase.max(r.energy - energy);
        energy = r.energy;
        check_failure(&rec, t, &mut summary);
        stop = on_step(&r).is_break();
    }
    summary.linear_solves = stepper.linear_solves();
    summary.linear_solves_by_stage = stepper.solves_by_stage();
    summary.newton_work = stepper.newton_work();
    summary.corner_contacts = corners.most_contacts;
    summary.redone_steps = corners.redone_steps;
    summary.deepest = rec.deepest;
    summary.events = rec.watch.into_events();
    let q = &stepper.state().q;
    summary.final_poses = (0..scene.n_blocks())
        .map(|k| Pose::from_slice(&q[3 * k..3 * k + 3]).into())
        .collect();
    if summary.steps > 0 {
        summary.newton_iterations_mean = iterations as f64 / summary.steps as f64;
    }
    if !summary.max_energy_increase.is_finite() {
        summary.max_energy_increase = 0.0;
    }
    summary.wall_time_s = solver_time;
    Ok(summary)
}

/// One line per kind of failure event: the blocks in the order they were affected,
/// each with its time.
fn write_events(f: &mut std::fmt::Formatter<'_>, events: &[FailureEvent]) -> std::fmt::Result {
    if events.is_empty() {
        return write!(f, "\nfailure events: none");
    }
    for (kind, heading) in [
        (EventKind::SupportLost, "blocks that lost their support"),
        (
            EventKind::Tipped,
            "blocks that tipped past their tipping angle",
        ),
        (
            EventKind::HeightDropped,
            "the column's height dropped by a block",
        ),
        (EventKind::TouchedFloor, "blocks that touched the floor"),
    ] {
        let of_kind: Vec<String> = events
            .iter()
            .filter(|e| e.kind == kind)
            .map(|e| match e.block {
                Some(k) => format!("block {k} at t = {:.4}", e.t),
                None => format!("at t = {:.4}", e.t),
            })
            .collect();
        if !of_kind.is_empty() {
            write!(f, "\n{heading}: {}", of_kind.join(", "))?;
        }
    }
    Ok(())
}

/// (t, iterations, retries, branch point) of an accepted step.
type Accepted = (f64, usize, usize, Option<BranchRecord>);

fn accepted(s: &nsga::StepStats) -> Accepted {
    (
        s.t,
        s.iterations,
        s.retries,
        s.branch.as_ref().map(|b| BranchRecord {
            t: b.t,
            candidates: b.tried,
            distinct: b.candidates.len(),
        }),
    )
}

/// Updates the failure and opening times from the contacts last recorded at t.
fn check_failure(rec: &Recorder<'_>, t: f64, summary: &mut RunSummary) {
    summary.failure_time = rec.watch.first_time(EventKind::SupportLost);
    if summary.opening_time.is_none() && rec.contacts.first_open(rec.open_tol).is_some() {
        summary.opening_time = Some(t);
    }
}

/// The JSON report of one run (`rollstack blocks run` and `lire`; docs/cli.md): the
/// summary's headline numbers, the time reached and the prox parameter used.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunReport {
    /// Number of time steps taken.
    pub steps: usize,
    /// First time any block loses support on the block beneath it (§4.4), or null.
    pub failure_time: Option<f64>,
    /// The run's failure ([`crate::events::failure`]): its first event (support lost,
    /// tipped, reached the floor, height dropped), with its kind, time and block; null
    /// while the column stands.
    pub failure: Option<FailureEvent>,
    /// Final poses of the free blocks, bottom to top.
    #[serde(rename = "final")]
    pub final_poses: Vec<BlockPose>,
    /// Smallest normal gap seen among the closed contacts (negative: penetration), or
    /// null when no contact was ever closed (or the run could not start).
    pub min_gap: Option<f64>,
    /// Mean number of Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver time (s), without I/O.
    pub wall_time_s: f64,
    /// First time any interface opens completely, or null.
    pub opening_time: Option<f64>,
    /// Steps whose first Newton attempt did not converge.
    pub failed_steps: usize,
    /// Number of branch points recorded.
    pub branch_points: usize,
    /// Steps that went through only as substeps (halved Δt).
    pub split_steps: usize,
    /// Steps taken by the last resort (a Moreau–Jean step solved by Lemke's method).
    pub fallback_steps: usize,
    /// The largest complementarity residual of those steps (0 when none).
    pub fallback_residual: f64,
    /// Steps taken without the friction percussions' half-step shift.
    pub unshifted_steps: usize,
    /// Why the consistent start failed, where the first step was taken by the last
    /// resort instead; null after a consistent start.
    pub start_failure: Option<String>,
    /// Linear solves of the Newton iterations in every attempt (the run's work).
    pub linear_solves: u64,
    /// The same by the stage of the step's policy that made them.
    pub linear_solves_by_stage: nsga::SolvesByStage,
    /// Where the Newton work went: operations by kind, why exact updates were made,
    /// seconds by kind.
    pub newton_work: nsga::NewtonWork,
    /// Largest energy increase between two steps (≤ ~0 in unforced runs).
    pub max_energy_increase: f64,
    /// The deepest penetration between any two bodies over the run (0 when they only
    /// touch); above `PENETRATION_TOL` of the smallest block height it is also a warning.
    pub max_penetration: f64,
    /// When and where it was measured.
    pub penetration: TimedPenetration,
    /// The most corner contacts beyond the stack's neighbours in use at once
    /// ([`crate::pairs`]; 0 while the column stands).
    pub corner_contacts: usize,
    /// Steps taken again because the broad phase had missed a contact
    /// ([`crate::stepping`]).
    pub redone_steps: usize,
    /// Failure events in the order they happened: a block lost its support, tipped past
    /// its tipping angle or touched the floor; the column's height dropped by a block.
    pub events: Vec<FailureEvent>,
    /// Why the run stopped early, or null.
    pub error: Option<String>,
    /// Time reached.
    pub t_final: f64,
    /// The prox parameter used: text `scaled, alpha = 1` or `constant r = 0.3`, JSON
    /// `"scaled(alpha=1)"` or `"constant(r=0.3)"` ([`Prox::label`]).
    #[serde(serialize_with = "crate::scene_info::serialize_prox")]
    pub prox: Prox,
    /// What the scene may do unexpectedly ([`Scene::warnings`]), and a penetration
    /// beyond the tolerance.
    pub warnings: Vec<RunWarning>,
    /// The parameters the run used, after defaults and overrides.
    pub scene: SceneReport,
}

impl RunReport {
    /// The report of a run of `scene` with `options` that reached `t_final`; `defaults`:
    /// the scene-file keys that took their defaults (empty for scenes built in code).
    #[must_use]
    pub fn new(
        summary: &RunSummary,
        scene: &Scene,
        options: &RunOptions,
        defaults: &Defaults,
        t_final: f64,
    ) -> Self {
        Self {
            steps: summary.steps,
            failure_time: summary.failure_time,
            failure: crate::events::failure(&summary.events),
            final_poses: summary.final_poses.clone(),
            min_gap: Some(summary.min_gap).filter(|g| g.is_finite()),
            newton_iterations_mean: summary.newton_iterations_mean,
            wall_time_s: summary.wall_time_s,
            opening_time: summary.opening_time,
            failed_steps: summary.failed_steps,
            branch_points: summary.branch_points.len(),
            split_steps: summary.split_steps,
            fallback_steps: summary.fallback_steps,
            fallback_residual: summary.fallback_residual,
            unshifted_steps: summary.unshifted_steps,
            start_failure: summary.start_failure.clone(),
            linear_solves: summary.linear_solves,
            linear_solves_by_stage: summary.linear_solves_by_stage,
            newton_work: summary.newton_work,
            max_energy_increase: summary.max_energy_increase,
            max_penetration: summary.deepest.depth(),
            penetration: summary.deepest,
            corner_contacts: summary.corner_contacts,
            redone_steps: summary.redone_steps,
            events: summary.events.clone(),
            error: summary.error.as_ref().map(ToString::to_string),
            t_final,
            prox: options.prox.unwrap_or(scene.solver.prox),
            warnings: RunWarning::of(scene, summary),
            scene: SceneReport::new(scene, options, defaults),
        }
    }
}

/// Something the reader of a run should know.
#[derive(Debug, Clone, PartialEq)]
pub enum RunWarning {
    /// What the scene may do unexpectedly.
    Scene(SceneWarning),
    /// Two bodies overlapped by more than the tolerance.
    Penetration {
        /// The deepest penetration.
        deepest: TimedPenetration,
        /// The tolerance it exceeded.
        tol: f64,
    },
    /// The consistent start failed, so the first step was taken by the last resort.
    StartFailed(String),
}

impl RunWarning {
    /// The scene's warnings, then the run's.
    #[must_use]
    pub fn of(scene: &Scene, summary: &RunSummary) -> Vec<Self> {
        let mut warnings: Vec<Self> = scene.warnings().into_iter().map(Self::Scene).collect();
        if summary.deepest.depth() > summary.penetration_tol {
            warnings.push(Self::Penetration {
                deepest: summary.deepest,
                tol: summary.penetration_tol,
            });
        }
        if let Some(why) = &summary.start_failure {
            warnings.push(Self::StartFailed(why.clone()));
        }
        warnings
    }
}

impl std::fmt::Display for RunWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Scene(w) => write!(f, "{w}"),
            Self::Penetration { deepest, tol } => write!(
                f,
                "at t = {:.4}, {} (tolerance {tol:.1e}): two bodies entered each other \
                 further than the contacts allow; the motion after that is not to be \
                 trusted (a smaller time step usually helps)",
                deepest.t, deepest.penetration
            ),
            Self::StartFailed(why) => write!(
                f,
                "{why}: the first step was taken by the last resort (a Moreau–Jean step, \
                 which needs no initial accelerations) and the run went on from there"
            ),
        }
    }
}

impl serde::Serialize for RunWarning {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// The readable summary `rollstack blocks run` prints: the scene as used, the run's
/// counts, its events, and each block's final pose (lines, no trailing newline).
impl std::fmt::Display for RunReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let time =
            |t: Option<f64>| t.map_or_else(|| "never".to_owned(), |t| format!("at t = {t:.4}"));
        let min_gap = self.min_gap.map_or_else(
            || "none (no contact could close)".to_owned(),
            |g| format!("{g:.3e}"),
        );
        writeln!(f, "{}", self.scene)?;
        writeln!(
            f,
            "{} steps to t = {:.4} (solver {:.3} s, {:.2} Newton iterations per step, prox {})",
            self.steps, self.t_final, self.wall_time_s, self.newton_iterations_mean, self.prox
        )?;
        writeln!(
            f,
            "failure (loss of support) {}, first full opening {}",
            time(self.failure_time),
            time(self.opening_time)
        )?;
        write!(
            f,
            "min gap {min_gap}, failed Newton steps {}, branch points {}, split steps {}, linear solves {}, largest energy increase {:.3e}",
            self.failed_steps, self.branch_points, self.split_steps, self.linear_solves, self.max_energy_increase
        )?;
        write!(
            f,
            "\nlargest penetration between two bodies {:.3e}",
            self.max_penetration
        )?;
        if self.max_penetration > 0.0 {
            let p = &self.penetration;
            write!(
                f,
                " ({} and {} at t = {:.4})",
                p.penetration.first, p.penetration.second, p.t
            )?;
        }
        if self.corner_contacts > 0 {
            write!(
                f,
                "\ncorner contacts between bodies beyond the stack's neighbours: up to {} at once, steps redone for a missed contact {}",
                self.corner_contacts, self.redone_steps
            )?;
        }
        write_events(f, &self.events)?;
        write!(
            f,
            "\n{}",
            crate::events::Verdict::new(self.failure, self.t_final, self.error.is_some())
        )?;
        if self.fallback_steps > 0 {
            write!(
                f,
                "\nlast-resort steps {} (Moreau–Jean, Lemke), largest residual {:.1e}",
                self.fallback_steps, self.fallback_residual
            )?;
        }
        for (k, p) in self.final_poses.iter().enumerate() {
            write!(
                f,
                "\nblock {}: x = {:.6}, y = {:.6}, theta = {:.6}",
                k + 1,
                p.x,
                p.y,
                p.theta
            )?;
        }
        Ok(())
    }
}
