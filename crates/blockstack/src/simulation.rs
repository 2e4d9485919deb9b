//! Running a scene with the nonsmooth generalized-α stepper (§4.2–4.5): records per
//! step, the failure times of §4.4, energy, branch points, and a summary.
//!
//! - **Start** (§4.3): nsga's consistent start solves once with every closed contact
//!   closed and sticking, so a resting column starts with its static contact forces and
//!   no first-step impulse.
//! - **Failure** (§4.4, Figure 4.6): `failure_time` is the first time any block has lost
//!   its support on the block beneath ((G.2.4) corrected, ERRATA 23); `opening_time` the
//!   first time any interface is open along its whole edge (both gaps above
//!   [`OPEN_GAP_TOL`] times the block height) or unsupported.
//! - **Energy**: kinetic plus potential energy of the free blocks; with a fixed base,
//!   e_N = e_F = 0 and Coulomb friction it must never increase ([`RunSummary`]'s
//!   `max_energy_increase`).
//! - **Branch points** (NSGA-SPEC §4, ERRATA 22): when Newton does not converge because
//!   the index sets alternate, nsga re-solves the step with each distinct set fixed and
//!   continues with the first self-consistent candidate; each such step is recorded with
//!   the number of sets tried and of distinct converged states.
//!   When nsga finds no candidate, the step is taken as two half steps with this same
//!   policy (up to [`MAX_HALVINGS`] times). Only when that fails too, the re-solves are
//!   repeated with a consistency test that accepts friction laws sitting exactly on their
//!   stick–slip bound (round-off then decides their index set), and with the sets one
//!   friction switch away from the visited ones (see `resolve_at_boundary`).
//! - **Redundant contacts**: a toppled column resting on the table edge and on the floor
//!   with several corners touches at more points than it has degrees of freedom; nsga's
//!   regularized Newton update ([`nsga::Options::regularization`]) carries it.
//! - **Errors**: a step that fails after every fallback ends the run; the summary up to
//!   it carries the message (`error`), it is not an `Err`.

use crate::coordinates::Pose;
use crate::error::BlockError;
use crate::scene::Scene;
use crate::stack::StackContacts;
use crate::system::StackSystem;
use nsga::{IndexSets, Options, RhoInfRetry, SolverChoice, StepError, Stepper};
use std::time::Instant;

pub use nsga::Prox;

/// The errors of [`simulate`]: bad scenes or options.
pub type BlockstackError = BlockError;

/// Relative tolerance (of the block height) above which a gap counts as open when
/// deciding that an interface has opened completely.
pub const OPEN_GAP_TOL: f64 = 1e-6;

/// Unknowns up to which the Newton matrix is factorized by [`nsga::MarkowitzLu`] (dense
/// storage, sparse elimination); above, by faer's sparse LU.
///
/// Measured on the Lire collapse on a floor (124 unknowns, fewer while the floor contacts
/// are open and pruned): the whole run is about twice as fast with dense LU as with
/// faer's sparse LU, and Markowitz LU, which skips the zeros that make up most of these
/// matrices, is faster again (`cargo run --release -p blockstack --example lire_nearby
/// 60 --floor`, paired
/// runs: median solver time 105–114 ms against 126–127 ms with dense LU). The banded
/// matrix of a tall column needs the sparse solver. Both small solvers detect the
/// singular matrices of redundant contacts by their pivots (see
/// `nsga::Options::regularization`).
pub const SMALL_LU_UP_TO: usize = 200;

/// Newton iterations allowed when checking that a fixed-set solution also solves the
/// free step (it converges at once when it does; see `resolve_at_boundary`).
pub const QUICK_CHECK_ITERATIONS: usize = 8;

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

/// Halvings allowed in the line search of each Newton update (`nsga::Options::line_search`).
/// Measured on the Lire collapse on a floor and 29 neighbours (`cargo run --release -p
/// blockstack --example lire_nearby 30 --floor`): with 3, failed steps fall from 6.5 to
/// 3.3 per run and linear solves by 5 %; more halvings change nothing.
pub const LINE_SEARCH_HALVINGS: usize = 3;

/// Newton iterations per attempt before nsga gives it up.
pub const MAX_NEWTON_ITERATIONS: usize = 40;

/// Which failed attempts nsga retries with other ρ∞ (thesis §4.2): only those stopped by
/// a singular Newton matrix, the case the thesis introduces the retries for. A step
/// whose index sets cycle goes straight to the fixed-set re-solves, then to halving.
///
/// Retried after every failure (`RhoInfRetry::AnyFailure`), the four other ρ∞ of
/// `nsga::Options` seldom converge: their attempts mostly retrace the first attempt's
/// cycle of sets to the same residuals. Over the Lire collapse on a floor and 99
/// neighbours (`cargo run --release -p blockstack --example lire_nearby 100 --floor`)
/// they cost 14 % of the linear solves: 1037 per run against 893 with this choice, with no run stopped by an
/// error either way and 2.9 against 2.7 steps per run needing a fallback.
pub const RHO_INF_RETRY: RhoInfRetry = RhoInfRetry::SingularMatrix;

/// Choices of a run that are not part of the scene.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// End time; overrides the scene's `solver.t_end`.
    pub t_end: Option<f64>,
    /// Prox parameter; overrides the scene's choice.
    pub prox: Option<Prox>,
    /// Record branch points (re-solve with fixed sets when Newton cycles).
    pub explore_branches: bool,
    /// Stop as soon as `failure_time` is known (sweeps).
    pub stop_at_failure: bool,
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
    /// One per interface (n of them), bottom to top.
    pub forces: Vec<InterfaceForce>,
    /// Smallest gap among the contacts that can close (+∞ if none can).
    pub min_gap: f64,
    /// Newton iterations of the step (0 for the initial state).
    pub iterations: usize,
    /// Kinetic plus potential energy of the free blocks.
    pub energy: f64,
}

/// A step resolved by fixed-set re-solves (NSGA-SPEC §4).
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
    /// Linear solves of the Newton iterations, in every attempt (failed ones, retries,
    /// fixed-set re-solves and substeps included): the run's work, independent of the
    /// machine ([`nsga::Stepper::linear_solves`]).
    pub linear_solves: u64,
    /// Largest increase of the energy between two steps (unforced runs: ≤ ~0).
    pub max_energy_increase: f64,
    /// The message of a step that finally failed (the run stopped there).
    pub error: Option<String>,
}

/// nsga's options for a scene.
///
/// # Errors
/// Bad run options (t_end, prox).
pub fn stepper_options(scene: &Scene, options: &RunOptions) -> Result<Options, BlockstackError> {
    let s = &scene.solver;
    let opts = Options {
        dt: s.dt,
        rho_inf: s.rho_inf,
        prox: options.prox.unwrap_or(s.prox),
        tol: s.tol,
        max_iter: MAX_NEWTON_ITERATIONS,
        explore_branches: options.explore_branches,
        // Markowitz LU for the small scenes of the thesis, faer's sparse LU for tall
        // columns (the Newton matrix of a chain is banded).
        solver: SolverChoice::Markowitz(SMALL_LU_UP_TO),
        prune_open_contacts: true,
        reuse_factorization: true,
        line_search: LINE_SEARCH_HALVINGS,
        rho_inf_retry: RHO_INF_RETRY,
        ..Options::default()
    };
    opts.validate()
        .map_err(|e| BlockError::Scene(format!("solver options: {e}")))?;
    Ok(opts)
}

/// Number of steps to reach t_end with the scene's Δt (a final partial step is taken
/// whole).
fn step_count(t_end: f64, dt: f64) -> usize {
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
struct Recorder<'a> {
    scene: &'a Scene,
    contacts: StackContacts<f64>,
    open_tol: f64,
}

impl Recorder<'_> {
    fn record(&mut self, t: f64, st: &nsga::State, iterations: usize) -> StepRecord {
        let n = self.scene.n_blocks();
        self.scene
            .contacts_into(t, &st.q, &st.u, &mut self.contacts);
        let poses = (0..n)
            .map(|k| Pose::from_slice(&st.q[3 * k..3 * k + 3]).into())
            .collect();
        let forces = (0..n)
            .map(|k| InterfaceForce {
                normal: [st.lambda_n[2 * k], st.lambda_n[2 * k + 1]],
                friction: st.lambda_f[k],
            })
            .collect();
        StepRecord {
            t,
            poses,
            base: self.scene.base().state(t).pose.into(),
            forces,
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
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    crate::block::positive("t_end", t_end)?;
    let opts = stepper_options(scene, options)?;
    let dt = opts.dt;
    let steps_wanted = step_count(t_end, dt);
    let q0 = scene.initial_coordinates();
    let u0 = vec![0.0; q0.len()];
    let height = scene
        .blocks()
        .iter()
        .map(crate::Block::height)
        .fold(f64::INFINITY, f64::min);
    let mut rec = Recorder {
        scene,
        contacts: StackContacts::default(),
        open_tol: OPEN_GAP_TOL * height,
    };
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
        linear_solves: 0,
        max_energy_increase: f64::NEG_INFINITY,
        error: None,
    };
    let clock = Instant::now();
    let started = Stepper::new(StackSystem::new(scene.clone()), 0.0, &q0, &u0, opts);
    let mut solver_time = clock.elapsed().as_secs_f64();
    let mut stepper = match started {
        Ok(s) => s,
        Err(e) => {
            summary.error = Some(format!("consistent start failed: {e}"));
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
    on_step(&first);
    let mut iterations = 0usize;
    for _ in 0..steps_wanted {
        if options.stop_at_failure && summary.failure_time.is_some() {
            break;
        }
        let clock = Instant::now();
        let result = advance(&mut stepper, options.explore_branches);
        solver_time += clock.elapsed().as_secs_f64();
        let (t, its, retries, branch) = match result {
            Ok(r) => r,
            Err(e) => {
                summary.failed_steps += 1;
                summary.error = Some(e.to_string());
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
        let r = rec.record(t, stepper.state(), its);
        summary.min_gap = summary.min_gap.min(r.min_gap);
        summary.max_energy_increase = summary.max_energy_increase.max(r.energy - energy);
        energy = r.energy;
        check_failure(&rec, t, &mut summary);
        on_step(&r);
    }
    summary.linear_solves = stepper.linear_solves();
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

/// One step: nsga's step (ρ∞ retries after a singular matrix, [`RHO_INF_RETRY`], and
/// fixed-set re-solves when the sets cycle);
/// when that fails, the step is taken as two half steps, each with this same policy,
/// up to [`MAX_HALVINGS`] times; only when that fails too, and `explore` is set, the
/// fixed-set re-solves are repeated with a weaker consistency test
/// ([`resolve_at_boundary`]), the costliest fallback.
fn advance(stepper: &mut Stepper<StackSystem>, explore: bool) -> Result<Accepted, StepError> {
    advance_with_halvings(stepper, explore, MAX_HALVINGS)
}

fn advance_with_halvings(
    stepper: &mut Stepper<StackSystem>,
    explore: bool,
    halvings: usize,
) -> Result<Accepted, StepError> {
    let error = match stepper.step() {
        Ok(s) => return Ok(accepted(s)),
        Err(e @ StepError::InvalidInput(_)) => return Err(e),
        Err(e) => e,
    };
    if halvings > 0 {
        let halves = stepper.split_step(2, |s| {
            advance_with_halvings(s, explore, halvings - 1).map(|_| ())
        });
        if let Ok(s) = halves {
            return Ok(accepted(s));
        }
    }
    match error {
        StepError::NotConverged {
            visited_sets,
            cycling: true,
            residual,
            ..
        } if explore => resolve_at_boundary(stepper, &visited_sets, residual),
        e => Err(e),
    }
}

/// Fixed-set re-solves (NSGA-SPEC §4) for a step whose Newton iterates cycle because
/// a contact sits exactly on the boundary between two states.
///
/// nsga keeps a fixed-set solution only when the index sets recomputed from it equal
/// the fixed ones. When a friction law sits exactly at its stick–slip bound (zero slip
/// and ‖λ_F‖ = μ Σλ_N, as happens when a column rotating about the table edge starts to
/// slip while the interfaces above it also reach their bound), round-off decides its
/// set, so no candidate passes that test although several solve the step. Here a
/// fixed-set solution is kept when its recomputed sets differ from the fixed ones only
/// in laws on their bound ([`at_friction_bounds`]), or else when a Newton solve with
/// free sets started from it converges (then that free solution is kept). When no
/// visited set gives a solution, the sets one friction-law switch away
/// ([`neighbour_sets`]) are tried the same way until the first solution. Candidates are
/// deduplicated by state and the first, in the order tried, is taken; the step is
/// reported as a branch point (sets tried, distinct solutions).
fn resolve_at_boundary(
    stepper: &mut Stepper<StackSystem>,
    visited: &[IndexSets],
    residual: f64,
) -> Result<Accepted, StepError> {
    let saved = stepper.state().clone();
    let rho = stepper.options().rho_inf;
    let mut candidates: Vec<(IndexSets, nsga::State)> = Vec::new();
    let mut first: Option<nsga::Trial> = None;
    let laws = stepper.system().scene().friction_laws();
    let all = neighbour_sets(visited, &laws);
    let options = stepper.options().clone();
    let quick = Options {
        max_iter: QUICK_CHECK_ITERATIONS,
        ..options.clone()
    };
    let mut tried = 0;
    for (i, sets) in all.iter().enumerate() {
        let is_visited = i < visited.len();
        // Neighbours only until a first solution is found.
        if !is_visited && first.is_some() {
            break;
        }
        tried += 1;
        let Ok(fixed) = stepper.trial(Some(sets), rho) else {
            continue;
        };
        let recomputed = stepper.sets_of(&fixed.state.x, rho);
        let candidate = if at_friction_bounds(stepper, sets, &recomputed, &fixed.state) {
            fixed
        } else {
            // Does a free Newton solve started from it converge?
            let mut start = saved.clone();
            start.x.clone_from(&fixed.state.x);
            stepper.set_state(start);
            stepper.set_options(quick.clone())?;
            let free = stepper.trial(None, rho);
            stepper.set_options(options.clone())?;
            stepper.set_state(saved.clone());
            let Ok(free) = free else { continue };
            free
        };
        let duplicate = candidates
            .iter()
            .any(|(_, s)| s.same_motion(&candidate.state));
        if !duplicate {
            candidates.push((candidate.stats.sets.clone(), candidate.state.clone()));
            if first.is_none() {
                first = Some(candidate);
            }
        }
    }
    let Some(mut trial) = first else {
        return Err(StepError::NotConverged {
            t: saved.t,
            residual,
            visited_sets: visited.to_vec(),
            cycling: true,
            state: Box::new(saved),
            best: None,
        });
    };
    trial.stats.retries = 1 + stepper.options().rho_inf_retries.len();
    trial.stats.branch = Some(nsga::BranchPoint {
        t: saved.t,
        candidates,
        tried,
        chosen: 0,
    });
    stepper.commit(trial);
    Ok(accepted(
        stepper.last_step().expect("a step was just committed"),
    ))
}

/// The sets to try with the sets fixed: those the Newton iterates visited, in order, then
/// each of them with one friction law switched to another state (slip, stick on velocity
/// level only, stick): the self-consistent sets of a step where one law crosses its
/// bound are often one switch away from the ones Newton alternates between.
fn neighbour_sets(visited: &[IndexSets], laws: &[crate::FrictionLaw]) -> Vec<IndexSets> {
    let mut out: Vec<IndexSets> = visited.to_vec();
    for sets in visited {
        for (j, law) in laws.iter().enumerate() {
            // An inactive law (all its gaps open) has no state to switch.
            if !law.normals.iter().any(|&k| sets.a[k]) {
                continue;
            }
            for (d, e) in [(false, false), (true, false), (true, true)] {
                let mut s = sets.clone();
                s.d[j] = d;
                s.e[j] = e;
                if !out.contains(&s) {
                    out.push(s);
                }
            }
        }
    }
    out
}

/// Whether the sets recomputed from a fixed-set solution differ from the fixed ones only
/// in friction laws that sit exactly on their stick–slip bound, where either set
/// describes the same solution (NSGA-SPEC §3, laws 137–142): on velocity level a slip
/// ξ_F = 0 with ‖P_F‖ = μP̂, on acceleration level γ̇_F = 0 with ‖λ_F‖ = μλ̂ (all within
/// the Newton tolerance, velocities and accelerations taken as impulses per unit mass
/// over one step).
fn at_friction_bounds(
    stepper: &Stepper<StackSystem>,
    fixed: &IndexSets,
    recomputed: &IndexSets,
    st: &nsga::State,
) -> bool {
    if fixed == recomputed {
        return true;
    }
    if fixed.a != recomputed.a || fixed.b != recomputed.b || fixed.c != recomputed.c {
        return false;
    }
    let scene = stepper.system().scene();
    let opts = stepper.options();
    let (tol, dt) = (opts.tol, opts.dt);
    let e_f = scene.contact.e_f;
    let at_end = scene.contacts(st.t, &st.q, &st.u);
    let laws = scene.friction_laws();
    laws.iter().enumerate().all(|(j, law)| {
        let same = fixed.d[j] == recomputed.d[j] && fixed.e[j] == recomputed.e[j];
        if same {
            return true;
        }
        let row = &at_end.slips[j];
        let p_hat: f64 = law.normals.iter().map(|&k| st.p_n[k]).sum::<f64>().max(0.0);
        let l_hat: f64 = law
            .normals
            .iter()
            .map(|&k| st.lambda_n[k])
            .sum::<f64>()
            .max(0.0);
        let velocity_ok = fixed.d[j] == recomputed.d[j] || {
            // e_F = 0 in every scene of the thesis; otherwise the e_F γ_F(q, u_n) part of
            // ξ_F is not known here and the case is not accepted.
            e_f == 0.0
                && row.value.abs() <= tol
                && (st.p_f[j].abs() - law.mu * p_hat).abs() <= tol * (1.0 + law.mu * p_hat)
        };
        let acceleration_ok = fixed.e[j] == recomputed.e[j] || {
            let rate = row.w.dot(&st.a) + row.zeta;
            rate.abs() * dt <= tol
                && (st.lambda_f[j].abs() - law.mu * l_hat).abs() * dt
                    <= tol * (1.0 + law.mu * l_hat * dt)
        };
        velocity_ok && acceleration_ok
    })
}

/// Updates the failure and opening times from the contacts last recorded at t.
fn check_failure(rec: &Recorder<'_>, t: f64, summary: &mut RunSummary) {
    if summary.failure_time.is_none() && rec.contacts.first_unsupported().is_some() {
        summary.failure_time = Some(t);
    }
    if summary.opening_time.is_none() && rec.contacts.first_open(rec.open_tol).is_some() {
        summary.opening_time = Some(t);
    }
}
