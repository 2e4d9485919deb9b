//! Options of the generalized-α stepper: time step, ρ∞, prox parameter, tolerances,
//! linear solver and the fallback policy of a step that does not converge
//! (docs/method.md §4, §7, §8).

use crate::error::StepError;
use crate::linalg::{MARKOWITZ_SPARSE_THRESHOLD, PIVOT_THRESHOLD, SYMBOLIC_CACHE};
use crate::tuning::Tuning;
#[cfg(doc)]
use crate::Stepper;

/// How the prox parameter r is chosen (docs/method.md §4).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Prox {
    /// r_k = α / (w_kᵀ M⁻¹ w_k) per constraint, α ∈ (0, 2); α = 1 is the default.
    /// Newton converges only while r·(wᵀM⁻¹w) < 2, whatever the masses and sizes.
    Scaled(f64),
    /// One constant r for every constraint (the thesis and paper use 0.3).
    Constant(f64),
}

impl Prox {
    /// The choice as one token for JSON and CSV: `scaled(alpha=1)` or `constant(r=0.3)`
    /// (numbers in shortest round-trip form, with an exponent outside 10⁻⁴ ≤ |x| < 10⁶).
    ///
    /// ```
    /// use nsga::Prox;
    ///
    /// assert_eq!(Prox::Scaled(1.0).label(), "scaled(alpha=1)");
    /// assert_eq!(Prox::Constant(0.3).label(), "constant(r=0.3)");
    /// assert_eq!(Prox::Constant(0.3).to_string(), "constant r = 0.3");
    /// assert_eq!(Prox::Scaled(0.5).to_string(), "scaled, alpha = 0.5");
    /// assert_eq!(Prox::Constant(1e300).label(), "constant(r=1e300)");
    /// ```
    #[must_use]
    pub fn label(self) -> String {
        match self {
            Self::Scaled(alpha) => format!("scaled(alpha={})", Short(alpha)),
            Self::Constant(r) => format!("constant(r={})", Short(r)),
        }
    }
}

impl std::fmt::Display for Prox {
    /// The choice as text: `scaled, alpha = 1` or `constant r = 0.3`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Scaled(alpha) => write!(f, "scaled, alpha = {}", Short(*alpha)),
            Self::Constant(r) => write!(f, "constant r = {}", Short(*r)),
        }
    }
}

/// A number in shortest round-trip form, with an exponent where the plain form would be
/// long (|x| ≥ 10⁶ or below 10⁻⁴): `0.3`, `1`, `1e300`, `1e-8`.
struct Short(f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

/// Which linear solver the Newton iteration uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SolverChoice {
    /// Dense LU up to the given number of unknowns, sparse LU above.
    Auto(usize),
    /// Always dense LU.
    Dense,
    /// Always sparse LU (faer).
    Sparse,
    /// Sparse LU with Markowitz pivots on dense storage ([`crate::MarkowitzLu`]) up to
    /// the given number of unknowns, sparse LU (faer) above. The default, with
    /// [`crate::linalg::MARKOWITZ_SPARSE_THRESHOLD`].
    Markowitz(usize),
}

/// What to do when a step fails after every retry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum FailurePolicy {
    /// Return [`StepError::NotConverged`]; the stepper stays at the last good state.
    Error,
    /// Accept the iterate with the smallest residual, mark the step not converged and go on.
    AcceptBest,
}

/// Which failed attempts the ρ∞ retries ([`PolicyOptions::rho_inf_retries`]) follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum RhoInfRetry {
    /// Any attempt that fails: a singular Newton matrix, a non-finite iterate, or
    /// iterates that do not converge.
    #[default]
    AnyFailure,
    /// Only an attempt stopped by a singular Newton matrix (or a non-finite iterate):
    /// the case thesis §4.2 introduces the retries for ("some values of ρ∞ can produce a
    /// singular Jacobian … simply changing the numerical value of ρ∞ eliminates the
    /// singularity"). Iterates that cycle between index sets go straight to the
    /// fixed-set re-solves: another ρ∞ changes the step's numerical damping, not which
    /// contacts alternate, and its attempts mostly retrace the same cycle.
    SingularMatrix,
}

/// Options of the stepper: the scheme (Δt, ρ∞, prox, tolerances), then one group each
/// for the Newton iteration, its linear algebra and the policy of a step that fails.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Options {
    /// Time step Δt > 0.
    pub dt: f64,
    /// Spectral radius at infinity ρ∞ ∈ [0, 1] (eq. 72); 0.5 in the thesis.
    pub rho_inf: f64,
    /// Prox parameter choice.
    pub prox: Prox,
    /// Newton tolerance on ‖R‖∞, rows scaled to impulse units (thesis 1e-10).
    pub tol: f64,
    /// Gap and gap-rate tolerance deciding which contacts are closed at t0 (§5).
    pub start_tol: f64,
    /// Whether the position correction carries half a step of the friction
    /// percussions: M Q = W_N κ_N + ½Δt W_F Λ_F, as in the paper (eq. 127, rows of Q).
    /// Without it, M Q = W_N κ_N: a friction percussion changes u_{n+1} and moves the
    /// bodies from the next step on, as a normal percussion does. Where the friction
    /// percussion of an impact has a lever arm (a block landing flat while it slides),
    /// its half-step shift turns the body, the normal position multipliers of its other
    /// closed contacts must turn it back, one of them with κ̂_N < 0, and the step's
    /// index sets have no self-consistent choice at any Δt (docs/method.md §8.2,
    /// "The friction percussion's half-step shift"). Both forms are first order at an
    /// impact. The percussions of bilateral velocity constraints keep their shift.
    #[serde(default = "yes")]
    pub friction_percussion_shift: bool,
    /// Whether an interval friction law (one component) slides along the sign of its
    /// prox argument, r ξ_F − P_F on velocity level (also on acceleration level where
    /// e_F = 0) and r γ̇_F − λ_F in D ∖ E, instead of its slip's own sign, the paper's rows
    /// (eqs. 138, 142). The solutions are the same; the Newton iterates differ where a law
    /// held on its friction bound slides at a round-off slip, whose own sign follows the
    /// round-off (docs/method.md §3, "An interval law slides along its prox argument").
    /// Measured with the harness: the matrix 21.9 % fewer linear solves and 11 % less
    /// solver time, the Lire collapse 10 % less time and its landing on a floor 41 %, the
    /// kicked 30-block column twice the time. Off by default and in the block stack: a
    /// symmetric column dropped flat tips at a landing under it (docs/experiments.md §3).
    #[serde(default)]
    pub interval_sign_from_prox: bool,
    /// The Newton iteration of one attempt.
    #[serde(default)]
    pub newton: NewtonOptions,
    /// The linear solves of the Newton updates.
    #[serde(default)]
    pub linear: LinearOptions,
    /// What a step does when its first attempt fails.
    #[serde(default)]
    pub policy: PolicyOptions,
    /// The measured constants: budgets, factors and thresholds (docs/tuning.md).
    #[serde(default)]
    pub tuning: Tuning,
}

/// Options of the Newton iteration of one attempt ([`Options::newton`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct NewtonOptions {
    /// Maximum Newton iterations per attempt. An attempt ends sooner when it cannot
    /// converge: its iterates settle into a cycle of index sets without progress, or,
    /// with fixed sets, its residual stalls (see `settled_cycle` and `stalled`).
    pub max_iter: usize,
    /// Free attempts (index sets not fixed) may take up to max(`max_iter`,
    /// `max_iter_per_contact` × number of normal contacts) updates; 0 leaves `max_iter`
    /// alone. Newton changes the index sets of a few contacts per update, so a system
    /// whose contacts change state by the dozen in one step (a tall column whose
    /// interfaces rock) needs updates in proportion to its contacts (docs/method.md
    /// §8.2).
    pub max_iter_per_contact: usize,
    /// Halvings of the Newton update allowed in its line search (0: full updates, as in
    /// the paper). With n > 0 the update is scaled by the first α = 1, ½, …, 2⁻ⁿ that
    /// reduces ‖R‖∞ by the factor 1 − 10⁻⁴α, or taken whole when none does. Damping
    /// the updates that overshoot keeps Newton from jumping between distant index sets
    /// when several contacts close at once. The held-sets attempt
    /// (`max_openings_per_update`) takes its updates whole regardless.
    pub line_search: usize,
    /// Openings per Newton update in the held-sets attempt (0: no such attempt). In a
    /// system whose free attempts may take more than `max_iter` updates (more normal
    /// contacts than `max_iter`, with `max_iter_per_contact` ≥ 1), the first attempt at
    /// a step solves it with the previous step's index sets held, and from that solution
    /// the contact laws may open at most this many contacts per update (those with the
    /// largest prox argument r g_N − κ̂_N), and of the contacts that stay closed, at most
    /// this many may leave the velocity or acceleration level (B, C); closings and
    /// friction changes are not limited, and convergence is judged on the laws' own
    /// sets. Only when that attempt fails does free Newton follow. A tall column that
    /// starts to tip then turns about its base as one body in a few updates, instead of
    /// opening a band of interfaces that free Newton moves up the column one interface
    /// per update (docs/method.md §8.2). The attempt takes its updates whole, without
    /// the line search of `line_search`: its updates change the sets of a contact or a
    /// few each, and halving them only delayed the next change.
    pub max_openings_per_update: usize,
    /// Whether the held-sets attempt's kept factors follow its sets: they serve while
    /// its residual falls at all, and on through a rise at sets that a low-rank update of
    /// up to [`Tuning::held_low_rank_rows`](crate::Tuning::held_low_rank_rows) rows
    /// reached first (docs/method.md §8.2, "The held-sets attempt"). Without, they serve
    /// as in other attempts. Only with `max_openings_per_update` > 0.
    pub held_factors_follow_sets: bool,
    /// Start the first attempt at a step from the unknowns predicted by extrapolating a
    /// and λ over the last steps, while their index sets stayed the same (quadratic
    /// through three solutions, linear through two; docs/method.md §4). An attempt from
    /// the prediction that has not converged after
    /// [`Tuning::predicted_start_iterations`](crate::Tuning::predicted_start_iterations) updates, and
    /// whose last update did not contract the residual by [`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction) at
    /// unchanged index sets, gives way to the usual one from the last solution. Off by
    /// default: the paper starts from the last solution.
    pub predict_start: bool,
    /// Leave out of the linear solve the normal contacts (and their friction laws) that
    /// are open, carry no force and cannot close within the step
    /// (g_N > 2Δt|ġ_N| + Δt²|g̈_N|); if one of them closes at an iterate, the attempt
    /// goes on from that iterate with that contact kept, which is where the unpruned
    /// attempt would be (docs/method.md §8.1). Fixed-set re-solves prune only the
    /// contacts their sets leave open.
    pub prune_open_contacts: bool,
}

/// Options of the linear solves of the Newton updates ([`Options::linear`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct LinearOptions {
    /// Linear solver.
    pub solver: SolverChoice,
    /// ε ≥ 0 added to the Newton matrix (not to the residual) on the multiplier diagonal
    /// of every closed contact row, scaled like the row's open form, when the Newton
    /// matrix is singular. Redundant closed contacts (a body resting on more points than
    /// it has degrees of freedom, as a toppled column on the floor) make it singular;
    /// with ε the update solves a compliant linearization whose redundant forces take a
    /// least-norm share, while the residual, and hence the converged solution, stays
    /// exact. 0 turns this off (a singular matrix then fails the attempt). Index sets
    /// whose normal contacts (A, B, C) are those of one of the last
    /// [`Tuning::singular_sets_kept`](crate::Tuning::singular_sets_kept) plain matrices found singular go straight to the
    /// regularized one, whatever their friction sets (D, E).
    pub regularization: f64,
    /// Simplified Newton: while the index sets (and pruned contacts, Δt, ρ∞) are those of
    /// the last factorized Newton matrix (or, for the same sets, more contacts are pruned
    /// than were then: docs/method.md §7), solve with its kept factors instead of
    /// assembling and factorizing a new one, as long as each such update at least
    /// [`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction)-fold reduces the residual, and at most [`Tuning::max_reuses`](crate::Tuning::max_reuses) times
    /// in a row. The iterates converge to the same tolerance; a quiet contact phase then
    /// costs residual evaluations and triangular solves, not factorizations.
    pub reuse_factorization: bool,
    /// With [`LinearOptions::reuse_factorization`], in the first attempt at each step:
    /// where the index sets differ from those of the kept factors in at most
    /// [`LOW_RANK_ROWS`](crate::stepper::LOW_RANK_ROWS) rows of the Newton matrix, the
    /// simplified update solves the kept matrix with those rows replaced, from the kept
    /// factors (a low-rank update, docs/method.md §7); and after a simplified update that
    /// did not contract, they are tried again once the matrix has been factorized anew.
    /// The retries, re-solves and halvings of a failed step factorize as before.
    pub low_rank_updates: bool,
    /// The threshold of [`MarkowitzLu`](crate::linalg::MarkowitzLu)'s pivot test, in
    /// (0, 1]: a pivot is at least this fraction of the largest active entry of its
    /// column (1 is partial pivoting). Default
    /// [`PIVOT_THRESHOLD`], where it is justified.
    pub pivot_threshold: f64,
    /// Matrix sizes whose sparsity pattern and symbolic analysis sparse LU keeps
    /// (at least 1). Default [`SYMBOLIC_CACHE`], where it
    /// is justified.
    pub symbolic_cache: usize,
    /// How the Newton matrix is formed: from the system's exact derivatives (the
    /// default), or by forward differences of the residual, as the thesis's code does.
    pub jacobian: JacobianChoice,
}

/// How the Newton matrix of eq. 143 is formed ([`LinearOptions::jacobian`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub enum JacobianChoice {
    /// From the system's exact derivatives (semismooth Jacobian, eq. 143).
    #[default]
    Exact,
    /// Column by column, (R(x + ε eᵢ) − R(x))/ε with the index sets held, ε > 0 absolute
    /// (the thesis's code: ε = 10⁻⁶, §4.2). One residual per unknown: for comparison
    /// with the thesis, not for speed (`stepper/fd_jacobian.rs`).
    FiniteDifference(f64),
}

/// The thesis's finite-difference parameter ε (§4.2, "Simulation Parameters").
pub const THESIS_FD_EPSILON: f64 = 1e-6;

/// The policy of a step whose first attempt fails ([`Options::policy`]): retries,
/// re-solves, halving and the last resort.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct PolicyOptions {
    /// Other ρ∞ values tried, in order, when a step does not converge (thesis §4.2).
    pub rho_inf_retries: Vec<f64>,
    /// Which failed attempts are retried with `rho_inf_retries`.
    pub rho_inf_retry: RhoInfRetry,
    /// Maximum Newton iterations of each ρ∞ retry and fixed-set re-solve (at most
    /// `max_iter`). A retry that converges does so within a few iterations; a failing
    /// one would otherwise spend all of `max_iter` cycling.
    pub retry_max_iter: usize,
    /// The branch trials (`Stage::BranchTrials`, docs/method.md §8.2): when the first
    /// attempt's index sets cycle, re-solve the step once per distinct set seen, with the
    /// sets fixed. The step continues with one of the candidates; which ones are branch
    /// points is only recorded ([`PolicyOptions::branch_rule`]).
    pub branch_trials: bool,
    /// Which fixed-set solutions count as continuations of a cycling step.
    pub branch_rule: BranchRule,
    /// Run the branch trials after every first attempt that did not converge within its
    /// iterations, not only after one whose index sets cycled: the thesis's code takes
    /// every failure of Newton as a branch point (§4.4, Algorithm 1). Off by default.
    pub branch_on_any_failure: bool,
    /// Let a fixed-set re-solve that converged continue the step even where its contact
    /// laws do not hold (the sets recomputed from it differ from those it was solved
    /// with), as the thesis's code does: every converged solve is a candidate, in the
    /// order found, marked not self-consistent. Off by default: the step continues with
    /// a self-consistent candidate only, whatever [`PolicyOptions::branch_rule`] records.
    pub continue_inconsistent: bool,
    /// After a step converges, re-solve it with the touching normal contacts' states fixed
    /// (every combination of open / closed sliding / closed sticking for at most 3 of them,
    /// else one contact flipped at a time: `stepper/enumerate.rs`) and report the self-consistent solutions that differ as a branch point: the
    /// non-uniqueness that Newton's iterates need not reveal by cycling (Painlevé's
    /// indeterminacy, docs/method.md §8). Costs up to 4³ = 64 fixed-set solves per step
    /// (every state of at most 3 touching contacts), up to four per touching contact
    /// beyond; off by default.
    pub probe_flips: bool,
    /// Run that probe only where Painlevé's indeterminacy is possible: a converged step
    /// with a closed contact that slides and whose normal acceleration decreases with its
    /// own normal force, friction counted (b ≤ 0 of App. I's (I.1.8), for any system with
    /// a diagonal mass matrix; `stepper/painleve.rs`). Free where no contact is in that
    /// region (a block with μ < 4/3 never is); off by default.
    #[serde(default)]
    pub probe_painleve: bool,
    /// With [`Options::friction_percussion_shift`]: a step whose fixed-set re-solves
    /// found no self-consistent solution is tried once more, from the start, without
    /// the shift (docs/method.md §8.2, `Stage::Unshifted`), before the best iterate, halving and
    /// the last resort.
    pub retry_without_friction_shift: bool,
    /// Hold a state at rest without solving (docs/method.md §8.2, "At rest"): after a
    /// step that converged at its start without a Newton update and left q unchanged to
    /// the bit, of a system autonomous from then on ([`System::autonomous_from`]), the
    /// next steps repeat the state one Δt later until the system stops being autonomous
    /// or the caller changes the state or the options. On by default; it changes
    /// nothing for a system that is never autonomous.
    ///
    /// [`System::autonomous_from`]: crate::System::autonomous_from
    pub rest: bool,
    /// How often a step that fails after every retry and fixed-set re-solve may be
    /// halved: it is then taken as two substeps of Δt/2 with this same policy, each of
    /// which may be halved again, down to Δt/2^`max_halvings` ([`Stepper::split_step`]).
    /// 0 (the default) turns halving off. A failure at one instant costs a bounded
    /// amount of work per level (only the half that contains it is split again), not
    /// 2^level substeps.
    pub max_halvings: usize,
    /// When every attempt above fails, take the step by the last resort: a Moreau–Jean
    /// step whose contact problem Lemke's method solves (it terminates, with a solution
    /// wherever one exists; docs/method.md §8.2). It takes every contact law: bilateral
    /// constraints exactly, disk friction approximately (a polygon of
    /// [`DISK_DIRECTIONS`](crate::friction_polygon::DISK_DIRECTIONS) sides inscribed in
    /// the disk). A system whose bilateral constraints are redundant at the initial state
    /// is refused when the stepper is set up ([`crate::Stepper::new`]). On by default.
    pub last_resort: bool,
    /// What to do when every retry fails.
    pub on_failure: FailurePolicy,
}

/// Which fixed-set solutions of a cycling step its branch point records as
/// continuations (branch candidates, docs/method.md §8). Only the record: the step
/// continues with a self-consistent one under either rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BranchRule {
    /// A converged solution whose own index sets, recomputed from it, are the sets it
    /// was solved with: a solution of the step's equations, contact laws included.
    #[default]
    SelfConsistent,
    /// Every converged fixed-set solve, as the thesis counts branches (§4.4: each contact
    /// state for which the scheme converges becomes a branch). A solve with fixed sets can
    /// converge to a state that breaks the contact laws it did not impose (a gap held
    /// closed by a pulling force, a contact held in stick beyond its friction cone); this
    /// rule keeps those too, to reproduce the thesis's count and compare with it.
    Converged,
}

impl BranchRule {
    /// `self_consistent` or `converged`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::SelfConsistent => "self_consistent",
            Self::Converged => "converged",
        }
    }
}

fn yes() -> bool {
    true
}

/// Default [`PolicyOptions::retry_max_iter`]. Measured with the Lire collapse and the two
/// block sweeps (`rollstack blocks lire --perturb bottom`, `blocks sweep frequency
/// --omega 1:12:1`, `blocks sweep slide --v0 0.05:5:0.35`): the same steps succeed and
/// fail as with 40, and the solver time drops by 40–50 %.
pub const DEFAULT_RETRY_MAX_ITER: usize = 12;

/// Default [`LinearOptions::regularization`]: small against the O(1) entries of the scaled
/// Newton rows, large against round-off. Measured on the Lire collapse (`cargo run
/// --release -p blockstack --example measure`): 1e-10 to 1e-6 all carry the toppled
/// column resting on the table edge and the floor.
pub const DEFAULT_REGULARIZATION: f64 = 1e-8;

impl Default for Options {
    fn default() -> Self {
        Self {
            dt: 2e-3,
            rho_inf: 0.5,
            prox: Prox::Scaled(1.0),
            tol: 1e-10,
            start_tol: 1e-9,
            friction_percussion_shift: true,
            interval_sign_from_prox: false,
            newton: NewtonOptions::default(),
            linear: LinearOptions::default(),
            policy: PolicyOptions::default(),
            tuning: Tuning::default(),
        }
    }
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            max_iter: 40,
            max_iter_per_contact: 0,
            line_search: 0,
            max_openings_per_update: 0,
            held_factors_follow_sets: true,
            predict_start: false,
            prune_open_contacts: false,
        }
    }
}

impl Default for LinearOptions {
    fn default() -> Self {
        Self {
            solver: SolverChoice::Markowitz(MARKOWITZ_SPARSE_THRESHOLD),
            regularization: DEFAULT_REGULARIZATION,
            reuse_factorization: false,
            low_rank_updates: false,
            pivot_threshold: PIVOT_THRESHOLD,
            symbolic_cache: SYMBOLIC_CACHE,
            jacobian: JacobianChoice::Exact,
        }
    }
}

impl Default for PolicyOptions {
    fn default() -> Self {
        Self {
            rho_inf_retries: vec![0.8, 0.2, 1.0, 0.0],
            rho_inf_retry: RhoInfRetry::AnyFailure,
            retry_max_iter: DEFAULT_RETRY_MAX_ITER,
            branch_trials: true,
            branch_rule: BranchRule::SelfConsistent,
            branch_on_any_failure: false,
            continue_inconsistent: false,
            probe_flips: false,
            probe_painleve: false,
            retry_without_friction_shift: false,
            rest: true,
            max_halvings: 0,
            last_resort: true,
            on_failure: FailurePolicy::Error,
        }
    }
}

impl Options {
    /// Checks the options.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] naming the bad option.
    pub fn validate(&self) -> Result<(), StepError> {
        let bad = |m: String| Err(StepError::InvalidInput(m));
        if !(self.dt > 0.0 && self.dt.is_finite()) {
            return bad(format!("dt = {} must be positive and finite", self.dt));
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return bad(format!("rho_inf = {} must be in [0, 1]", self.rho_inf));
        }
        if self
            .policy
            .rho_inf_retries
            .iter()
            .any(|r| !(0.0..=1.0).contains(r))
        {
            return bad("every retry rho_inf must be in [0, 1]".into());
        }
        match self.prox {
            Prox::Scaled(a) if !(a > 0.0 && a < 2.0) => {
                return bad(format!("scaled prox alpha = {a} must be in (0, 2)"));
            }
            Prox::Constant(r) if !(r > 0.0 && r.is_finite()) => {
                return bad(format!("prox r = {r} must be positive"));
            }
            _ => {}
        }
        let threshold = self.linear.pivot_threshold;
        if !(threshold > 0.0 && threshold <= 1.0) {
            return bad(format!("pivot_threshold = {threshold} must be in (0, 1]"));
        }
        if let JacobianChoice::FiniteDifference(h) = self.linear.jacobian {
            if !(h > 0.0 && h.is_finite()) {
                return bad(format!("finite-difference epsilon = {h} must be positive"));
            }
        }
        if self.linear.symbolic_cache == 0 {
            return bad("symbolic_cache must be at least 1".into());
        }
        let eps = self.linear.regularization;
        if !(eps >= 0.0 && eps.is_finite()) {
            return bad(format!("regularization = {eps} must be finite and >= 0"));
        }
        if self.tol.is_nan()
            || self.tol <= 0.0
            || self.newton.max_iter == 0
            || self.policy.retry_max_iter == 0
        {
            return bad("tol must be > 0, and max_iter and retry_max_iter >= 1".into());
        }
        self.tuning.check().map_err(StepError::InvalidInput)
    }
}
