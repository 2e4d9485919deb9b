//! The nonsmooth generalized-α stepper (docs/method.md §3–4, paper eqs. 71–143).
//!
//! One concept per module:
//! - `unknowns`: the unknowns x of a step (eq. 126) and their offsets;
//! - `iterate`: what one iterate derives from x (eqs. 71–125), the system evaluated
//!   there, and its index sets (eqs. 128–142);
//! - `assemble`: the residual R(x) (eqs. 127–142) and its semismooth Jacobian (eq. 143);
//! - `slip`: the sliding rows of a friction law and their guarded directions;
//! - `kinematic`: the unknowns z the Newton matrix is assembled in, and back to x;
//! - `rows`: sparse rows over x and the chain rule through q_{n+1}(x), u_{n+1}(x);
//! - `spec`: one attempt at the step as a value (start, index-set rule, ρ∞, budget, …);
//! - `scheme`: what an attempt's iterates are evaluated and updated with;
//! - `solve`: one Newton attempt at the step on nsga's [`newton`](crate::newton)
//!   engine;
//! - `prune`: the open contacts left out of an attempt's linear solve;
//! - `direction`: the Newton update, exact (regularized when singular) or from kept
//!   factors;
//! - `trial`: the uncommitted step an attempt ends on;
//! - `predict`: the Newton start extrapolated from the last steps' solutions;
//! - `policy`: the stages of a step, the one transition table between them, and the
//!   loop of [`Stepper::step`] over them;
//! - `stages`: what each stage runs;
//! - `islands`: the islands of bodies at rest, held out of the solve;
//! - `halving`: a step taken as substeps (the halving stage, [`Stepper::split_step`]);
//! - `branch`: the fixed-set re-solves and their self-consistent, deduplicated
//!   candidates (branch points);
//! - `last_resort`: the Moreau–Jean step of the last stage.

use crate::attempt::Trial;
use crate::error::StepError;
use crate::linalg::{AutoSolver, DenseLu, LinearSolver, SparseLu};
use crate::newton::NewtonScratch;
use crate::options::{Options, SolverChoice};
use crate::report::{NewtonWork, RunStats, SolvesByStage, StepStats};
use crate::sets::IndexSets;
use crate::start::{consistent_start, Start};
use crate::state::State;
use crate::system::{Derivatives, Evaluation, Layout, System, Triplets};
use direction::Refusal;
use iterate::Iterate;
pub(crate) use policy::Stage;
use rows::RowMat;
use spec::SetRule;
use state_levels::StateLevels;
use unknowns::Offsets;

mod assemble;
mod branch;
mod direction;
mod enumerate;
mod far;
mod fd_jacobian;
mod halving;
mod held;
mod islands;
mod iterate;
mod kinematic;
mod last_resort;
mod low_rank;
mod multipliers;
mod painleve;
mod policy;
mod predict;
mod prune;
mod resize;
mod rest;
pub(crate) mod rows;
mod scheme;
mod slip;
mod solve;
mod spec;
mod stages;
mod state_levels;
mod trial;
mod unknowns;
mod z_columns;

pub use assemble::GAP_ROUND_OFF;
pub use direction::WILD_UPDATE;
pub use iterate::SET_TIE;
pub use low_rank::LOW_RANK_ROWS;
pub use slip::NEGLIGIBLE_SLIP;

/// Spent index sets kept for their buffers: a step evaluates a few iterates, each of
/// which decides its sets anew (five vectors of flags), and most of them are dropped by
/// the end of the step.
const SPARE_SETS: usize = 8;

/// The state at (k, t, q, u) with the accelerations and forces of a consistent start
/// (docs/method.md §5): ā = a, λ̄ = λ, and the next Newton start x holding them.
fn started_state(
    off: &Offsets,
    (k, t, q, u): (u64, f64, Vec<f64>, Vec<f64>),
    start: Start,
    p_n: Vec<f64>,
    p_f: Vec<f64>,
) -> State {
    let mut x = vec![0.0; off.n];
    x[off.a..off.a + off.nu].copy_from_slice(&start.a);
    x[off.lg..off.lg + off.ng].copy_from_slice(&start.lambda_g);
    x[off.lga..off.lga + off.nga].copy_from_slice(&start.lambda_gamma);
    x[off.ln..off.ln + off.nn].copy_from_slice(&start.lambda_n);
    x[off.lf..off.lf + off.nf].copy_from_slice(&start.lambda_f);
    State {
        k,
        t,
        q,
        u,
        a: start.a.clone(),
        a_bar: start.a,
        lambda_n: start.lambda_n.clone(),
        lambda_n_bar: start.lambda_n,
        lambda_f: start.lambda_f.clone(),
        lambda_f_bar: start.lambda_f,
        p_n,
        p_f,
        x,
    }
}

/// The nonsmooth generalized-α stepper for one system.
#[derive(Debug)]
pub struct Stepper<S: System> {
    system: S,
    layout: Layout,
    off: Offsets,
    options: Options,
    state: State,
    stats: RunStats,
    last: Option<StepStats>,
    work: Work,
    law_off: Vec<usize>,
    comp_ef: Vec<f64>,
    /// (t, k) from which the time grid t_k is counted.
    time_base: (f64, u64),
    /// Linear solves by stage (`other` left zero: it is what the stages do not count).
    stage_solves: SolvesByStage,
    /// The Newton work by kind ([`Stepper::newton_work`]).
    newton_work: NewtonWork,
    /// Why the simplified update the Newton engine last asked for was refused, until the
    /// exact update that follows counts it (`NewtonWork::exact_because`; None there:
    /// none was asked for, `not_asked`).
    refusal: Option<Refusal>,
    /// Why the consistent start failed, when the stepper started without consistent
    /// accelerations and forces (docs/method.md §5).
    start_failure: Option<String>,
    /// The last steps' solutions, for a predicted Newton start
    /// ([`NewtonOptions::predict_start`](crate::NewtonOptions::predict_start)).
    predictor: predict::StartPredictor,
    /// Where the state stands on the way to rest (`stepper/rest.rs`).
    rest: rest::Rest,
    /// How the last commit moved q (`stepper/rest.rs`).
    moved: rest::Moved,
    /// Whether the last commit kept the index sets of the step before.
    same_sets: bool,
    /// The islands held at rest (`stepper/islands.rs`).
    islands: islands::Islands,
    /// When the step in progress should stop ([`Stepper::set_interrupt`]).
    interrupt: crate::Interrupt,
}

/// Buffers reused from iterate to iterate and step to step.
#[derive(Debug)]
struct Work {
    eval: Evaluation<f64>,
    der: Derivatives,
    bt: Triplets<f64>,
    b: RowMat,
    bdot_u: Vec<f64>,
    jac: Vec<(usize, usize, f64)>,
    /// The positions in `jac` of the regularization entries (§7 of docs/method.md), and
    /// the open form's diagonal entry of each row, which ε multiplies.
    regularized: Vec<usize>,
    regularization_scale: Vec<assemble::EpsScale>,
    /// `jac` renumbered to the unknowns left after pruning; `jac` itself is kept, so
    /// that a singular plain matrix is regularized without being assembled again.
    jac_pruned: Vec<(usize, usize, f64)>,
    /// Scratch of the assembly of a sliding friction row: its radius's columns.
    radius_cols: Vec<(usize, f64)>,
    /// Power-of-two row scales of an equilibrated regularized matrix.
    row_scale: Vec<f64>,
    rhs_red: Vec<f64>,
    res: Vec<f64>,
    newton: NewtonScratch,
    // Derivative rows over x: p, ξ_p, p̈, ξ_v, v, v̇.
    dg: RowMat,
    dxp: RowMat,
    dap: RowMat,
    dxv: RowMat,
    dgv: RowMat,
    dav: RowMat,
    r_pos: Vec<f64>,
    r_vel: Vec<f64>,
    r_law: Vec<f64>,
    /// Index sets no longer needed, whose buffers [`Stepper::compute_sets`] reuses (at
    /// most [`SPARE_SETS`]).
    spare_sets: Vec<IndexSets>,
    /// The list of the sets a committed trial visited, emptied, for the next Newton
    /// run's ([`NewtonProblem::visited_list`](crate::newton::NewtonProblem::visited_list)).
    spare_visited: Vec<IndexSets>,
    /// The state the last commit replaced, whose buffers the next trial fills.
    spare_state: State,
    /// Scratch of `prox_parameters`: the diagonal of M.
    mass_diagonal: Vec<f64>,
    it: Iterate,
    solver: Box<dyn LinearSolver>,
    /// Linear solves since the stepper was built, failed attempts included.
    linear_solves: u64,
    /// The last index sets (at most [`Tuning::singular_sets_kept`](crate::Tuning::singular_sets_kept), oldest first) whose Newton
    /// matrix was found singular without regularization.
    singular_sets: Vec<IndexSets>,
    /// The contacts an attempt may not prune (`Stepper::attempt`), a buffer reused from
    /// attempt to attempt.
    keep: Vec<bool>,
    /// The normal contacts that cannot close within the step (`Stepper::open_contacts`),
    /// the last prune map given back, and the pruned contacts that closed at a restart
    /// (`StepProblem::restart`): buffers reused from run to run.
    unclosable: Vec<bool>,
    prune_map: Vec<usize>,
    closing: Vec<bool>,
    /// The name of the linear solver in the statistics the last commit replaced, whose
    /// buffer the next trial's statistics reuse.
    spare_solver_name: String,
    /// Constraints pruned from the current attempt's Newton matrix (empty when none).
    unused_position: Vec<bool>,
    unused_velocity: Vec<bool>,
    /// What the solver's kept factors were assembled for (None: nothing reusable).
    factored: Option<FactoredFor>,
    /// The kept factors' matrix and the scratch of updates for changed sets.
    low_rank: low_rank::LowRank,
    /// The levels of the last converged trial's state, and of the current state, for
    /// the pruning of open contacts (`state_levels`).
    trial_levels: StateLevels,
    state_levels: StateLevels,
    /// Scratch of `Stepper::correction_ratio`: √Mᵢᵢ.
    root_mass_diagonal: Vec<f64>,
}

impl Work {
    /// Buffers for a system of this layout, with the linear solver the options choose.
    fn new(layout: &Layout, options: &Options) -> Self {
        let linear = &options.linear;
        let solver: Box<dyn LinearSolver> = match linear.solver {
            SolverChoice::Auto(t) => Box::new(AutoSolver::new(t).keeping(linear.symbolic_cache)),
            SolverChoice::Dense => Box::new(DenseLu::default()),
            SolverChoice::Sparse => Box::new(SparseLu::keeping(linear.symbolic_cache)),
            SolverChoice::Markowitz(t) => Box::new(
                AutoSolver::markowitz(t)
                    .with_pivot_threshold(linear.pivot_threshold)
                    .keeping(linear.symbolic_cache),
            ),
        };
        Self {
            eval: Evaluation::new(layout),
            der: Derivatives::default(),
            bt: Triplets::default(),
            b: RowMat::default(),
            bdot_u: vec![0.0; layout.nq],
            jac: Vec::new(),
            regularized: Vec::new(),
            regularization_scale: Vec::new(),
            jac_pruned: Vec::new(),
            radius_cols: Vec::new(),
            row_scale: Vec::new(),
            rhs_red: Vec::new(),
            res: vec![0.0; Offsets::new(layout).n],
            newton: NewtonScratch::default(),
            dg: RowMat::default(),
            dxp: RowMat::default(),
            dap: RowMat::default(),
            dxv: RowMat::default(),
            dgv: RowMat::default(),
            dav: RowMat::default(),
            r_pos: Vec::new(),
            r_vel: Vec::new(),
            r_law: Vec::new(),
            spare_sets: Vec::new(),
            spare_visited: Vec::new(),
            spare_state: State::default(),
            mass_diagonal: Vec::new(),
            it: Iterate::default(),
            solver,
            linear_solves: 0,
            singular_sets: Vec::new(),
            factored: None,
            low_rank: low_rank::LowRank::default(),
            keep: Vec::new(),
            unclosable: Vec::new(),
            prune_map: Vec::new(),
            closing: Vec::new(),
            spare_solver_name: String::new(),
            unused_position: Vec::new(),
            unused_velocity: Vec::new(),
            trial_levels: StateLevels::default(),
            state_levels: StateLevels::default(),
            root_mass_diagonal: Vec::new(),
        }
    }
}

/// The index sets, pruned contacts, Δt and ρ∞ of a factorized Newton matrix: its factors
/// serve a simplified Newton update while all four are unchanged, and for the same
/// sets also where more contacts are pruned than when they were made
/// (`Stepper::kept_direction`).
#[derive(Debug, Clone, PartialEq)]
struct FactoredFor {
    sets: IndexSets,
    prune: Option<prune::Pruning>,
    dt: f64,
    rho_inf: f64,
    /// Factors of the regularized matrix with its rows equilibrated (`work.row_scale`
    /// scales a right-hand side for them): they serve these sets only, without
    /// low-rank updates, whose kept matrix is that of the last plain factorization.
    regularized: bool,
}

impl<S: System> Stepper<S> {
    /// A stepper at t0 = `t0`, q0, u0, with consistent initial accelerations and forces
    /// (docs/method.md §5).
    ///
    /// Where the consistent start fails and
    /// [`PolicyOptions::last_resort`](crate::PolicyOptions::last_resort) is on, the stepper
    /// starts anyway: [`Stepper::start_failure`] says why, and its first step
    /// is taken by the last resort, a Moreau–Jean step, which needs no accelerations and
    /// after which the generalized-α state restarts from a consistent start there.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for bad sizes, options or non-finite input, and where
    /// [`PolicyOptions::last_resort`](crate::PolicyOptions::last_resort) is on for a system the last resort cannot take (bilateral
    /// constraints redundant at t0; the message says which);
    /// [`StepError::Start`] when the acceleration-level start problem is not solved and
    /// the last resort is off.
    pub fn new(
        system: S,
        t0: f64,
        q0: &[f64],
        u0: &[f64],
        options: Options,
    ) -> Result<Self, StepError> {
        options.validate()?;
        let layout = system.layout();
        layout.validate().map_err(StepError::InvalidInput)?;
        if q0.len() != layout.nq || u0.len() != layout.nu {
            return Err(StepError::InvalidInput(format!(
                "q0 has {} entries and u0 {}, the system needs {} and {}",
                q0.len(),
                u0.len(),
                layout.nq,
                layout.nu
            )));
        }
        if !t0.is_finite() || q0.iter().chain(u0).any(|x| !x.is_finite()) {
            return Err(StepError::InvalidInput(
                "t0, q0 and u0 must be finite".into(),
            ));
        }
        last_resort::check_coverage(&system, &layout, options.policy.last_resort, t0, (q0, u0))?;
        let off = Offsets::new(&layout);
        let (start, start_failure) = match consistent_start(&system, &layout, t0, q0, u0, &options)
        {
            Ok(start) => (start, None),
            Err(failed @ StepError::Start { .. }) if options.policy.last_resort => {
                let unforced = Start::unforced(&system, &layout, t0, q0, u0);
                (unforced, Some(failed.to_string()))
            }
            Err(e) => return Err(e),
        };
        let at = (0, t0, q0.to_vec(), u0.to_vec());
        let state = started_state(&off, at, start, vec![0.0; off.nn], vec![0.0; off.nf]);
        let work = Work::new(&layout, &options);
        let law_off = layout.friction_offsets();
        let comp_ef = layout.friction_restitution();
        Ok(Self {
            system,
            layout,
            off,
            options,
            state,
            stats: RunStats::default(),
            last: None,
            work,
            law_off,
            comp_ef,
            time_base: (t0, 0),
            stage_solves: SolvesByStage::default(),
            newton_work: NewtonWork::default(),
            refusal: None,
            start_failure,
            predictor: predict::StartPredictor::default(),
            rest: rest::Rest::Moving,
            moved: rest::Moved::Beyond,
            same_sets: false,
            islands: islands::Islands::default(),
            interrupt: crate::Interrupt::default(),
        })
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }
    /// The system, mutably (to change parameters between steps; the layout must not
    /// change). The stepper then forgets the constraint levels it kept from the last
    /// step's solution and evaluates the state again (docs/method.md §7, "Pruned
    /// matrices").
    pub fn system_mut(&mut self) -> &mut S {
        self.forget_levels();
        &mut self.system
    }
    /// The layout of the system.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// The current (last accepted) state.
    pub fn state(&self) -> &State {
        &self.state
    }
    /// Replaces the state (to continue from a saved state or follow another branch).
    /// After a failed start, the state at k = 0 is again stepped by the last resort.
    pub fn set_state(&mut self, state: State) {
        self.time_base = (state.t, state.k);
        self.state = state;
        self.forget_solutions();
    }
    /// A stepper for the same system and options that continues from `state`, one of
    /// this stepper's states or a candidate of its last branch point (how an exploration
    /// follows each continuation of a fork, [`mod@crate::explore`]). Its time grid is this
    /// stepper's, so t_k of a branch agrees bitwise with the run it forked from; its
    /// statistics start at zero and its buffers (kept factors, remembered singular sets)
    /// are fresh.
    #[must_use]
    pub fn branch_from(&self, state: State) -> Self
    where
        S: Clone,
    {
        Self {
            system: self.system.clone(),
            layout: self.layout.clone(),
            off: self.off,
            options: self.options.clone(),
            state,
            stats: RunStats::default(),
            last: None,
            work: Work::new(&self.layout, &self.options),
            law_off: self.law_off.clone(),
            comp_ef: self.comp_ef.clone(),
            time_base: self.time_base,
            stage_solves: SolvesByStage::default(),
            newton_work: NewtonWork::default(),
            refusal: None,
            start_failure: None,
            predictor: predict::StartPredictor::default(),
            rest: rest::Rest::Moving,
            moved: rest::Moved::Beyond,
            same_sets: false,
            islands: islands::Islands::default(),
            interrupt: self.interrupt.clone(),
        }
    }
    /// Drops the solver's buffers and kept factors (rebuilt at the next step), to hold a
    /// stepper that waits cheaply (an exploration's parked branches).
    pub fn release_buffers(&mut self) {
        let solves = self.work.linear_solves;
        self.work = Work::new(&self.layout, &self.options);
        self.work.linear_solves = solves;
    }

    /// Stops the steps from here on when `interrupt` asks (a caller's flag, a deadline):
    /// a step in progress then ends before its next stage or Newton update with
    /// [`StepError::Interrupted`], the state where the step started
    /// ([`mod@crate::interrupt`]).
    pub fn set_interrupt(&mut self, interrupt: crate::Interrupt) {
        self.interrupt = interrupt;
    }

    /// The options.
    pub fn options(&self) -> &Options {
        &self.options
    }
    /// Changes the options (for example Δt or the prox parameter) mid-run.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] when they are invalid, or switch the last resort on
    /// for a system it cannot take at the current state; nothing changes then.
    pub fn set_options(&mut self, options: Options) -> Result<(), StepError> {
        options.validate()?;
        if options.policy.last_resort && !self.options.policy.last_resort {
            let st = &self.state;
            last_resort::check_coverage(&self.system, &self.layout, true, st.t, (&st.q, &st.u))?;
        }
        if options.dt != self.options.dt {
            self.time_base = (self.state.t, self.state.k);
        }
        self.options = options;
        self.rest = rest::Rest::Moving;
        self.islands.release();
        Ok(())
    }
    /// Accumulated statistics.
    pub fn run_stats(&self) -> &RunStats {
        &self.stats
    }

    /// Linear solves (Newton matrices factored) since the stepper was built, in every
    /// attempt: failed ones, retries, fixed-set re-solves and substeps included. Unlike
    /// [`RunStats::newton_iterations`], which counts accepted attempts, this is the
    /// whole work, and does not depend on the machine's speed.
    #[must_use]
    pub fn linear_solves(&self) -> u64 {
        self.work.linear_solves
    }
    /// [`Stepper::linear_solves`] by the stage of the step's policy that made them.
    #[must_use]
    pub fn solves_by_stage(&self) -> SolvesByStage {
        let counted = self.stage_solves.total();
        SolvesByStage {
            other: self.work.linear_solves - counted,
            ..self.stage_solves
        }
    }
    /// The work of the Newton iterations since the stepper was built, by kind, with why
    /// exact updates were made and the seconds each kind took (see [`NewtonWork`]).
    #[must_use]
    pub fn newton_work(&self) -> NewtonWork {
        self.newton_work
    }
    /// Why the consistent start at t0 failed, where the stepper started without it and
    /// took its first step by the last resort (see [`Stepper::new`]); `None` after a
    /// consistent start.
    #[must_use]
    pub fn start_failure(&self) -> Option<&str> {
        self.start_failure.as_deref()
    }
    /// Statistics (including the index sets) of the last accepted step.
    pub fn last_step(&self) -> Option<&StepStats> {
        self.last.as_ref()
    }
    /// Number of unknowns per step (eq. 126).
    pub fn n_unknowns(&self) -> usize {
        self.off.n
    }

    /// Solves the step from the current state with ρ∞ = `rho_inf`, computing the index
    /// sets at each Newton iterate, or keeping `fixed` sets throughout. Nothing is
    /// committed: pass the result to [`Stepper::commit`] to advance.
    ///
    /// The state is left as it was, but not the solver's kept factors: they are the
    /// trial's last, and the next step's simplified updates start from them
    /// ([`LinearOptions::reuse_factorization`](crate::LinearOptions::reuse_factorization)).
    /// That step converges to the same tolerance by another path, so its bits (and its
    /// count of linear solves) may differ from a step taken without the trial.
    ///
    /// # Errors
    /// [`StepError::NotConverged`] (carrying the best residual, the sets visited and the
    /// current state), [`StepError::NonFinite`], [`StepError::Linear`];
    /// [`StepError::InvalidInput`] for fixed sets of the wrong sizes or nesting.
    pub fn trial(&mut self, fixed: Option<&IndexSets>, rho_inf: f64) -> Result<Trial, StepError> {
        if let Some(s) = fixed {
            if !s.is_consistent(self.off.nn, self.layout.friction.len()) {
                return Err(StepError::InvalidInput(
                    "fixed index sets have wrong sizes or break A ⊇ B ⊇ C, D ⊇ E".into(),
                ));
            }
        }
        let sets = fixed.map_or(SetRule::Free, |s| SetRule::Fixed(s.clone()));
        self.attempt(self.spec(sets, rho_inf))
            .map_err(|f| f.into_error(&self.state))
    }

    /// Commits a trial: the stepper advances to its state.
    pub fn commit(&mut self, mut trial: Trial) {
        self.account(&trial.stats);
        let w = &mut self.work;
        if w.trial_levels.describe(&trial.state) {
            std::mem::swap(&mut w.trial_levels, &mut w.state_levels);
        } else {
            w.state_levels.forget();
        }
        w.trial_levels.forget();
        trial.state.flush_subnormals();
        // The solution the state leaves behind, for the next steps' predicted starts:
        // smooth only while two generalized-α steps in a row keep their index sets.
        let same_sets = trial.stats.last_resort.is_none()
            && self
                .last
                .as_ref()
                .is_some_and(|last| last.last_resort.is_none() && last.sets == trial.stats.sets);
        for sets in trial.visited.drain(..) {
            self.recycle_sets(sets);
        }
        self.work.spare_visited = trial.visited;
        let mut left = std::mem::replace(&mut self.state, trial.state);
        (self.moved, self.same_sets) = (rest::Moved::between(&left.q, &self.state.q), same_sets);
        if self.holds_islands() {
            let before = self.last.as_ref().map(|last| &last.sets);
            let qs = (&left.q[..], &self.state.q[..]);
            self.islands.committed(qs, before, &trial.stats.sets);
        }
        self.rest = rest::Rest::Moving;
        let x = std::mem::take(&mut left.x);
        self.predictor.record(left.k, self.options.dt, x, same_sets);
        // Its buffers serve the next step's trial state.
        self.work.spare_state = left;
        if let Some(last) = self.last.replace(trial.stats) {
            self.recycle_sets(last.sets);
            self.work.spare_solver_name = last.solver;
        }
    }

    /// Keeps `sets` for [`Stepper::compute_sets`] to reuse, while fewer than
    /// [`SPARE_SETS`] are kept.
    fn recycle_sets(&mut self, sets: IndexSets) {
        if self.work.spare_sets.len() < SPARE_SETS {
            self.work.spare_sets.push(sets);
        }
    }

    /// A copy of `sets` in the buffers of spent ones ([`Stepper::recycle_sets`]).
    fn copy_sets(&mut self, sets: &IndexSets) -> IndexSets {
        let mut copy = self.work.spare_sets.pop().unwrap_or_default();
        copy.clone_from(sets);
        copy
    }

    /// Adds one accepted step to the run statistics.
    fn account(&mut self, step: &StepStats) {
        self.stats.steps += 1;
        self.stats.newton_iterations += step.iterations as u64;
        self.stats.max_iterations = self.stats.max_iterations.max(step.iterations);
        if step.retries > 0 {
            self.stats.retried_steps += 1;
        }
        if !step.converged {
            self.stats.unconverged_steps += 1;
        }
        if step.branch.as_ref().is_some_and(|b| b.candidates.len() > 1) {
            self.stats.branch_points += 1;
        }
        if step.unshifted {
            self.stats.unshifted_steps += 1;
        }
        if let Some(last) = &step.last_resort {
            self.stats.last_resort_steps += 1;
            self.stats.last_resort_residual = self.stats.last_resort_residual.max(last.residual);
        }
    }

    /// Forgets what the last solutions left for the next steps (the predicted start's
    /// history, the state's levels, the islands held at rest): the state was replaced or
    /// the system changed.
    fn forget_solutions(&mut self) {
        self.forget_history();
        self.islands.release();
    }

    /// [`Stepper::forget_solutions`] but for the islands held at rest.
    fn forget_history(&mut self) {
        self.predictor.clear();
        self.forget_levels();
    }

    /// Forgets the constraint levels kept from the last step's solution and any state
    /// at rest (the next step is solved): the system or the unknowns they describe
    /// changed.
    fn forget_levels(&mut self) {
        self.work.state_levels.forget();
        self.rest = rest::Rest::Moving;
    }

    /// The statistics of the step just committed.
    fn committed(&self) -> &StepStats {
        self.last.as_ref().expect("a step was just committed")
    }

    /// Re-solves the current step with the index sets fixed by the caller and commits it
    /// when it converges. Returns the statistics; `stats.sets` are the fixed sets.
    ///
    /// # Errors
    /// As [`Stepper::trial`].
    pub fn step_with_sets(&mut self, sets: &IndexSets) -> Result<&StepStats, StepError> {
        let trial = self.trial(Some(sets), self.options.rho_inf)?;
        self.commit(trial);
        Ok(self.committed())
    }

    /// One step, by the policy of docs/method.md §8.2: the stages listed there (the
    /// crate's `Stage` enum), each switched on by the [`Options`], in the order of their
    /// one transition table; the first stage that finds the step commits it.
    ///
    /// # Errors
    /// [`StepError::NoSolution`] when the last resort finds that the step's contact
    /// problem has no solution. Without the last resort: [`StepError::NotConverged`] carrying t and the last good state;
    /// [`StepError::Linear`] when the Newton matrix was singular on every attempt. The
    /// stepper stays at the last good state, so the run can continue from it (for
    /// example after changing the options).
    pub fn step(&mut self) -> Result<&StepStats, StepError> {
        if self.at_rest() {
            self.rest_step();
            return Ok(self.committed());
        }
        let (t0, before) = (self.state.t, self.rest);
        if self.start_failure.is_some() && self.state.k == 0 {
            // The initial state after a failed start has no consistent a0 to start a
            // generalized-α step from (§5): a Moreau–Jean step needs none, and restarts
            // the state consistently after it.
            self.last_resort()?;
        } else {
            let holding = !self.islands.held().is_empty();
            self.run_policy()?;
            self.stats.held_island_steps += u64::from(holding);
            self.rest = self.rest_after_step(before, t0);
            self.update_islands();
        }
        Ok(self.committed())
    }

    /// Whether the state is at rest for good: the next [`Stepper::step`] repeats it one
    /// Δt later without solving ([`PolicyOptions::rest`](crate::PolicyOptions::rest)).
    #[must_use]
    pub fn at_rest(&self) -> bool {
        self.rest == rest::Rest::Held && self.system.autonomous_from(self.state.t)
    }

    /// Runs `n` steps, calling `observe` after each accepted one.
    ///
    /// # Errors
    /// The first step error.
    pub fn run(
        &mut self,
        n: usize,
        mut observe: impl FnMut(&State, &StepStats),
    ) -> Result<(), StepError> {
        for _ in 0..n {
            self.step()?;
            observe(&self.state, self.committed());
        }
        Ok(())
    }
}
