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
//!   sets alternate, re-solves with each distinct set fixed, continuing with the first
//!   self-consistent candidate (a branch point, ERRATA 22); then the step as two half
//!   steps with this same policy (up to [`MAX_HALVINGS`] times). These re-solves are
//!   part of every run's solver: [`RunOptions::explore_branches`] and
//!   [`RunOptions::branch_rule`] only decide which branch points are recorded, so a
//!   run's trajectory is the same whatever they are.
//! - **Redundant contacts**: a toppled column resting on the table edge and on the floor
//!   with several corners touches at more points than it has degrees of freedom; nsga's
//!   regularized Newton update ([`nsga::LinearOptions::regularization`]) carries it.
//! - **Errors**: a step that fails after every fallback ends the run; the summary up to
//!   it carries the typed error ([`RunError`], with the state it failed at), it is not
//!   an `Err`.

use crate::broad_phase::Scan;
use crate::coordinates::{same_bits, same_pose, Pose};
use crate::error::BlockError;
use crate::events::{EventKind, EventWatch, FailureEvent};
use crate::exploration::{StackWalker, WalkSettings};
use crate::overlap::{deepest_penetration, deepest_penetration_placed, Body, Penetration};
use crate::scene::Scene;
use crate::scene_info::{Defaults, SceneReport, SceneWarning};
use crate::stack::StackContacts;
pub use crate::time_guard::STOPPED_BY_WATCHDOG;
use crate::time_guard::{Clock, Overrun, WallClock, Watchdog};
use nsga::explore::Walker;
use nsga::{LinearOptions, NewtonOptions, Options, PolicyOptions, SolverChoice, StepError};
use std::ops::ControlFlow;

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
/// blocks collapsing into piles (docs/linear-algebra.md, "Crossovers (measured)") take
/// 14.0 s of solver time instead of 20.0 s. Above it, the banded matrix of a tall column
/// needs the sparse solver. Both small solvers detect the singular matrices of redundant
/// contacts by their pivots (see `nsga::LinearOptions::regularization`).
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
/// whole regardless (docs/method.md §8.2, `Stage::HeldSets` and `Stage::Free`).
pub const LINE_SEARCH_HALVINGS: usize = 3;

/// Openings per Newton update in nsga's held-sets attempt
/// (`nsga::NewtonOptions::max_openings_per_update`), the first attempt at each step of a
/// column with more contacts than [`MAX_NEWTON_ITERATIONS`]. With one opening per
/// update, a 300-block column moving with its base tips as one body: to t = 0.5 it
/// takes 13 linear solves instead of 5393.
pub const MAX_OPENINGS_PER_UPDATE: usize = 1;

/// Newton iterations per attempt before nsga gives it up.
pub const MAX_NEWTON_ITERATIONS: usize = 40;

/// Choices of a run that are not part of the scene. The defaults are those of the
/// command line and of the Python module (a test of the command line checks it).
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// End time; overrides the scene's `solver.t_end`.
    pub t_end: Option<f64>,
    /// Prox parameter; overrides the scene's choice.
    pub prox: Option<Prox>,
    /// Record branch points ([`RunSummary::branch_points`]): the steps whose Newton
    /// iterates cycled and that fixed-set re-solves resolved, with the candidates found.
    /// Only the record: those re-solves are a stage of every run's solver (the module
    /// docs), so the trajectory is the same with this on or off. On by default.
    pub explore_branches: bool,
    /// Which fixed-set solutions a branch point records as candidates (default: the
    /// self-consistent ones; [`nsga::BranchRule::Converged`] adds the other converged
    /// solves, the thesis's count). Only the record: the run continues with a
    /// self-consistent candidate under either rule, and an exploration
    /// ([`crate::exploration`]) follows every recorded one.
    pub branch_rule: nsga::BranchRule,
    /// Probe every converged step for other solutions, the touching contacts' states
    /// enumerated ([`nsga::PolicyOptions::probe_flips`]; costly, for exploring).
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
    /// The run-time watchdog's bound, s ([`crate::time_guard::Watchdog`]): a run
    /// projected, as it goes, to take longer is stopped with [`RunError::Stopped`].
    /// `None` (the default, and a forced run): not watched. The CLI sets
    /// [`TIME_BOUND_S`] unless `--force`, Python unless `force=True`.
    pub time_bound: Option<f64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            t_end: None,
            prox: None,
            explore_branches: true,
            branch_rule: nsga::BranchRule::default(),
            probe_flips: false,
            spread_branches: 0,
            stop_at_failure: false,
            skip_last_resort: false,
            skip_low_rank_updates: false,
            skip_predicted_start: false,
            cancel: None,
            tuning: Vec::new(),
            time_bound: None,
        }
    }
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

/// The contact forces λ of one interface (a column's bottom to top, base/block 1 first;
/// any arrangement's in the order of [`crate::arrangement`]).
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
    /// One per interface (a column: n of them, bottom to top).
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

/// What a run did: the one summary of a run, which the JSON report of
/// `rollstack blocks run` holds ([`RunReport`], docs/cli.md: the keys are those named by
/// the `serde` attributes).
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: usize,
    /// First time any block lost its support on the block beneath (§4.4).
    pub failure_time: Option<f64>,
    /// First time any interface opened completely.
    pub opening_time: Option<f64>,
    /// Poses at the end, bottom to top.
    #[serde(rename = "final")]
    pub final_poses: Vec<BlockPose>,
    /// Smallest gap over the run (+∞, JSON null, when no contact could close or the run
    /// could not start).
    #[serde(serialize_with = "finite_or_null")]
    pub min_gap: f64,
    /// Mean Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver time only (no I/O, no callback time), seconds.
    pub wall_time_s: f64,
    /// Steps whose first Newton attempt did not converge.
    pub failed_steps: usize,
    /// The branch points met ([`RunOptions::explore_branches`]; empty with it off). JSON:
    /// their number.
    #[serde(serialize_with = "count")]
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
    /// Steps that repeated a state at rest without solving, once the base stood still
    /// for good ([`nsga::PolicyOptions::rest`], docs/method.md §8.2 "At rest").
    pub resting_steps: u64,
    /// Steps solved with an island of blocks at rest held out of the solve
    /// ([`nsga::RunStats::held_island_steps`], docs/method.md §8.2 "Islands at rest").
    pub held_island_steps: u64,
    /// Times a held island's rows exceeded the tolerance and it returned to the solve
    /// ([`nsga::RunStats::island_wakes`]).
    pub island_wakes: u64,
    /// Why the consistent start failed, where the run started without it and took its
    /// first step by the last resort ([`nsga::Stepper::start_failure`]); `None` after a
    /// consistent start.
    pub start_failure: Option<String>,
    /// Linear solves of the Newton iterations, in every attempt (failed ones, retries,
    /// fixed-set re-solves and substeps included): the run's work, independent of the
    /// machine ([`nsga::Stepper::linear_solves`]).
    pub linear_solves: u64,
    /// The same by the stage of the step's policy that made them (first attempt, ρ∞
    /// retries, branch trials, unshifted, other;
    /// [`nsga::Stepper::solves_by_stage`]).
    pub linear_solves_by_stage: nsga::SolvesByStage,
    /// The Newton work by kind, why exact updates were made, and the seconds of each
    /// kind ([`nsga::Stepper::newton_work`]).
    pub newton_work: nsga::NewtonWork,
    /// Largest increase of the energy between two steps (unforced runs: ≤ ~0).
    pub max_energy_increase: f64,
    /// The deepest penetration between any two bodies over the run (base, blocks,
    /// floor), with its time: the overlap check of every recorded state.
    #[serde(rename = "penetration")]
    pub deepest: TimedPenetration,
    /// [`PENETRATION_TOL`] times the smallest block height: deeper is warned about.
    #[serde(skip)]
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
    /// The watchdog ([`RunOptions::time_bound`]) stopped the run: it was projected to
    /// take longer than the bound.
    #[error("{}", .0.message())]
    Stopped(Overrun),
}

/// The message of a failed start: nsga's own when it already says "consistent start".
fn start_message(e: &StepError) -> String {
    match e {
        StepError::Start { .. } => e.to_string(),
        other => format!("consistent start failed: {other}"),
    }
}

impl RunError {
    /// The step error (none for a run the watchdog stopped).
    #[must_use]
    pub fn step_error(&self) -> Option<&StepError> {
        match self {
            Self::Start(e) | Self::Step(e) => Some(e),
            Self::Stopped(_) => None,
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
            held_factors_follow_sets: true,
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
            // Solver stages of every run; `RunOptions::explore_branches` only records.
            branch_trials: true,
            branch_rule: options.branch_rule,
            probe_flips: options.probe_flips,
            probe_painleve: true,
            retry_without_friction_shift: true,
            // No ρ∞ retries (thesis §4.2): they paid less than 1 % on the reference
            // workload (docs/method.md §8.3, "The stages measured").
            rho_inf_retries: Vec::new(),
            max_halvings: MAX_HALVINGS,
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
    /// The last state's deepest penetration with the base's pose and the block
    /// coordinates it was measured at: a state at the same ones, to the bit, has it too
    /// (at rest, every state after the first).
    last_overlap: Option<(Pose, Vec<f64>, Penetration)>,
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
            last_overlap: None,
        }
    }

    /// The deepest penetration at `t` and `q` ([`deepest_penetration`]), where the base
    /// is at `base`; `scan`: the broad phase's findings at that state, whose placings of
    /// the bodies serve it.
    fn overlap(&mut self, t: f64, q: &[f64], base: &Pose, scan: Option<&Scan>) -> Penetration {
        if let Some((b, at, p)) = &self.last_overlap {
            if same_pose(b, base) && same_bits(at, q) {
                return *p;
            }
        }
        let p = deepest_penetration_placed(self.scene, t, q, |i, pose, size| {
            scan.and_then(|s| s.placed_at(i, pose, size))
        });
        // The last one's list of coordinates, reused.
        let mut at = self
            .last_overlap
            .take()
            .map_or_else(Vec::new, |(_, at, _)| at);
        at.clear();
        at.extend_from_slice(q);
        self.last_overlap = Some((*base, at, p));
        p
    }

    /// The record of state `st` at `t`; `scan`: the broad phase's findings at that state,
    /// if kept, whose placings of the bodies serve the deepest overlap.
    pub(crate) fn record(
        &mut self,
        t: f64,
        st: &nsga::State,
        iterations: usize,
        scan: Option<&Scan>,
    ) -> StepRecord {
        let n = self.scene.n_blocks();
        self.scene
            .contacts_into(t, &st.q, &st.u, &mut self.contacts);
        let poses = (0..n)
            .map(|k| Pose::from_slice(&st.q[3 * k..3 * k + 3]).into())
            .collect();
        self.watch.observe(self.scene, t, &st.q, &self.contacts);
        let base = self.scene.base().state(t).pose;
        let p = self.overlap(t, &st.q, &base, scan);
        if p.depth > self.deepest.penetration.depth {
            self.deepest = TimedPenetration { t, penetration: p };
        }
        let forces = (0..self.scene.n_interfaces())
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
            base: base.into(),
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
/// The run is stepped by the loop of an exploration's branches
/// ([`crate::exploration::StackWalker`]), so both count the same statistics.
///
/// # Errors
/// Only bad scenes or options, as [`simulate`].
pub fn simulate_until(
    scene: &Scene,
    options: &RunOptions,
    on_step: impl FnMut(&StepRecord) -> ControlFlow<()>,
) -> Result<RunSummary, BlockstackError> {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let bound = options.time_bound.unwrap_or(f64::INFINITY);
    let watchdog = Watchdog::new(WallClock::start(), 0.0, t_end, bound);
    simulate_watched(scene, options, watchdog, on_step)
}

/// [`simulate_until`] watched by `watchdog` instead of one at
/// [`RunOptions::time_bound`], on any clock (a test's).
///
/// # Errors
/// Only bad scenes or options, as [`simulate`].
pub fn simulate_watched(
    scene: &Scene,
    options: &RunOptions,
    mut watchdog: Watchdog<impl Clock>,
    mut on_step: impl FnMut(&StepRecord) -> ControlFlow<()>,
) -> Result<RunSummary, BlockstackError> {
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    input::positive("t_end", t_end)?;
    let opts = stepper_options(scene, options)?;
    let steps = step_count(t_end, opts.dt) as u64;
    let settings = WalkSettings {
        sample_every: u64::MAX,
        stop_at_failure: options.stop_at_failure,
        ..WalkSettings::default()
    };
    let mut walker =
        match StackWalker::start(scene, opts, steps, settings, options.explore_branches) {
            Ok(w) => w,
            Err((e, solver_time)) => return Ok(RunSummary::failed_start(scene, e, solver_time)),
        };
    let cancelled = || {
        options
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
    };
    // A step that outlasts the bound (or the caller's cancel) is stopped within it: the
    // watchdog's checks come only between steps, and one step can take hours.
    let deadline = watchdog.deadline();
    walker.set_interrupt(nsga::Interrupt::new(options.cancel.clone(), deadline));
    let mut stop = on_step(&walker.record_state()).is_break();
    let mut error = None;
    while !(stop || cancelled() || walker.done()) {
        match walker.step() {
            Ok(_) => {}
            // Cancelled: the run up to here, as a cancel between steps leaves it.
            Err(StepError::Interrupted { .. }) if cancelled() => break,
            Err(StepError::Interrupted { t, .. }) => {
                watchdog.stop_within_step(t);
                break;
            }
            Err(e) => {
                error = Some(RunError::Step(e));
                break;
            }
        }
        let record = walker.record_state();
        stop = on_step(&record).is_break() || watchdog.check(record.t).is_break();
    }
    let mut summary = walker.into_summary();
    summary.error = error.or(watchdog.overrun().map(RunError::Stopped));
    Ok(summary)
}

impl RunSummary {
    /// The summary of a run of `scene` before its first state is recorded by `rec`.
    pub(crate) fn before_the_run(scene: &Scene, rec: &Recorder<'_>) -> Self {
        Self {
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
            resting_steps: 0,
            held_island_steps: 0,
            island_wakes: 0,
            start_failure: None,
            linear_solves: 0,
            linear_solves_by_stage: nsga::SolvesByStage::default(),
            newton_work: nsga::NewtonWork::default(),
            max_energy_increase: f64::NEG_INFINITY,
            deepest: rec.deepest,
            penetration_tol: PENETRATION_TOL * scene.smallest_block_height(),
            events: Vec::new(),
            corner_contacts: 0,
            redone_steps: 0,
            error: None,
        }
    }

    /// The summary of a run whose consistent start failed with `e` after `solver_time`
    /// seconds: the blocks where they started.
    fn failed_start(scene: &Scene, e: StepError, solver_time: f64) -> Self {
        let q0 = scene.initial_coordinates();
        Self {
            error: Some(RunError::Start(e)),
            final_poses: final_poses(scene, &q0),
            max_energy_increase: 0.0,
            wall_time_s: solver_time,
            ..Self::before_the_run(scene, &Recorder::new(scene, &q0))
        }
    }

    /// Counts an accepted step with statistics `stats`; `record_branches`: list its
    /// branch point, if any.
    pub(crate) fn count_step(&mut self, stats: &nsga::StepStats, record_branches: bool) {
        self.steps += 1;
        if stats.retries > 0 {
            self.failed_steps += 1;
        }
        if record_branches {
            self.branch_points
                .extend(stats.branch.as_ref().map(|b| BranchRecord {
                    t: b.t,
                    candidates: b.tried,
                    distinct: b.candidates.len(),
                }));
        }
        if stats.substeps > 1 {
            self.split_steps += 1;
        }
        if stats.unshifted {
            self.unshifted_steps += 1;
        }
        if let Some(last) = &stats.last_resort {
            self.fallback_steps += 1;
            self.fallback_residual = self.fallback_residual.max(last.residual);
        }
    }
}

/// The poses of the blocks at coordinates `q`, bottom to top.
pub(crate) fn final_poses(scene: &Scene, q: &[f64]) -> Vec<BlockPose> {
    (0..scene.n_blocks())
        .map(|k| Pose::from_slice(&q[3 * k..3 * k + 3]).into())
        .collect()
}

/// One line per kind of failure event: the blocks in the order they were affected (named
/// by `label`), each with its time.
fn write_events(
    f: &mut std::fmt::Formatter<'_>,
    events: &[FailureEvent],
    label: &dyn Fn(Body) -> String,
) -> std::fmt::Result {
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
            "the stack's height dropped by a block",
        ),
        (EventKind::TouchedFloor, "blocks that touched the floor"),
    ] {
        let of_kind: Vec<String> = events
            .iter()
            .filter(|e| e.kind == kind)
            .map(|e| match (e.block, e.on) {
                (Some(k), Some(on)) => format!(
                    "{} on {} at t = {:.4}",
                    label(Body::Block(k)),
                    label(on),
                    e.t
                ),
                (Some(k), None) => format!("{} at t = {:.4}", label(Body::Block(k)), e.t),
                (None, _) => format!("at t = {:.4}", e.t),
            })
            .collect();
        if !of_kind.is_empty() {
            write!(f, "\n{heading}: {}", of_kind.join(", "))?;
        }
    }
    Ok(())
}

/// Updates the failure and opening times from the contacts last recorded at t.
pub(crate) fn check_failure(rec: &Recorder<'_>, t: f64, summary: &mut RunSummary) {
    summary.failure_time = rec.watch.first_time(EventKind::SupportLost);
    if summary.opening_time.is_none() && rec.contacts.first_open(rec.open_tol).is_some() {
        summary.opening_time = Some(t);
    }
}

/// The JSON report of one run (`rollstack blocks run` and `lire`; docs/cli.md): the
/// run's summary (its keys inline), what follows from it, the time reached and the prox
/// parameter used.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunReport {
    /// What the run did.
    #[serde(flatten)]
    pub summary: RunSummary,
    /// The run's failure ([`crate::events::failure`]): its first event (support lost,
    /// tipped, reached the floor, height dropped), with its kind, time and block; null
    /// while the column stands.
    pub failure: Option<FailureEvent>,
    /// The deepest penetration between any two bodies over the run (0 when they only
    /// touch); above `PENETRATION_TOL` of the smallest block height it is also a warning.
    pub max_penetration: f64,
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
    /// The blocks' names (for the text: `block 3 (lintel)`); the JSON numbers them.
    #[serde(skip)]
    names: Vec<Option<String>>,
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
            summary: summary.clone(),
            failure: crate::events::failure(&summary.events),
            max_penetration: summary.deepest.depth(),
            t_final,
            prox: options.prox.unwrap_or(scene.solver.prox),
            warnings: RunWarning::of(scene, summary),
            scene: SceneReport::new(scene, options, defaults),
            names: (1..=scene.n_blocks())
                .map(|k| scene.block_name(k).map(str::to_owned))
                .collect(),
        }
    }

    /// A body as the text names it: `block 3 (lintel)` for a named block.
    fn label(&self, body: Body) -> String {
        match body {
            Body::Block(k) => match self.names.get(k - 1).and_then(Option::as_deref) {
                Some(name) => format!("{body} ({name})"),
                None => body.to_string(),
            },
            other => other.to_string(),
        }
    }
}

/// A gap that may be +∞ as JSON: null when it is not finite.
fn finite_or_null<S: serde::Serializer>(x: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&Some(*x).filter(|x| x.is_finite()), serializer)
}

/// A list as JSON: its length.
fn count<T, S: serde::Serializer>(v: &[T], serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_u64(v.len() as u64)
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
        let s = &self.summary;
        let min_gap = Some(s.min_gap).filter(|g| g.is_finite()).map_or_else(
            || "none (no contact could close)".to_owned(),
            |g| format!("{g:.3e}"),
        );
        writeln!(f, "{}", self.scene)?;
        writeln!(
            f,
            "{} steps to t = {:.4} (solver {:.3} s, {:.2} Newton iterations per step, prox {})",
            s.steps, self.t_final, s.wall_time_s, s.newton_iterations_mean, self.prox
        )?;
        writeln!(
            f,
            "failure (loss of support) {}, first full opening {}",
            time(s.failure_time),
            time(s.opening_time)
        )?;
        write!(
            f,
            "min gap {min_gap}, failed Newton steps {}, branch points {}, split steps {}, linear solves {}, largest energy increase {:.3e}",
            s.failed_steps, s.branch_points.len(), s.split_steps, s.linear_solves, s.max_energy_increase
        )?;
        write!(
            f,
            "\nlargest penetration between two bodies {:.3e}",
            self.max_penetration
        )?;
        if self.max_penetration > 0.0 {
            let p = &s.deepest;
            write!(
                f,
                " ({} and {} at t = {:.4})",
                p.penetration.first, p.penetration.second, p.t
            )?;
        }
        if s.corner_contacts > 0 {
            write!(
                f,
                "\ncorner contacts between bodies beyond the stack's neighbours: up to {} at once, steps redone for a missed contact {}",
                s.corner_contacts, s.redone_steps
            )?;
        }
        let label = |b: Body| self.label(b);
        write_events(f, &s.events, &label)?;
        write!(
            f,
            "\n{}",
            crate::events::Verdict::new(self.failure, self.t_final, s.error.is_some()).line(&label)
        )?;
        if s.resting_steps > 0 {
            write!(
                f,
                "\nsteps held at rest without solving (the base standing still): {}",
                s.resting_steps
            )?;
        }
        if s.held_island_steps > 0 {
            write!(
                f,
                "\nsteps with blocks at rest held out of the solve: {} (woken by a force {} times)",
                s.held_island_steps, s.island_wakes
            )?;
        }
        if s.fallback_steps > 0 {
            write!(
                f,
                "\nlast-resort steps {} (Moreau–Jean, Lemke), largest residual {:.1e}",
                s.fallback_steps, s.fallback_residual
            )?;
        }
        for (k, p) in s.final_poses.iter().enumerate() {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};
    use crate::time_guard::WATCHDOG_GRACE_S;
    use input::watchdog::TickingClock;

    /// A recorder keeps the last state's deepest overlap for a state at the same
    /// coordinates, to the bit, and measures it anew for any other: each record's is the
    /// one measured afresh, at a state, another where block 2 sinks into block 1 and
    /// the first again, with and without the broad phase's findings of that state.
    #[test]
    fn a_recorder_measures_each_states_overlap_as_a_fresh_measure_would() {
        let scene = shaking_column(&Shaking {
            blocks: 2,
            ..Shaking::default()
        })
        .unwrap();
        let options = stepper_options(&scene, &RunOptions::default()).unwrap();
        let (q0, u0) = (scene.initial_coordinates(), scene.initial_velocities());
        let stepper = nsga::Stepper::new(
            crate::StackSystem::new(scene.clone()),
            0.0,
            &q0,
            &u0,
            options,
        )
        .unwrap();
        let at = stepper.state().clone();
        let mut sunk = at.clone();
        sunk.q[4] -= 0.01;
        let mut rec = Recorder::new(&scene, &q0);
        for (st, scanned) in [(&at, false), (&sunk, true), (&sunk, false), (&at, true)] {
            let found = crate::broad_phase::scan(&scene, 0.0, &st.q, &st.u, 1e-3);
            rec.record(0.0, st, 0, scanned.then_some(&found));
            let fresh = deepest_penetration(&scene, 0.0, &st.q);
            assert_eq!(rec.last_overlap.as_ref().map(|l| l.2), Some(fresh));
        }
        assert!(rec.deepest.penetration.depth > 0.009, "{:?}", rec.deepest);
    }

    #[test]
    fn the_watchdog_stops_a_run_with_a_typed_error() {
        // A second a step: once past the grace time, projected at a second per step.
        let scene = shaking_column(&Shaking::default()).unwrap();
        let options = RunOptions::default();
        let t_end = scene.solver.t_end;
        let dog = Watchdog::new(TickingClock::default(), 0.0, t_end, TIME_BOUND_S);
        let s = simulate_watched(&scene, &options, dog, |_| ControlFlow::Continue(())).unwrap();
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let grace = WATCHDOG_GRACE_S as usize;
        assert_eq!(s.steps, grace);
        let Some(RunError::Stopped(o)) = &s.error else {
            panic!("{:?}", s.error)
        };
        #[allow(clippy::cast_precision_loss)]
        let steps = step_count(t_end, scene.solver.dt) as f64;
        assert!((o.projected_s - steps).abs() < 1e-6 * steps, "{o:?}");
        let said = s.error.as_ref().unwrap().to_string();
        assert!(
            said.starts_with("stopped by the watchdog: the run was projected"),
            "{said}"
        );
        assert!(
            said.contains("more than 600 s") && said.contains("--force"),
            "{said}"
        );
    }

    /// One step can outlast the bound by hours (a 10 000-block column that tips within
    /// its first step at Δt = 0.01, docs/method.md §8.2): the run is stopped within the
    /// step, not after it. Here the bound has passed before the first step ends, and the
    /// blocks stay where they started.
    #[test]
    fn a_step_that_outlasts_the_bound_is_stopped_within_it() {
        let scene = shaking_column(&Shaking::default()).unwrap();
        let t_end = scene.solver.t_end;
        let dog = Watchdog::new(TickingClock::default(), 0.0, t_end, 1e-9);
        let options = RunOptions::default();
        let s = simulate_watched(&scene, &options, dog, |_| ControlFlow::Continue(())).unwrap();
        assert_eq!((s.steps, s.failed_steps), (0, 0));
        let Some(RunError::Stopped(o)) = &s.error else {
            panic!("{:?}", s.error)
        };
        assert_eq!(o.t, 0.0);
        assert!(o.projected_s.is_infinite(), "{o:?}");
        let said = s.error.as_ref().unwrap().to_string();
        assert!(said.contains("without getting past t = 0"), "{said}");
        let start = final_poses(&scene, &scene.initial_coordinates());
        assert_eq!(s.final_poses, start);
    }

    #[test]
    fn a_run_options_time_bound_watches_the_run_and_none_does_not() {
        let scene = shaking_column(&Shaking::default()).unwrap();
        // A bound of a microsecond: any run of 1000 steps is projected past it.
        let bounded = RunOptions {
            t_end: Some(100.0 * scene.solver.dt),
            time_bound: Some(1e-6),
            ..RunOptions::default()
        };
        let s = simulate(&scene, &bounded, |_| {}).unwrap();
        assert!(
            matches!(s.error, Some(RunError::Stopped(_))),
            "{:?}",
            s.error
        );
        assert!(s.steps < 100, "{}", s.steps);
        let free = RunOptions {
            time_bound: None,
            ..bounded
        };
        let s = simulate(&scene, &free, |_| {}).unwrap();
        assert!(s.error.is_none() && s.steps == 100, "{:?}", s.error);
    }
}
