//! Residual (eqs. 127–142) and its semismooth Jacobian (eq. 143), rows scaled to
//! impulse units: acceleration-level rows × Δt, position-level rows ÷ Δt.

use super::rows::{push_q_derivative, push_u_derivative, RowMat};
use super::unknowns::Offsets;
use super::Stepper;
use crate::linalg::norm;
use crate::params::GenAlpha;
use crate::sets::IndexSets;
use crate::system::{Probes, System};

impl<S: System> Stepper<S> {
    /// Fills `work.res` with R(x) for the given sets.
    pub(super) fn residual(&mut self, x: &[f64], sets: &IndexSets, _p: &GenAlpha) {
        let o = self.off;
        let dt = self.options.dt;
        let l = &self.layout;
        let w = &mut self.work;
        let e = &w.eval;
        let it = &w.it;
        let r = &mut w.res;
        r.iter_mut().for_each(|v| *v = 0.0);
        // Smooth rows (eq. 127).
        for &(i, j, m) in &e.mass.entries {
            r[o.a + i] += dt * m * x[o.a + j];
            r[o.uu + i] += m * x[o.uu + j];
            r[o.qq + i] += m * x[o.qq + j] / dt;
        }
        for i in 0..o.nu {
            r[o.a + i] -= dt * e.forces[i];
        }
        for &(i, c, v) in &e.position_w.entries {
            r[o.a + i] -= dt * v * it.lam_p[c];
            r[o.uu + i] -= v * it.cap_p[c];
            r[o.qq + i] -= v * it.kap_p[c] / dt;
        }
        for &(i, c, v) in &e.velocity_w.entries {
            r[o.a + i] -= dt * v * it.lam_v[c];
            r[o.uu + i] -= v * it.cap_v[c];
            r[o.qq + i] -= v * it.half_cap_v[c] / dt;
        }
        // Bilateral constraints on all their levels.
        for i in 0..o.ng {
            let rp = w.r_pos[i];
            r[o.kg + i] = rp * it.p[i] / dt;
            r[o.cg + i] = rp * it.xi_p[i];
            r[o.lg + i] = rp * it.acc_p[i] * dt;
        }
        for i in 0..o.nga {
            let rv = w.r_vel[i];
            r[o.cga + i] = rv * it.xi_v[i];
            r[o.lga + i] = rv * it.acc_v[i] * dt;
        }
        // Normal contacts (eqs. 128–136).
        for k in 0..o.nn {
            let pk = o.ng + k;
            let rp = w.r_pos[pk];
            r[o.kn + k] = if sets.a[k] {
                rp * it.p[pk]
            } else {
                it.kappa_hat[k]
            } / dt;
            r[o.cn + k] = if sets.b[k] {
                rp * it.xi_p[pk]
            } else {
                it.p_n[k]
            };
            r[o.ln + k] = if sets.c[k] {
                rp * it.acc_p[pk]
            } else {
                x[o.ln + k]
            } * dt;
        }
        // Friction laws (eqs. 137–142).
        for (j, law) in l.friction.iter().enumerate() {
            let f0 = self.law_off[j];
            let nc = law.components;
            let vs = o.nga + f0;
            let active = law.normals.iter().any(|&k| sets.a[k]);
            let rl = w.r_law[j];
            let p_hat = law.mu * law.normals.iter().map(|&k| it.p_n[k]).sum::<f64>().max(0.0);
            let l_hat = law.mu
                * law
                    .normals
                    .iter()
                    .map(|&k| x[o.ln + k])
                    .sum::<f64>()
                    .max(0.0);
            let dirs = active.then(|| {
                SlidingDirections::new(
                    rl,
                    (sets.d[j], sets.e[j]),
                    &it.xi_v[vs..vs + nc],
                    &it.p_f[f0..f0 + nc],
                    (&it.v[vs..vs + nc], &it.acc_v[vs..vs + nc]),
                    &x[o.lf + f0..o.lf + f0 + nc],
                )
            });
            for m in 0..nc {
                let c = f0 + m;
                let (vel_row, acc_row) = match &dirs {
                    None => (it.p_f[c], x[o.lf + c]),
                    Some(dirs) => {
                        let vel = match &dirs.velocity {
                            None => rl * it.xi_v[vs + m],
                            Some(d) => it.p_f[c] + p_hat * direction(d.vector(), m),
                        };
                        let acc = match &dirs.acceleration {
                            None => rl * it.acc_v[vs + m],
                            Some(d) => x[o.lf + c] + l_hat * direction(d.vector(), m),
                        };
                        (vel, acc)
                    }
                };
                r[o.cf + c] = vel_row;
                r[o.lf + c] = acc_row * dt;
            }
        }
    }

    /// Fills `work.jac` with the semismooth Jacobian for frozen sets (eq. 143), in the
    /// columns of the unknowns z of [`KinematicColumns`]: ∂R/∂x · T.
    ///
    /// The closed contact rows get an explicit zero entry where
    /// [`Self::regularize`] puts ε times the diagonal entry the row has when open (see
    /// `Options::regularization`); `work.regularized` lists their positions in `work.jac`.
    pub(super) fn jacobian(&mut self, x: &[f64], sets: &IndexSets, p: &GenAlpha) {
        self.derivative_rows(x);
        self.assemble_jacobian(x, sets, p, None);
    }

    /// The system's exact derivatives at the current iterate, and from them the rows
    /// ∂(level)/∂x of every constraint's levels that the Jacobian's contact rows copy.
    fn derivative_rows(&mut self, x: &[f64]) {
        let o = self.off;
        let dt = self.options.dt;
        let t1 = self.state.t + dt;
        let l = &self.layout;
        let w = &mut self.work;
        // Exact derivatives from the system.
        w.der.clear();
        {
            let it = &w.it;
            let probes = Probes {
                a: &x[o.a..o.a + o.nu],
                u_old: &self.state.u,
                dynamics: [
                    (&x[o.a..o.a + o.nu], &it.lam_p, &it.lam_v),
                    (&x[o.uu..o.uu + o.nu], &it.cap_p, &it.cap_v),
                    (&x[o.qq..o.qq + o.nu], &it.kap_p, &it.half_cap_v),
                ],
                unused_position: &w.unused_position,
                unused_velocity: &w.unused_velocity,
            };
            self.system
                .derivatives(t1, &it.q1, &it.u1, &probes, &mut w.der);
        }
        let d = &w.der;
        let e = &w.eval;
        let b = &w.b;
        // q_{n+1} and u_{n+1} depend on z through y_q and y_u alone.
        let qcols = [(o.qq, 1.0)];
        let ucols = [(o.uu, 1.0)];
        let np = l.n_position();
        let nv = l.n_velocity();
        // Rows of ∂(level)/∂x.
        push_q_derivative(&mut w.dg.tmp, &d.position_q, b, 0, 1.0, &qcols);
        w.dg.build(np);
        push_q_derivative(&mut w.dxp.tmp, &d.position_rate_q[0], b, 0, 1.0, &qcols);
        for &(r, j, v) in &d.position_rate_q[1].entries {
            let en = if r < o.ng { 0.0 } else { l.e_n[r - o.ng] };
            if en != 0.0 {
                for (i, bij) in b.row(j) {
                    for &(off, c) in &qcols {
                        w.dxp.tmp.push((r, off + i, en * c * v * bij));
                    }
                }
            }
        }
        push_u_derivative(&mut w.dxp.tmp, &e.position_w, true, 0, 1.0, &ucols);
        w.dxp.build(np);
        push_q_derivative(&mut w.dap.tmp, &d.position_accel_q, b, 0, 1.0, &qcols);
        push_u_derivative(&mut w.dap.tmp, &d.position_accel_u, false, 0, 1.0, &ucols);
        push_u_derivative(&mut w.dap.tmp, &e.position_w, true, 0, 1.0, &[(o.a, 1.0)]);
        w.dap.build(np);
        push_q_derivative(&mut w.dxv.tmp, &d.velocity_q[0], b, 0, 1.0, &qcols);
        for &(r, j, v) in &d.velocity_q[1].entries {
            let ef = if r < o.nga {
                0.0
            } else {
                self.comp_ef[r - o.nga]
            };
            if ef != 0.0 {
                for (i, bij) in b.row(j) {
                    for &(off, c) in &qcols {
                        w.dxv.tmp.push((r, off + i, ef * c * v * bij));
                    }
                }
            }
        }
        push_u_derivative(&mut w.dxv.tmp, &e.velocity_w, true, 0, 1.0, &ucols);
        w.dxv.build(nv);
        push_q_derivative(&mut w.dgv.tmp, &d.velocity_q[0], b, 0, 1.0, &qcols);
        push_u_derivative(&mut w.dgv.tmp, &e.velocity_w, true, 0, 1.0, &ucols);
        w.dgv.build(nv);
        push_q_derivative(&mut w.dav.tmp, &d.velocity_accel_q, b, 0, 1.0, &qcols);
        push_u_derivative(&mut w.dav.tmp, &d.velocity_accel_u, false, 0, 1.0, &ucols);
        push_u_derivative(&mut w.dav.tmp, &e.velocity_w, true, 0, 1.0, &[(o.a, 1.0)]);
        w.dav.build(nv);
    }

    /// [`Self::jacobian`] from the derivative rows [`Self::derivative_rows`] computed last,
    /// which need not be those of this iterate: the low-rank update (`low_rank`) forms
    /// the rows of changed index sets at the kept factors' linearization point.
    pub(super) fn assemble_jacobian(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &GenAlpha,
        only: Option<&ContactRows>,
    ) {
        let o = self.off;
        let dt = self.options.dt;
        let shifted = self.shifted_velocity_constraints();
        let KinematicColumns { c_ua, c_qa } = KinematicColumns::new(dt, p);
        // ∂P/∂λ and ∂κ̂/∂λ_N: the percussions follow λ (eqs. 95, 96) as u_{n+1} and
        // q_{n+1} follow a (eqs. 73, 125), with the same factors Δt γ α_r and Δt² β α_r.
        let (c_pl, c_kl) = (c_ua, c_qa);
        let l = &self.layout;
        let w = &mut self.work;
        let d = &w.der;
        let e = &w.eval;
        let b = &w.b;
        let qcols = [(o.qq, 1.0)];
        let ucols = [(o.uu, 1.0)];
        let jac = &mut w.jac;
        // Where the ε entries go, so that the rows can be scaled by their plain entries.
        let mut regularized = Regularized {
            at: &mut w.regularized,
            scale: &mut w.regularization_scale,
        };
        regularized.at.clear();
        regularized.scale.clear();
        jac.clear();
        let col_p = |c: usize, first: usize, second: usize| {
            if c < o.ng {
                first + c
            } else {
                second + c - o.ng
            }
        };
        let col_v = |c: usize, first: usize, second: usize| {
            if c < o.nga {
                first + c
            } else {
                second + c - o.nga
            }
        };
        let copy_row =
            |jac: &mut Vec<(usize, usize, f64)>, m: &RowMat, src: usize, dst: usize, s: f64| {
                for (c, v) in m.row(src) {
                    jac.push((dst, c, s * v));
                }
            };
        // The rows no set changes, left out of a low-rank update's rows.
        if only.is_none() {
            // Smooth rows (eq. 127).
            push_u_derivative(jac, &e.mass, false, o.a, dt, &[(o.a, 1.0)]);
            push_u_derivative(jac, &d.forces_u, false, o.a, -dt, &ucols);
            push_q_derivative(jac, &d.dynamics_q[0], b, o.a, dt, &qcols);
            push_q_derivative(jac, &d.forces_q, b, o.a, -dt, &qcols);
            // M U = M (y_u − c_u a) and M Q = M (y_q − c_q a).
            push_u_derivative(jac, &e.mass, false, o.uu, 1.0, &[(o.uu, 1.0), (o.a, -c_ua)]);
            push_q_derivative(jac, &d.dynamics_q[1], b, o.uu, 1.0, &qcols);
            push_u_derivative(
                jac,
                &e.mass,
                false,
                o.qq,
                1.0 / dt,
                &[(o.qq, 1.0), (o.a, -c_qa)],
            );
            push_q_derivative(jac, &d.dynamics_q[2], b, o.qq, 1.0 / dt, &qcols);
            for &(i, c, v) in &e.position_w.entries {
                jac.push((o.a + i, col_p(c, o.lg, o.ln), -dt * v));
                jac.push((o.uu + i, col_p(c, o.cg, o.cn), -v));
                jac.push((o.qq + i, col_p(c, o.kg, o.kn), -v / dt));
            }
            for &(i, c, v) in &e.velocity_w.entries {
                jac.push((o.a + i, col_v(c, o.lga, o.lf), -dt * v));
                jac.push((o.uu + i, col_v(c, o.cga, o.cf), -v));
                if c < shifted {
                    jac.push((o.qq + i, col_v(c, o.cga, o.cf), -0.5 * v));
                }
            }
            for i in 0..o.ng {
                let rp = w.r_pos[i];
                copy_row(jac, &w.dg, i, o.kg + i, rp / dt);
                copy_row(jac, &w.dxp, i, o.cg + i, rp);
                copy_row(jac, &w.dap, i, o.lg + i, rp * dt);
            }
            for i in 0..o.nga {
                let rv = w.r_vel[i];
                copy_row(jac, &w.dxv, i, o.cga + i, rv);
                copy_row(jac, &w.dav, i, o.lga + i, rv * dt);
            }
        }
        // Normal contacts.
        for k in 0..o.nn {
            if only.is_some_and(|only| !only.normals[k]) {
                continue;
            }
            let pk = o.ng + k;
            let rp = w.r_pos[pk];
            if sets.a[k] {
                copy_row(jac, &w.dg, pk, o.kn + k, rp / dt);
                regularized.push(jac, o.kn + k, EpsScale::PerDt);
            } else {
                jac.push((o.kn + k, o.kn + k, 1.0 / dt));
                jac.push((o.kn + k, o.ln + k, c_kl / dt));
            }
            if sets.b[k] {
                copy_row(jac, &w.dxp, pk, o.cn + k, rp);
                regularized.push(jac, o.cn + k, EpsScale::One);
            } else {
                jac.push((o.cn + k, o.cn + k, 1.0));
                jac.push((o.cn + k, o.ln + k, c_pl));
            }
            if sets.c[k] {
                copy_row(jac, &w.dap, pk, o.ln + k, rp * dt);
                regularized.push(jac, o.ln + k, EpsScale::TimesDt);
            } else {
                jac.push((o.ln + k, o.ln + k, dt));
            }
        }
        // Friction laws.
        let it = &w.it;
        for (j, law) in l.friction.iter().enumerate() {
            if only.is_some_and(|only| !only.laws[j]) {
                continue;
            }
            let f0 = self.law_off[j];
            let nc = law.components;
            let vs = o.nga + f0;
            let active = law.normals.iter().any(|&k| sets.a[k]);
            let rl = w.r_law[j];
            let p_sum: f64 = law.normals.iter().map(|&k| it.p_n[k]).sum();
            let l_sum: f64 = law.normals.iter().map(|&k| x[o.ln + k]).sum();
            if !active {
                for c in f0..f0 + nc {
                    jac.push((o.cf + c, o.cf + c, 1.0));
                    jac.push((o.cf + c, o.lf + c, c_pl));
                    jac.push((o.lf + c, o.lf + c, dt));
                }
                continue;
            }
            let dirs = SlidingDirections::new(
                rl,
                (sets.d[j], sets.e[j]),
                &it.xi_v[vs..vs + nc],
                &it.p_f[f0..f0 + nc],
                (&it.v[vs..vs + nc], &it.acc_v[vs..vs + nc]),
                &x[o.lf + f0..o.lf + f0 + nc],
            );
            // P_F = Λ_F + c λ_F and λ_F, as the force columns of the prox arguments
            // r ξ − P_F and r γ̇ − λ_F.
            let p_f_cols = [(o.cf + f0, 1.0), (o.lf + f0, c_pl)];
            let lambda_f_cols = [(o.lf + f0, 1.0)];
            for m in 0..nc {
                let c = f0 + m;
                let (rv, ra) = (o.cf + c, o.lf + c);
                match &dirs.velocity {
                    None => {
                        copy_row(jac, &w.dxv, vs + m, rv, rl);
                        regularized.push(jac, rv, EpsScale::One);
                    }
                    Some(d) => {
                        // P_F + μ P̂ ξ/‖ξ‖
                        jac.push((rv, o.cf + c, 1.0));
                        jac.push((rv, o.lf + c, c_pl));
                        let radius_cols: Vec<(usize, f64)> = law
                            .normals
                            .iter()
                            .flat_map(|&k| [(o.cn + k, 1.0), (o.ln + k, c_pl)])
                            .collect();
                        let arg = if d.projected {
                            SlipArgument::Projected(&w.dxv, vs, rl, &p_f_cols)
                        } else {
                            SlipArgument::Rows(&w.dxv, vs)
                        };
                        slip_row(
                            jac,
                            rv,
                            1.0,
                            law.mu,
                            p_sum,
                            &radius_cols,
                            d.vector(),
                            m,
                            arg,
                        );
                    }
                }
                match &dirs.acceleration {
                    None => {
                        copy_row(jac, &w.dav, vs + m, ra, rl * dt);
                        regularized.push(jac, ra, EpsScale::TimesDt);
                    }
                    Some(d) => {
                        jac.push((ra, o.lf + c, dt));
                        let radius_cols: Vec<(usize, f64)> =
                            law.normals.iter().map(|&k| (o.ln + k, 1.0)).collect();
                        let arg = match (sets.d[j], d.projected) {
                            (true, false) => SlipArgument::Rows(&w.dav, vs),
                            (true, true) => SlipArgument::Projected(&w.dav, vs, rl, &lambda_f_cols),
                            (false, false) => SlipArgument::Rows(&w.dgv, vs),
                            (false, true) => SlipArgument::Projected(&w.dxv, vs, rl, &p_f_cols),
                        };
                        slip_row(jac, ra, dt, law.mu, l_sum, &radius_cols, d.vector(), m, arg);
                    }
                }
            }
        }
    }
}

/// The contacts and friction laws whose rows [`Stepper::assemble_jacobian`] assembles
/// alone (a low-rank update's changed rows).
#[derive(Debug, Clone, Default)]
pub(super) struct ContactRows {
    pub normals: Vec<bool>,
    pub laws: Vec<bool>,
}

/// The diagonal entry a closed contact row has in its open form, of which its
/// regularization entry is ε times: 1/Δt (κ rows), 1 (Λ rows) or Δt (λ rows).
#[derive(Debug, Clone, Copy)]
pub(super) enum EpsScale {
    PerDt,
    One,
    TimesDt,
}

impl EpsScale {
    fn entry(self, eps: f64, dt: f64) -> f64 {
        match self {
            Self::PerDt => eps / dt,
            Self::One => eps,
            Self::TimesDt => eps * dt,
        }
    }
}

/// Where the regularization entries of the Newton matrix go.
struct Regularized<'a> {
    at: &'a mut Vec<usize>,
    scale: &'a mut Vec<EpsScale>,
}

impl Regularized<'_> {
    /// Pushes the diagonal entry of `row` (a multiplier's own row and column), zero until
    /// [`Stepper::regularize`] sets it.
    fn push(&mut self, jac: &mut Vec<(usize, usize, f64)>, row: usize, scale: EpsScale) {
        self.at.push(jac.len());
        self.scale.push(scale);
        jac.push((row, row, 0.0));
    }
}

impl<S: System> Stepper<S> {
    /// Sets the regularization entries of the assembled Jacobian to ε times the open
    /// form's diagonal entry of their rows (docs/method.md §7).
    pub(super) fn regularize(&mut self, eps: f64) {
        let dt = self.options.dt;
        let w = &mut self.work;
        for (&i, &scale) in w.regularized.iter().zip(&w.regularization_scale) {
            w.jac[i].2 = scale.entry(eps, dt);
        }
    }
}

/// The unknowns in which the Newton matrix is assembled and factored:
/// z = (a, y_u, y_q, the multipliers) with y_u = U + c_u a and y_q = Q + c_q a, where
/// c_u = ∂u_{n+1}/∂a = Δt γ α_r and c_q B(q_n) = ∂q_{n+1}/∂a = Δt² β α_r B(q_n) (eqs. 73,
/// 125). Then u_{n+1} depends on z through y_u alone and q_{n+1} through y_q alone, so
/// every derivative of the system enters the matrix once, in the columns of y, instead of
/// once in y's and once in a's columns: a's columns keep only the explicit M a, M U, M Q
/// and Wᵀa. That halves the entries the system's derivatives put in the matrix and leaves
/// a's columns nearly empty, which the sparse elimination's fill follows
/// (docs/method.md §4, "The Jacobian"). The update dx = T dz is recovered by
/// [`KinematicColumns::to_unknowns`].
#[derive(Debug, Clone, Copy)]
pub(super) struct KinematicColumns {
    /// c_u = ∂u_{n+1}/∂a.
    pub c_ua: f64,
    /// c_q = ∂q_{n+1}/∂a, times B(q_n).
    pub c_qa: f64,
}

impl KinematicColumns {
    pub(super) fn new(dt: f64, p: &GenAlpha) -> Self {
        let ar = p.alpha_r();
        Self {
            c_ua: dt * p.gamma * ar,
            c_qa: dt * dt * p.beta * ar,
        }
    }

    /// dx = T dz: dU = dy_u − c_u da and dQ = dy_q − c_q da, in place.
    pub(super) fn to_unknowns(self, o: &Offsets, dz: &mut [f64]) {
        for i in 0..o.nu {
            let da = dz[o.a + i];
            dz[o.uu + i] -= self.c_ua * da;
            dz[o.qq + i] -= self.c_qa * da;
        }
    }

    /// The columns of ∂R/∂x from those of ∂R/∂x · T (`j`, dense), in place:
    /// ∂R/∂a = (∂R/∂z)_a + c_u (∂R/∂z)_{y_u} + c_q (∂R/∂z)_{y_q}.
    pub(super) fn to_unknown_columns(self, o: &Offsets, j: &mut nalgebra::DMatrix<f64>) {
        for i in 0..o.nu {
            let col = j.column(o.uu + i) * self.c_ua + j.column(o.qq + i) * self.c_qa;
            let mut a = j.column_mut(o.a + i);
            a += col;
        }
    }
}

/// Below this ratio r‖ξ‖ / ‖r ξ − P_F‖ the slip velocity ξ of a two-component law outside
/// D carries no direction (it is round-off around a rolling contact): the law's sliding
/// rows then take the direction of the prox argument r ξ − P_F instead (docs/method.md
/// §3).
pub const NEGLIGIBLE_SLIP: f64 = 1e-9;

/// The vector whose direction one sliding row of a friction law takes: its own vector
/// (ξ_F, γ_F or γ̇_F as in eqs. 139–142) while that has a direction, the prox argument of
/// the law's level when a disk law's own vector is negligible against it
/// (r‖own‖ ≤ [`NEGLIGIBLE_SLIP`] ‖argument‖).
///
/// Outside D, a = r ξ − P_F has ‖a‖ > μP̂ ≥ 0, so it always has a direction; and at a
/// solution outside D, P_F = −μP̂ a/‖a‖ gives r ξ = a (1 − μP̂/‖a‖), so ξ ∥ a and both
/// forms agree (likewise b = r γ̇ − λ_F outside E). A sliding row written with ξ/‖ξ‖
/// when ‖ξ‖ is round-off has derivatives of order P̂/‖ξ‖ (measured 1e31 at the start of
/// a cylinder's spin-up, whose floor contact rolls; and with γ̇ at a contact held on its
/// stick–slip bound) and makes the Newton matrix numerically singular; with a/‖a‖ they
/// stay of order 1. An interval law (one component) has no such blow-up, its projector
/// 1 − d d being zero, and keeps the paper's rows.
struct GuardedDirection {
    n: usize,
    vector: [f64; 2],
    /// Whether `vector` is the prox argument.
    projected: bool,
}

impl GuardedDirection {
    fn new(r: f64, own: &[f64], argument: &[f64; 2]) -> Self {
        let n = own.len().min(2);
        let tiny = if n == 2 {
            NEGLIGIBLE_SLIP * norm(&argument[..n])
        } else {
            0.0
        };
        let projected = tiny > 0.0 && r * norm(own) <= tiny;
        let mut vector = *argument;
        if !projected {
            vector[..n].copy_from_slice(&own[..n]);
        }
        Self {
            n,
            vector,
            projected,
        }
    }

    fn vector(&self) -> &[f64] {
        &self.vector[..self.n]
    }
}

/// r s − f over a law's one or two components.
fn prox_argument(r: f64, s: &[f64], f: &[f64]) -> [f64; 2] {
    let mut a = [0.0; 2];
    for (m, am) in a.iter_mut().enumerate().take(s.len()) {
        *am = r * s[m] - f[m];
    }
    a
}

/// The sliding directions of one active friction law under its sets: None for a row
/// that sticks (velocity level in D, acceleration level in E).
struct SlidingDirections {
    velocity: Option<GuardedDirection>,
    acceleration: Option<GuardedDirection>,
}

impl SlidingDirections {
    /// For sets (in D, in E), with ξ_F and P_F, (γ_F, γ̇_F) and λ_F of the law.
    fn new(
        r: f64,
        (d, e): (bool, bool),
        xi: &[f64],
        p_f: &[f64],
        (v, acc): (&[f64], &[f64]),
        lambda_f: &[f64],
    ) -> Self {
        let a = (!d).then(|| prox_argument(r, xi, p_f));
        Self {
            velocity: a.map(|a| GuardedDirection::new(r, xi, &a)),
            acceleration: match a {
                Some(a) => Some(GuardedDirection::new(r, v, &a)),
                None if !e => Some(GuardedDirection::new(
                    r,
                    acc,
                    &prox_argument(r, acc, lambda_f),
                )),
                None => None,
            },
        }
    }
}

/// The derivative rows ∂v_m'/∂x of the vector a sliding row takes its direction from.
#[derive(Clone, Copy)]
pub(crate) enum SlipArgument<'a> {
    /// Rows `vs + m'` of a kept derivative matrix.
    Rows(&'a RowMat, usize),
    /// A prox argument r s − f: r times rows `vs + m'` of ∂s/∂x, minus ∂f/∂x, f_m' being
    /// the sum of coefficient times unknown over `(column of component 0, coefficient)`.
    Projected(&'a RowMat, usize, f64, &'a [(usize, f64)]),
}

impl SlipArgument<'_> {
    fn for_each(self, mp: usize, mut f: impl FnMut(usize, f64)) {
        match self {
            Self::Rows(dv, vs) => dv.row(vs + mp).for_each(|(c, v)| f(c, v)),
            Self::Projected(ds, vs, r, force) => {
                ds.row(vs + mp).for_each(|(col, v)| f(col, r * v));
                for &(col, coef) in force {
                    f(col + mp, -coef);
                }
            }
        }
    }
}

/// Component `m` of v/‖v‖, 0 when ‖v‖ = 0 (ERRATA 24: the zero norm is guarded).
pub(crate) fn direction(v: &[f64], m: usize) -> f64 {
    let n = norm(v);
    if n > 0.0 {
        v[m] / n
    } else {
        0.0
    }
}

/// Jacobian of the sliding term μ S d_m(v), S = Σ multipliers clamped at zero, d = v/‖v‖:
/// μ d_m ∂S + μ S (δ_mm' − d_m d_m')/‖v‖ ∂v_m' (docs/method.md §4).
#[allow(clippy::too_many_arguments)]
pub(crate) fn slip_row(
    jac: &mut Vec<(usize, usize, f64)>,
    row: usize,
    scale: f64,
    mu: f64,
    sum: f64,
    radius_cols: &[(usize, f64)],
    v: &[f64],
    m: usize,
    dv: SlipArgument<'_>,
) {
    let n = norm(v);
    if n <= 0.0 || sum <= 0.0 {
        return;
    }
    let dm = v[m] / n;
    for &(c, f) in radius_cols {
        jac.push((row, c, scale * mu * dm * f));
    }
    let radius = mu * sum;
    for (mp, &vmp) in v.iter().enumerate() {
        let proj = f64::from(u8::from(m == mp)) - dm * vmp / n;
        if proj == 0.0 {
            continue;
        }
        dv.for_each(mp, |c, val| {
            jac.push((row, c, scale * radius * proj / n * val));
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{FrictionLaw, Layout};
    use nalgebra::{DMatrix, DVector};

    /// The matrix the stepper factors, J T, and the update it returns, T dz, are those
    /// of the Jacobian in x: (J T) dz = J (T dz) for any J T and dz. With the
    /// finite-difference check of `to_unknown_columns` (crates/nsga/tests/jacobian.rs),
    /// this makes the update an exact Newton update in x.
    #[test]
    fn the_update_in_x_solves_the_system_in_z() {
        let layout = Layout {
            nq: 3,
            nu: 3,
            n_bilateral_position: 1,
            n_bilateral_velocity: 0,
            e_n: vec![0.0, 0.5],
            friction: vec![FrictionLaw {
                mu: 0.3,
                e_f: 0.0,
                normals: vec![1],
                components: 1,
            }],
        };
        let o = Offsets::new(&layout);
        let columns = KinematicColumns::new(0.01, &GenAlpha::new(0.5));
        let entry = |i: usize, j: usize| ((7 * i + 3 * j) as f64).sin();
        let j_z = DMatrix::from_fn(o.n, o.n, entry);
        let dz = DVector::from_fn(o.n, |i, _| (i as f64).cos());
        let mut j_x = j_z.clone();
        columns.to_unknown_columns(&o, &mut j_x);
        let mut dx = dz.clone();
        columns.to_unknowns(&o, dx.as_mut_slice());
        let (lhs, rhs) = (&j_z * &dz, &j_x * &dx);
        assert!((lhs - rhs).amax() < 1e-12);
        assert!(
            (&dx - &dz).amax() > 1e-6,
            "the change of unknowns is not the identity"
        );
    }

    /// A one-component (interval) law sliding at a round-off slip, down to where its
    /// square is subnormal: the row is μ d ∂S alone, d = ±1, since the projector 1 − d²
    /// is zero. When ‖v‖ was taken as √(v²), a slip of 1e-160 gave d ≠ ±1 and entries
    /// of order μS/‖v‖·ε ≈ 1e140 on the slip's columns, a singular Newton matrix.
    #[test]
    fn an_interval_law_has_no_projector_at_a_round_off_slip() {
        let mut dv = RowMat::default();
        dv.tmp.push((0, 3, 0.7));
        dv.tmp.push((0, 4, -0.7));
        dv.build(1);
        for slip in [1e-3, 1e-150, -1e-155, 1e-160, -3e-161, 1e-300] {
            let mut jac = Vec::new();
            let cols = [(7, 1.0), (8, 0.5)];
            slip_row(
                &mut jac,
                0,
                1.0,
                0.5,
                2.0,
                &cols,
                &[slip],
                0,
                SlipArgument::Rows(&dv, 0),
            );
            let sign = slip.signum();
            assert_eq!(
                jac,
                vec![(0, 7, 0.5 * sign), (0, 8, 0.25 * sign)],
                "slip {slip:e}"
            );
        }
    }
}
