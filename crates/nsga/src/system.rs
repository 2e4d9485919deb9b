//! The system interface: what a mechanical system tells the stepper.
//!
//! A system has coordinates q (nq), velocities u (nu) with q̇ = B(t,q) u, and the
//! equality of measures (docs/method.md §1)
//!
//! ```text
//!     M(t,q) du = h(t,q,u) dt + W_g dP_g + W_γ dP_γ + W_N dP_N + W_F dP_F.
//! ```
//!
//! Constraints are stacked in two families, each written with its force directions W
//! (columns of an nu × n matrix) and the terms that complete their time derivatives:
//!
//! * **position level** `p = (g, g_N)`: ng bilateral constraints g(t,q) = 0 followed by
//!   nN normal gaps g_N(t,q) ≥ 0, with ṗ = W_pᵀ u + χ_p(t,q) and
//!   p̈ = W_pᵀ a + ζ_p(t,q,u);
//! * **velocity level** `v = (γ, γ_F)`: nγ bilateral velocity constraints γ = 0 followed
//!   by nF friction slip components, with v = W_vᵀ u + χ_v(t,q) and
//!   v̇ = W_vᵀ a + ζ_v(t,q,u).
//!
//! χ carries prescribed motion (a driven base), ζ everything else of the second
//! derivative: ζ_p = (dW_p/dt)ᵀ u + dχ_p/dt with d/dt = ∂/∂t + q̇·∂/∂q (for a gap
//! g_N(q) with B = I and no prescribed motion: ζ = uᵀ (∂²g_N/∂q²) u); the same for ζ_v.
//! All functions are evaluated at the integrator's own time t (ERRATA 20).
//!
//! [`System::evaluate`] is written once, generic over a [`Scalar`] (f64 or a dual
//! number), so that the stepper gets **exact** Jacobians by forward-mode automatic
//! differentiation (`num-dual`) without the user writing a single derivative. Large
//! systems (a chain of a thousand blocks) override [`System::derivatives`] with a
//! sparse implementation, because the default one costs one evaluation per coordinate.
//!
//! # Writing a system
//!
//! 1. Return a [`Layout`] with the sizes, the restitution coefficients of the normal
//!    contacts and the friction laws (components, μ, e_F and the normal contacts whose
//!    forces bound each law).
//! 2. Implement [`System::evaluate`]: fill the mass matrix and the W matrices as
//!    triplets (row = velocity index, column = constraint index), the force vector h and
//!    the constraint values; set χ and ζ where they are not zero (the stepper zeroes
//!    every vector and clears every triplet list before each call).
//! 3. If q̇ ≠ u, override [`System::kinematics`] and [`System::kinematics_rate`].
//!
//! See `systems::ball` for a complete example, and the crate docs for a small one.

use crate::sets::IndexSets;
use crate::state::State;
use num_dual::{Dual64, DualNum};

/// A number type the system functions are written in: `f64` for values, dual numbers
/// for exact derivatives.
pub trait Scalar: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// One Coulomb friction law (docs/method.md §1, paper eqs. 137–142).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrictionLaw {
    /// Number of tangential components: 1 (prox onto an interval) or 2 (onto a disk).
    pub components: usize,
    /// Friction coefficient μ ≥ 0.
    pub mu: f64,
    /// Tangential restitution e_F ∈ [0, 1] (ERRATA 19: really e_F, not e_N).
    pub e_f: f64,
    /// Normal contacts (indices into the nN normal gaps) whose forces, summed, bound the
    /// law: `‖λ_F‖ ≤ μ Σ_k λ_{N,k}`. One for a point contact, two for a block interface.
    pub normals: Vec<usize>,
}

/// Sizes and contact data of a system, fixed for the whole run.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Layout {
    /// Number of generalized coordinates q.
    pub nq: usize,
    /// Number of generalized velocities u.
    pub nu: usize,
    /// Number ng of bilateral position constraints g(t,q) = 0.
    pub n_bilateral_position: usize,
    /// Number nγ of bilateral velocity constraints γ(t,q,u) = 0.
    pub n_bilateral_velocity: usize,
    /// Newton restitution coefficient e_N ∈ \[0, 1\] of every normal contact (its length
    /// is nN).
    pub e_n: Vec<f64>,
    /// The friction laws; their components are stacked in this order (nF in all).
    pub friction: Vec<FrictionLaw>,
}

impl Layout {
    /// Number nN of normal contacts.
    #[must_use]
    pub fn n_normal(&self) -> usize {
        self.e_n.len()
    }
    /// Number nF of friction components (sum over the laws).
    #[must_use]
    pub fn n_friction(&self) -> usize {
        self.friction.iter().map(|f| f.components).sum()
    }
    /// Size of the position-level family p = (g, g_N).
    #[must_use]
    pub fn n_position(&self) -> usize {
        self.n_bilateral_position + self.n_normal()
    }
    /// Size of the velocity-level family v = (γ, γ_F).
    #[must_use]
    pub fn n_velocity(&self) -> usize {
        self.n_bilateral_velocity + self.n_friction()
    }
    /// Index of the first component of friction law `j` within γ_F.
    #[must_use]
    pub fn friction_offset(&self, j: usize) -> usize {
        self.friction[..j].iter().map(|f| f.components).sum()
    }

    /// Index of the first component of every friction law within γ_F (O(n) at once).
    #[must_use]
    pub fn friction_offsets(&self) -> Vec<usize> {
        let mut acc = 0;
        self.friction
            .iter()
            .map(|f| {
                let o = acc;
                acc += f.components;
                o
            })
            .collect()
    }
    /// Tangential restitution e_F of every friction component.
    #[must_use]
    pub fn friction_restitution(&self) -> Vec<f64> {
        self.friction
            .iter()
            .flat_map(|f| std::iter::repeat_n(f.e_f, f.components))
            .collect()
    }

    /// Checks sizes and coefficients.
    ///
    /// # Errors
    /// A message naming the first bad entry (negative or NaN μ, e_N outside \[0, 1\], a law
    /// with 0 or more than 2 components or without normal contacts, an index out of range).
    pub fn validate(&self) -> Result<(), String> {
        if self.nu == 0 || self.nq == 0 {
            return Err("a system needs nq > 0 and nu > 0".into());
        }
        for (k, e) in self.e_n.iter().enumerate() {
            if !(0.0..=1.0).contains(e) {
                return Err(format!("normal contact {k}: e_N = {e} is not in [0, 1]"));
            }
        }
        for (j, f) in self.friction.iter().enumerate() {
            if !(1..=2).contains(&f.components) {
                return Err(format!(
                    "friction law {j}: {} components (1 or 2 allowed)",
                    f.components
                ));
            }
            if !(f.mu >= 0.0 && f.mu.is_finite()) {
                return Err(format!(
                    "friction law {j}: mu = {} must be finite and >= 0",
                    f.mu
                ));
            }
            if !(0.0..=1.0).contains(&f.e_f) {
                return Err(format!(
                    "friction law {j}: e_F = {} is not in [0, 1]",
                    f.e_f
                ));
            }
            if f.normals.is_empty() || f.normals.iter().any(|&k| k >= self.n_normal()) {
                return Err(format!(
                    "friction law {j}: normal contacts {:?} invalid",
                    f.normals
                ));
            }
        }
        Ok(())
    }
}

/// A sparse matrix as (row, column, value) triplets; duplicates are summed.
#[derive(Debug, Clone)]
pub struct Triplets<T> {
    /// The entries.
    pub entries: Vec<(usize, usize, T)>,
}

impl<T> Default for Triplets<T> {
    fn default() -> Self {
        Self {
            entries: Vec::new(),
        }
    }
}

impl<T> Triplets<T> {
    /// Adds `value` at (`row`, `col`).
    #[inline]
    pub fn push(&mut self, row: usize, col: usize, value: T) {
        self.entries.push((row, col, value));
    }
    /// Removes all entries, keeping the allocation.
    pub fn clear(&mut self) {
        self.entries.clear();
    }
}

/// Everything a system reports at one (t, q, u); filled by [`System::evaluate`].
///
/// Vectors come zeroed and triplet lists empty. Conventions: W matrices have one row
/// per velocity u_i and one column per constraint.
#[derive(Debug, Clone, Default)]
pub struct Evaluation<T> {
    /// Mass matrix M(t,q), nu × nu.
    pub mass: Triplets<T>,
    /// Forces h(t,q,u) (applied and gyroscopic), nu.
    pub forces: Vec<T>,
    /// Position-level values p = (g, g_N)(t,q), ng + nN.
    pub position: Vec<T>,
    /// W_p(t,q), nu × (ng + nN): ṗ = W_pᵀ u + χ_p.
    pub position_w: Triplets<T>,
    /// χ_p(t,q): the part of ṗ not proportional to u (prescribed motion).
    pub position_chi: Vec<T>,
    /// ζ_p(t,q,u): the part of p̈ not proportional to a.
    pub position_zeta: Vec<T>,
    /// W_v(t,q), nu × (nγ + nF): v = W_vᵀ u + χ_v.
    pub velocity_w: Triplets<T>,
    /// χ_v(t,q).
    pub velocity_chi: Vec<T>,
    /// ζ_v(t,q,u): the part of v̇ not proportional to a.
    pub velocity_zeta: Vec<T>,
}

impl<T: Scalar> Evaluation<T> {
    /// An evaluation buffer sized for `layout`.
    #[must_use]
    pub fn new(layout: &Layout) -> Self {
        let z = |n: usize| vec![T::from(0.0); n];
        Self {
            mass: Triplets::default(),
            forces: z(layout.nu),
            position: z(layout.n_position()),
            position_w: Triplets::default(),
            position_chi: z(layout.n_position()),
            position_zeta: z(layout.n_position()),
            velocity_w: Triplets::default(),
            velocity_chi: z(layout.n_velocity()),
            velocity_zeta: z(layout.n_velocity()),
        }
    }

    /// Zeroes every vector and clears every triplet list.
    pub fn reset(&mut self) {
        let zero = T::from(0.0);
        self.mass.clear();
        self.position_w.clear();
        self.velocity_w.clear();
        for v in [
            &mut self.forces,
            &mut self.position,
            &mut self.position_chi,
            &mut self.position_zeta,
            &mut self.velocity_chi,
            &mut self.velocity_zeta,
        ] {
            v.iter_mut().for_each(|x| *x = zero);
        }
    }
}

/// The vectors the Newton Jacobian is linearised along (see [`Derivatives`]).
#[derive(Debug, Clone, Copy)]
pub struct Probes<'a> {
    /// The smooth acceleration a (for ∂p̈/∂q and ∂v̇/∂q: ∂(W_pᵀ a)/∂q).
    pub a: &'a [f64],
    /// The velocity u_n at the start of the step (for the restitution terms
    /// ∂(ṗ(q,u_n))/∂q).
    pub u_old: &'a [f64],
    /// Three (v, μ_p, μ_v) triples for ∂/∂q [M(q) v − W_p(q) μ_p − W_v(q) μ_v].
    pub dynamics: [(&'a [f64], &'a [f64], &'a [f64]); 3],
    /// Position-level constraints the stepper leaves out of this Newton matrix (pruned
    /// open contacts, `NewtonOptions::prune_open_contacts`); empty when none. Their multipliers
    /// in `dynamics` are zero, so a system may leave their rows out of every list.
    pub unused_position: &'a [bool],
    /// Velocity-level constraints left out likewise; empty when none.
    pub unused_velocity: &'a [bool],
}

impl Probes<'_> {
    /// Whether the stepper uses the rows of position-level constraint `i`.
    #[must_use]
    pub fn uses_position(&self, i: usize) -> bool {
        self.unused_position.get(i) != Some(&true)
    }
    /// Whether the stepper uses the rows of velocity-level constraint `i`.
    #[must_use]
    pub fn uses_velocity(&self, i: usize) -> bool {
        self.unused_velocity.get(i) != Some(&true)
    }
}

/// The exact derivatives the Newton iteration needs, all at one (t, q, u).
///
/// Every field is a triplet list; `*_q` have nq columns, `*_u` nu columns. The stepper
/// clears them before calling [`System::derivatives`].
#[derive(Debug, Clone, Default)]
pub struct Derivatives {
    /// ∂/∂q [M v_k − W_p μ_{p,k} − W_v μ_{v,k}] for the three probes k, each nu × nq.
    pub dynamics_q: [Triplets<f64>; 3],
    /// ∂h/∂q, nu × nq.
    pub forces_q: Triplets<f64>,
    /// ∂h/∂u, nu × nu.
    pub forces_u: Triplets<f64>,
    /// ∂p/∂q, np × nq.
    pub position_q: Triplets<f64>,
    /// ∂ṗ/∂q at the evaluation's u (index 0) and at `probes.u_old` (index 1).
    pub position_rate_q: [Triplets<f64>; 2],
    /// ∂p̈/∂q at `probes.a`, np × nq.
    pub position_accel_q: Triplets<f64>,
    /// ∂p̈/∂u = ∂ζ_p/∂u, np × nu.
    pub position_accel_u: Triplets<f64>,
    /// ∂v/∂q at the evaluation's u (index 0) and at `probes.u_old` (index 1).
    pub velocity_q: [Triplets<f64>; 2],
    /// ∂v̇/∂q at `probes.a`, nv × nq.
    pub velocity_accel_q: Triplets<f64>,
    /// ∂v̇/∂u = ∂ζ_v/∂u, nv × nu.
    pub velocity_accel_u: Triplets<f64>,
    scratch: Option<Box<AdScratch>>,
}

impl Derivatives {
    /// Clears every list.
    pub fn clear(&mut self) {
        let [d0, d1, d2] = &mut self.dynamics_q;
        let [r0, r1] = &mut self.position_rate_q;
        let [v0, v1] = &mut self.velocity_q;
        for t in [
            d0,
            d1,
            d2,
            &mut self.forces_q,
            &mut self.forces_u,
            &mut self.position_q,
            r0,
            r1,
            &mut self.position_accel_q,
            &mut self.position_accel_u,
            v0,
            v1,
            &mut self.velocity_accel_q,
            &mut self.velocity_accel_u,
        ] {
            t.clear();
        }
    }
}

#[derive(Debug, Clone)]
struct AdScratch {
    q: Vec<Dual64>,
    u: Vec<Dual64>,
    eval: Evaluation<Dual64>,
}

/// A mechanical system with frictional contacts; see the module docs.
///
/// Units are the system's own, used consistently (SI in the bundled systems): the
/// stepper never mixes them with constants of its own, except that its tolerances are
/// on impulses (force × time) and lengths; see [`Options::tol`](crate::Options::tol).
/// Signs: a gap is positive when open and negative when penetrating; the force
/// directions W point along the force the constraint's multiplier exerts for a
/// positive multiplier (a normal force pushes the gap open).
pub trait System {
    /// Sizes and contact data, fixed for the whole run (called once, when a stepper is
    /// built): nq, nu, the numbers of bilateral constraints, e_N per normal contact and
    /// the friction laws ([`Layout::validate`] checks it).
    fn layout(&self) -> Layout;

    /// Evaluates everything the stepper needs at (t, q, u) into `out`, whose vectors
    /// come zeroed and whose triplet lists come empty (shapes in [`Evaluation`]):
    ///
    /// - `mass`: M(t, q), nu × nu, symmetric positive definite;
    /// - `forces`: h(t, q, u), nu: applied and gyroscopic forces (gravity as −m g);
    /// - `position`: p = (g, g_N), ng + nN: bilateral constraints (0 when satisfied),
    ///   then the normal gaps (≥ 0 when open);
    /// - `position_w`: W_p, nu × (ng + nN) as (velocity index, constraint index, value),
    ///   so that ṗ = W_pᵀ u + χ_p; `position_chi`: χ_p (prescribed motion, else 0);
    ///   `position_zeta`: ζ_p with p̈ = W_pᵀ a + ζ_p;
    /// - `velocity_w`: W_v, nu × (nγ + nF): the bilateral velocity constraints γ and the
    ///   friction slips γ_F (components of each law in a row, laws in layout order), so
    ///   that v = W_vᵀ u + χ_v; `velocity_chi`: χ_v; `velocity_zeta`: ζ_v with
    ///   v̇ = W_vᵀ a + ζ_v.
    ///
    /// Written generically over [`Scalar`] so that the default
    /// [`System::derivatives`] can differentiate it exactly. W and χ must not depend on
    /// u. `t` is the integrator's own time t_k = t0 + kΔt (ERRATA 20).
    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>);

    /// [`System::evaluate`] at a real state: what the stepper calls for every Newton
    /// iterate. Default: `evaluate::<f64>`. A system may override it to keep between
    /// calls the buffers that an evaluation generic over the scalar cannot keep (the
    /// block stack's contact lists); it must fill `out` exactly as `evaluate` does.
    fn evaluate_real(&self, t: f64, q: &[f64], u: &[f64], out: &mut Evaluation<f64>) {
        self.evaluate(t, q, u, out);
    }

    /// Whether the system's equations no longer depend on time from `t` on (no
    /// prescribed motion or force changes any more): then a step that leaves the state
    /// at rest leaves it at rest for good, and the stepper holds it there without
    /// solving ([`PolicyOptions::rest`](crate::PolicyOptions::rest)). Default: never.
    fn autonomous_from(&self, _t: f64) -> bool {
        false
    }

    /// A friction coefficient below which no contact of the system can have App. I's
    /// b ≤ 0 (a normal acceleration that decreases with the contact's own normal force,
    /// friction counted): the check of
    /// [`PolicyOptions::probe_painleve`](crate::PolicyOptions::probe_painleve) skips the
    /// friction laws below it. Default 0: every sliding law is checked.
    fn least_painleve_friction(&self) -> f64 {
        0.0
    }

    /// The kinematic matrix B(t,q) (nq × nu, as (coordinate, velocity, value) triplets)
    /// of q̇ = B u. Default: the identity (q̇ = u).
    fn kinematics(&self, _t: f64, q: &[f64], b: &mut Triplets<f64>) {
        for i in 0..q.len() {
            b.push(i, i, 1.0);
        }
    }

    /// Ḃ(t,q,u) u (nq), the velocity-dependent part of q̈ = B a + Ḃ u, added to `out`
    /// (which comes zeroed). Default: zero.
    fn kinematics_rate(&self, _t: f64, _q: &[f64], _u: &[f64], _out: &mut [f64]) {}

    /// The exact derivatives of [`System::evaluate`] the Newton iteration needs.
    ///
    /// The default differentiates `evaluate` by forward-mode automatic differentiation
    /// (one dual-number pass per coordinate and per velocity): exact, and cheap for
    /// small systems. Override it for large systems, filling the same lists from the
    /// system's sparse structure (each contact depends on a few coordinates).
    fn derivatives(&self, t: f64, q: &[f64], u: &[f64], probes: &Probes<'_>, out: &mut Derivatives)
    where
        Self: Sized,
    {
        forward_derivatives(self, t, q, u, probes, out);
    }

    /// Which continuation to follow at a branch point: a step from time `t` with several
    /// self-consistent, distinct solutions (docs/method.md §8). `candidates` holds each
    /// with the index sets it was solved with, in the order the fixed-set re-solves found
    /// them; return an index into it (an index past the end counts as the last).
    ///
    /// This is the one decision of the fallback policy that belongs to the system, not
    /// to the method (for example: prefer the continuation that keeps a contact closed,
    /// or the one of least energy). The policy itself (when to re-solve, which sets,
    /// self-consistency, deduplication) stays in the stepper. Default: the first.
    fn choose_branch(&self, _t: f64, _candidates: &[(IndexSets, State)]) -> usize {
        0
    }
}

/// Exact derivatives of [`System::evaluate`] by forward-mode automatic differentiation:
/// one `Dual64` pass per coordinate q_j (seeding q_j) and per velocity u_j. This is the
/// default of [`System::derivatives`]; cost (nq + nu) evaluations.
pub fn forward_derivatives<S: System>(
    system: &S,
    t: f64,
    q: &[f64],
    u: &[f64],
    probes: &Probes<'_>,
    out: &mut Derivatives,
) {
    let mut scratch = out.scratch.take().unwrap_or_else(|| {
        let layout = system.layout();
        Box::new(AdScratch {
            q: Vec::new(),
            u: Vec::new(),
            eval: Evaluation::new(&layout),
        })
    });
    let s = &mut *scratch;
    s.q.clear();
    s.q.extend(q.iter().map(|&x| Dual64::from_re(x)));
    s.u.clear();
    s.u.extend(u.iter().map(|&x| Dual64::from_re(x)));
    // Passes over q: every q-derivative at once.
    for j in 0..q.len() {
        s.q[j].eps = 1.0;
        s.eval.reset();
        system.evaluate(t, &s.q, &s.u, &mut s.eval);
        s.q[j].eps = 0.0;
        let e = &s.eval;
        for &(r, c, m) in &e.mass.entries {
            if m.eps != 0.0 {
                for (k, (v, _, _)) in probes.dynamics.iter().enumerate() {
                    out.dynamics_q[k].push(r, j, m.eps * v[c]);
                }
            }
        }
        for &(r, c, w) in &e.position_w.entries {
            if w.eps != 0.0 {
                for (k, (_, mp, _)) in probes.dynamics.iter().enumerate() {
                    out.dynamics_q[k].push(r, j, -w.eps * mp[c]);
                }
                out.position_rate_q[0].push(c, j, w.eps * u[r]);
                out.position_rate_q[1].push(c, j, w.eps * probes.u_old[r]);
                out.position_accel_q.push(c, j, w.eps * probes.a[r]);
            }
        }
        for &(r, c, w) in &e.velocity_w.entries {
            if w.eps != 0.0 {
                for (k, (_, _, mv)) in probes.dynamics.iter().enumerate() {
                    out.dynamics_q[k].push(r, j, -w.eps * mv[c]);
                }
                out.velocity_q[0].push(c, j, w.eps * u[r]);
                out.velocity_q[1].push(c, j, w.eps * probes.u_old[r]);
                out.velocity_accel_q.push(c, j, w.eps * probes.a[r]);
            }
        }
        push_column(&mut out.forces_q, &e.forces, j);
        push_column(&mut out.position_q, &e.position, j);
        push_column(&mut out.position_rate_q[0], &e.position_chi, j);
        push_column(&mut out.position_rate_q[1], &e.position_chi, j);
        push_column(&mut out.position_accel_q, &e.position_zeta, j);
        push_column(&mut out.velocity_q[0], &e.velocity_chi, j);
        push_column(&mut out.velocity_q[1], &e.velocity_chi, j);
        push_column(&mut out.velocity_accel_q, &e.velocity_zeta, j);
    }
    // Passes over u: h and the curvature terms ζ are the only u-dependent parts.
    for j in 0..u.len() {
        s.u[j].eps = 1.0;
        s.eval.reset();
        system.evaluate(t, &s.q, &s.u, &mut s.eval);
        s.u[j].eps = 0.0;
        push_column(&mut out.forces_u, &s.eval.forces, j);
        push_column(&mut out.position_accel_u, &s.eval.position_zeta, j);
        push_column(&mut out.velocity_accel_u, &s.eval.velocity_zeta, j);
    }
    out.scratch = Some(scratch);
}

fn push_column(out: &mut Triplets<f64>, values: &[Dual64], col: usize) {
    for (r, v) in values.iter().enumerate() {
        if v.eps != 0.0 {
            out.push(r, col, v.eps);
        }
    }
}
