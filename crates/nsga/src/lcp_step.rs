//! One Moreau–Jean step whose contact problem is a linear complementarity problem solved
//! by Lemke's method ([`crate::lcp`]), which terminates (docs/method.md §6 and §8.2). It
//! serves the generalized-α stepper's last resort ([`crate::fallback`]) and the
//! Moreau–Jean baseline when its Newton iteration does not converge. It takes every
//! contact law nsga offers: disk friction through a polygon, approximately
//! ([`crate::friction_polygon`]), everything else exactly.
//!
//! The velocity-level problem, in the form of Anitescu and Potra (1997): with
//! ũ = u_n + Δt M⁻¹h at the midpoint q_M,
//!
//! u⁺ = ũ + M⁻¹(W_B P_B + W_N P_N + W_F Σᵢ βᵢ dᵢ),
//! W_Bᵀu⁺ + χ_B = 0 (the bilateral constraints' rates g and γ, P_B free),
//! 0 ≤ P_N ⟂ ξ_N = W_Nᵀu⁺ + χ_N + e_N ġ_N(u_n) ≥ 0,
//! 0 ≤ βᵢ ⟂ λ + dᵢᵀξ_F ≥ 0,  0 ≤ λ ⟂ μ Σ P_N − Σᵢ βᵢ ≥ 0,
//!
//! with ξ_F = W_Fᵀu⁺ + χ_F + e_F γ_F(u_n) and the directions dᵢ of each friction law (±1
//! for a planar law: Coulomb's law exactly, λ the slip speed). The bilateral block is
//! eliminated first ([`crate::constrained_mass`]). Which contacts take part is the
//! [`Activation`]. Then q_{n+1} = q_M + ½Δt B u⁺, and, if asked, the positions are
//! projected back: the least M-norm displacement that closes the bilateral position
//! constraints g(q) = 0 and the gaps that end below zero, itself an LCP with an
//! equality block, 0 ≤ δ ⟂ g_N + W_Nᵀ du ≥ 0, g + W_gᵀ du = 0, du = M⁻¹(W_g z + W_N δ).

use crate::constrained_mass::{ConstrainedInverse, InverseMass};
use crate::coulomb_lcp::{ContactMatrices, CoulombLcp, SparseColumns};
use crate::lcp::{lemke, LcpFailure};
use crate::linalg::max_norm;
use crate::moreau::advance;
use crate::system::{Evaluation, Layout, System};
use nalgebra::DVector;

/// Largest complementarity residual (relative to 1 + ‖rhs‖∞, a speed) accepted from a
/// regularized solve of the step's contact problem (`nsga::lcp::lemke_regularized`): an
/// approach speed of that size moves a gap by Δt times as much in the step, and the
/// position projection removes it.
const ACCEPT: f64 = 1e-8;

/// Largest penetration left by the position projection (length units).
///
/// Why 10⁻¹²: the interpenetration rollstack promises for every step, last resort
/// included (soft-contact engines leave 10⁻³–10⁻²): a step that the last resort takes
/// must not be the one that breaks it. It is far above round-off of the positions of
/// bodies of unit size (10⁻¹⁶), so the projection's own arithmetic meets it.
const PROJECTION_TOL: f64 = 1e-12;

/// Which contacts take part in the step's contact problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Activation {
    /// Those closed at q_M (g_N ≤ 0), with the friction laws of a closed contact: the
    /// Moreau–Jean scheme of §6.
    ClosedAtMidpoint,
    /// Every contact (posed first over those within reach of the step, see [`lcp_step`]);
    /// one still open at q_M has ξ_N = W_Nᵀu⁺ + χ_N + g_N/(½Δt), so that it is pushed
    /// only if its gap would close by the end of the step (with e_N > 0 and a gap that
    /// the free motion closes, Newton's restitution instead, bounded by that term). (With the contacts
    /// closed at q_M only, a column resting on gaps of 1e-9 sinks by ½Δt‖u‖ in a step.)
    GapAware,
}

/// The outcome of one step.
#[derive(Debug, Clone)]
pub(crate) struct LcpStep {
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    pub p_n: Vec<f64>,
    pub p_f: Vec<f64>,
    pub pivots: usize,
    pub residual: f64,
    /// Largest coordinate change of the projection (0: none needed or asked).
    pub projection: f64,
}

/// The bilateral constraints of an evaluation eliminated from M⁻¹ (position
/// constraints 0..ng of W_p, velocity constraints 0..nγ of W_v where `velocity`).
///
/// # Errors
/// The first redundant constraint, by its kind and index.
fn eliminated<'a>(
    l: &Layout,
    d: &'a ContactMatrices,
    velocity: bool,
) -> Result<ConstrainedInverse<'a>, String> {
    let (ng, nga) = (
        l.n_bilateral_position,
        if velocity { l.n_bilateral_velocity } else { 0 },
    );
    let columns = (0..ng)
        .map(|i| d.w_p.dense(i))
        .chain((0..nga).map(|i| d.w_v.dense(i)))
        .collect();
    ConstrainedInverse::new(&d.m_inv, columns, |i| {
        if i < ng {
            format!("bilateral position constraint {i}")
        } else {
            format!("bilateral velocity constraint {}", i - ng)
        }
    })
}

/// Why the step cannot take the system at (t, q, u), if it cannot: its bilateral
/// constraints are redundant there. (A singular M is left to the step, which reports
/// it.)
pub(crate) fn refusal<S: System>(
    system: &S,
    l: &Layout,
    t: f64,
    (q, u): (&[f64], &[f64]),
) -> Option<String> {
    if l.n_bilateral_position + l.n_bilateral_velocity == 0 {
        return None;
    }
    let mut eval = Evaluation::new(l);
    system.evaluate(t, q, u, &mut eval);
    let d = ContactMatrices::of(&eval, l.nu, l.n_bilateral_position, l.n_bilateral_velocity)?;
    eliminated(l, &d, true).err()
}

/// The free acceleration M⁻¹h at (t, q, u), zero if M is singular.
pub(crate) fn free_acceleration<S: System>(
    system: &S,
    l: &Layout,
    t: f64,
    q: &[f64],
    u: &[f64],
) -> Vec<f64> {
    let mut eval = Evaluation::new(l);
    system.evaluate(t, q, u, &mut eval);
    ContactMatrices::of(&eval, l.nu, 0, 0).map_or_else(
        || vec![0.0; l.nu],
        |d| d.m_inv.apply(&eval.forces).iter().copied().collect(),
    )
}

/// One step from (t, q, u) to t + `dt` (`t1`, on the caller's grid).
///
/// With [`Activation::GapAware`], the contact problem is first solved over the contacts
/// within reach of the step ([`ContactProblem::within_reach`]); a contact left out is
/// then checked at the solution's u⁺, and the problem is solved again with those that
/// would end below zero. The set only grows, so this ends, and its solution solves the
/// problem over every contact: a contact left out has P_N = 0 with ξ_N ≥ 0, and its
/// friction laws no normal percussion. A 300-block column on a base has 600 contacts
/// between blocks and 1200 floor contacts metres away, which made Lemke's dense tableau
/// 9 times larger than needed.
pub(crate) fn lcp_step<S: System>(
    system: &S,
    l: &Layout,
    (t, t1): (f64, f64),
    (q, u): (&[f64], &[f64]),
    dt: f64,
    activation: Activation,
    project: bool,
) -> Result<LcpStep, String> {
    let (nu, ng, nn, nf) = (l.nu, l.n_bilateral_position, l.n_normal(), l.n_friction());
    let q_m = advance(system, t, q, u, 0.5 * dt);
    let t_m = t + 0.5 * dt;
    let mut eval = Evaluation::new(l);
    system.evaluate(t_m, &q_m, u, &mut eval);
    let d = ContactMatrices::of(&eval, nu, l.n_position(), l.n_velocity())
        .ok_or("the mass matrix is singular")?;
    let inertia = eliminated(l, &d, true)?;
    let problem = ContactProblem::new(l, &eval, &d, &inertia, u, dt);
    let (closed, solved) = match activation {
        Activation::GapAware => problem.solve_growing(problem.within_reach())?,
        Activation::ClosedAtMidpoint => {
            let closed: Vec<usize> = (0..nn).filter(|&k| eval.position[ng + k] <= 0.0).collect();
            let solved = problem.solve(&closed)?;
            (closed, solved)
        }
    };
    let mut p_n = vec![0.0; nn];
    let mut p_f = vec![0.0; nf];
    for (&k, &p) in closed.iter().zip(&solved.p_n) {
        p_n[k] = p;
    }
    for &(j, p) in &solved.p_f {
        p_f[j] = p;
    }
    let u1: Vec<f64> = solved.u1.iter().copied().collect();
    let mut q1 = advance(system, t_m, &q_m, &u1, 0.5 * dt);
    let projection = if project {
        project_positions(system, l, t1, &mut q1, &u1)
    } else {
        0.0
    };
    if q1.iter().chain(&u1).any(|x| !x.is_finite()) {
        return Err("the LCP step gave a non-finite state".into());
    }
    Ok(LcpStep {
        q: q1,
        u: u1,
        p_n,
        p_f,
        pivots: solved.pivots,
        residual: solved.residual,
        projection,
    })
}

/// The step's contact problem at q_M, to be solved over a set of its contacts, with the
/// bilateral constraints eliminated.
struct ContactProblem<'a> {
    l: &'a Layout,
    eval: &'a Evaluation<f64>,
    d: &'a ContactMatrices,
    /// M̃⁻¹: M⁻¹ on the motions the bilateral constraints allow.
    inertia: &'a ConstrainedInverse<'a>,
    dt: f64,
    u_n: DVector<f64>,
    /// Π(ũ), ũ = u_n + Δt M⁻¹h: the free motion with the bilateral constraints kept.
    u_free: DVector<f64>,
    /// Per contact, what its normal row adds to ξ_N(u): Newton's restitution e_N ξ_N(u_n)
    /// of a closed gap or of an open one with e_N > 0 that the free motion closes within
    /// the step, the gap-aware term g/(½Δt) of any other open one.
    closing_term: Vec<f64>,
    /// The first component of each friction law among γ_F.
    offsets: Vec<usize>,
}

/// The solution of [`ContactProblem::solve`].
struct ContactSolution {
    u1: DVector<f64>,
    /// P_N of the contacts solved over, in their order.
    p_n: Vec<f64>,
    /// (friction component, its percussion) of the active laws.
    p_f: Vec<(usize, f64)>,
    pivots: usize,
    residual: f64,
    /// The complementarity residual accepted (a speed).
    accept: f64,
    /// Lemke solves taken ([`ContactProblem::solve_growing`] may take several).
    solves: usize,
}

impl<'a> ContactProblem<'a> {
    /// The problem of a step of `dt` from the velocities `u`, with M, W and the gaps of
    /// `eval` (at q_M) and the bilateral constraints eliminated by `inertia`.
    fn new(
        l: &'a Layout,
        eval: &'a Evaluation<f64>,
        d: &'a ContactMatrices,
        inertia: &'a ConstrainedInverse<'a>,
        u: &[f64],
        dt: f64,
    ) -> Self {
        let (ng, nga) = (l.n_bilateral_position, l.n_bilateral_velocity);
        let u_n = DVector::from_column_slice(u);
        let kick = DVector::from_iterator(l.nu, eval.forces.iter().map(|h| h * dt));
        let u_tilde = &u_n + d.m_inv.apply(kick.as_slice());
        let chi_b: Vec<f64> = eval.position_chi[..ng]
            .iter()
            .chain(&eval.velocity_chi[..nga])
            .copied()
            .collect();
        let mut problem = Self {
            l,
            eval,
            d,
            inertia,
            dt,
            u_free: inertia.project(&u_tilde, &chi_b),
            u_n,
            closing_term: Vec::new(),
            offsets: l.friction_offsets(),
        };
        let closing_term = (0..l.n_normal())
            .map(|k| {
                let (g, e_n) = (eval.position[ng + k], l.e_n[k]);
                let restitution = e_n * problem.xi_n(k, &problem.u_n);
                if g <= 0.0 {
                    restitution
                } else if e_n > 0.0 && g + 0.5 * dt * problem.xi_n(k, &problem.u_free) < 0.0 {
                    // The free motion strikes the contact within the step: Newton's law
                    // on the approach speed, the mass leaving at most ½Δt‖u‖ early (with
                    // the gap-aware term alone it would land plastically, its e_N lost),
                    // and never below the gap-aware bound.
                    restitution.min(g / (0.5 * dt))
                } else {
                    g / (0.5 * dt)
                }
            })
            .collect();
        problem.closing_term = closing_term;
        problem
    }

    /// ġ_N of contact k at u.
    fn xi_n(&self, k: usize, u: &DVector<f64>) -> f64 {
        let c = self.l.n_bilateral_position + k;
        self.d.w_p.dot(c, u.as_slice()) + self.eval.position_chi[c]
    }

    /// γ_F of friction component j at u.
    fn xi_f(&self, j: usize, u: &DVector<f64>) -> f64 {
        let c = self.l.n_bilateral_velocity + j;
        self.d.w_v.dot(c, u.as_slice()) + self.eval.velocity_chi[c]
    }

    /// The normal row of contact k at u: ξ_N with Newton's restitution of a closed gap,
    /// or with the gap-aware term g/(½Δt) of an open one.
    fn rate(&self, k: usize, u: &DVector<f64>) -> f64 {
        self.xi_n(k, u) + self.closing_term[k]
    }

    /// The contacts within reach of the step: a closed gap, one the free motion closes
    /// within the step, or one that the fastest free approach in the system would close
    /// in two steps. (Gaps of 1e-15 between blocks resting on each other have rates of
    /// nearly zero: taking the rates alone, the contacts of a kicked column were added
    /// one interface per solve.)
    fn within_reach(&self) -> Vec<usize> {
        let (ng, nn) = (self.l.n_bilateral_position, self.l.n_normal());
        let fastest = (0..nn)
            .map(|k| self.xi_n(k, &self.u_free).abs())
            .fold(0.0, f64::max);
        let reach = 2.0 * self.dt * fastest;
        (0..nn)
            .filter(|&k| self.eval.position[ng + k] <= reach || self.rate(k, &self.u_free) <= 0.0)
            .collect()
    }

    /// Solves over `closed` (sorted), then again with the contacts left out that would
    /// end below zero at the solution's u⁺, until none would. Returns the contacts
    /// solved over and the solution, its pivots and solves summed over the solves.
    fn solve_growing(
        &self,
        mut closed: Vec<usize>,
    ) -> Result<(Vec<usize>, ContactSolution), String> {
        let (mut pivots, mut solves) = (0, 0);
        loop {
            let mut solved = self.solve(&closed)?;
            pivots += solved.pivots;
            solves += 1;
            let missing: Vec<usize> = (0..self.l.n_normal())
                .filter(|k| closed.binary_search(k).is_err())
                .filter(|&k| self.rate(k, &solved.u1) < -solved.accept)
                .collect();
            if missing.is_empty() {
                solved.pivots = pivots;
                solved.solves = solves;
                return Ok((closed, solved));
            }
            closed.extend(missing);
            closed.sort_unstable();
        }
    }

    /// The friction components of the laws `active`, with their laws' e_F.
    fn components<'b>(&'b self, active: &'b [usize]) -> impl Iterator<Item = (usize, f64)> + 'b {
        active.iter().flat_map(move |&j| {
            let law = &self.l.friction[j];
            (0..law.components).map(move |m| (self.offsets[j] + m, law.e_f))
        })
    }

    /// Solves the LCP of the module docs over the contacts `closed` (sorted) and the
    /// friction laws of a contact among them, by Lemke's method.
    fn solve(&self, closed: &[usize]) -> Result<ContactSolution, String> {
        let (l, d) = (self.l, self.d);
        let active: Vec<usize> = (0..l.friction.len())
            .filter(|&j| {
                l.friction[j]
                    .normals
                    .iter()
                    .any(|k| closed.binary_search(k).is_ok())
            })
            .collect();
        // The percussions act along the rows' own W columns.
        let rows = CoulombLcp::rows_of(l, d, closed, &active);
        let free = closed
            .iter()
            .map(|&k| self.rate(k, &self.u_free))
            .chain(
                self.components(&active)
                    .map(|(j, e_f)| self.xi_f(j, &self.u_free) + e_f * self.xi_f(j, &self.u_n)),
            )
            .collect::<Vec<_>>();
        let bounds = CoulombLcp::bounds_of(l, closed, &active);
        let accept = ACCEPT * (1.0 + max_norm(&free));
        let problem = CoulombLcp {
            forces: rows.clone(),
            rows,
            normals: closed.len(),
            bounds,
            free,
        };
        let sol = problem.solve(self.inertia, accept).map_err(|e| match e {
            LcpFailure::Ray { .. } => format!(
                "the step's contact problem has no solution: {e} (a Painlevé-type inconsistency)"
            ),
            e => e.to_string(),
        })?;
        Ok(ContactSolution {
            u1: &self.u_free + sol.change,
            p_n: sol.normal,
            p_f: self
                .components(&active)
                .map(|(j, _)| j)
                .zip(sol.friction)
                .collect(),
            pivots: sol.pivots,
            residual: sol.residual,
            accept,
            solves: 1,
        })
    }
}

/// Moves `q` by the least M-norm displacement that closes the bilateral position
/// constraints and every negative gap (to round-off, five linearizations at most);
/// returns the size of the displacement in the coordinates (∞-norm).
fn project_positions<S: System>(
    system: &S,
    l: &Layout,
    t: f64,
    q: &mut Vec<f64>,
    u: &[f64],
) -> f64 {
    let (nu, ng, nn) = (l.nu, l.n_bilateral_position, l.n_normal());
    let mut moved = 0.0_f64;
    for _ in 0..5 {
        let mut eval = Evaluation::new(l);
        system.evaluate(t, q, u, &mut eval);
        let (g, gaps) = eval.position[..ng + nn].split_at(ng);
        if g.iter().all(|x| x.abs() <= PROJECTION_TOL) && gaps.iter().all(|&x| x >= -PROJECTION_TOL)
        {
            break;
        }
        let Some(d) = ContactMatrices::of(&eval, nu, ng + nn, 0) else {
            break;
        };
        let Ok(inertia) = eliminated(l, &d, false) else {
            break;
        };
        let Some(du) = displacement(&inertia, &d.w_p, g, gaps) else {
            break;
        };
        let before = q.clone();
        *q = advance(system, t, q, du.as_slice(), 1.0);
        moved = q
            .iter()
            .zip(&before)
            .map(|(a, b)| (a - b).abs())
            .fold(moved, f64::max);
    }
    moved
}

/// The least M-norm displacement after which the linearized bilateral constraints `g`
/// are zero and the linearized `gaps` nonnegative (None: Lemke's method failed): the
/// part Π(0) = −M⁻¹W_g G⁻¹g that closes g, then the closing displacement of the gaps
/// it leaves, with M̃⁻¹ (`inertia`). `w` holds W_g, then W_N.
fn displacement(
    inertia: &ConstrainedInverse,
    w: &SparseColumns,
    g: &[f64],
    gaps: &[f64],
) -> Option<DVector<f64>> {
    if g.is_empty() {
        return closing_displacement(inertia, w, 0, gaps);
    }
    let ng = g.len();
    let closing_g = inertia.project(&DVector::zeros(inertia.dim()), g);
    let left: Vec<f64> = (0..gaps.len())
        .map(|k| gaps[k] + w.dot(ng + k, closing_g.as_slice()))
        .collect();
    Some(closing_g + closing_displacement(inertia, w, ng, &left)?)
}

/// The least M-norm displacement du = M⁻¹ W_N z, z ≥ 0, after which the linearized gaps
/// g + W_Nᵀ du are nonnegative, complementary to z (None: Lemke's method failed); contact
/// k's column is `first` + k of `w`.
///
/// Closing one gap must not open another below zero, so the problem is over every
/// contact; but one that no displacement reaches keeps z = 0. It is solved over the
/// gaps below −[`PROJECTION_TOL`] first, then again with the contacts the displacement
/// pushes below that, until none: a contact left out has z = 0 and its gap stays above
/// the tolerance that [`project_positions`] accepts, as [`ContactProblem::solve_growing`]
/// does for the step. Posed over all 6000 contacts of a 1000-block column on a floor at
/// once, with dense products, it was still running after 9 minutes.
fn closing_displacement(
    inertia: &impl InverseMass,
    w: &SparseColumns,
    first: usize,
    gaps: &[f64],
) -> Option<DVector<f64>> {
    let mut set: Vec<usize> = (0..gaps.len())
        .filter(|&k| gaps[k] < -PROJECTION_TOL)
        .collect();
    loop {
        let du = displacement_over(inertia, w, first, gaps, &set)?;
        let missing: Vec<usize> = (0..gaps.len())
            .filter(|k| set.binary_search(k).is_err())
            .filter(|&k| gaps[k] + w.dot(first + k, du.as_slice()) < -PROJECTION_TOL)
            .collect();
        if missing.is_empty() {
            return Some(du);
        }
        set.extend(missing);
        set.sort_unstable();
    }
}

/// The displacement of [`closing_displacement`] with the contacts `set` alone taking
/// part: 0 ≤ z ⟂ g_S + W_Sᵀ M⁻¹ W_S z ≥ 0, du = M⁻¹ W_S z (None: Lemke's method failed).
fn displacement_over(
    inertia: &impl InverseMass,
    w: &SparseColumns,
    first: usize,
    gaps: &[f64],
    set: &[usize],
) -> Option<DVector<f64>> {
    let n = set.len();
    let g_cols: Vec<DVector<f64>> = set
        .iter()
        .map(|&k| inertia.apply(w.dense(first + k).as_slice()))
        .collect();
    let mut m = vec![0.0; n * n];
    for (r, &k) in set.iter().enumerate() {
        for (c, g_c) in g_cols.iter().enumerate() {
            m[r * n + c] = w.dot(first + k, g_c.as_slice());
        }
    }
    let q: Vec<f64> = set.iter().map(|&k| gaps[k]).collect();
    let sol = lemke(&m, &q, 50 * n + 50).ok()?;
    let mut du = DVector::zeros(inertia.dim());
    for (g_c, delta) in g_cols.iter().zip(&sol.z) {
        du.axpy(*delta, g_c, 1.0);
    }
    Some(du)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::chain::Chain;

    /// A 30-block chain falling onto the ground, its interfaces open by k·10⁻¹⁴ (as
    /// blocks resting on each other are, to round-off) and its top block 1 m up.
    fn hovering_chain() -> (Chain, Layout, Evaluation<f64>, Vec<f64>) {
        let chain = Chain::benchmark(30);
        let l = chain.layout();
        let (mut q, u) = chain.resting(0.0);
        for k in 0..chain.n {
            q[2 * k + 1] += k as f64 * 1e-14;
        }
        q[2 * chain.n - 1] += 1.0;
        let mut eval = Evaluation::new(&l);
        chain.evaluate(0.0, &q, &u, &mut eval);
        (chain, l, eval, u)
    }

    #[test]
    fn the_contacts_within_reach_solve_the_step_at_once() {
        let (chain, l, eval, u) = hovering_chain();
        let d = ContactMatrices::of(&eval, l.nu, l.n_normal(), l.n_friction()).expect("M regular");
        let inertia = eliminated(&l, &d, true).expect("no bilateral constraints");
        let problem = ContactProblem::new(&l, &eval, &d, &inertia, &u, 1e-3);
        let reach = problem.within_reach();
        // Every interface but the top one, 1 m up.
        assert_eq!(reach, (0..chain.n - 1).collect::<Vec<_>>());
        let (closed, at_once) = problem.solve_growing(reach).expect("solved");
        assert_eq!((closed.len(), at_once.solves), (chain.n - 1, 1));
        // From the ground contact alone (the only one the free motion closes), the
        // contacts join one interface per solve, to the same solution.
        let (_, grown) = problem.solve_growing(vec![0]).expect("solved");
        assert_eq!(grown.solves, chain.n - 1);
        let every: Vec<usize> = (0..l.n_normal()).collect();
        let full = problem.solve(&every).expect("solved");
        for (a, b) in [(&at_once.u1, &full.u1), (&grown.u1, &full.u1)] {
            assert!((a - b).amax() < 1e-12, "{}", (a - b).amax());
        }
        // The chain below the top block stops (up to closing its gaps of 1e-14 in ½Δt),
        // where the free fall is 9.81·10⁻³ m/s: no block falls through another.
        assert!(at_once
            .u1
            .iter()
            .take(2 * (chain.n - 1))
            .all(|v| v.abs() < 1e-8));
        assert!(at_once.u1[2 * chain.n - 1] < -9e-3);
    }

    /// A resting 5-block chain whose second block has sunk 10⁻⁶ into the first: closing
    /// that gap alone would push the first block into the ground, so the projection's
    /// problem must grow by the ground contact; it then lifts the second block only.
    #[test]
    fn the_closing_displacement_grows_to_the_contacts_it_would_open() {
        let chain = Chain::benchmark(5);
        let l = chain.layout();
        let (mut q, u) = chain.resting(0.0);
        q[3] -= 1e-6;
        let mut eval = Evaluation::new(&l);
        chain.evaluate(0.0, &q, &u, &mut eval);
        let nn = l.n_normal();
        let gaps = &eval.position[..nn];
        let d = ContactMatrices::of(&eval, l.nu, nn, 0).expect("M regular");
        let du = closing_displacement(&d.m_inv, &d.w_p, 0, gaps).expect("solved");
        for (k, g) in gaps.iter().enumerate() {
            let after = g + d.w_p.dot(k, du.as_slice());
            assert!(after >= -PROJECTION_TOL, "gap {k}: {after}");
        }
        // The same displacement as the problem over every contact at once.
        let every: Vec<usize> = (0..nn).collect();
        let full = displacement_over(&d.m_inv, &d.w_p, 0, gaps, &every).expect("solved");
        assert!((&du - &full).amax() < 1e-15, "{}", (&du - &full).amax());
        // Block 1 (y at index 3) rises by the depth; block 0 stays on the ground.
        assert!((du[3] - 1e-6).abs() < 1e-15 && du[1].abs() < 1e-15, "{du}");
    }
}
