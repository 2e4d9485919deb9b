//! The Moreau–Jean midpoint baseline (docs/method.md §6) on the same [`System`] trait,
//! solved by the crate's one semismooth Newton engine ([`crate::newton`]).

use crate::error::StepError;
use crate::fallback::{FallbackStep, MoreauLemke};
use crate::level::{by_constraint, LevelProblem, LevelRows};
use crate::linalg::{AutoSolver, LinearSolver};
use crate::newton::{self, GiveUp, NewtonProblem, NewtonScratch, NewtonSettings, Outcome};
use crate::options::Prox;
use crate::prox::prox_parameters;
use crate::state::State;
use crate::system::{Evaluation, Layout, System, Triplets};

/// Options of the Moreau–Jean stepper.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MoreauOptions {
    /// Time step Δt.
    pub dt: f64,
    /// Prox parameter choice (as for the generalized-α stepper).
    pub prox: Prox,
    /// Newton tolerance on ‖R‖∞ (impulse units).
    pub tol: f64,
    /// Maximum Newton iterations.
    pub max_iter: usize,
}

impl Default for MoreauOptions {
    fn default() -> Self {
        Self {
            dt: 2e-3,
            prox: Prox::Scaled(1.0),
            tol: 1e-10,
            max_iter: 40,
        }
    }
}

/// State of the Moreau–Jean stepper.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MoreauState {
    /// Step counter k.
    pub k: u64,
    /// Time t_k = t0 + k Δt.
    pub t: f64,
    /// Coordinates.
    pub q: Vec<f64>,
    /// Velocities.
    pub u: Vec<f64>,
    /// Normal percussions of the last step.
    pub p_n: Vec<f64>,
    /// Friction percussions of the last step.
    pub p_f: Vec<f64>,
}

/// Moreau–Jean midpoint time stepping: q_M = q_n + ½Δt B u_n; solve
/// M(u_{n+1} − u_n) = hΔt + W P with Newton's impact law on the contacts closed at
/// q_M and Coulomb's law on the velocity level; q_{n+1} = q_M + ½Δt B(q_M) u_{n+1}.
#[derive(Debug)]
pub struct MoreauStepper<S: System> {
    system: S,
    layout: Layout,
    options: MoreauOptions,
    t0: f64,
    state: MoreauState,
    eval: Evaluation<f64>,
    solver: AutoSolver,
    iterations: u64,
    lcp_steps: u64,
}

impl<S: System> MoreauStepper<S> {
    /// A stepper at (t0, q0, u0).
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for bad sizes, options or non-finite input.
    pub fn new(
        system: S,
        t0: f64,
        q0: &[f64],
        u0: &[f64],
        options: MoreauOptions,
    ) -> Result<Self, StepError> {
        let layout = system.layout();
        layout.validate().map_err(StepError::InvalidInput)?;
        if q0.len() != layout.nq || u0.len() != layout.nu {
            return Err(StepError::InvalidInput(
                "q0/u0 sizes do not match the system".into(),
            ));
        }
        let finite_input = t0.is_finite() && q0.iter().chain(u0).all(|x| x.is_finite());
        if !(options.dt > 0.0 && options.dt.is_finite() && finite_input) {
            return Err(StepError::InvalidInput(
                "dt must be positive; t0, q0, u0 finite".into(),
            ));
        }
        let state = MoreauState {
            k: 0,
            t: t0,
            q: q0.to_vec(),
            u: u0.to_vec(),
            p_n: vec![0.0; layout.n_normal()],
            p_f: vec![0.0; layout.n_friction()],
        };
        let eval = Evaluation::new(&layout);
        Ok(Self {
            system,
            layout,
            options,
            t0,
            state,
            eval,
            solver: AutoSolver::default(),
            iterations: 0,
            lcp_steps: 0,
        })
    }

    /// The current state.
    pub fn state(&self) -> &MoreauState {
        &self.state
    }
    /// Total Newton iterations so far.
    pub fn newton_iterations(&self) -> u64 {
        self.iterations
    }
    /// Steps whose Newton iteration did not converge and whose contact problem Lemke's
    /// method solved instead (the same scheme, another solver).
    pub fn lcp_steps(&self) -> u64 {
        self.lcp_steps
    }

    /// One step. Returns the Newton iterations it took.
    ///
    /// # Errors
    /// [`StepError::Linear`] when the Newton matrix is singular or Newton does not
    /// converge; the stepper stays at the last good state.
    pub fn step(&mut self) -> Result<usize, StepError> {
        let l = &self.layout;
        let (ng, nn) = (l.n_bilateral_position, l.n_normal());
        let dt = self.options.dt;
        let st = &self.state;
        let q_m = advance(&self.system, st.t, &st.q, &st.u, 0.5 * dt);
        let t_m = st.t + 0.5 * dt;
        self.eval.reset();
        self.system.evaluate(t_m, &q_m, &st.u, &mut self.eval);
        let e = &self.eval;
        let (mut r_pos, mut r_vel, mut r_law) = (Vec::new(), Vec::new(), Vec::new());
        prox_parameters(
            self.options.prox,
            l,
            e,
            (&mut r_pos, &mut r_vel, &mut r_law),
            &mut Vec::new(),
        );
        let closed: Vec<bool> = (0..nn).map(|k| e.position[ng + k] <= 0.0).collect();
        // ṗ(u_n), v(u_n) for the restitution terms.
        let mut rate_old = e.position_chi.clone();
        for &(r, c, v) in &e.position_w.entries {
            rate_old[c] += v * st.u[r];
        }
        let mut v_old = e.velocity_chi.clone();
        for &(r, c, v) in &e.velocity_w.entries {
            v_old[c] += v * st.u[r];
        }
        let impulse: Vec<f64> = e.forces.iter().map(|h| h * dt).collect();
        let fixed_slip = vec![None; l.friction.len()];
        let mut problem = MoreauProblem {
            level: LevelProblem {
                layout: l,
                eval: e,
                rhs: &impulse,
                v_ref: Some(&st.u),
                closed: &closed,
                fixed_slip: &fixed_slip,
                r_pos: &r_pos,
                r_vel: &r_vel,
                r_law: &r_law,
                w_p: by_constraint(&e.position_w, l.n_position()),
                w_v: by_constraint(&e.velocity_w, l.n_velocity()),
            },
            rows: LevelRows::default(),
            rate_old,
            v_old,
            xi_p: Vec::new(),
            xi_v: Vec::new(),
            solver: &mut self.solver,
        };
        // Unknowns z = (u_{n+1}, P_p, P_v); Newton starts from u_n.
        let mut z = vec![0.0; problem.level.n()];
        z[..l.nu].copy_from_slice(&st.u);
        let settings = NewtonSettings {
            tol: self.options.tol,
            max_iter: self.options.max_iter,
            line_search: 0,
            reuse_factorization: false,
            resume_reuse: false,
            new_factors: true,
            follow_sets: false,
            give_up: GiveUp::Never,
            contracting_extra: 0,
            start_limit: f64::INFINITY,
            tuning: crate::Tuning::default(),
        };
        match newton::solve(
            &mut problem,
            &mut z,
            &settings,
            &mut NewtonScratch::default(),
        ) {
            Outcome::Converged { iterations, .. } => {
                self.finish(t_m, &q_m, &z);
                self.iterations += iterations as u64;
                Ok(iterations)
            }
            Outcome::Singular(message) => self.by_lemke(&message),
            Outcome::NotConverged { .. }
            | Outcome::NonFinite
            | Outcome::Restart
            | Outcome::Interrupted => self.by_lemke("Moreau–Jean Newton did not converge"),
        }
    }

    /// The step with its contact problem solved by Lemke's method, which terminates
    /// (the contacts closed at q_M, as Newton had them; docs/method.md §6). Returns 0
    /// Newton iterations.
    fn by_lemke(&mut self, newton: &str) -> Result<usize, StepError> {
        let st = &self.state;
        let k = st.k + 1;
        let t1 = self.t0 + k as f64 * self.options.dt;
        let step = MoreauLemke::BASELINE
            .step(
                &self.system,
                &self.layout,
                (st.t, t1),
                (&st.q, &st.u),
                self.options.dt,
            )
            .map_err(|why| StepError::Linear {
                t: st.t,
                message: format!("{newton}; by Lemke's method: {why}"),
                state: Box::new(st.as_state()),
            })?;
        self.state = MoreauState {
            k,
            t: t1,
            q: step.q,
            u: step.u,
            p_n: step.p_n,
            p_f: step.p_f,
        };
        self.lcp_steps += 1;
        Ok(0)
    }

    /// q_{n+1} = q_M + ½Δt B(q_M) u_{n+1}, and the new state from the solution z.
    fn finish(&mut self, t_m: f64, q_m: &[f64], z: &[f64]) {
        let l = &self.layout;
        let (nu, np) = (l.nu, l.n_position());
        let (ng, nga) = (l.n_bilateral_position, l.n_bilateral_velocity);
        let dt = self.options.dt;
        let q1 = advance(&self.system, t_m, q_m, &z[..nu], 0.5 * dt);
        let k = self.state.k + 1;
        self.state = MoreauState {
            k,
            t: self.t0 + k as f64 * dt,
            q: q1,
            u: z[..nu].to_vec(),
            p_n: z[nu + ng..nu + np].to_vec(),
            p_f: z[nu + np + nga..].to_vec(),
        };
    }
}

impl MoreauState {
    /// The state in the generalized-α stepper's form (no accelerations or forces).
    fn as_state(&self) -> State {
        State {
            k: self.k,
            t: self.t,
            q: self.q.clone(),
            u: self.u.clone(),
            p_n: self.p_n.clone(),
            p_f: self.p_f.clone(),
            ..State::default()
        }
    }
}

/// q + h B(t, q) u: a half step of the midpoint rule.
pub(crate) fn advance<S: System>(system: &S, t: f64, q: &[f64], u: &[f64], h: f64) -> Vec<f64> {
    let mut b = Triplets::default();
    system.kinematics(t, q, &mut b);
    let mut out = q.to_vec();
    for &(j, i, v) in &b.entries {
        out[j] += h * v * u[i];
    }
    out
}

/// The velocity-level problem of one Moreau–Jean step on the Newton engine.
struct MoreauProblem<'a> {
    level: LevelProblem<'a>,
    rows: LevelRows,
    /// ṗ(q_M, u_n) and v(q_M, u_n), for the restitution terms.
    rate_old: Vec<f64>,
    v_old: Vec<f64>,
    xi_p: Vec<f64>,
    xi_v: Vec<f64>,
    solver: &'a mut AutoSolver,
}

impl NewtonProblem for MoreauProblem<'_> {
    type Sets = Vec<usize>;

    /// ξ_N = ġ_N(u_{n+1}) + e_N ġ_N(u_n), ξ_F = γ_F(u_{n+1}) + e_F γ_F(u_n) at q_M.
    fn evaluate(&mut self, z: &[f64], _first: bool) -> (Vec<usize>, f64) {
        let l = self.level.layout;
        let e = self.level.eval;
        let (ng, nga) = (l.n_bilateral_position, l.n_bilateral_velocity);
        self.xi_p.clone_from(&e.position_chi);
        for &(r, c, v) in &e.position_w.entries {
            self.xi_p[c] += v * z[r];
        }
        for (k, e_n) in l.e_n.iter().enumerate() {
            self.xi_p[ng + k] += e_n * self.rate_old[ng + k];
        }
        self.xi_v.clone_from(&e.velocity_chi);
        for &(r, c, v) in &e.velocity_w.entries {
            self.xi_v[c] += v * z[r];
        }
        for (law, f0) in l.friction.iter().zip(l.friction_offsets()) {
            let vs = nga + f0;
            for m in 0..law.components {
                self.xi_v[vs + m] += law.e_f * self.v_old[vs + m];
            }
        }
        self.level
            .rows(z, (&self.xi_p, &self.xi_v), None, &mut self.rows);
        let r = crate::linalg::max_norm(&self.rows.res);
        (self.rows.closed_rows.clone(), r)
    }

    fn exact_direction(
        &mut self,
        _z: &[f64],
        _: &Vec<usize>,
        dz: &mut [f64],
    ) -> Result<(), String> {
        dz.iter_mut().zip(&self.rows.res).for_each(|(d, r)| *d = -r);
        self.solver
            .solve(self.level.n(), &self.rows.jac, dz)
            .map_err(|e| e.0)
    }
}
