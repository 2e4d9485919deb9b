//! The Moreau–Jean midpoint baseline (NSGA-SPEC §6) on the same [`System`] trait.

use crate::error::StepError;
use crate::linalg::{AutoSolver, LinearSolver};
use crate::stepper::{norm, prox_parameters, Prox};
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

    /// One step. Returns the Newton iterations it took.
    ///
    /// # Errors
    /// [`StepError::Linear`] when the Newton matrix is singular or Newton does not
    /// converge; the stepper stays at the last good state.
    #[allow(clippy::too_many_lines)]
    pub fn step(&mut self) -> Result<usize, StepError> {
        let l = &self.layout;
        let (nu, ng, nga, nn) = (
            l.nu,
            l.n_bilateral_position,
            l.n_bilateral_velocity,
            l.n_normal(),
        );
        let (np, nv) = (l.n_position(), l.n_velocity());
        let dt = self.options.dt;
        let law_off = l.friction_offsets();
        let st = &self.state;
        let mut bt = Triplets::default();
        self.system.kinematics(st.t, &st.q, &mut bt);
        let mut q_m = st.q.clone();
        for &(j, i, b) in &bt.entries {
            q_m[j] += 0.5 * dt * b * st.u[i];
        }
        let t_m = st.t + 0.5 * dt;
        self.eval.reset();
        self.system.evaluate(t_m, &q_m, &st.u, &mut self.eval);
        let e = &self.eval;
        let (mut r_pos, mut r_vel, mut r_law) = (Vec::new(), Vec::new(), Vec::new());
        prox_parameters(self.options.prox, l, e, &mut r_pos, &mut r_vel, &mut r_law);
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
        // Unknowns z = (u_{n+1}, P_p, P_v).
        let (ou, op, ov) = (0, nu, nu + np);
        let n = ov + nv;
        let mut z = vec![0.0; n];
        z[..nu].copy_from_slice(&st.u);
        let mut res = vec![0.0; n];
        let mut jac: Vec<(usize, usize, f64)> = Vec::new();
        let row_of = |jac: &mut Vec<(usize, usize, f64)>,
                      w: &Triplets<f64>,
                      c0: usize,
                      row: usize,
                      s: f64| {
            for &(i, c, v) in &w.entries {
                if c == c0 {
                    jac.push((row, ou + i, s * v));
                }
            }
        };
        for iter in 0..=self.options.max_iter {
            let mut xi_p = e.position_chi.clone();
            for &(r, c, v) in &e.position_w.entries {
                xi_p[c] += v * z[ou + r];
            }
            for k in 0..nn {
                xi_p[ng + k] += l.e_n[k] * rate_old[ng + k];
            }
            let mut xi_v = e.velocity_chi.clone();
            for &(r, c, v) in &e.velocity_w.entries {
                xi_v[c] += v * z[ou + r];
            }
            for (j, law) in l.friction.iter().enumerate() {
                let vs = nga + law_off[j];
                for m in 0..law.components {
                    xi_v[vs + m] += law.e_f * v_old[vs + m];
                }
            }
            res.iter_mut().for_each(|x| *x = 0.0);
            jac.clear();
            for &(i, j, m) in &e.mass.entries {
                res[ou + i] += m * (z[ou + j] - st.u[j]);
                jac.push((ou + i, ou + j, m));
            }
            for i in 0..nu {
                res[ou + i] -= e.forces[i] * dt;
            }
            for &(i, c, v) in &e.position_w.entries {
                res[ou + i] -= v * z[op + c];
                jac.push((ou + i, op + c, -v));
            }
            for &(i, c, v) in &e.velocity_w.entries {
                res[ou + i] -= v * z[ov + c];
                jac.push((ou + i, ov + c, -v));
            }
            for i in 0..ng {
                res[op + i] = r_pos[i] * xi_p[i];
                row_of(&mut jac, &e.position_w, i, op + i, r_pos[i]);
            }
            for i in 0..nga {
                res[ov + i] = r_vel[i] * xi_v[i];
                row_of(&mut jac, &e.velocity_w, i, ov + i, r_vel[i]);
            }
            for k in 0..nn {
                let pk = ng + k;
                if closed[k] && r_pos[pk] * xi_p[pk] - z[op + pk] <= 0.0 {
                    res[op + pk] = r_pos[pk] * xi_p[pk];
                    row_of(&mut jac, &e.position_w, pk, op + pk, r_pos[pk]);
                } else {
                    res[op + pk] = z[op + pk];
                    jac.push((op + pk, op + pk, 1.0));
                }
            }
            for (j, law) in l.friction.iter().enumerate() {
                let vs = nga + law_off[j];
                let nc = law.components;
                let active = law.normals.iter().any(|&k| closed[k]);
                let p_sum: f64 = law.normals.iter().map(|&k| z[op + ng + k]).sum();
                let radius = law.mu * p_sum.max(0.0);
                let dist: f64 = (0..nc)
                    .map(|m| (r_law[j] * xi_v[vs + m] - z[ov + vs + m]).powi(2))
                    .sum();
                let stick = active && dist.sqrt() <= radius;
                let dn = norm(&xi_v[vs..vs + nc]);
                for m in 0..nc {
                    let row = ov + vs + m;
                    if stick {
                        res[row] = r_law[j] * xi_v[vs + m];
                        row_of(&mut jac, &e.velocity_w, vs + m, row, r_law[j]);
                        continue;
                    }
                    res[row] = z[row];
                    jac.push((row, row, 1.0));
                    if !active || dn == 0.0 || p_sum <= 0.0 {
                        continue;
                    }
                    let dm = xi_v[vs + m] / dn;
                    res[row] += radius * dm;
                    for &k in &law.normals {
                        jac.push((row, op + ng + k, law.mu * dm));
                    }
                    for mp in 0..nc {
                        let proj = f64::from(u8::from(m == mp)) - dm * xi_v[vs + mp] / dn;
                        row_of(&mut jac, &e.velocity_w, vs + mp, row, radius * proj / dn);
                    }
                }
            }
            let r = res.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            if !r.is_finite() {
                break;
            }
            if r <= self.options.tol {
                // q_{n+1} = q_M + ½Δt B(q_M) u_{n+1}
                let mut bm = Triplets::default();
                self.system.kinematics(t_m, &q_m, &mut bm);
                let mut q1 = q_m.clone();
                for &(j, i, b) in &bm.entries {
                    q1[j] += 0.5 * dt * b * z[ou + i];
                }
                let k = self.state.k + 1;
                self.state = MoreauState {
                    k,
                    t: self.t0 + k as f64 * dt,
                    q: q1,
                    u: z[..nu].to_vec(),
                    p_n: z[op + ng..op + np].to_vec(),
                    p_f: z[ov + nga..ov + nv].to_vec(),
                };
                self.iterations += iter as u64;
                return Ok(iter);
            }
            let mut dz: Vec<f64> = res.iter().map(|x| -x).collect();
            self.solver
                .solve(n, &jac, &mut dz)
                .map_err(|err| StepError::Linear {
                    t: self.state.t,
                    message: err.0,
                    state: Box::new(crate::stepper::State {
                        k: self.state.k,
                        t: self.state.t,
                        q: self.state.q.clone(),
                        u: self.state.u.clone(),
                        a: Vec::new(),
                        a_bar: Vec::new(),
                        lambda_n: Vec::new(),
                        lambda_n_bar: Vec::new(),
                        lambda_f: Vec::new(),
                        lambda_f_bar: Vec::new(),
                        p_n: self.state.p_n.clone(),
                        p_f: self.state.p_f.clone(),
                        x: Vec::new(),
                    }),
                })?;
            for (zi, d) in z.iter_mut().zip(&dz) {
                *zi += d;
            }
        }
        Err(StepError::Linear {
            t: self.state.t,
            message: "Moreau–Jean Newton did not converge".into(),
            state: Box::default(),
        })
    }
}
