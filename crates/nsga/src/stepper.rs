//! The nonsmooth generalized-α step (NSGA-SPEC §3–4, paper eqs. 71–143).

use crate::error::StepError;
use crate::linalg::{AutoSolver, DenseLu, LinearSolver, SparseLu, MARKOWITZ_SPARSE_THRESHOLD};
use crate::params::GenAlpha;
use crate::sets::IndexSets;
use crate::start::consistent_start;
use crate::system::{Derivatives, Evaluation, Layout, System, Triplets};
use nalgebra::DMatrix;

mod assemble;

/// How the prox parameter r is chosen (NSGA-SPEC §4).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Prox {
    /// r_k = α / (w_kᵀ M⁻¹ w_k) per constraint, α ∈ (0, 2); α = 1 is the default.
    /// Newton converges only while r·(wᵀM⁻¹w) < 2, whatever the masses and sizes.
    Scaled(f64),
    /// One constant r for every constraint (the thesis and paper use 0.3).
    Constant(f64),
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

/// Which failed attempts the ρ∞ retries ([`Options::rho_inf_retries`]) follow.
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

/// Options of the stepper.
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
    /// Maximum Newton iterations per attempt. An attempt ends sooner when it cannot
    /// converge: its iterates settle into a cycle of index sets without progress, or,
    /// with fixed sets, its residual stalls (see `settled_cycle` and `stalled`).
    pub max_iter: usize,
    /// Other ρ∞ values tried, in order, when a step does not converge (thesis §4.2).
    pub rho_inf_retries: Vec<f64>,
    /// Which failed attempts are retried with `rho_inf_retries`.
    #[serde(default)]
    pub rho_inf_retry: RhoInfRetry,
    /// Maximum Newton iterations of each ρ∞ retry and fixed-set re-solve (at most
    /// `max_iter`). A retry that converges does so within a few iterations; a failing
    /// one would otherwise spend all of `max_iter` cycling.
    #[serde(default = "default_retry_max_iter")]
    pub retry_max_iter: usize,
    /// Re-solve with fixed index sets when the sets cycle (branch exploration).
    pub explore_branches: bool,
    /// Linear solver.
    pub solver: SolverChoice,
    /// What to do when every retry fails.
    pub on_failure: FailurePolicy,
    /// Gap and gap-rate tolerance deciding which contacts are closed at t0 (§5).
    pub start_tol: f64,
    /// Leave out of the linear solve the normal contacts (and their friction laws) that
    /// are open, carry no force and cannot close within the step
    /// (g_N > 2Δt|ġ_N| + Δt²|g̈_N|); if one of them closes at an iterate, the attempt
    /// is redone with that contact kept. Fixed-set re-solves prune only the contacts
    /// their sets leave open.
    pub prune_open_contacts: bool,
    /// ε ≥ 0 added to the Newton matrix (not to the residual) on the multiplier diagonal
    /// of every closed contact row, scaled like the row's open form, when the Newton
    /// matrix is singular. Redundant closed contacts (a body resting on more points than
    /// it has degrees of freedom, as a toppled column on the floor) make it singular;
    /// with ε the update solves a compliant linearization whose redundant forces take a
    /// least-norm share, while the residual, and hence the converged solution, stays
    /// exact. 0 turns this off (a singular matrix then fails the attempt). Index sets
    /// whose normal contacts (A, B, C) are those of one of the last
    /// [`SINGULAR_SETS_KEPT`] plain matrices found singular go straight to the
    /// regularized one, whatever their friction sets (D, E).
    #[serde(default = "default_regularization")]
    pub regularization: f64,
    /// Simplified Newton: while the index sets (and pruned contacts, Δt, ρ∞) are those of
    /// the last factorized Newton matrix, solve with its kept factors instead of
    /// assembling and factorizing a new one, as long as each such update at least
    /// [`REUSE_CONTRACTION`]-fold reduces the residual, and at most [`MAX_REUSES`] times
    /// in a row. The iterates converge to the same tolerance; a quiet contact phase then
    /// costs residual evaluations and triangular solves, not factorizations.
    #[serde(default)]
    pub reuse_factorization: bool,
    /// Halvings of the Newton update allowed in its line search (0: full updates, as in
    /// the paper). With n > 0 the update is scaled by the first α = 1, ½, …, 2⁻ⁿ that
    /// reduces ‖R‖∞ by the factor 1 − 10⁻⁴α, or taken whole when none does. Damping
    /// the updates that overshoot keeps Newton from jumping between distant index sets
    /// when several contacts close at once.
    #[serde(default)]
    pub line_search: usize,
}

/// Sufficient-decrease constant of the line search (see [`Options::line_search`]).
const ARMIJO: f64 = 1e-4;

/// Residual reduction a simplified Newton update must reach; below it the next update
/// is exact (see [`Options::reuse_factorization`]).
pub const REUSE_CONTRACTION: f64 = 0.1;

/// How many index sets found to have a singular plain Newton matrix are remembered
/// (see [`Options::regularization`]). Redundancy is a property of which contacts are
/// closed, so the normal sets (A, B, C) of such a matrix stay singular while the bodies
/// keep their arrangement, whatever the friction laws do. After the Lire collapse
/// lands on a floor, Newton moves among a handful of normal sets and dozens of stick–slip
/// combinations; remembering only the last singular set made it rediscover each at the
/// cost of a failed plain factorization and a dense LU. Over the Lire collapse on a floor
/// and 99 neighbours (`cargo run --release -p blockstack --example lire_nearby 100
/// --floor`) that took
/// 938 linear solves per run, against 810 remembering the normal sets of the last 16.
pub const SINGULAR_SETS_KEPT: usize = 16;

/// Simplified Newton updates in a row before an exact one (see
/// [`Options::reuse_factorization`]).
pub const MAX_REUSES: usize = 4;

/// Default [`Options::retry_max_iter`]. Measured with the Lire collapse and the two
/// block sweeps (`rollstack blocks lire --perturb bottom`, `blocks sweep frequency
/// --omega 1:12:1`, `blocks sweep slide --v0 0.05:5:0.35`): the same steps succeed and
/// fail as with 40, and the solver time drops by 40–50 %.
pub const DEFAULT_RETRY_MAX_ITER: usize = 12;

fn default_retry_max_iter() -> usize {
    DEFAULT_RETRY_MAX_ITER
}

/// Default [`Options::regularization`]: small against the O(1) entries of the scaled
/// Newton rows, large against round-off. Measured on the Lire collapse (`cargo run
/// --release -p blockstack --example measure`): 1e-10 to 1e-6 all carry the toppled
/// column resting on the table edge and the floor.
pub const DEFAULT_REGULARIZATION: f64 = 1e-8;

fn default_regularization() -> f64 {
    DEFAULT_REGULARIZATION
}

impl Default for Options {
    fn default() -> Self {
        Self {
            dt: 2e-3,
            rho_inf: 0.5,
            prox: Prox::Scaled(1.0),
            tol: 1e-10,
            max_iter: 40,
            rho_inf_retries: vec![0.8, 0.2, 1.0, 0.0],
            rho_inf_retry: RhoInfRetry::AnyFailure,
            retry_max_iter: DEFAULT_RETRY_MAX_ITER,
            explore_branches: true,
            solver: SolverChoice::Markowitz(MARKOWITZ_SPARSE_THRESHOLD),
            on_failure: FailurePolicy::Error,
            start_tol: 1e-9,
            prune_open_contacts: false,
            regularization: DEFAULT_REGULARIZATION,
            reuse_factorization: false,
            line_search: 0,
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
        if !(self.regularization >= 0.0 && self.regularization.is_finite()) {
            return bad(format!(
                "regularization = {} must be finite and >= 0",
                self.regularization
            ));
        }
        if self.tol.is_nan() || self.tol <= 0.0 || self.max_iter == 0 || self.retry_max_iter == 0 {
            return bad("tol must be > 0, and max_iter and retry_max_iter >= 1".into());
        }
        Ok(())
    }
}

/// The state carried from step to step (NSGA-SPEC §3 "Carried over").
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Step counter k (t = t0 + k Δt, ERRATA 20).
    pub k: u64,
    /// Time t_k.
    pub t: f64,
    /// Coordinates q.
    pub q: Vec<f64>,
    /// Velocities u.
    pub u: Vec<f64>,
    /// Smooth acceleration a.
    pub a: Vec<f64>,
    /// Auxiliary acceleration ā.
    pub a_bar: Vec<f64>,
    /// Normal contact forces λ_N.
    pub lambda_n: Vec<f64>,
    /// Auxiliary λ̄_N.
    pub lambda_n_bar: Vec<f64>,
    /// Friction forces λ_F.
    pub lambda_f: Vec<f64>,
    /// Auxiliary λ̄_F.
    pub lambda_f_bar: Vec<f64>,
    /// Normal percussions P_N of the last step (eq. 95).
    pub p_n: Vec<f64>,
    /// Friction percussions P_F of the last step.
    pub p_f: Vec<f64>,
    /// The last step's unknowns x (eq. 126), the next Newton start.
    pub x: Vec<f64>,
}

impl State {
    /// Whether two states are the same continuation: q and u agree to 1e-8 relative to
    /// 1 + ‖q‖ + ‖u‖ (how branch candidates are deduplicated, NSGA-SPEC §4).
    #[must_use]
    pub fn same_motion(&self, other: &State) -> bool {
        let squared =
            |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum() };
        let distance = (squared(&self.q, &other.q) + squared(&self.u, &other.u)).sqrt();
        distance <= 1e-8 * (1.0 + norm(&other.q) + norm(&other.u))
    }
}

/// A branch point: several self-consistent solutions of one step (NSGA-SPEC §4, ERRATA 22).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BranchPoint {
    /// Time t_n at the start of the step.
    pub t: f64,
    /// Distinct converged continuations (deduplicated by state), each with the sets it
    /// was solved with.
    pub candidates: Vec<(IndexSets, State)>,
    /// How many fixed-set re-solves were tried.
    pub tried: usize,
    /// Index of the candidate the stepper continued with (the first, in the order the
    /// sets were first visited by the failed Newton iteration).
    pub chosen: usize,
}

/// Statistics of one step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepStats {
    /// Time t_{n+1} at the end of the step.
    pub t: f64,
    /// Newton iterations (linear solves) of the accepted attempt.
    pub iterations: usize,
    /// Final ‖R‖∞ (scaled rows).
    pub residual: f64,
    /// ρ∞ of the accepted attempt.
    pub rho_inf: f64,
    /// Index sets of the accepted solution.
    pub sets: IndexSets,
    /// Failed attempts before the accepted one.
    pub retries: usize,
    /// Whether Newton converged (false only with [`FailurePolicy::AcceptBest`]).
    pub converged: bool,
    /// Set when the step was resolved by fixed-set re-solves.
    pub branch: Option<BranchPoint>,
    /// Linear solver used ("dense", "markowitz" or "sparse").
    pub solver: String,
    /// Substeps the step was taken in: 1, or more when it was split
    /// ([`Stepper::split_step`]).
    #[serde(default = "one")]
    pub substeps: usize,
}

fn one() -> usize {
    1
}

/// Accumulated statistics of a run.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: u64,
    /// Sum of Newton iterations.
    pub newton_iterations: u64,
    /// Largest Newton iteration count of a step.
    pub max_iterations: usize,
    /// Steps that needed a retry (another ρ∞ or fixed sets).
    pub retried_steps: u64,
    /// Steps accepted without convergence.
    pub unconverged_steps: u64,
    /// Branch points met (steps with more than one distinct candidate).
    pub branch_points: u64,
    /// Steps taken as several substeps ([`Stepper::split_step`]).
    pub split_steps: u64,
}

impl RunStats {
    /// Mean Newton iterations per step.
    #[must_use]
    pub fn mean_iterations(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.newton_iterations as f64 / self.steps as f64
        }
    }
}

/// The result of solving one step without committing it (see [`Stepper::trial`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    /// The state at t_{n+1}.
    pub state: State,
    /// Statistics of the solve.
    pub stats: StepStats,
    /// Sets visited by the Newton iterates, in first-visit order.
    pub visited: Vec<IndexSets>,
    /// Whether the visited sets cycled in the last iterations (a branch-point sign).
    pub cycling: bool,
}

/// Sizes and offsets of the unknown vector x (eq. 126).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Offsets {
    pub nu: usize,
    pub nq: usize,
    pub ng: usize,
    pub nga: usize,
    pub nn: usize,
    pub nf: usize,
    pub a: usize,
    pub uu: usize,
    pub qq: usize,
    pub kg: usize,
    pub cg: usize,
    pub lg: usize,
    pub cga: usize,
    pub lga: usize,
    pub kn: usize,
    pub cn: usize,
    pub ln: usize,
    pub cf: usize,
    pub lf: usize,
    pub n: usize,
}

impl Offsets {
    pub(crate) fn new(l: &Layout) -> Self {
        let (nu, ng, nga, nn, nf) = (
            l.nu,
            l.n_bilateral_position,
            l.n_bilateral_velocity,
            l.n_normal(),
            l.n_friction(),
        );
        let a = 0;
        let uu = nu;
        let qq = 2 * nu;
        let kg = 3 * nu;
        let cg = kg + ng;
        let lg = cg + ng;
        let cga = lg + ng;
        let lga = cga + nga;
        let kn = lga + nga;
        let cn = kn + nn;
        let ln = cn + nn;
        let cf = ln + nn;
        let lf = cf + nf;
        let n = lf + nf;
        Self {
            nu,
            nq: l.nq,
            ng,
            nga,
            nn,
            nf,
            a,
            uu,
            qq,
            kg,
            cg,
            lg,
            cga,
            lga,
            kn,
            cn,
            ln,
            cf,
            lf,
            n,
        }
    }
}

/// Rows of a sparse matrix over the columns of x, compressed by row.
#[derive(Debug, Clone, Default)]
pub(crate) struct RowMat {
    ptr: Vec<usize>,
    idx: Vec<usize>,
    val: Vec<f64>,
    fill: Vec<usize>,
    pub tmp: Vec<(usize, usize, f64)>,
}

impl RowMat {
    /// Compresses `tmp` (row, col, value) into rows 0..nrows.
    pub(crate) fn build(&mut self, nrows: usize) {
        self.ptr.clear();
        self.ptr.resize(nrows + 1, 0);
        for &(r, _, _) in &self.tmp {
            self.ptr[r + 1] += 1;
        }
        for i in 0..nrows {
            self.ptr[i + 1] += self.ptr[i];
        }
        self.idx.resize(self.tmp.len(), 0);
        self.val.resize(self.tmp.len(), 0.0);
        self.fill.clone_from(&self.ptr);
        for &(r, c, v) in &self.tmp {
            self.idx[self.fill[r]] = c;
            self.val[self.fill[r]] = v;
            self.fill[r] += 1;
        }
        self.tmp.clear();
    }
    pub(crate) fn row(&self, r: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.ptr[r]..self.ptr[r + 1]).map(move |i| (self.idx[i], self.val[i]))
    }
}

/// Pushes `scale · D · B` into `out` rows, with `D` given in q-columns, placing the
/// result in the a-block (× c_qa) and the Q-block (× 1): ∂q_{n+1}/∂a = Δt²βα_r B,
/// ∂q_{n+1}/∂Q = B (NSGA-SPEC §4).
pub(crate) fn push_q_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    b: &RowMat,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r, j, v) in &d.entries {
        for (i, bij) in b.row(j) {
            for &(off, c) in cols {
                out.push((row_off + r, off + i, scale * c * v * bij));
            }
        }
    }
}

/// Pushes `scale · D` (D in u-columns, or transposed W when `transpose`) into the
/// column blocks `cols` (offset, factor).
pub(crate) fn push_u_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    transpose: bool,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r0, c0, v) in &d.entries {
        let (r, c) = if transpose { (c0, r0) } else { (r0, c0) };
        for &(off, f) in cols {
            out.push((row_off + r, off + c, scale * f * v));
        }
    }
}

/// Euclidean norm of a short slice.
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Per-constraint prox parameters r for position- and velocity-level constraints
/// and friction laws (NSGA-SPEC §4): r_k = α/(w_kᵀ M⁻¹ w_k), or a constant.
pub(crate) fn prox_parameters(
    prox: Prox,
    layout: &Layout,
    eval: &Evaluation<f64>,
    r_pos: &mut Vec<f64>,
    r_vel: &mut Vec<f64>,
    r_law: &mut Vec<f64>,
) {
    let (np, nv) = (layout.n_position(), layout.n_velocity());
    r_pos.clear();
    r_vel.clear();
    r_law.clear();
    let alpha = match prox {
        Prox::Constant(r) => {
            r_pos.resize(np, r);
            r_vel.resize(nv, r);
            r_law.resize(layout.friction.len(), r);
            return;
        }
        Prox::Scaled(a) => a,
    };
    let nu = layout.nu;
    // wᵀM⁻¹w: exact through a dense factorisation for small systems, Jacobi (diagonal
    // of M) for large ones, exact for the block-diagonal masses of rigid bodies with
    // diagonal inertia.
    let mut quad_pos = vec![0.0; np];
    let mut quad_vel = vec![0.0; nv];
    // A diagonal M (point masses, planar rigid bodies) is inverted exactly below.
    let diagonal_mass = eval.mass.entries.iter().all(|&(r, c, _)| r == c);
    if nu <= 60 && !diagonal_mass {
        let columns = |w: &Triplets<f64>, n: usize| {
            let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
            for &(r, c, v) in &w.entries {
                cols[c].push((r, v));
            }
            cols
        };
        let mut m = DMatrix::<f64>::zeros(nu, nu);
        for &(r, c, v) in &eval.mass.entries {
            m[(r, c)] += v;
        }
        if let Some(minv) = m.try_inverse() {
            let quad = |col: &[(usize, f64)]| {
                let mut s = 0.0;
                for &(i, wi) in col {
                    for &(j, wj) in col {
                        s += wi * minv[(i, j)] * wj;
                    }
                }
                s
            };
            for (k, c) in columns(&eval.position_w, np).iter().enumerate() {
                quad_pos[k] = quad(c);
            }
            for (k, c) in columns(&eval.velocity_w, nv).iter().enumerate() {
                quad_vel[k] = quad(c);
            }
        }
    } else {
        let mut diag = vec![0.0; nu];
        for &(r, c, v) in &eval.mass.entries {
            if r == c {
                diag[r] += v;
            }
        }
        // Σ w_i²/M_ii per column, accumulated straight from the triplets.
        let accumulate = |w: &Triplets<f64>, quad: &mut [f64]| {
            for &(i, c, v) in &w.entries {
                if diag[i] > 0.0 {
                    quad[c] += v * v / diag[i];
                }
            }
        };
        accumulate(&eval.position_w, &mut quad_pos);
        accumulate(&eval.velocity_w, &mut quad_vel);
    }
    let r_of = |w: f64| {
        if w > 1e-300 && w.is_finite() {
            alpha / w
        } else {
            alpha
        }
    };
    r_pos.extend(quad_pos.iter().map(|&w| r_of(w)));
    r_vel.extend(quad_vel.iter().map(|&w| r_of(w)));
    let ngam = layout.n_bilateral_velocity;
    for (law, f0) in layout.friction.iter().zip(layout.friction_offsets()) {
        let off = ngam + f0;
        let w = (0..law.components)
            .map(|m| quad_vel[off + m])
            .fold(0.0, f64::max);
        r_law.push(r_of(w));
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
}

#[derive(Debug)]
struct Work {
    eval: Evaluation<f64>,
    der: Derivatives,
    bt: Triplets<f64>,
    b: RowMat,
    bdot_u: Vec<f64>,
    jac: Vec<(usize, usize, f64)>,
    rhs_red: Vec<f64>,
    res: Vec<f64>,
    dx: Vec<f64>,
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
    it: Iterate,
    solver: Box<dyn LinearSolver>,
    /// Linear solves since the stepper was built, failed attempts included.
    linear_solves: u64,
    /// The last index sets (at most [`SINGULAR_SETS_KEPT`], oldest first) whose Newton
    /// matrix was found singular without regularization.
    singular_sets: Vec<IndexSets>,
    /// Constraints pruned from the current attempt's Newton matrix (empty when none).
    unused_position: Vec<bool>,
    unused_velocity: Vec<bool>,
    /// What the solver's kept factors were assembled for (None: nothing reusable).
    factored: Option<FactoredFor>,
    /// The iterate a line search starts from.
    x_from: Vec<f64>,
}

/// The index sets, prune map, Δt and ρ∞ of a factorized Newton matrix: its factors
/// serve a simplified Newton update only while all four are unchanged.
#[derive(Debug, Clone, PartialEq)]
struct FactoredFor {
    sets: IndexSets,
    map: Option<Vec<usize>>,
    dt: f64,
    rho_inf: f64,
}

/// Periods (in Newton iterations) of set cycles that [`settled_cycle`] recognizes. Three
/// periods of 12 fit in the 40 iterations of blockstack's first attempts; the landings of
/// the Lire collapse cycle with periods of 7 to 9 iterations, which with periods only up
/// to 4 ran on to the iteration limit.
const CYCLE_PERIODS: std::ops::RangeInclusive<usize> = 2..=12;

/// Whether the Newton iterates have settled into a cycle of index sets that makes no
/// progress: the last three periods visit the same sets in the same order, and the
/// smallest residual of the last period is no smaller than half that of the period
/// before. Newton's iterates are then a discrete map caught in an attractor; running
/// on to the iteration limit only repeats it.
fn settled_cycle(history: &[usize], residuals: &[f64]) -> bool {
    let n = history.len();
    CYCLE_PERIODS.into_iter().any(|p| {
        n >= 3 * p
            && (0..2 * p).all(|i| history[n - 1 - i] == history[n - 1 - i - p])
            && history[n - p..].iter().any(|&id| id != history[n - 1])
            && {
                let min = |r: &[f64]| r.iter().copied().fold(f64::INFINITY, f64::min);
                min(&residuals[n - p..]) >= 0.5 * min(&residuals[n - 2 * p..n - p])
            }
    })
}

/// Iterations without progress after which a fixed-set solve is given up.
const STALL_ITERATIONS: usize = 3;

/// Whether a Newton solve with fixed index sets has stalled: none of its last
/// [`STALL_ITERATIONS`] residuals is below half the smallest one before them. With the
/// sets fixed the residual is smooth and Newton converges quadratically near a solution;
/// a residual that stops shrinking means these sets have no solution near the iterates.
fn stalled(residuals: &[f64]) -> bool {
    let n = residuals.len();
    n > STALL_ITERATIONS && {
        let (before, last) = residuals.split_at(n - STALL_ITERATIONS);
        let floor = before.iter().copied().fold(f64::INFINITY, f64::min);
        last.iter().all(|&r| r >= 0.5 * floor)
    }
}

/// Quantities derived from x at one Newton iterate (eqs. 71, 73, 125, 95, 102, 113).
#[derive(Debug, Clone, Default)]
struct Iterate {
    q1: Vec<f64>,
    u1: Vec<f64>,
    a_bar1: Vec<f64>,
    lbar_n1: Vec<f64>,
    p_n: Vec<f64>,
    kappa_hat: Vec<f64>,
    lbar_f1: Vec<f64>,
    p_f: Vec<f64>,
    // evaluated
    p: Vec<f64>,
    xi_p: Vec<f64>,
    acc_p: Vec<f64>,
    xi_v: Vec<f64>,
    v: Vec<f64>,
    acc_v: Vec<f64>,
    // scratch: ṗ at u_{n+1} and u_n, v at u_n
    rate_new: Vec<f64>,
    rate_old: Vec<f64>,
    v_old: Vec<f64>,
    // multipliers reassembled per family, for the probes
    lam_p: Vec<f64>,
    lam_v: Vec<f64>,
    cap_p: Vec<f64>,
    cap_v: Vec<f64>,
    kap_p: Vec<f64>,
    half_cap_v: Vec<f64>,
}

impl<S: System> Stepper<S> {
    /// A stepper at t0 = `t0`, q0, u0, with consistent initial accelerations and forces
    /// (NSGA-SPEC §5).
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for bad sizes, options or non-finite input;
    /// [`StepError::Start`] when the acceleration-level start problem has no solution.
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
        let off = Offsets::new(&layout);
        let solver: Box<dyn LinearSolver> = match options.solver {
            SolverChoice::Auto(t) => Box::new(AutoSolver::new(t)),
            SolverChoice::Dense => Box::new(DenseLu::default()),
            SolverChoice::Sparse => Box::new(SparseLu::default()),
            SolverChoice::Markowitz(t) => Box::new(AutoSolver::markowitz(t)),
        };
        let start = consistent_start(&system, &layout, t0, q0, u0, &options)?;
        let mut x = vec![0.0; off.n];
        x[off.a..off.a + off.nu].copy_from_slice(&start.a);
        x[off.lg..off.lg + off.ng].copy_from_slice(&start.lambda_g);
        x[off.lga..off.lga + off.nga].copy_from_slice(&start.lambda_gamma);
        x[off.ln..off.ln + off.nn].copy_from_slice(&start.lambda_n);
        x[off.lf..off.lf + off.nf].copy_from_slice(&start.lambda_f);
        let state = State {
            k: 0,
            t: t0,
            q: q0.to_vec(),
            u: u0.to_vec(),
            a: start.a.clone(),
            a_bar: start.a,
            lambda_n: start.lambda_n.clone(),
            lambda_n_bar: start.lambda_n,
            lambda_f: start.lambda_f.clone(),
            lambda_f_bar: start.lambda_f,
            p_n: vec![0.0; off.nn],
            p_f: vec![0.0; off.nf],
            x,
        };
        let work = Work {
            eval: Evaluation::new(&layout),
            der: Derivatives::default(),
            bt: Triplets::default(),
            b: RowMat::default(),
            bdot_u: vec![0.0; layout.nq],
            jac: Vec::new(),
            rhs_red: Vec::new(),
            res: vec![0.0; off.n],
            dx: vec![0.0; off.n],
            dg: RowMat::default(),
            dxp: RowMat::default(),
            dap: RowMat::default(),
            dxv: RowMat::default(),
            dgv: RowMat::default(),
            dav: RowMat::default(),
            r_pos: Vec::new(),
            r_vel: Vec::new(),
            r_law: Vec::new(),
            it: Iterate::default(),
            solver,
            linear_solves: 0,
            singular_sets: Vec::new(),
            factored: None,
            x_from: Vec::new(),
            unused_position: Vec::new(),
            unused_velocity: Vec::new(),
        };
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
        })
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }
    /// The system, mutably (to change parameters between steps; the layout must not
    /// change).
    pub fn system_mut(&mut self) -> &mut S {
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
    pub fn set_state(&mut self, state: State) {
        self.time_base = (state.t, state.k);
        self.state = state;
    }
    /// The options.
    pub fn options(&self) -> &Options {
        &self.options
    }
    /// Changes the options (for example Δt or the prox parameter) mid-run.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] when they are invalid; nothing changes then.
    pub fn set_options(&mut self, options: Options) -> Result<(), StepError> {
        options.validate()?;
        if options.dt != self.options.dt {
            self.time_base = (self.state.t, self.state.k);
        }
        self.options = options;
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
    /// # Errors
    /// [`StepError::NotConverged`] (carrying the best iterate's residual, the sets
    /// visited and the current state), [`StepError::NonFinite`], [`StepError::Linear`].
    pub fn trial(&mut self, fixed: Option<&IndexSets>, rho_inf: f64) -> Result<Trial, StepError> {
        if let Some(s) = fixed {
            if !s.is_consistent(self.off.nn, self.layout.friction.len()) {
                return Err(StepError::InvalidInput(
                    "fixed index sets have wrong sizes or break A ⊇ B ⊇ C, D ⊇ E".into(),
                ));
            }
        }
        self.solve(fixed, rho_inf, self.state.x.clone())
    }

    /// Commits a trial: the stepper advances to its state.
    pub fn commit(&mut self, trial: Trial) {
        self.account(&trial.stats);
        self.state = trial.state;
        self.last = Some(trial.stats);
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
    }

    /// Re-solves the current step with the index sets fixed by the caller and commits it
    /// when it converges. Returns the statistics; `stats.sets` are the fixed sets.
    ///
    /// # Errors
    /// As [`Stepper::trial`].
    pub fn step_with_sets(&mut self, sets: &IndexSets) -> Result<&StepStats, StepError> {
        let trial = self.trial(Some(sets), self.options.rho_inf)?;
        self.commit(trial);
        Ok(self.last.as_ref().expect("just committed"))
    }

    /// One step with the robustness policy of thesis §4.2: solve with the default ρ∞;
    /// on failure retry with each of `rho_inf_retries` (after the failures that
    /// [`Options::rho_inf_retry`] names); if the sets cycled, re-solve
    /// once per distinct set seen with the sets fixed, keep the self-consistent
    /// candidates, deduplicate them by state and continue with the first (reported as a
    /// [`BranchPoint`] in the step statistics); otherwise fail or accept the best
    /// iterate per [`Options::on_failure`].
    ///
    /// # Errors
    /// [`StepError::NotConverged`] carrying t and the last good state; the stepper
    /// stays at that state, so the run can continue from it (for example after
    /// changing the options). [`StepError::Linear`] when the Newton matrix was singular
    /// on every attempt (no iterate to report).
    ///
    /// A caller can take a step that fails even so as substeps, with this or its own
    /// policy: see [`Stepper::split_step`].
    pub fn step(&mut self) -> Result<&StepStats, StepError> {
        let rho0 = self.options.rho_inf;
        // A singular Newton matrix on every attempt: reported as such, not as a
        // non-converged step without iterates.
        let mut singular: Option<StepError> = None;
        let first = self.solve(None, rho0, self.state.x.clone());
        let iterated = matches!(first, Err(StepError::NotConverged { .. }));
        let (visited, cycling, best) = match first {
            Ok(t) => {
                self.commit(t);
                return Ok(self.last.as_ref().expect("just committed"));
            }
            Err(StepError::NotConverged {
                visited_sets,
                cycling,
                best,
                ..
            }) => (visited_sets, cycling, best),
            // A singular Newton matrix or a non-finite iterate is retried like a
            // non-converged step; only invalid input stops at once.
            Err(e @ StepError::InvalidInput(_)) => return Err(e),
            Err(e) => {
                singular = matches!(e, StepError::Linear { .. }).then_some(e);
                (Vec::new(), false, None)
            }
        };
        let mut retries = 1;
        let mut best = best;
        let rho_retries = match self.options.rho_inf_retry {
            RhoInfRetry::SingularMatrix if iterated => Vec::new(),
            _ => self.options.rho_inf_retries.clone(),
        };
        for rho in rho_retries {
            match self.solve_retry(None, rho) {
                Ok(mut t) => {
                    t.stats.retries = retries;
                    self.commit(t);
                    return Ok(self.last.as_ref().expect("just committed"));
                }
                Err(StepError::NotConverged { best: b, .. }) => {
                    singular = None;
                    if b.as_ref().map_or(f64::INFINITY, |t| t.stats.residual)
                        < best.as_ref().map_or(f64::INFINITY, |t| t.stats.residual)
                    {
                        best = b;
                    }
                }
                Err(e @ StepError::InvalidInput(_)) => return Err(e),
                Err(StepError::Linear { .. }) => {}
                Err(_) => singular = None,
            }
            retries += 1;
        }
        if cycling && self.options.explore_branches {
            if let Some(t) = self.branch_trial(&visited, rho0, retries) {
                self.commit(t);
                return Ok(self.last.as_ref().expect("just committed"));
            }
        }
        if self.options.on_failure == FailurePolicy::AcceptBest {
            if let Some(mut t) = best.take().map(|b| *b) {
                if t.state.q.iter().chain(&t.state.u).all(|x| x.is_finite()) {
                    t.stats.retries = retries;
                    t.stats.converged = false;
                    self.commit(t);
                    return Ok(self.last.as_ref().expect("just committed"));
                }
            }
        }
        if let (Some(e), true, None) = (singular, visited.is_empty(), &best) {
            return Err(e);
        }
        Err(StepError::NotConverged {
            t: self.state.t,
            residual: best.as_ref().map_or(f64::INFINITY, |b| b.stats.residual),
            visited_sets: visited,
            cycling,
            state: Box::new(self.state.clone()),
            best: None,
        })
    }

    /// Takes the step t_n → t_n + Δt as `parts` substeps of Δt/`parts`, each committed
    /// by `substep` (for example `|s| s.step().map(|_| ())`, or a caller's own policy),
    /// then puts the state back on the time grid: k advances by one and t = t₀ + kΔt
    /// exactly. The generalized-α auxiliary variables (ā, λ̄) carry over between step
    /// sizes unchanged, since their recursion (eqs. 71, 73) does not involve Δt.
    ///
    /// The substeps' statistics are merged into one [`StepStats`]: iterations and retries
    /// summed (plus one retry for the failed whole step), `substeps` counted, the first
    /// branch point kept; [`RunStats`] counts one step.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for `parts` = 0; otherwise the first substep error,
    /// after which the stepper is back at the state, options and statistics it had.
    pub fn split_step(
        &mut self,
        parts: usize,
        mut substep: impl FnMut(&mut Self) -> Result<(), StepError>,
    ) -> Result<&StepStats, StepError> {
        if parts == 0 {
            return Err(StepError::InvalidInput(
                "a step splits into at least one part".into(),
            ));
        }
        let saved_state = self.state.clone();
        let saved_options = self.options.clone();
        let saved_base = self.time_base;
        let saved_stats = self.stats.clone();
        let saved_last = self.last.clone();
        let mut sub = saved_options.clone();
        sub.dt = saved_options.dt / parts as f64;
        self.set_options(sub)?;
        let mut merged: Option<StepStats> = None;
        for _ in 0..parts {
            if let Err(e) = substep(self) {
                self.options = saved_options;
                self.time_base = saved_base;
                self.state = saved_state;
                self.stats = saved_stats;
                self.last = saved_last;
                return Err(e);
            }
            let last = self.last.clone().expect("a substep commits a step");
            merged = Some(match merged {
                None => last,
                Some(m) => StepStats {
                    t: last.t,
                    iterations: m.iterations + last.iterations,
                    residual: m.residual.max(last.residual),
                    retries: m.retries + last.retries,
                    converged: m.converged && last.converged,
                    branch: m.branch.or(last.branch),
                    substeps: m.substeps + last.substeps,
                    ..last
                },
            });
        }
        let mut merged = merged.expect("parts >= 1");
        merged.retries += 1;
        self.options = saved_options;
        self.time_base = saved_base;
        self.state.k = saved_state.k + 1;
        self.state.t = self.grid_time(self.state.k);
        merged.t = self.state.t;
        self.stats = saved_stats;
        self.stats.split_steps += 1;
        self.account(&merged);
        self.last = Some(merged);
        Ok(self.last.as_ref().expect("just stored"))
    }

    /// The fixed-set re-solves of a cycling step (NSGA-SPEC §4): one per visited set, in
    /// first-visit order; the self-consistent ones, deduplicated by state, make the
    /// branch point, and the first is returned (with `retries` failed attempts before it).
    fn branch_trial(&mut self, visited: &[IndexSets], rho0: f64, retries: usize) -> Option<Trial> {
        let mut candidates: Vec<(IndexSets, State)> = Vec::new();
        let mut first_trial: Option<Trial> = None;
        for sets in visited {
            let Ok(t) = self.solve_retry(Some(sets), rho0) else {
                continue;
            };
            // Self-consistency: the sets recomputed from the converged x.
            let recomputed = self.sets_of(&t.state.x, rho0);
            if &recomputed != sets {
                continue;
            }
            let duplicate = candidates.iter().any(|(_, s)| s.same_motion(&t.state));
            if !duplicate {
                candidates.push((sets.clone(), t.state.clone()));
                if first_trial.is_none() {
                    first_trial = Some(t);
                }
            }
        }
        let mut t = first_trial?;
        t.stats.retries = retries;
        t.stats.branch = Some(BranchPoint {
            t: self.state.t,
            candidates,
            tried: visited.len(),
            chosen: 0,
        });
        Some(t)
    }

    /// A retry or fixed-set re-solve from the state's unknowns, with at most
    /// [`Options::retry_max_iter`] Newton iterations.
    fn solve_retry(&mut self, fixed: Option<&IndexSets>, rho_inf: f64) -> Result<Trial, StepError> {
        let full = self.options.max_iter;
        self.options.max_iter = self.options.retry_max_iter.min(full);
        let out = self.solve(fixed, rho_inf, self.state.x.clone());
        self.options.max_iter = full;
        out
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
            let s = self.last.as_ref().expect("step committed");
            observe(&self.state, s);
        }
        Ok(())
    }

    /// The index sets the contact laws give at unknowns `x` (no Newton update).
    pub fn sets_of(&mut self, x: &[f64], rho_inf: f64) -> IndexSets {
        let p = GenAlpha::new(rho_inf);
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(true);
        self.finish_accelerations(x);
        self.compute_sets(x)
    }

    /// Test oracle hook: the scaled residual R(x) and the semismooth Jacobian ∂R/∂x
    /// (dense) for fixed sets. `update_prox` recomputes the prox parameters from this x
    /// (keep it false when finite-differencing, so that r stays fixed).
    #[doc(hidden)]
    pub fn newton_system(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        rho_inf: f64,
        update_prox: bool,
    ) -> (Vec<f64>, DMatrix<f64>) {
        let p = GenAlpha::new(rho_inf);
        self.prepare_step();
        self.derive(x, &p);
        self.evaluate_iterate(update_prox);
        self.finish_accelerations(x);
        self.residual(x, sets, &p);
        // The full matrix: nothing pruned.
        self.mark_unused(None);
        self.jacobian(x, sets, &p, 0.0);
        let n = self.off.n;
        let mut j = DMatrix::zeros(n, n);
        for &(r, c, v) in &self.work.jac {
            j[(r, c)] += v;
        }
        (self.work.res.clone(), j)
    }

    // ---------------------------------------------------------------- internals

    /// B(q_n) and Ḃu at the start of the step.
    fn prepare_step(&mut self) {
        let w = &mut self.work;
        let st = &self.state;
        w.bt.clear();
        self.system.kinematics(st.t, &st.q, &mut w.bt);
        w.b.tmp.clear();
        w.b.tmp.extend(w.bt.entries.iter().copied());
        w.b.build(self.off.nq);
        w.bdot_u.iter_mut().for_each(|x| *x = 0.0);
        self.system
            .kinematics_rate(st.t, &st.q, &st.u, &mut w.bdot_u);
    }

    /// Kinematic updates (eqs. 71, 73, 125, 95, 96, 102, 113, 114).
    fn derive(&mut self, x: &[f64], p: &GenAlpha) {
        let o = self.off;
        let st = &self.state;
        let dt = self.options.dt;
        let it = &mut self.work.it;
        let b = &self.work.b;
        it.a_bar1.clear();
        it.u1.clear();
        for i in 0..o.nu {
            let ab = p.bar(st.a[i], x[o.a + i], st.a_bar[i]);
            it.a_bar1.push(ab);
            it.u1
                .push(st.u[i] + dt * ((1.0 - p.gamma) * st.a_bar[i] + p.gamma * ab) + x[o.uu + i]);
        }
        it.q1.clear();
        for j in 0..o.nq {
            // q_{n+1} = q_n + Δt B u_n + ½Δt²(B a_β + Ḃu_n) + B Q   (eq. 125, second order)
            let mut bu = 0.0;
            let mut ba = 0.0;
            let mut bq = 0.0;
            for (i, bij) in b.row(j) {
                bu += bij * st.u[i];
                let a_beta = (1.0 - 2.0 * p.beta) * st.a_bar[i] + 2.0 * p.beta * it.a_bar1[i];
                ba += bij * a_beta;
                bq += bij * x[o.qq + i];
            }
            it.q1
                .push(st.q[j] + dt * bu + 0.5 * dt * dt * (ba + self.work.bdot_u[j]) + bq);
        }
        it.lbar_n1.clear();
        it.p_n.clear();
        it.kappa_hat.clear();
        for k in 0..o.nn {
            let lb = p.bar(st.lambda_n[k], x[o.ln + k], st.lambda_n_bar[k]);
            it.lbar_n1.push(lb);
            it.p_n
                .push(x[o.cn + k] + dt * ((1.0 - p.gamma) * st.lambda_n_bar[k] + p.gamma * lb));
            it.kappa_hat
                .push(x[o.kn + k] + dt * dt * ((0.5 - p.beta) * st.lambda_n_bar[k] + p.beta * lb));
        }
        it.lbar_f1.clear();
        it.p_f.clear();
        for c in 0..o.nf {
            let lb = p.bar(st.lambda_f[c], x[o.lf + c], st.lambda_f_bar[c]);
            it.lbar_f1.push(lb);
            it.p_f
                .push(x[o.cf + c] + dt * ((1.0 - p.gamma) * st.lambda_f_bar[c] + p.gamma * lb));
        }
        // Multipliers per family, for the smooth rows and the derivative probes.
        let fam = |v: &mut Vec<f64>, first: &[f64], second: &[f64]| {
            v.clear();
            v.extend_from_slice(first);
            v.extend_from_slice(second);
        };
        fam(&mut it.lam_p, &x[o.lg..o.lg + o.ng], &x[o.ln..o.ln + o.nn]);
        fam(
            &mut it.lam_v,
            &x[o.lga..o.lga + o.nga],
            &x[o.lf..o.lf + o.nf],
        );
        fam(&mut it.cap_p, &x[o.cg..o.cg + o.ng], &x[o.cn..o.cn + o.nn]);
        fam(
            &mut it.cap_v,
            &x[o.cga..o.cga + o.nga],
            &x[o.cf..o.cf + o.nf],
        );
        fam(&mut it.kap_p, &x[o.kg..o.kg + o.ng], &x[o.kn..o.kn + o.nn]);
        it.half_cap_v.clear();
        it.half_cap_v.extend(it.cap_v.iter().map(|c| 0.5 * dt * c));
    }

    /// Evaluates the system at (t_{n+1}, q_{n+1}, u_{n+1}) and the constraint levels.
    fn evaluate_iterate(&mut self, update_prox: bool) {
        let t1 = self.t_next();
        let w = &mut self.work;
        w.eval.reset();
        self.system.evaluate(t1, &w.it.q1, &w.it.u1, &mut w.eval);
        if update_prox {
            prox_parameters(
                self.options.prox,
                &self.layout,
                &w.eval,
                &mut w.r_pos,
                &mut w.r_vel,
                &mut w.r_law,
            );
        }
        let l = &self.layout;
        let (np, nv, ng, nga) = (
            l.n_position(),
            l.n_velocity(),
            l.n_bilateral_position,
            l.n_bilateral_velocity,
        );
        let e = &w.eval;
        let it = &mut w.it;
        let u0 = &self.state.u;
        // ṗ(q1,u1), ṗ(q1,u_n), p̈ = W_pᵀa + ζ_p (buffers reused: no allocation per iterate)
        it.rate_new.clone_from(&e.position_chi);
        it.rate_old.clone_from(&e.position_chi);
        for &(r, c, v) in &e.position_w.entries {
            it.rate_new[c] += v * it.u1[r];
            it.rate_old[c] += v * u0[r];
        }
        it.p.clone_from(&e.position);
        it.xi_p.clear();
        for k in 0..np {
            let en = if k < ng { 0.0 } else { l.e_n[k - ng] };
            it.xi_p.push(it.rate_new[k] + en * it.rate_old[k]);
        }
        // velocity level
        it.v.clone_from(&e.velocity_chi);
        it.v_old.clone_from(&e.velocity_chi);
        for &(r, c, v) in &e.velocity_w.entries {
            it.v[c] += v * it.u1[r];
            it.v_old[c] += v * u0[r];
        }
        it.xi_v.clear();
        for k in 0..nv {
            let ef = if k < nga { 0.0 } else { self.comp_ef[k - nga] };
            it.xi_v.push(it.v[k] + ef * it.v_old[k]);
        }
        it.acc_p.clone_from(&e.position_zeta);
        it.acc_v.clone_from(&e.velocity_zeta);
    }

    /// Adds W_pᵀ a and W_vᵀ a to the acceleration levels (needs x).
    fn finish_accelerations(&mut self, x: &[f64]) {
        let o = self.off;
        let w = &mut self.work;
        for &(r, c, v) in &w.eval.position_w.entries {
            w.it.acc_p[c] += v * x[o.a + r];
        }
        for &(r, c, v) in &w.eval.velocity_w.entries {
            w.it.acc_v[c] += v * x[o.a + r];
        }
    }

    /// t_{n+1} = t_base + (k + 1 − k_base) Δt: the integrator's own time grid, not an
    /// accumulated sum (ERRATA 20).
    fn t_next(&self) -> f64 {
        self.grid_time(self.state.k + 1)
    }

    /// t_k = t_base + (k − k_base)Δt on the current grid.
    fn grid_time(&self, k: u64) -> f64 {
        let (t_base, k_base) = self.time_base;
        t_base + (k - k_base) as f64 * self.options.dt
    }

    /// Index sets from the current iterate (eqs. 128–142).
    fn compute_sets(&mut self, x: &[f64]) -> IndexSets {
        let o = self.off;
        let l = &self.layout;
        let w = &self.work;
        let it = &w.it;
        let mut s = IndexSets::empty(o.nn, l.friction.len());
        for k in 0..o.nn {
            let pk = o.ng + k;
            let r = w.r_pos[pk];
            s.a[k] = r * it.p[pk] - it.kappa_hat[k] <= 0.0;
            s.b[k] = s.a[k] && r * it.xi_p[pk] - it.p_n[k] <= 0.0;
            s.c[k] = s.b[k] && r * it.acc_p[pk] - x[o.ln + k] <= 0.0;
        }
        for (j, law) in l.friction.iter().enumerate() {
            let active = law.normals.iter().any(|&k| s.a[k]);
            if !active {
                continue;
            }
            let f0 = self.law_off[j];
            let r = w.r_law[j];
            let p_hat: f64 = law.normals.iter().map(|&k| it.p_n[k]).sum::<f64>().max(0.0);
            let l_hat: f64 = law
                .normals
                .iter()
                .map(|&k| x[o.ln + k])
                .sum::<f64>()
                .max(0.0);
            let mut nd = 0.0;
            let mut ne = 0.0;
            for m in 0..law.components {
                let c = f0 + m;
                let vc = o.nga + c;
                nd += (r * it.xi_v[vc] - it.p_f[c]).powi(2);
                ne += (r * it.acc_v[vc] - x[o.lf + c]).powi(2);
            }
            s.d[j] = nd.sqrt() <= law.mu * p_hat;
            s.e[j] = s.d[j] && ne.sqrt() <= law.mu * l_hat;
        }
        s
    }

    /// One Newton solve of the step (eq. 143), with the open contacts pruned when the
    /// option asks for it.
    fn solve(
        &mut self,
        fixed: Option<&IndexSets>,
        rho_inf: f64,
        x: Vec<f64>,
    ) -> Result<Trial, StepError> {
        // Contacts that may not be pruned: with fixed sets, those the sets close.
        let keep = self.options.prune_open_contacts.then(|| {
            (0..self.off.nn)
                .map(|k| fixed.is_some_and(|f| f.a[k]))
                .collect()
        });
        self.solve_inner(fixed, rho_inf, x, keep)
    }

    /// Marks the unknowns of contacts that are open, force-free and cannot close within
    /// the step, sets them to zero in `x`, and returns the map full → reduced index
    /// (`usize::MAX` for pruned) and the reduced size; None when nothing is pruned.
    fn open_contacts(&mut self, x: &mut [f64], keep: &[bool]) -> Option<(Vec<usize>, usize)> {
        let o = self.off;
        let dt = self.options.dt;
        let st = &self.state;
        let w = &mut self.work;
        w.eval.reset();
        self.system.evaluate(st.t, &st.q, &st.u, &mut w.eval);
        let e = &w.eval;
        let mut rate = e.position_chi.clone();
        let mut acc = e.position_zeta.clone();
        for &(r, c, v) in &e.position_w.entries {
            rate[c] += v * st.u[r];
            acc[c] += v * st.a[r];
        }
        let mut pruned_n = vec![false; o.nn];
        for (k, pr) in pruned_n.iter_mut().enumerate() {
            let pk = o.ng + k;
            let margin = 2.0 * dt * rate[pk].abs() + dt * dt * acc[pk].abs();
            *pr = !keep[k]
                && e.position[pk] > margin
                && e.position[pk] > 0.0
                && st.lambda_n[k] == 0.0
                && st.lambda_n_bar[k] == 0.0;
        }
        if !pruned_n.iter().any(|&b| b) {
            return None;
        }
        let mut map = vec![0usize; o.n];
        let prune_unknown = |i: usize, map: &mut Vec<usize>, x: &mut [f64]| {
            map[i] = usize::MAX;
            x[i] = 0.0;
        };
        for (k, &pr) in pruned_n.iter().enumerate() {
            if pr {
                for base in [o.kn, o.cn, o.ln] {
                    prune_unknown(base + k, &mut map, x);
                }
            }
        }
        for (j, law) in self.layout.friction.iter().enumerate() {
            let f0 = self.law_off[j];
            let quiet = (0..law.components)
                .all(|m| st.lambda_f[f0 + m] == 0.0 && st.lambda_f_bar[f0 + m] == 0.0);
            if quiet && law.normals.iter().all(|&k| pruned_n[k]) {
                for m in 0..law.components {
                    prune_unknown(o.cf + f0 + m, &mut map, x);
                    prune_unknown(o.lf + f0 + m, &mut map, x);
                }
            }
        }
        let mut n_red = 0;
        for m in &mut map {
            if *m != usize::MAX {
                *m = n_red;
                n_red += 1;
            }
        }
        Some((map, n_red))
    }

    /// Marks the constraints whose unknowns the prune `map` leaves out (none without).
    fn mark_unused(&mut self, map: Option<&[usize]>) {
        let o = self.off;
        let w = &mut self.work;
        w.unused_position.clear();
        w.unused_velocity.clear();
        if let Some(map) = map {
            let pruned = |i: usize| map[i] == usize::MAX;
            w.unused_position.resize(o.ng, false);
            w.unused_position
                .extend((0..o.nn).map(|k| pruned(o.kn + k)));
            w.unused_velocity.resize(o.nga, false);
            w.unused_velocity
                .extend((0..o.nf).map(|c| pruned(o.cf + c)));
        }
    }

    /// One Newton solve of the step (eq. 143). With `keep` (the contacts that may not be
    /// pruned), open contacts are pruned (`Options::prune_open_contacts`).
    fn solve_inner(
        &mut self,
        fixed: Option<&IndexSets>,
        rho_inf: f64,
        mut x: Vec<f64>,
        keep: Option<Vec<bool>>,
    ) -> Result<Trial, StepError> {
        let x_start = keep.is_some().then(|| x.clone());
        let prune = keep.as_ref().and_then(|k| self.open_contacts(&mut x, k));
        self.mark_unused(prune.as_ref().map(|(map, _)| map.as_slice()));
        let p = GenAlpha::new(rho_inf);
        let o = self.off;
        let tol = self.options.tol;
        let max_iter = self.options.max_iter;
        self.prepare_step();
        let mut visited: Vec<IndexSets> = Vec::new();
        let mut history: Vec<usize> = Vec::new();
        let mut residuals: Vec<f64> = Vec::new();
        // Best iterate so far: (residual, iteration, visited-set id) and its x.
        let mut best: Option<(f64, usize, usize)> = None;
        let mut best_x: Vec<f64> = Vec::new();
        let mut pending: Option<(IndexSets, f64)> = None;
        // Simplified Newton bookkeeping: the last update reused kept factors, how many in
        // a row did, and the residual before the last update.
        let (mut reused, mut reuses, mut last_res) = (false, 0, f64::INFINITY);
        let mut may_reuse = self.options.reuse_factorization;
        for iter in 0..=max_iter {
            let (sets, res) = match pending.take() {
                Some(e) => e,
                None => self.evaluate_at(&x, fixed, &p, iter == 0),
            };
            let id = match visited.iter().position(|v| v == &sets) {
                Some(i) => i,
                None => {
                    visited.push(sets.clone());
                    visited.len() - 1
                }
            };
            history.push(id);
            if !res.is_finite() {
                return Err(StepError::NonFinite {
                    t: self.state.t,
                    state: Box::new(self.state.clone()),
                });
            }
            if let (Some((map, _)), Some(x0)) = (&prune, &x_start) {
                let closing = |k: usize| map[o.kn + k] == usize::MAX && sets.a[k];
                if (0..o.nn).any(closing) {
                    // A pruned contact closes at this iterate after all: redo the step
                    // with it kept in the system.
                    let mut keep = keep.unwrap_or_else(|| vec![false; o.nn]);
                    for (k, kk) in keep.iter_mut().enumerate() {
                        *kk |= closing(k);
                    }
                    return self.solve_inner(fixed, rho_inf, x0.clone(), Some(keep));
                }
            }
            if res <= tol {
                return Ok(self.make_trial(x, sets, iter, res, p.rho_inf, true, visited, false));
            }
            if best.as_ref().is_none_or(|b| res < b.0) {
                best = Some((res, iter, id));
                best_x.clear();
                best_x.extend_from_slice(&x);
            }
            residuals.push(res);
            let hopeless = if fixed.is_some() {
                stalled(&residuals)
            } else {
                settled_cycle(&history, &residuals)
            };
            if iter == max_iter || hopeless {
                break;
            }
            // Simplified Newton while it contracts (Options::reuse_factorization).
            if reused && res > REUSE_CONTRACTION * last_res {
                may_reuse = false;
            }
            reused =
                may_reuse && reuses < MAX_REUSES && self.kept_direction(&sets, &p, prune.as_ref());
            if reused {
                reuses += 1;
            } else {
                reuses = 0;
                self.exact_direction(&x, &sets, &p, prune.as_ref())?;
            }
            last_res = res;
            pending = Some(self.line_search(&mut x, fixed, &p, res));
        }
        // Cycling: more than one distinct set among the last half of the iterates.
        let tail = &history[history.len().saturating_sub(1) / 2..];
        let cycling = fixed.is_none() && tail.iter().any(|&i| i != tail[0]);
        let best_trial = best.map(|(res, biter, bid)| {
            // Re-derive the best iterate's state.
            self.derive(&best_x, &p);
            let bsets = visited[bid].clone();
            Box::new(self.make_trial(
                best_x,
                bsets,
                biter,
                res,
                p.rho_inf,
                false,
                Vec::new(),
                cycling,
            ))
        });
        Err(StepError::NotConverged {
            t: self.state.t,
            residual: best_trial
                .as_ref()
                .map_or(f64::INFINITY, |b| b.stats.residual),
            visited_sets: visited,
            cycling,
            state: Box::new(self.state.clone()),
            best: best_trial,
        })
    }

    /// Evaluates the iterate `x`: kinematic updates, system, index sets (the fixed ones
    /// when given) and residual; returns the sets and ‖R‖∞.
    fn evaluate_at(
        &mut self,
        x: &[f64],
        fixed: Option<&IndexSets>,
        p: &GenAlpha,
        update_prox: bool,
    ) -> (IndexSets, f64) {
        self.derive(x, p);
        self.evaluate_iterate(update_prox);
        self.finish_accelerations(x);
        let sets = match fixed {
            Some(s) => s.clone(),
            None => self.compute_sets(x),
        };
        self.residual(x, &sets, p);
        let res = self.work.res.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
        (sets, res)
    }

    /// Takes the Newton update: x ← x + α dx with the first α = 1, ½, ¼, … (at most
    /// [`Options::line_search`] halvings) for which ‖R‖∞ falls to (1 − 10⁻⁴α) times
    /// `res0`, its value at x; when none does, the full update, since a semismooth
    /// Newton step must stay free to change the index sets. Returns the sets and ‖R‖∞
    /// at the new x, whose evaluation is left in the work buffers.
    fn line_search(
        &mut self,
        x: &mut [f64],
        fixed: Option<&IndexSets>,
        p: &GenAlpha,
        res0: f64,
    ) -> (IndexSets, f64) {
        let halvings = self.options.line_search;
        self.work.x_from.clear();
        self.work.x_from.extend_from_slice(x);
        let mut alpha = 1.0;
        for _ in 0..=halvings {
            self.step_along(x, alpha);
            let (sets, res) = self.evaluate_at(x, fixed, p, false);
            if halvings == 0 || res <= (1.0 - ARMIJO * alpha) * res0 {
                return (sets, res);
            }
            alpha *= 0.5;
        }
        self.step_along(x, 1.0);
        self.evaluate_at(x, fixed, p, false)
    }

    /// x = x_from + α dx (for α = 1 exactly x_from + dx).
    fn step_along(&self, x: &mut [f64], alpha: f64) {
        let w = &self.work;
        for ((xi, x0), d) in x.iter_mut().zip(&w.x_from).zip(&w.dx) {
            *xi = x0 + alpha * d;
        }
    }

    /// The exact Newton update at `x` (eq. 143): assembles and factors the Jacobian,
    /// regularized (`Options::regularization`) when it is singular.
    fn exact_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &GenAlpha,
        prune: Option<&(Vec<usize>, usize)>,
    ) -> Result<(), StepError> {
        let eps = self.options.regularization;
        let linear_error = |e: crate::linalg::LinalgError, st: &State| StepError::Linear {
            t: st.t,
            message: e.0,
            state: Box::new(st.clone()),
        };
        // Only plain factors are kept for simplified Newton updates: the regularized
        // linearization of redundant contacts already converges just linearly.
        self.work.factored = None;
        // Redundancy is a property of which contacts are closed: sets whose normal
        // contacts are those of a singular plain matrix go straight to the regularized
        // one, whatever their friction sets.
        let redundant = |known: &IndexSets| known.same_normal_sets(sets);
        if !(eps > 0.0 && self.work.singular_sets.iter().any(redundant)) {
            self.jacobian(x, sets, p, 0.0);
            match self.newton_direction(prune, false) {
                Ok(()) => {
                    self.work.factored = Some(FactoredFor {
                        sets: sets.clone(),
                        map: prune.map(|(map, _)| map.clone()),
                        dt: self.options.dt,
                        rho_inf: p.rho_inf,
                    });
                    return Ok(());
                }
                Err(e) if eps <= 0.0 => return Err(linear_error(e, &self.state)),
                Err(_) => {}
            }
        }
        // Redundant closed contacts: solve the regularized linearization.
        let known = &mut self.work.singular_sets;
        if !known.iter().any(redundant) {
            if known.len() == SINGULAR_SETS_KEPT {
                known.remove(0);
            }
            known.push(sets.clone());
        }
        self.jacobian(x, sets, p, eps);
        self.newton_direction(prune, false)
            .map_err(|e| linear_error(e, &self.state))
    }

    /// The simplified Newton update from the solver's kept factors, when they were
    /// assembled for these sets, prune map, Δt and ρ∞; false (and no update) otherwise.
    fn kept_direction(
        &mut self,
        sets: &IndexSets,
        p: &GenAlpha,
        prune: Option<&(Vec<usize>, usize)>,
    ) -> bool {
        let fits = self.work.factored.as_ref().is_some_and(|f| {
            &f.sets == sets
                && f.map.as_ref() == prune.map(|(map, _)| map)
                && f.dt == self.options.dt
                && f.rho_inf == p.rho_inf
        });
        fits && self.newton_direction(prune, true).is_ok()
    }

    /// The Newton update dx = −J⁻¹R from the assembled Jacobian and residual, or with
    /// `again` from the solver's kept factors (a simplified Newton update), on the reduced
    /// system when open contacts are pruned (their updates are 0).
    fn newton_direction(
        &mut self,
        prune: Option<&(Vec<usize>, usize)>,
        again: bool,
    ) -> Result<(), crate::linalg::LinalgError> {
        let w = &mut self.work;
        if !again {
            w.linear_solves += 1;
        }
        w.dx.iter_mut().zip(&w.res).for_each(|(d, r)| *d = -r);
        let Some((map, n_red)) = prune else {
            return if again {
                w.solver.solve_again(&mut w.dx)
            } else {
                w.solver.solve(self.off.n, &w.jac, &mut w.dx)
            };
        };
        w.rhs_red.clear();
        w.rhs_red.resize(*n_red, 0.0);
        for (i, &m) in map.iter().enumerate() {
            if m != usize::MAX {
                w.rhs_red[m] = w.dx[i];
            }
        }
        let out = if again {
            w.solver.solve_again(&mut w.rhs_red)
        } else {
            // Renumbered in place (the assembled Jacobian is not used again), without a
            // branch per entry: about one entry in seven is pruned, in no predictable order.
            let mut kept = 0;
            for i in 0..w.jac.len() {
                let (r, c, v) = w.jac[i];
                let (r, c) = (map[r], map[c]);
                w.jac[kept] = (r, c, v);
                kept += usize::from(r != usize::MAX && c != usize::MAX);
            }
            w.jac.truncate(kept);
            w.solver.solve(*n_red, &w.jac, &mut w.rhs_red)
        };
        for (i, &m) in map.iter().enumerate() {
            w.dx[i] = if m == usize::MAX { 0.0 } else { w.rhs_red[m] };
        }
        out
    }

    #[allow(clippy::fn_params_excessive_bools)]
    fn make_trial(
        &mut self,
        x: Vec<f64>,
        sets: IndexSets,
        iterations: usize,
        residual: f64,
        rho_inf: f64,
        converged: bool,
        visited: Vec<IndexSets>,
        cycling: bool,
    ) -> Trial {
        let o = self.off;
        let it = &self.work.it;
        let st = &self.state;
        let state = State {
            k: st.k + 1,
            t: self.t_next(),
            q: it.q1.clone(),
            u: it.u1.clone(),
            a: x[o.a..o.a + o.nu].to_vec(),
            a_bar: it.a_bar1.clone(),
            lambda_n: x[o.ln..o.ln + o.nn].to_vec(),
            lambda_n_bar: it.lbar_n1.clone(),
            lambda_f: x[o.lf..o.lf + o.nf].to_vec(),
            lambda_f_bar: it.lbar_f1.clone(),
            p_n: it.p_n.clone(),
            p_f: it.p_f.clone(),
            x,
        };
        let stats = StepStats {
            t: state.t,
            iterations,
            residual,
            rho_inf,
            sets,
            retries: 0,
            converged,
            branch: None,
            solver: self.work.solver.name().to_owned(),
            substeps: 1,
        };
        Trial {
            state,
            stats,
            visited,
            cycling,
        }
    }
}

#[cfg(test)]
mod give_up_tests {
    use super::{settled_cycle, stalled};

    #[test]
    fn a_period_three_cycle_without_progress_is_settled() {
        // Sets 0, 1, 2 repeating; residuals repeating too.
        let history = [5, 0, 1, 2, 0, 1, 2, 0, 1, 2];
        let residuals = [
            1e-3, 2e-2, 1e-2, 4.7e-4, 2e-2, 1e-2, 4.7e-4, 2e-2, 1e-2, 4.7e-4,
        ];
        assert!(settled_cycle(&history, &residuals));
        // Two periods are not enough evidence.
        assert!(!settled_cycle(&history[3..], &residuals[3..]));
    }

    #[test]
    fn a_landing_cycle_of_period_seven_is_settled() {
        // As in the Lire collapse's landings: two sets that jump the residual up, then
        // five damped updates within one set, again and again.
        let period = [0, 1, 2, 2, 2, 2, 2];
        let r = [2.0e-2, 1.0e-2, 4.7e-4, 2.3e-4, 1.2e-4, 8.8e-5, 6.6e-5];
        let history: Vec<usize> = period.iter().cycle().take(21).copied().collect();
        let residuals: Vec<f64> = r.iter().cycle().take(21).copied().collect();
        assert!(settled_cycle(&history, &residuals));
        assert!(!settled_cycle(&history[..20], &residuals[..20]));
    }

    #[test]
    fn a_cycle_that_still_makes_progress_goes_on() {
        let history = [0, 1, 0, 1, 0, 1];
        let residuals = [1e-2, 1e-2, 1e-3, 1e-3, 1e-4, 1e-4];
        assert!(!settled_cycle(&history, &residuals));
    }

    #[test]
    fn one_set_is_not_a_cycle() {
        // Slow convergence within one set is left to max_iter.
        let history = [3; 12];
        let residuals = [1e-3; 12];
        assert!(!settled_cycle(&history, &residuals));
    }

    #[test]
    fn a_broken_pattern_is_not_a_cycle() {
        let history = [0, 1, 2, 0, 1, 2, 0, 1, 3];
        let residuals = [1e-2; 9];
        assert!(!settled_cycle(&history, &residuals));
    }

    #[test]
    fn fixed_set_solves_stall_only_without_progress() {
        assert!(!stalled(&[1.0, 0.1, 0.01, 1e-4]));
        assert!(!stalled(&[1.0, 0.9, 0.8]));
        assert!(stalled(&[1.0, 0.1, 0.09, 0.2, 0.06]));
        // Quadratic convergence after a slow start.
        assert!(!stalled(&[1.0, 0.1, 0.09, 0.2, 0.04]));
    }
}
