//! Consistent initial accelerations and forces at t0 (docs/method.md §5).

use crate::error::StepError;
use crate::level::{by_constraint, LevelProblem, LevelRows};
use crate::linalg::{norm, AutoSolver, LinearSolver};
use crate::newton::{self, GiveUp, NewtonProblem, NewtonScratch, NewtonSettings, Outcome};
use crate::options::Options;
use crate::prox::prox_parameters;
use crate::system::{Evaluation, Layout, System};

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
}

impl NewtonProblem for StartProblem<'_> {
    type Sets = Vec<usize>;

    fn evaluate(&mut self, y: &[f64], _first: bool) -> (Vec<usize>, f64) {
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
        self.level.rows(y, &self.acc_p, &self.acc_v, &mut self.rows);
        let r = crate::linalg::max_norm(&self.rows.res);
        (self.rows.closed_rows.clone(), r)
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
            // Redundant closed contacts (see `Options::regularization`): ε on the
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
/// [`crate::newton`] engine, full updates, to ‖R‖∞ ≤ 1e-12 (1 + ‖h‖∞)).
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
    let scale = 1.0 + e.forces.iter().fold(0.0_f64, |m, h| m.max(h.abs()));
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
        regularization: options.regularization,
    };
    // Starting from zero forces, Newton changes the index sets of a few contacts per
    // iteration: a tall column on a moving base, whose bottom block slides at t0 and
    // whose interfaces rock, needed 45 iterations at 50 blocks and 87 at 100. The
    // iterations allowed therefore grow with the number of contacts.
    let settings = NewtonSettings {
        tol: 1e-12 * scale,
        max_iter: options.max_iter.max(nn),
        line_search: 0,
        reuse_factorization: false,
        resume_reuse: false,
        give_up: GiveUp::Never,
    };
    let mut y = vec![0.0; problem.level.n()];
    let failed = |message: String| StepError::Start { t: t0, message };
    match newton::solve(
        &mut problem,
        &mut y,
        &settings,
        &mut NewtonScratch::default(),
    ) {
        Outcome::Converged { sets, .. } => {
            let (op, ov) = (nu, nu + layout.n_position());
            zero_separation_rows(layout, &closed, &sets, op + ng, ov + nga, &mut y);
            Ok(Start {
                a: y[..nu].to_vec(),
                lambda_g: y[op..op + ng].to_vec(),
                lambda_gamma: y[ov..ov + nga].to_vec(),
                lambda_n: y[op + ng..op + ng + nn].to_vec(),
                lambda_f: y[ov + nga..].to_vec(),
            })
        }
        Outcome::Singular(message) => Err(failed(message)),
        Outcome::NotConverged { .. } | Outcome::NonFinite | Outcome::Restart => {
            Err(failed("semismooth Newton did not converge".into()))
        }
    }
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
