//! Residual (eqs. 127–142) and its semismooth Jacobian (eq. 143), rows scaled to
//! impulse units: acceleration-level rows × Δt, position-level rows ÷ Δt.

use super::rows::{push_q_derivative, push_u_derivative, RowMat};
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
            let xi = &it.xi_v[vs..vs + nc];
            let slip = SlipDirections::new(rl, xi, &it.v[vs..vs + nc], &it.p_f[f0..f0 + nc]);
            for m in 0..nc {
                let c = f0 + m;
                let (vel_row, acc_row) = if !active {
                    (it.p_f[c], x[o.lf + c])
                } else if sets.d[j] {
                    let acc = if sets.e[j] {
                        rl * it.acc_v[vs + m]
                    } else {
                        let stick = StickAcceleration::new(
                            rl,
                            &it.acc_v[vs..vs + nc],
                            &x[o.lf + f0..o.lf + f0 + nc],
                        );
                        x[o.lf + c] + l_hat * direction(stick.direction(), m)
                    };
                    (rl * it.xi_v[vs + m], acc)
                } else {
                    (
                        it.p_f[c] + p_hat * direction(slip.velocity_level(), m),
                        x[o.lf + c] + l_hat * direction(slip.acceleration_level(), m),
                    )
                };
                r[o.cf + c] = vel_row;
                r[o.lf + c] = acc_row * dt;
            }
        }
    }

    /// Fills `work.jac` with the semismooth Jacobian ∂R/∂x for frozen sets (eq. 143).
    ///
    /// `eps` regularizes the closed contact rows (see `Options::regularization`): ε times
    /// the diagonal entry the row has when open.
    pub(super) fn jacobian(&mut self, x: &[f64], sets: &IndexSets, p: &GenAlpha, eps: f64) {
        let o = self.off;
        let dt = self.options.dt;
        let ar = p.alpha_r();
        let c_ua = dt * p.gamma * ar; // ∂u_{n+1}/∂a
        let c_qa = dt * dt * p.beta * ar; // ∂q_{n+1}/∂a (times B)
        let c_pl = dt * p.gamma * ar; // ∂P/∂λ
        let c_kl = dt * dt * p.beta * ar; // ∂κ̂/∂λ_N
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
        let qcols = [(o.a, c_qa), (o.qq, 1.0)];
        let ucols = [(o.a, c_ua), (o.uu, 1.0)];
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

        let jac = &mut w.jac;
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
        // Smooth rows (eq. 127).
        push_u_derivative(jac, &e.mass, false, o.a, dt, &[(o.a, 1.0)]);
        push_u_derivative(jac, &d.forces_u, false, o.a, -dt, &ucols);
        push_q_derivative(jac, &d.dynamics_q[0], b, o.a, dt, &qcols);
        push_q_derivative(jac, &d.forces_q, b, o.a, -dt, &qcols);
        push_u_derivative(jac, &e.mass, false, o.uu, 1.0, &[(o.uu, 1.0)]);
        push_q_derivative(jac, &d.dynamics_q[1], b, o.uu, 1.0, &qcols);
        push_u_derivative(jac, &e.mass, false, o.qq, 1.0 / dt, &[(o.qq, 1.0)]);
        push_q_derivative(jac, &d.dynamics_q[2], b, o.qq, 1.0 / dt, &qcols);
        for &(i, c, v) in &e.position_w.entries {
            jac.push((o.a + i, col_p(c, o.lg, o.ln), -dt * v));
            jac.push((o.uu + i, col_p(c, o.cg, o.cn), -v));
            jac.push((o.qq + i, col_p(c, o.kg, o.kn), -v / dt));
        }
        for &(i, c, v) in &e.velocity_w.entries {
            jac.push((o.a + i, col_v(c, o.lga, o.lf), -dt * v));
            jac.push((o.uu + i, col_v(c, o.cga, o.cf), -v));
            jac.push((o.qq + i, col_v(c, o.cga, o.cf), -0.5 * v));
        }
        let copy_row =
            |jac: &mut Vec<(usize, usize, f64)>, m: &RowMat, src: usize, dst: usize, s: f64| {
                for (c, v) in m.row(src) {
                    jac.push((dst, c, s * v));
                }
            };
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
        // Normal contacts.
        for k in 0..o.nn {
            let pk = o.ng + k;
            let rp = w.r_pos[pk];
            if sets.a[k] {
                copy_row(jac, &w.dg, pk, o.kn + k, rp / dt);
                jac.push((o.kn + k, o.kn + k, eps / dt));
            } else {
                jac.push((o.kn + k, o.kn + k, 1.0 / dt));
                jac.push((o.kn + k, o.ln + k, c_kl / dt));
            }
            if sets.b[k] {
                copy_row(jac, &w.dxp, pk, o.cn + k, rp);
                jac.push((o.cn + k, o.cn + k, eps));
            } else {
                jac.push((o.cn + k, o.cn + k, 1.0));
                jac.push((o.cn + k, o.ln + k, c_pl));
            }
            if sets.c[k] {
                copy_row(jac, &w.dap, pk, o.ln + k, rp * dt);
                jac.push((o.ln + k, o.ln + k, eps * dt));
            } else {
                jac.push((o.ln + k, o.ln + k, dt));
            }
        }
        // Friction laws.
        let it = &w.it;
        for (j, law) in l.friction.iter().enumerate() {
            let f0 = self.law_off[j];
            let nc = law.components;
            let vs = o.nga + f0;
            let active = law.normals.iter().any(|&k| sets.a[k]);
            let rl = w.r_law[j];
            let p_sum: f64 = law.normals.iter().map(|&k| it.p_n[k]).sum();
            let l_sum: f64 = law.normals.iter().map(|&k| x[o.ln + k]).sum();
            let slip = SlipDirections::new(
                rl,
                &it.xi_v[vs..vs + nc],
                &it.v[vs..vs + nc],
                &it.p_f[f0..f0 + nc],
            );
            // ∂(r ξ − P_F)/∂x, for the directions of a slip law that ξ cannot give.
            let argument = SlipArgument::Projected {
                dxv: &w.dxv,
                vs,
                r: rl,
                p_f: (o.cf + f0, o.lf + f0, c_pl),
            };
            for m in 0..nc {
                let c = f0 + m;
                let (rv, ra) = (o.cf + c, o.lf + c);
                if !active {
                    jac.push((rv, o.cf + c, 1.0));
                    jac.push((rv, o.lf + c, c_pl));
                    jac.push((ra, o.lf + c, dt));
                    continue;
                }
                if sets.d[j] {
                    copy_row(jac, &w.dxv, vs + m, rv, rl);
                    jac.push((rv, o.cf + c, eps));
                } else {
                    // P_F + μ P̂ ξ/‖ξ‖
                    jac.push((rv, o.cf + c, 1.0));
                    jac.push((rv, o.lf + c, c_pl));
                    let radius_cols: Vec<(usize, f64)> = law
                        .normals
                        .iter()
                        .flat_map(|&k| [(o.cn + k, 1.0), (o.ln + k, c_pl)])
                        .collect();
                    let arg = if slip.projected_velocity {
                        argument
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
                        slip.velocity_level(),
                        m,
                        arg,
                    );
                }
                if sets.d[j] && sets.e[j] {
                    copy_row(jac, &w.dav, vs + m, ra, rl * dt);
                    jac.push((ra, o.lf + c, eps * dt));
                } else {
                    jac.push((ra, o.lf + c, dt));
                    let radius_cols: Vec<(usize, f64)> =
                        law.normals.iter().map(|&k| (o.ln + k, 1.0)).collect();
                    let stick = StickAcceleration::new(
                        rl,
                        &it.acc_v[vs..vs + nc],
                        &x[o.lf + f0..o.lf + f0 + nc],
                    );
                    let (v, arg) = if sets.d[j] && stick.projected {
                        // ∂(r γ̇ − λ_F)/∂x.
                        let projected = SlipArgument::Projected {
                            dxv: &w.dav,
                            vs,
                            r: rl,
                            p_f: (o.lf + f0, o.lf + f0, 0.0),
                        };
                        (stick.direction(), projected)
                    } else if sets.d[j] {
                        (&it.acc_v[vs..vs + nc], SlipArgument::Rows(&w.dav, vs))
                    } else if slip.projected_acceleration {
                        (slip.acceleration_level(), argument)
                    } else {
                        (slip.acceleration_level(), SlipArgument::Rows(&w.dgv, vs))
                    };
                    slip_row(jac, ra, dt, law.mu, l_sum, &radius_cols, v, m, arg);
                }
            }
        }
    }
}

/// Below this ratio r‖ξ‖ / ‖r ξ − P_F‖ the slip velocity ξ of a two-component law outside
/// D carries no direction (it is round-off around a rolling contact): the law's sliding
/// rows then take the direction of the prox argument r ξ − P_F instead (docs/method.md
/// §3).
pub const NEGLIGIBLE_SLIP: f64 = 1e-9;

/// The vectors whose directions the sliding rows of one friction law take: ξ and v as
/// in eqs. 139–142 while they have one; the prox argument a = r ξ − P_F when they are
/// negligible against it.
///
/// Outside D, ‖a‖ > μP̂ ≥ 0, so a always has a direction; and at a solution outside D,
/// P_F = −μP̂ a/‖a‖ gives r ξ = a (1 − μP̂/‖a‖), so ξ ∥ a and both forms agree. A sliding
/// row written with ξ/‖ξ‖ when ‖ξ‖ is round-off has derivatives of order P̂/‖ξ‖
/// (measured 1e31 at the start of a cylinder's spin-up, whose floor contact rolls) and
/// makes the Newton matrix numerically singular; with a/‖a‖ they stay of order 1.
struct SlipDirections {
    n: usize,
    xi: [f64; 2],
    v: [f64; 2],
    a: [f64; 2],
    projected_velocity: bool,
    projected_acceleration: bool,
}

impl SlipDirections {
    /// For a law of one or two components (eq. 141's interval or disk).
    fn new(r: f64, xi: &[f64], v: &[f64], p_f: &[f64]) -> Self {
        let n = xi.len().min(2);
        let (mut xs, mut vs, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        for m in 0..n {
            xs[m] = xi[m];
            vs[m] = v[m];
            a[m] = r * xi[m] - p_f[m];
        }
        // Only a disk law (two components) blows up: an interval law's projector
        // 1 − d d is zero, and its rows keep the paper's form.
        let tiny = if n == 2 {
            NEGLIGIBLE_SLIP * norm(&a[..n])
        } else {
            0.0
        };
        Self {
            n,
            projected_velocity: tiny > 0.0 && r * norm(&xs[..n]) <= tiny,
            projected_acceleration: tiny > 0.0 && r * norm(&vs[..n]) <= tiny,
            xi: xs,
            v: vs,
            a,
        }
    }

    /// The vector whose direction the velocity-level sliding row takes.
    fn velocity_level(&self) -> &[f64] {
        if self.projected_velocity {
            &self.a[..self.n]
        } else {
            &self.xi[..self.n]
        }
    }

    /// The vector whose direction the acceleration-level sliding row takes outside D.
    fn acceleration_level(&self) -> &[f64] {
        if self.projected_acceleration {
            &self.a[..self.n]
        } else {
            &self.v[..self.n]
        }
    }
}

/// The vector whose direction the acceleration-level sliding row of a law in D ∖ E takes:
/// γ̇_F as in eq. 142, or the prox argument b = r γ̇_F − λ_F where a two-component law's
/// γ̇_F is negligible against it (outside E, ‖b‖ > μλ̂ ≥ 0; at a solution they agree, as
/// for [`SlipDirections`]). A contact held at its stick–slip bound has γ̇_F of round-off:
/// measured on the pushed cylinders at their minimum force, where the matrix was
/// singular.
struct StickAcceleration {
    n: usize,
    acc: [f64; 2],
    b: [f64; 2],
    projected: bool,
}

impl StickAcceleration {
    fn new(r: f64, acc: &[f64], lambda_f: &[f64]) -> Self {
        let n = acc.len().min(2);
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        for m in 0..n {
            a[m] = acc[m];
            b[m] = r * acc[m] - lambda_f[m];
        }
        let tiny = if n == 2 {
            NEGLIGIBLE_SLIP * norm(&b[..n])
        } else {
            0.0
        };
        Self {
            n,
            acc: a,
            b,
            projected: tiny > 0.0 && r * norm(&a[..n]) <= tiny,
        }
    }

    fn direction(&self) -> &[f64] {
        if self.projected {
            &self.b[..self.n]
        } else {
            &self.acc[..self.n]
        }
    }
}

/// The derivative rows ∂v_m'/∂x of the vector a sliding row takes its direction from.
#[derive(Clone, Copy)]
pub(crate) enum SlipArgument<'a> {
    /// Rows `vs + m'` of a kept derivative matrix.
    Rows(&'a RowMat, usize),
    /// The prox argument r ξ − P_F: r times rows `vs + m'` of ∂ξ/∂x, minus ∂P_F/∂x with
    /// P_F = Λ_F + c λ_F (columns of Λ_F and λ_F of component 0, and c).
    Projected {
        dxv: &'a RowMat,
        vs: usize,
        r: f64,
        p_f: (usize, usize, f64),
    },
}

impl SlipArgument<'_> {
    fn for_each(self, mp: usize, mut f: impl FnMut(usize, f64)) {
        match self {
            Self::Rows(dv, vs) => dv.row(vs + mp).for_each(|(c, v)| f(c, v)),
            Self::Projected {
                dxv,
                vs,
                r,
                p_f: (cap, small, c),
            } => {
                dxv.row(vs + mp).for_each(|(col, v)| f(col, r * v));
                f(cap + mp, -1.0);
                f(small + mp, -c);
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
