//! Consistent initial accelerations and forces at t0 (docs/method.md §5).

use crate::coulomb_lcp::{ContactMatrices, CoulombLcp};
use crate::error::StepError;
use crate::lcp::LcpFailure;
use crate::level::{by_constraint, LevelProblem, LevelRows, OpeningLimit};
use crate::linalg::{max_norm, norm, AutoSolver, LinearSolver};
use crate::newton::{self, GiveUp, NewtonProblem, NewtonScratch, NewtonSettings, Outcome};
use crate::options::Options;
use crate::prox::prox_parameters;
use crate::system::{Evaluation, Layout, System};
use nalgebra::DVector;

/// Complementarity residual accepted from Lemke's solution of the start's contact
/// problem, relative to 1 + its largest free row (an acceleration): Newton polishes the
/// solution to the start's own tolerance from there.
const LCP_ACCEPT: f64 = 1e-10;

/// Largest start problem (unknowns of its LCP: one per closed contact, three per
/// sticking friction law) handed to Lemke's method when Newton fails. Its dense tableau
/// costs O(n²) per pivot and about n pivots: the 20-block column's 105 unknowns take
/// milliseconds, while a 300-block column's 2400 took 14 s.
const LCP_START_UP_TO: usize = 600;

/// Accelerations and forces at t0 that satisfy the contact laws on acceleration level.
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// a_0.
    pub a: Vec<f64>,
    /// λ_g of the bilateral position constraints.
    pub lambda_g: Vec<f64>,
    /// λ_γ of the bilateral velocity constraints.
    pub lambda_gamma: Vec<f64>,
    /// λ_N.
    pub lambda_n: Vec<f64>,
    /// λ_F.
    pub lambda_f: Vec<f64>,
    /// Newton updates the start took (both solves where Lemke's method ran between
    /// them); 0 where the start failed and the free accelerations stand in for it.
    pub updates: usize,
}

impl Start {
    /// The free accelerations M⁻¹h at (t, q, u) and no forces: what the generalized-α
    /// state carries where the consistent start failed, until a last-resort step (which
    /// needs no accelerations) has moved the state on.
    pub(crate) fn unforced<S: System>(
        system: &S,
        layout: &Layout,
        t: f64,
        q: &[f64],
        u: &[f64],
    ) -> Self {
        Self {
            a: crate::lcp_step::free_acceleration(system, layout, t, q, u),
            lambda_g: vec![0.0; layout.n_bilateral_position],
            lambda_gamma: vec![0.0; layout.n_bilateral_velocity],
            lambda_n: vec![0.0; layout.n_normal()],
            lambda_f: vec![0.0; layout.n_friction()],
            updates: 0,
        }
    }
}

/// The acceleration-level problem at t0 on the Newton engine: unknowns
/// y = (a, λ_g, λ_N, λ_γ, λ_F).
struct StartProblem<'a> {
    level: LevelProblem<'a>,
    rows: LevelRows,
    acc_p: Vec<f64>,
    acc_v: Vec<f64>,
    solver: AutoSolver,
    regularization: f64,
    /// Per normal contact: on its contact row at the last iterate.
    was_contact: Vec<bool>,
    /// Per friction law: on its stick rows at the last iterate.
    was_stick: Vec<bool>,
    /// ‖h‖∞, with the largest force of an iterate the scale of its residual.
    force_scale: f64,
}

impl StartProblem<'_> {
    /// Records which contacts and friction laws the last iterate put on their contact
    /// and stick rows, for the next one's [`OpeningLimit`].
    fn remember_sets(&mut self) {
        let l = self.level.layout;
        let (normal_row, friction_row) = (l.nu + l.n_bilateral_position, l.nu + l.n_position());
        let offsets = l.friction_offsets();
        self.was_contact.clear();
        self.was_contact.resize(l.n_normal(), false);
        self.was_stick.clear();
        self.was_stick.resize(l.friction.len(), false);
        let first_stick_row = |j: usize| friction_row + l.n_bilateral_velocity + offsets[j];
        for &row in &self.rows.closed_rows {
            if let Some(c) = self.was_contact.get_mut(row.wrapping_sub(normal_row)) {
                *c = true;
            }
        }
        for (j, stick) in self.was_stick.iter_mut().enumerate() {
            *stick = self
                .rows
                .closed_rows
                .binary_search(&first_stick_row(j))
                .is_ok();
        }
    }
}

/// Tolerance of the start on ‖R‖∞ / (1 + max(‖h‖∞, largest force)). The rows are
/// in force units, and their round-off grows with the forces in them: at the bottom of
/// a column of n blocks, n times the weight of one. Relative to ‖h‖∞ alone (the
/// weight of one block), a 280-block column's solution stalled at 3.6·10⁻¹², above its
/// tolerance of 2·10⁻¹², and the start failed on it.
const START_TOL: f64 = 1e-12;

/// Contacts that may leave their contact row per Newton update of the start
/// ([`OpeningLimit`]).
const OPENINGS_PER_UPDATE: usize = 1;

impl NewtonProblem for StartProblem<'_> {
    type Sets = Vec<usize>;

    fn evaluate(&mut self, y: &[f64], first: bool) -> (Vec<usize>, f64) {
        // Acceleration levels p̈ = W_pᵀa + ζ_p, v̇ = W_vᵀa + ζ_v.
        let e = self.level.eval;
        self.acc_p.clone_from(&e.position_zeta);
        for &(r, c, v) in &e.position_w.entries {
            self.acc_p[c] += v * y[r];
        }
        self.acc_v.clone_from(&e.velocity_zeta);
        for &(r, c, v) in &e.velocity_w.entries {
            self.acc_v[c] += v * y[r];
        }
        let limit = (!first).then_some(OpeningLimit {
            was_contact: &self.was_contact,
            was_stick: &self.was_stick,
            per_update: OPENINGS_PER_UPDATE,
        });
        let levels = (&self.acc_p[..], &self.acc_v[..]);
        self.level.rows(y, levels, limit, &mut self.rows);
        self.remember_sets();
        let size = 1.0 + self.force_scale.max(max_norm(&y[self.level.layout.nu..]));
        (
            self.rows.closed_rows.clone(),
            self.rows.free_residual() / size,
        )
    }

    fn exact_direction(
        &mut self,
        _y: &[f64],
        _: &Vec<usize>,
        dy: &mut [f64],
    ) -> Result<(), String> {
        let n = self.level.n();
        let rows = &mut self.rows;
        dy.iter_mut().zip(&rows.res).for_each(|(d, r)| *d = -r);
        let mut solved = self.solver.solve(n, &rows.jac, dy);
        let eps = self.regularization;
        if solved.is_err() && eps > 0.0 {
            // Redundant closed contacts (see `LinearOptions::regularization`): ε on the
            // multiplier diagonal of every closed row.
            rows.jac
                .extend(rows.closed_rows.iter().map(|&r| (r, r, eps)));
            dy.iter_mut().zip(&rows.res).for_each(|(d, r)| *d = -r);
            solved = self.solver.solve(n, &rows.jac, dy);
        }
        solved.map_err(|e| e.0)
    }
}

/// Solves, at (t0, q0, u0), M a = h + W λ with g̈ = 0, γ̇ = 0 for the bilateral
/// constraints and, for the contacts with g_N ≤ tol and ġ_N ≤ tol (closed), the
/// acceleration-level laws g̈_N ≥ 0 ⟂ λ_N ≥ 0 and Coulomb on λ_F (sliding contacts
/// along −γ_F/‖γ_F‖, sticking ones by the prox on γ̇_F), by semismooth Newton (nsga's
/// [`crate::newton`] engine, full updates, at most one contact opening and one law
/// starting to slip per update (docs/method.md §5), to ‖R‖∞ ≤ 10⁻¹² (1 + max(‖h‖∞,
/// ‖λ‖∞))).
///
/// # Errors
/// [`StepError::Start`] when Newton does not converge or the matrix is singular.
pub fn consistent_start<S: System>(
    system: &S,
    layout: &Layout,
    t0: f64,
    q0: &[f64],
    u0: &[f64],
    options: &Options,
) -> Result<Start, StepError> {
    let (nu, ng, nga, nn) = (
        layout.nu,
        layout.n_bilateral_position,
        layout.n_bilateral_velocity,
        layout.n_normal(),
    );
    let tol = options.start_tol;
    let mut e = Evaluation::<f64>::new(layout);
    system.evaluate(t0, q0, u0, &mut e);
    let (mut r_pos, mut r_vel, mut r_law) = (Vec::new(), Vec::new(), Vec::new());
    prox_parameters(
        options.prox,
        layout,
        &e,
        (&mut r_pos, &mut r_vel, &mut r_law),
        &mut Vec::new(),
    );
    let mut rate = e.position_chi.clone();
    for &(r, c, v) in &e.position_w.entries {
        rate[c] += v * u0[r];
    }
    let mut slip = e.velocity_chi.clone();
    for &(r, c, v) in &e.velocity_w.entries {
        slip[c] += v * u0[r];
    }
    let closed: Vec<bool> = (0..nn)
        .map(|k| e.position[ng + k] <= tol && rate[ng + k] <= tol)
        .collect();
    // A law whose contact slides at t0 takes its friction direction from that slip.
    let offsets = layout.friction_offsets();
    let fixed_slip: Vec<Option<Vec<f64>>> = layout
        .friction
        .iter()
        .zip(&offsets)
        .map(|(law, &f0)| {
            let s = &slip[nga + f0..nga + f0 + law.components];
            (norm(s) > tol).then(|| s.to_vec())
        })
        .collect();
    let mut problem = StartProblem {
        level: LevelProblem {
            layout,
            eval: &e,
            rhs: &e.forces,
            v_ref: None,
            closed: &closed,
            fixed_slip: &fixed_slip,
            r_pos: &r_pos,
            r_vel: &r_vel,
            r_law: &r_law,
            w_p: by_constraint(&e.position_w, layout.n_position()),
            w_v: by_constraint(&e.velocity_w, layout.n_velocity()),
        },
        rows: LevelRows::default(),
        acc_p: Vec::new(),
        acc_v: Vec::new(),
        solver: AutoSolver::default(),
        regularization: options.linear.regularization,
        was_contact: Vec::new(),
        was_stick: Vec::new(),
        force_scale: max_norm(&e.forces),
    };
    // Starting from zero forces, Newton changes the index sets of at most one contact
    // and one friction law per update after the first: the iterations allowed grow
    // with the number of contacts.
    let settings = NewtonSettings {
        tol: START_TOL,
        max_iter: options.newton.max_iter.max(nn),
        line_search: 0,
        reuse_factorization: false,
        resume_reuse: false,
        new_factors: true,
        follow_sets: false,
        give_up: GiveUp::Never,
        contracting_extra: 0,
        start_limit: f64::INFINITY,
        tuning: options.tuning,
    };
    let mut y = vec![0.0; problem.level.n()];
    let failed = |message: String| StepError::Start { t: t0, message };
    let mut scratch = NewtonScratch::default();
    let mut outcome = newton::solve(&mut problem, &mut y, &settings, &mut scratch);
    // Updates of a first solve that did not converge, before Lemke's method.
    let mut before_lemke = 0;
    if !matches!(outcome, Outcome::Converged { .. }) {
        before_lemke = scratch.evaluations().saturating_sub(1);
        // Newton changes the index sets of a few contacts per update and can cycle
        // through them (docs/method.md §5); Lemke's method pivots to the problem's
        // solution, whose sets Newton then only polishes.
        let newton_failure = describe(&outcome);
        y = lcp_start(layout, &e, &closed, &fixed_slip)
            .map_err(|lcp| failed(format!("{newton_failure}, and by Lemke's method: {lcp}")))?;
        outcome = newton::solve(&mut problem, &mut y, &settings, &mut scratch);
    }
    match outcome {
        Outcome::Converged {
            sets, iterations, ..
        } => {
            let (op, ov) = (nu, nu + layout.n_position());
            zero_separation_rows(layout, &closed, &sets, op + ng, ov + nga, &mut y);
            Ok(Start {
                a: y[..nu].to_vec(),
                lambda_g: y[op..op + ng].to_vec(),
                lambda_gamma: y[ov..ov + nga].to_vec(),
                lambda_n: y[op + ng..op + ng + nn].to_vec(),
                lambda_f: y[ov + nga..].to_vec(),
                updates: before_lemke + iterations,
            })
        }
        other => Err(failed(describe(&other))),
    }
}

/// The generalized force directions of the start LCP's unknowns: a closed contact's
/// w_N, less μ sign(γ_F) w_F for each law that slides along γ_F and bounds it; a
/// sticking law's w_F.
fn force_directions(
    layout: &Layout,
    d: &ContactMatrices,
    normals: &[usize],
    sticking: &[usize],
    slide: impl Fn(usize) -> Option<f64>,
) -> Vec<DVector<f64>> {
    let normal = |k: usize| {
        let mut f = d.w_p.dense(k);
        for (j, law) in layout.friction.iter().enumerate() {
            if let (Some(sign), true) = (slide(j), law.normals.contains(&k)) {
                for &(i, w) in d.w_v.entries(j) {
                    f[i] -= w * law.mu * sign;
                }
            }
        }
        f
    };
    normals
        .iter()
        .map(|&k| normal(k))
        .chain(sticking.iter().map(|&j| d.w_v.dense(j)))
        .collect()
}

/// Why the start's Newton iteration ended without a solution.
fn describe(outcome: &Outcome<Vec<usize>>) -> String {
    match outcome {
        Outcome::Singular(message) => message.clone(),
        _ => "semismooth Newton did not converge".into(),
    }
}

/// The acceleration-level problem at t0 as a planar Coulomb LCP (`crate::coulomb_lcp`),
/// solved by Lemke's method, which ends on a solution wherever its matrix is
/// copositive-plus and the problem has one. Returns the unknowns y = (a, λ_N, λ_F) of
/// [`consistent_start`] (planar friction and no bilateral constraints only:
/// [`crate::coulomb_lcp::planar_without_bilateral`]).
///
/// The rows are g̈_N = W_Nᵀa + ζ_N of the closed contacts and γ̇_F = W_Fᵀa + ζ_F of their
/// sticking friction laws. A law whose contact slides at t0 has no unknown of its own:
/// its force −μ Σλ_N sign(γ_F) acts with the normal forces it bounds, whose force
/// directions become w_N − μ sign(γ_F) w_F.
fn lcp_start(
    layout: &Layout,
    e: &Evaluation<f64>,
    closed: &[bool],
    fixed_slip: &[Option<Vec<f64>>],
) -> Result<Vec<f64>, String> {
    crate::coulomb_lcp::planar_without_bilateral(layout)?;
    let (nu, nn, nf) = (layout.nu, layout.n_normal(), layout.n_friction());
    let normals: Vec<usize> = (0..nn).filter(|&k| closed[k]).collect();
    let touching = |j: usize| layout.friction[j].normals.iter().any(|&k| closed[k]);
    let sticking: Vec<usize> = (0..nf)
        .filter(|&j| touching(j) && fixed_slip[j].is_none())
        .collect();
    let unknowns = normals.len() + 3 * sticking.len();
    if unknowns > LCP_START_UP_TO {
        return Err(format!(
            "not tried, for {unknowns} unknowns (more than {LCP_START_UP_TO})"
        ));
    }
    let d = ContactMatrices::of(e, nu, nn, nf).ok_or("the mass matrix is singular")?;
    let a_free = d.m_inv.apply(&e.forces);
    // The sign of a sliding law's slip (planar laws: one component).
    let slide = |j: usize| fixed_slip[j].as_ref().map(|s| s[0].signum());
    let forces = force_directions(layout, &d, &normals, &sticking, slide);
    let rows = CoulombLcp::rows_of(layout, &d, &normals, &sticking);
    let zeta = normals
        .iter()
        .map(|&k| e.position_zeta[k])
        .chain(sticking.iter().map(|&j| e.velocity_zeta[j]));
    let free: Vec<f64> = rows
        .iter()
        .zip(zeta)
        .map(|(w, z)| w.dot(&a_free) + z)
        .collect();
    let bounds = CoulombLcp::bounds_of(layout, &normals, &sticking);
    let accept = LCP_ACCEPT * (1.0 + crate::linalg::max_norm(&free));
    let problem = CoulombLcp {
        rows,
        forces,
        normals: normals.len(),
        bounds,
        free,
    };
    let sol = problem.solve(&d.m_inv, accept).map_err(|e| match e {
        LcpFailure::Ray { .. } => format!(
            "{e}: no forces satisfy the contact laws at t0 (a Painlevé-type \
             inconsistency, where the motion starts with an impulse)"
        ),
        e => e.to_string(),
    })?;
    let a: Vec<f64> = (a_free + &sol.change).iter().copied().collect();
    Ok(start_unknowns(
        layout,
        a,
        (&normals, &sol.normal),
        (&sticking, &sol.friction),
        slide,
    ))
}

/// y = (a, λ_N, λ_F) of the start from the accelerations `a`, the normal forces of the
/// closed contacts, the forces of the sticking laws, and the sliding laws' forces
/// −μ Σλ_N sign(γ_F).
fn start_unknowns(
    layout: &Layout,
    mut a: Vec<f64>,
    (normals, lambda_n): (&[usize], &[f64]),
    (sticking, lambda_f): (&[usize], &[f64]),
    slide: impl Fn(usize) -> Option<f64>,
) -> Vec<f64> {
    let (nu, nn) = (layout.nu, layout.n_normal());
    a.resize(nu + nn + layout.n_friction(), 0.0);
    let mut y = a;
    for (&k, &z) in normals.iter().zip(lambda_n) {
        y[nu + k] = z;
    }
    for (&j, &z) in sticking.iter().zip(lambda_f) {
        y[nu + nn + j] = z;
    }
    for (j, law) in layout.friction.iter().enumerate() {
        if let Some(sign) = slide(j) {
            let sum: f64 = law.normals.iter().map(|&k| y[nu + k]).sum();
            y[nu + nn + j] = -law.mu * sum * sign;
        }
    }
    y
}

/// Sets to exactly zero the forces whose rows say they are zero: a normal contact on
/// its separation row (not among the `closed_rows`), and a friction law none of whose
/// normal contacts is closed. The LU leaves round-off there (±3·10⁻¹⁴ on floor contacts
/// 200 m below a 1000-block column), and a force that is not exactly zero keeps an open
/// contact from being pruned (docs/method.md §8.1) until it has decayed, which changed
/// the pruned set, and so forced a new factorization, a few steps later. `normal_row`
/// and `friction_row` are the indices in y of the first normal force and of the first
/// friction component.
fn zero_separation_rows(
    layout: &Layout,
    closed: &[bool],
    closed_rows: &[usize],
    normal_row: usize,
    friction_row: usize,
    y: &mut [f64],
) {
    let mut separating = vec![true; closed.len()];
    for &r in closed_rows {
        if let Some(k) = r.checked_sub(normal_row).filter(|&k| k < closed.len()) {
            separating[k] = false;
        }
    }
    for (k, &sep) in separating.iter().enumerate() {
        if sep {
            y[normal_row + k] = 0.0;
        }
    }
    let offsets = layout.friction_offsets();
    for (law, &f0) in layout.friction.iter().zip(&offsets) {
        if !law.normals.iter().any(|&k| closed[k]) {
            y[friction_row + f0..friction_row + f0 + law.components].fill(0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::rocking::RockingBlock;

    /// A block of half-width b = 0.1 and half-height h = 0.2 (the blocks of the stacks)
    /// standing on both bottom corners and sliding along +x at unit speed, with friction
    /// coefficient μ. Corner 0 is the leading one, at x = +b.
    fn sliding_block(mu: f64) -> (RockingBlock, Layout, [f64; 3], [f64; 3]) {
        let block = RockingBlock {
            mass: 1.0,
            half_width: 0.1,
            half_height: 0.2,
            gravity: 9.81,
            mu,
            e_n: 0.0,
        };
        let layout = block.layout();
        (block, layout, [0.0, 0.2, 0.0], [1.0, 0.0, 0.0])
    }

    /// The leading corner's normal acceleration per unit normal force, friction
    /// −μλ included: 1/m + b(b − μh)/Θ. Past μ = b/h the block tips onto that corner
    /// alone; where this is negative (μ > (b + Θ/(m b))/h = 4/3), pressing the corner
    /// down accelerates it into the ground, and no force satisfies the contact laws
    /// (Painlevé's paradox).
    fn leading_corner_compliance(block: &RockingBlock) -> f64 {
        let (b, h) = (block.half_width, block.half_height);
        1.0 / block.mass + b * (b - block.mu * h) / block.inertia()
    }

    fn problem_of(
        block: &RockingBlock,
        layout: &Layout,
        q: &[f64],
        u: &[f64],
    ) -> (Evaluation<f64>, Vec<bool>, Vec<Option<Vec<f64>>>) {
        let mut e = Evaluation::new(layout);
        block.evaluate(0.0, q, u, &mut e);
        // Both corners touch; both slide at ẋ = 1 along +x.
        (e, vec![true, true], vec![Some(vec![1.0]), Some(vec![1.0])])
    }

    #[test]
    fn lemkes_start_of_a_sliding_block_tipping_onto_its_leading_corner() {
        let (block, layout, q, u) = sliding_block(0.8);
        let (e, closed, slip) = problem_of(&block, &layout, &q, &u);
        let y = lcp_start(&layout, &e, &closed, &slip).expect("a start exists for μ < 4/3");
        // y = (a, λ_N, λ_F): the leading corner alone carries the block.
        let lambda = block.gravity / leading_corner_compliance(&block);
        assert!((y[3] - lambda).abs() < 1e-12 * lambda, "{y:?}");
        assert_eq!(y[4], 0.0);
        assert!((y[5] + block.mu * lambda).abs() < 1e-12 * lambda, "{y:?}");
        // Newton's start, from zero forces, is the same.
        let newton = consistent_start(&block, &layout, 0.0, &q, &u, &Options::default())
            .expect("Newton converges");
        assert!((newton.lambda_n[0] - lambda).abs() < 1e-9 * lambda);
        for (n, l) in newton.a.iter().zip(&y[..3]) {
            assert!((n - l).abs() < 1e-9, "{:?} against {:?}", newton.a, &y[..3]);
        }
    }

    #[test]
    fn a_block_sliding_past_painleves_bound_has_no_start() {
        let (block, layout, q, u) = sliding_block(1.5);
        assert!(leading_corner_compliance(&block) < 0.0);
        let (e, closed, slip) = problem_of(&block, &layout, &q, &u);
        let lcp = lcp_start(&layout, &e, &closed, &slip).expect_err("no start exists");
        assert!(lcp.contains("ray"), "{lcp}");
        let err = consistent_start(&block, &layout, 0.0, &q, &u, &Options::default())
            .expect_err("no start exists");
        let message = err.to_string();
        assert!(
            message.contains("semismooth Newton") && message.contains("Painlevé"),
            "{message}"
        );
    }
}
