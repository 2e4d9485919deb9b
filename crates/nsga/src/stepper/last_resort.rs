//! The last resort of a step that every attempt of the fallback policy failed
//! (docs/method.md §8, step 7): one Moreau–Jean step of the same system whose contact
//! problem is posed as a linear complementarity problem and solved by Lemke's method
//! ([`crate::lcp`]), which terminates, followed by a projection of the positions back
//! onto the gaps. The generalized-α state then restarts from the consistent
//! accelerations and forces at the new state, as at t0.
//!
//! The velocity-level problem (Anitescu and Potra 1997, in the form of docs/method.md
//! §6): with ũ = u_n + Δt M⁻¹h at the midpoint q_M, the normal contacts N and the
//! friction laws F,
//!
//! u⁺ = ũ + M⁻¹(W_N P_N + W_F (β⁺ − β⁻)),
//! 0 ≤ P_N ⟂ ξ_N = W_Nᵀu⁺ + χ_N + e_N ġ_N(u_n) ≥ 0,
//! 0 ≤ β⁺ ⟂ λ + ξ_F ≥ 0,  0 ≤ β⁻ ⟂ λ − ξ_F ≥ 0,  0 ≤ λ ⟂ μ Σ P_N − β⁺ − β⁻ ≥ 0,
//!
//! with ξ_F = W_Fᵀu⁺ + χ_F + e_F γ_F(u_n): Coulomb's law of a planar contact exactly (λ
//! is the slip speed). Every contact takes part: one still open at q_M (g_N > 0) has
//! ξ_N = W_Nᵀu⁺ + χ_N + g_N/(½Δt) instead, so that it is pushed only if its gap would
//! close by the end of the step. (Activating only the contacts closed at q_M, as the
//! Moreau–Jean baseline does, lets a column resting on gaps of 1e-9 fall through by
//! ½Δt‖u‖ in a step.) Then q_{n+1} = q_M + ½Δt B u⁺. Gaps that end below zero are closed
//! by the least M-norm displacement, itself an LCP: 0 ≤ δ ⟂ g + W_Nᵀ M⁻¹ W_N δ ≥ 0.

use super::Stepper;
use crate::error::StepError;
use crate::lcp::{lemke, LcpFailure};
use crate::report::{LastResort, StepStats};
use crate::sets::IndexSets;
use crate::start::consistent_start;
use crate::state::State;
use crate::system::{Evaluation, System, Triplets};
use nalgebra::{DMatrix, DVector};

/// Largest penetration left by the position projection, relative to the gap scale 1.
const PROJECTION_TOL: f64 = 1e-12;

/// The dense pieces of one evaluation the LCPs are built from.
struct Dense {
    /// M⁻¹ (nu × nu).
    m_inv: DMatrix<f64>,
    /// Columns of W_p (nu × np).
    w_p: DMatrix<f64>,
    /// Columns of W_v (nu × nv).
    w_v: DMatrix<f64>,
}

impl Dense {
    fn of(eval: &Evaluation<f64>, nu: usize, np: usize, nv: usize) -> Option<Self> {
        let mut m = DMatrix::zeros(nu, nu);
        for &(i, j, v) in &eval.mass.entries {
            m[(i, j)] += v;
        }
        let mut w_p = DMatrix::zeros(nu, np);
        // np or nv = 0: that family is not needed.
        for &(i, c, v) in eval.position_w.entries.iter().filter(|e| e.1 < np) {
            w_p[(i, c)] += v;
        }
        let mut w_v = DMatrix::zeros(nu, nv);
        for &(i, c, v) in eval.velocity_w.entries.iter().filter(|e| e.1 < nv) {
            w_v[(i, c)] += v;
        }
        Some(Self {
            m_inv: m.try_inverse()?,
            w_p,
            w_v,
        })
    }
}

impl<S: System> Stepper<S> {
    /// Takes the step by the last resort and commits it.
    ///
    /// # Errors
    /// [`StepError::NoSolution`] when the step's contact problem has no solution (Lemke's
    /// method ends on a ray: a Painlevé-type inconsistency); [`StepError::InvalidInput`]
    /// for systems it does not cover (bilateral constraints, spatial friction laws); the
    /// stepper stays where it was.
    pub(super) fn last_resort(&mut self) -> Result<(), StepError> {
        let l = self.layout.clone();
        if l.n_bilateral_position + l.n_bilateral_velocity > 0
            || l.friction.iter().any(|f| f.components != 1)
        {
            return Err(StepError::InvalidInput(
                "the last resort covers planar friction without bilateral constraints".into(),
            ));
        }
        let (nu, nn, nf) = (l.nu, l.n_normal(), l.n_friction());
        let dt = self.options.dt;
        let st = self.state.clone();
        let q_m = self.advance(st.t, &st.q, &st.u, 0.5 * dt);
        let t_m = st.t + 0.5 * dt;
        let mut eval = Evaluation::new(&l);
        self.system.evaluate(t_m, &q_m, &st.u, &mut eval);
        let no_solution = |message: String| StepError::NoSolution {
            t: st.t,
            message,
            state: Box::new(st.clone()),
        };
        let d = Dense::of(&eval, nu, nn, nf)
            .ok_or_else(|| no_solution("the mass matrix is singular".into()))?;
        // Every contact and friction law takes part: an open one carries no percussion
        // unless its gap would close within the step.
        let closed: Vec<usize> = (0..nn).collect();
        let active: Vec<usize> = (0..l.friction.len()).collect();
        // ũ, and the constant parts of ξ_N and ξ_F.
        let u_n = DVector::from_column_slice(&st.u);
        let u_free =
            &u_n + &d.m_inv * DVector::from_iterator(nu, eval.forces.iter().map(|h| h * dt));
        let xi_n = |k: usize, u: &DVector<f64>| d.w_p.column(k).dot(u) + eval.position_chi[k];
        let xi_f = |j: usize, u: &DVector<f64>| d.w_v.column(j).dot(u) + eval.velocity_chi[j];
        // Unknowns z = (P_N over the contacts, β⁺, β⁻, λ over the friction laws).
        let (a, b) = (closed.len(), active.len());
        let n = a + 3 * b;
        let cols: Vec<DVector<f64>> = closed
            .iter()
            .map(|&k| d.w_p.column(k).into_owned())
            .chain(active.iter().map(|&j| d.w_v.column(j).into_owned()))
            .collect();
        let g_cols: Vec<DVector<f64>> = cols.iter().map(|c| &d.m_inv * c).collect();
        let mut m = vec![0.0; n * n];
        let mut q = vec![0.0; n];
        // Row r of the velocity part, as a combination over the columns: ±(column r)ᵀ M⁻¹.
        for (r, col_r) in cols.iter().enumerate() {
            let rows: Vec<(usize, f64)> = if r < a {
                vec![(r, 1.0)]
            } else {
                vec![(a + (r - a), 1.0), (a + b + (r - a), -1.0)]
            };
            for (row, sign) in rows {
                for (c, g_c) in g_cols.iter().enumerate() {
                    let v = sign * col_r.dot(g_c);
                    if c < a {
                        m[row * n + c] = v;
                    } else {
                        m[row * n + a + (c - a)] = v;
                        m[row * n + a + b + (c - a)] = -v;
                    }
                }
            }
        }
        for (i, &k) in closed.iter().enumerate() {
            let g = eval.position[k];
            q[i] = xi_n(k, &u_free)
                + if g <= 0.0 {
                    l.e_n[k] * xi_n(k, &u_n)
                } else {
                    g / (0.5 * dt)
                };
        }
        for (i, &j) in active.iter().enumerate() {
            let c = xi_f(j, &u_free) + l.friction[j].e_f * xi_f(j, &u_n);
            q[a + i] = c;
            q[a + b + i] = -c;
            // λ enters both slip rows; the friction bound row closes the system.
            m[(a + i) * n + a + 2 * b + i] = 1.0;
            m[(a + b + i) * n + a + 2 * b + i] = 1.0;
            let row = a + 2 * b + i;
            for &k in &l.friction[j].normals {
                if let Some(p) = closed.iter().position(|&c| c == k) {
                    m[row * n + p] = l.friction[j].mu;
                }
            }
            m[row * n + a + i] = -1.0;
            m[row * n + a + b + i] = -1.0;
        }
        let sol = lemke(&m, &q, 50 * n + 50).map_err(|e| match e {
            LcpFailure::Ray { .. } => no_solution(format!(
                "the step's contact problem has no solution: {e} (a Painlevé-type inconsistency)"
            )),
            e => no_solution(e.to_string()),
        })?;
        let mut u1 = u_free;
        let mut p_n = vec![0.0; nn];
        let mut p_f = vec![0.0; nf];
        for (i, &k) in closed.iter().enumerate() {
            p_n[k] = sol.z[i];
            u1 += &g_cols[i] * sol.z[i];
        }
        for (i, &j) in active.iter().enumerate() {
            p_f[j] = sol.z[a + i] - sol.z[a + b + i];
            u1 += &g_cols[a + i] * p_f[j];
        }
        let u1: Vec<f64> = u1.iter().copied().collect();
        let mut q1 = self.advance(t_m, &q_m, &u1, 0.5 * dt);
        let k = st.k + 1;
        let t1 = self.grid_time(k);
        let moved = self.project_onto_gaps(t1, &mut q1, &u1);
        let state = self.restarted_state(k, t1, q1, u1, p_n, p_f);
        if state.q.iter().chain(&state.u).any(|x| !x.is_finite()) {
            return Err(no_solution(
                "the last resort gave a non-finite state".into(),
            ));
        }
        let stats = StepStats {
            t: t1,
            iterations: 0,
            residual: sol.residual,
            rho_inf: self.options.rho_inf,
            sets: IndexSets::default(),
            retries: 1,
            converged: true,
            branch: None,
            solver: "lemke".into(),
            substeps: 1,
            last_resort: Some(LastResort {
                pivots: sol.pivots,
                residual: sol.residual,
                projection: moved,
            }),
        };
        self.account(&stats);
        self.state = state;
        self.last = Some(stats);
        Ok(())
    }

    /// q + h B(t, q) u.
    fn advance(&self, t: f64, q: &[f64], u: &[f64], h: f64) -> Vec<f64> {
        let mut b = Triplets::default();
        self.system.kinematics(t, q, &mut b);
        let mut out = q.to_vec();
        for &(j, i, v) in &b.entries {
            out[j] += h * v * u[i];
        }
        out
    }

    /// Moves `q` by the least M-norm displacement that closes every negative gap (to
    /// round-off, five linearizations at most); returns the size of the displacement
    /// in the coordinates (∞-norm).
    fn project_onto_gaps(&self, t: f64, q: &mut Vec<f64>, u: &[f64]) -> f64 {
        let l = &self.layout;
        let (nu, nn) = (l.nu, l.n_normal());
        let mut moved = 0.0_f64;
        for _ in 0..5 {
            let mut eval = Evaluation::new(l);
            self.system.evaluate(t, q, u, &mut eval);
            if (0..nn).all(|k| eval.position[k] >= -PROJECTION_TOL) {
                break;
            }
            // All contacts: closing one gap must not open another below zero.
            let low: Vec<usize> = (0..nn).collect();
            let Some(d) = Dense::of(&eval, nu, nn, 0) else {
                break;
            };
            let g_cols: Vec<DVector<f64>> =
                low.iter().map(|&k| &d.m_inv * d.w_p.column(k)).collect();
            let n = low.len();
            let mut m = vec![0.0; n * n];
            for (r, &k) in low.iter().enumerate() {
                for (c, g_c) in g_cols.iter().enumerate() {
                    m[r * n + c] = d.w_p.column(k).dot(g_c);
                }
            }
            let gaps: Vec<f64> = low.iter().map(|&k| eval.position[k]).collect();
            let Ok(sol) = lemke(&m, &gaps, 50 * n + 50) else {
                break;
            };
            let mut du = vec![0.0; nu];
            for (g_c, delta) in g_cols.iter().zip(&sol.z) {
                for (x, y) in du.iter_mut().zip(g_c.iter()) {
                    *x += y * delta;
                }
            }
            let before = q.clone();
            *q = self.advance(t, q, &du, 1.0);
            moved = moved.max(
                q.iter()
                    .zip(&before)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max),
            );
        }
        moved
    }

    /// The generalized-α state at (t, q, u) after a last-resort step: accelerations and
    /// forces from the consistent start there (docs/method.md §5), or, if that fails,
    /// the free acceleration M⁻¹h and no forces.
    fn restarted_state(
        &self,
        k: u64,
        t: f64,
        q: Vec<f64>,
        u: Vec<f64>,
        p_n: Vec<f64>,
        p_f: Vec<f64>,
    ) -> State {
        let o = self.off;
        let start = consistent_start(&self.system, &self.layout, t, &q, &u, &self.options)
            .ok()
            .unwrap_or_else(|| {
                let mut eval = Evaluation::new(&self.layout);
                self.system.evaluate(t, &q, &u, &mut eval);
                let a = Dense::of(&eval, o.nu, 0, 0).map_or_else(
                    || vec![0.0; o.nu],
                    |d| {
                        (&d.m_inv * DVector::from_column_slice(&eval.forces))
                            .iter()
                            .copied()
                            .collect()
                    },
                );
                crate::start::Start {
                    a,
                    lambda_g: vec![0.0; o.ng],
                    lambda_gamma: vec![0.0; o.nga],
                    lambda_n: vec![0.0; o.nn],
                    lambda_f: vec![0.0; o.nf],
                }
            });
        let mut x = vec![0.0; o.n];
        x[o.a..o.a + o.nu].copy_from_slice(&start.a);
        x[o.ln..o.ln + o.nn].copy_from_slice(&start.lambda_n);
        x[o.lf..o.lf + o.nf].copy_from_slice(&start.lambda_f);
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
}
