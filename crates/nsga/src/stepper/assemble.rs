//! Residual (eqs. 127–142) and its semismooth Jacobian (eq. 143), rows scaled to
//! impulse units: acceleration-level rows × Δt, position-level rows ÷ Δt.

use super::iterate::Iterate;
use super::kinematic::KinematicColumns;
use super::rows::{push_q_derivative, push_u_derivative, RowMat};
use super::scheme::Scheme;
use super::slip::{direction, slip_row, GuardedDirection, SlidingDirections, SlipArgument};
use super::unknowns::Offsets;
use super::{Stepper, Work};
use crate::linalg::max_norm;
use crate::options::JacobianChoice;
use crate::sets::IndexSets;
use crate::system::{Evaluation, FrictionLaw, Probes, System};

/// The round-off of a gap evaluated at coordinates q, in units of ε max|q|: a gap is a
/// difference of coordinates and of offsets of their size, each rounded once. Position
/// rows r g / Δt amplify it by r / Δt, and on heavy bodies (the drum column, r ≈ 200,
/// Δt = 0.005) their round-off reaches 5·10⁻¹¹, above a tolerance of 10⁻¹¹ (docs/method.md
/// §4, "The residual's round-off").
///
/// An argued bound, not a tuned one: it does not pay on the reference workload, whose
/// round-off is a thousandth of the tolerance (the matrix 0.2 % fewer linear solves,
/// time ratio 0.98), but on heavy bodies, where without it Newton cannot converge: the
/// classical column's step at t = 2.135 needed the last resort (976 linear solves to
/// t = 2.14 against 323), and at tol 10⁻¹¹ the drum column took the last resort at 1465
/// of its 1600 steps (1.03·10⁶ linear solves against 759). 0.5 and 1 also converged on
/// the drum column; 2 keeps a margin for gaps summed from several rounded terms.
pub const GAP_ROUND_OFF: f64 = 2.0;

impl<S: System> Stepper<S> {
    /// ‖R‖∞ of `work.res` (for `sets`) beyond the round-off of its position rows: the
    /// measure every attempt compares with the tolerance (docs/method.md §4, "The
    /// residual's round-off"). Where ‖R‖∞ is within the tolerance it is that norm.
    pub(super) fn residual_norm(&self, sets: &IndexSets) -> f64 {
        let (o, r) = (self.off, &self.work.res[..]);
        // A residual that is not finite stays so.
        let plain = max_norm(r);
        if plain <= self.options.tol || plain.is_nan() {
            return plain;
        }
        let (bilateral, contacts) = (o.kg..o.kg + o.ng, o.kn..o.kn + o.nn);
        let others = max_norm(&r[..bilateral.start])
            .max(max_norm(&r[bilateral.end..contacts.start]))
            .max(max_norm(&r[contacts.end..]));
        let round_off = self.gap_round_off();
        bilateral
            .chain(contacts)
            .map(|i| r[i].abs() - self.row_round_off(i, sets, round_off))
            .fold(others, f64::max)
    }

    /// The round-off of a gap at the iterate, ε max|q| times [`GAP_ROUND_OFF`], over Δt
    /// (the position rows' scale, eq. 129).
    pub(super) fn gap_round_off(&self) -> f64 {
        GAP_ROUND_OFF * super::rest::resolution(&self.work.it.q1) / self.options.dt
    }

    /// The round-off of row `i` of R for `sets`, with `gap_round_off` from
    /// [`Stepper::gap_round_off`]: r times it in the position rows r g / Δt of the
    /// bilateral constraints and the contacts in A, zero elsewhere.
    pub(super) fn row_round_off(&self, i: usize, sets: &IndexSets, gap_round_off: f64) -> f64 {
        let o = self.off;
        let r_pos = &self.work.r_pos;
        if (o.kg..o.kg + o.ng).contains(&i) {
            r_pos[i - o.kg] * gap_round_off
        } else if (o.kn..o.kn + o.nn).contains(&i) && sets.a[i - o.kn] {
            r_pos[o.ng + i - o.kn] * gap_round_off
        } else {
            0.0
        }
    }

    /// Fills `work.res` with R(x) for the given sets.
    pub(super) fn residual(&mut self, x: &[f64], sets: &IndexSets, _p: &Scheme) {
        let o = self.off;
        let dt = self.options.dt;
        let l = &self.layout;
        let w = &mut self.work;
        let e = &w.eval;
        let it = &w.it;
        // Slices, not the vectors: their pointers and lengths are read once, not at each
        // entry of the loops over the triplets.
        let r: &mut [f64] = &mut w.res;
        r.fill(0.0);
        smooth_residual(r, o, x, dt, e, it);
        // Bilateral constraints on all their levels.
        let (p, xi_p, acc_p) = (&it.p[..], &it.xi_p[..], &it.acc_p[..]);
        for i in 0..o.ng {
            let rp = w.r_pos[i];
            r[o.kg + i] = rp * p[i] / dt;
            r[o.cg + i] = rp * xi_p[i];
            r[o.lg + i] = rp * acc_p[i] * dt;
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
                rp * p[pk]
            } else {
                it.kappa_hat[k]
            } / dt;
            r[o.cn + k] = if sets.b[k] { rp * xi_p[pk] } else { it.p_n[k] };
            r[o.ln + k] = if sets.c[k] {
                rp * acc_p[pk]
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
                let law = (rl, law, self.options.interval_sign_from_prox);
                SlidingDirections::of_law(it, x, law, (sets.d[j], sets.e[j]), (vs, o.lf, f0))
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
    /// `LinearOptions::regularization`); `work.regularized` lists their positions in `work.jac`.
    pub(super) fn jacobian(&mut self, x: &[f64], sets: &IndexSets, p: &Scheme) {
        self.derivative_rows(x);
        self.assemble_jacobian(x, sets, p, None);
        if let JacobianChoice::FiniteDifference(eps) = self.options.linear.jacobian {
            // The exact matrix has marked the rows a singular matrix regularizes.
            self.finite_difference_jacobian(x, sets, p, eps);
        }
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
        p: &Scheme,
        only: Option<&ContactRows>,
    ) {
        let o = self.off;
        let shifted = self.shifted_velocity_constraints(p.friction_shift);
        // Taken out of the buffers while the rows are read from the others.
        let w = &mut self.work;
        let mut jac = std::mem::take(&mut w.jac);
        let mut at = std::mem::take(&mut w.regularized);
        let mut scale = std::mem::take(&mut w.regularization_scale);
        let mut radius = std::mem::take(&mut w.radius_cols);
        jac.clear();
        at.clear();
        scale.clear();
        let mut rows = Assembly {
            o,
            dt: self.options.dt,
            columns: KinematicColumns::new(self.options.dt, &p.alpha),
            w: &self.work,
            jac: &mut jac,
            at: &mut at,
            scale: &mut scale,
            radius: &mut radius,
            interval_sign_from_prox: self.options.interval_sign_from_prox,
        };
        // The rows no set changes, left out of a low-rank update's rows.
        if only.is_none() {
            rows.smooth(shifted);
            rows.bilateral();
        }
        for k in 0..o.nn {
            if only.is_none_or(|only| only.normals[k]) {
                rows.normal_contact(k, sets);
            }
        }
        for (j, law) in self.layout.friction.iter().enumerate() {
            if only.is_none_or(|only| only.laws[j]) {
                rows.friction_law(x, sets, (j, law), self.law_off[j]);
            }
        }
        let w = &mut self.work;
        (w.jac, w.regularized, w.regularization_scale) = (jac, at, scale);
        w.radius_cols = radius;
    }
}

/// Adds the smooth rows of R (eq. 127) to `r`: its a, U and Q rows, three consecutive
/// blocks of one row per velocity.
fn smooth_residual(
    r: &mut [f64],
    o: Offsets,
    x: &[f64],
    dt: f64,
    e: &Evaluation<f64>,
    it: &Iterate,
) {
    let (ra, rest) = r[o.a..o.qq + o.nu].split_at_mut(o.nu);
    let (ru, rq) = rest.split_at_mut(o.nu);
    let block = |start: usize| &x[start..start + o.nu];
    let (xa, xu, xq) = (block(o.a), block(o.uu), block(o.qq));
    for &(i, j, m) in &e.mass.entries {
        ra[i] += dt * m * xa[j];
        ru[i] += m * xu[j];
        rq[i] += m * xq[j] / dt;
    }
    for (ri, f) in ra.iter_mut().zip(&e.forces) {
        *ri -= dt * f;
    }
    let (lam, cap, kap) = (&it.lam_p[..], &it.cap_p[..], &it.kap_p[..]);
    for &(i, c, v) in &e.position_w.entries {
        ra[i] -= dt * v * lam[c];
        ru[i] -= v * cap[c];
        rq[i] -= v * kap[c] / dt;
    }
    let (lam, cap, half_cap) = (&it.lam_v[..], &it.cap_v[..], &it.half_cap_v[..]);
    for &(i, c, v) in &e.velocity_w.entries {
        ra[i] -= dt * v * lam[c];
        ru[i] -= v * cap[c];
        rq[i] -= v * half_cap[c] / dt;
    }
}

/// The Newton matrix's rows being assembled (eq. 143), in the columns of the unknowns z of
/// [`KinematicColumns`], from the derivative rows and scales of the iterate in `w`.
struct Assembly<'a> {
    o: Offsets,
    dt: f64,
    columns: KinematicColumns,
    w: &'a Work,
    jac: &'a mut Vec<(usize, usize, f64)>,
    /// Where the ε entries go, so that the rows can be scaled by their plain entries.
    at: &'a mut Vec<usize>,
    scale: &'a mut Vec<EpsScale>,
    /// The columns of a sliding row's friction radius, rewritten for each such row.
    radius: &'a mut Vec<(usize, f64)>,
    /// [`Options::interval_sign_from_prox`](crate::Options::interval_sign_from_prox).
    interval_sign_from_prox: bool,
}

impl Assembly<'_> {
    /// Row `src` of `m`, times `s`, as row `dst` of the matrix.
    fn copy_row(&mut self, m: &RowMat, src: usize, dst: usize, s: f64) {
        for (c, v) in m.row(src) {
            self.jac.push((dst, c, s * v));
        }
    }

    /// Pushes the diagonal entry of `row` (a multiplier's own row and column), zero until
    /// [`Stepper::regularize`] sets it.
    fn regularization_entry(&mut self, row: usize, scale: EpsScale) {
        self.at.push(self.jac.len());
        self.scale.push(scale);
        self.jac.push((row, row, 0.0));
    }

    /// The column of position constraint `c`'s multiplier: bilateral from `first`,
    /// normal contacts from `second`.
    fn position_column(&self, c: usize, first: usize, second: usize) -> usize {
        if c < self.o.ng {
            first + c
        } else {
            second + c - self.o.ng
        }
    }

    /// The column of velocity constraint `c`'s multiplier: bilateral from `first`,
    /// friction components from `second`.
    fn velocity_column(&self, c: usize, first: usize, second: usize) -> usize {
        if c < self.o.nga {
            first + c
        } else {
            second + c - self.o.nga
        }
    }

    /// The smooth rows (eq. 127), with the half-step shift of the first `shifted`
    /// velocity constraints' percussions in the Q rows.
    fn smooth(&mut self, shifted: usize) {
        let (o, dt) = (self.o, self.dt);
        let KinematicColumns { c_ua, c_qa } = self.columns;
        let (d, e, b) = (&self.w.der, &self.w.eval, &self.w.b);
        let qcols = [(o.qq, 1.0)];
        let ucols = [(o.uu, 1.0)];
        let jac = &mut *self.jac;
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
            self.jac
                .push((o.a + i, self.position_column(c, o.lg, o.ln), -dt * v));
            self.jac
                .push((o.uu + i, self.position_column(c, o.cg, o.cn), -v));
            self.jac
                .push((o.qq + i, self.position_column(c, o.kg, o.kn), -v / dt));
        }
        for &(i, c, v) in &e.velocity_w.entries {
            self.jac
                .push((o.a + i, self.velocity_column(c, o.lga, o.lf), -dt * v));
            self.jac
                .push((o.uu + i, self.velocity_column(c, o.cga, o.cf), -v));
            if c < shifted {
                self.jac
                    .push((o.qq + i, self.velocity_column(c, o.cga, o.cf), -0.5 * v));
            }
        }
    }

    /// The rows of the bilateral constraints on all their levels.
    fn bilateral(&mut self) {
        let (o, dt, w) = (self.o, self.dt, self.w);
        for i in 0..o.ng {
            let rp = w.r_pos[i];
            self.copy_row(&w.dg, i, o.kg + i, rp / dt);
            self.copy_row(&w.dxp, i, o.cg + i, rp);
            self.copy_row(&w.dap, i, o.lg + i, rp * dt);
        }
        for i in 0..o.nga {
            let rv = w.r_vel[i];
            self.copy_row(&w.dxv, i, o.cga + i, rv);
            self.copy_row(&w.dav, i, o.lga + i, rv * dt);
        }
    }

    /// The three rows of normal contact `k` (eqs. 128–136): a closed level's constraint
    /// row, an open level's multiplier row.
    fn normal_contact(&mut self, k: usize, sets: &IndexSets) {
        let (o, dt, w) = (self.o, self.dt, self.w);
        // ∂P/∂λ and ∂κ̂/∂λ_N: the percussions follow λ (eqs. 95, 96) as u_{n+1} and
        // q_{n+1} follow a (eqs. 73, 125), with the same factors Δt γ α_r and Δt² β α_r.
        let KinematicColumns {
            c_ua: c_pl,
            c_qa: c_kl,
        } = self.columns;
        let pk = o.ng + k;
        let rp = w.r_pos[pk];
        if sets.a[k] {
            self.copy_row(&w.dg, pk, o.kn + k, rp / dt);
            self.regularization_entry(o.kn + k, EpsScale::PerDt);
        } else {
            self.jac.push((o.kn + k, o.kn + k, 1.0 / dt));
            self.jac.push((o.kn + k, o.ln + k, c_kl / dt));
        }
        if sets.b[k] {
            self.copy_row(&w.dxp, pk, o.cn + k, rp);
            self.regularization_entry(o.cn + k, EpsScale::One);
        } else {
            self.jac.push((o.cn + k, o.cn + k, 1.0));
            self.jac.push((o.cn + k, o.ln + k, c_pl));
        }
        if sets.c[k] {
            self.copy_row(&w.dap, pk, o.ln + k, rp * dt);
            self.regularization_entry(o.ln + k, EpsScale::TimesDt);
        } else {
            self.jac.push((o.ln + k, o.ln + k, dt));
        }
    }

    /// The rows of friction law `j` (eqs. 137–142), whose components start at `f0`: a
    /// sticking level's constraint rows, a sliding level's rows along its direction, an
    /// inactive law's multiplier rows.
    fn friction_law(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        (j, law): (usize, &FrictionLaw),
        f0: usize,
    ) {
        let (o, dt, w) = (self.o, self.dt, self.w);
        let c_pl = self.columns.c_ua;
        let nc = law.components;
        let vs = o.nga + f0;
        if !law.normals.iter().any(|&k| sets.a[k]) {
            for c in f0..f0 + nc {
                self.jac.push((o.cf + c, o.cf + c, 1.0));
                self.jac.push((o.cf + c, o.lf + c, c_pl));
                self.jac.push((o.lf + c, o.lf + c, dt));
            }
            return;
        }
        let (it, rl) = (&w.it, w.r_law[j]);
        let signs = (rl, law, self.interval_sign_from_prox);
        let dirs = SlidingDirections::of_law(it, x, signs, (sets.d[j], sets.e[j]), (vs, o.lf, f0));
        let law_at = LawAt {
            law,
            f0,
            vs,
            rl,
            p_sum: law.normals.iter().map(|&k| it.p_n[k]).sum(),
            l_sum: law.normals.iter().map(|&k| x[o.ln + k]).sum(),
        };
        for m in 0..nc {
            self.velocity_row(&law_at, m, dirs.velocity.as_ref());
            self.acceleration_row(&law_at, m, dirs.acceleration.as_ref(), sets.d[j]);
        }
    }

    /// The velocity-level row of component `m` of an active law: its slip's row while it
    /// sticks (in D), P_F + μ P̂ ξ/‖ξ‖ while it slides.
    fn velocity_row(&mut self, at: &LawAt, m: usize, slides: Option<&GuardedDirection>) {
        let (o, w) = (self.o, self.w);
        let c_pl = self.columns.c_ua;
        let c = at.f0 + m;
        let rv = o.cf + c;
        let Some(d) = slides else {
            self.copy_row(&w.dxv, at.vs + m, rv, at.rl);
            self.regularization_entry(rv, EpsScale::One);
            return;
        };
        self.jac.push((rv, o.cf + c, 1.0));
        self.jac.push((rv, o.lf + c, c_pl));
        self.radius.clear();
        self.radius.extend(
            at.law
                .normals
                .iter()
                .flat_map(|&k| [(o.cn + k, 1.0), (o.ln + k, c_pl)]),
        );
        let p_f_cols = at.p_f_columns(o, c_pl);
        let arg = if d.projected {
            SlipArgument::Projected(&w.dxv, at.vs, at.rl, &p_f_cols)
        } else {
            SlipArgument::Rows(&w.dxv, at.vs)
        };
        let (mu, sum) = (at.law.mu, at.p_sum);
        slip_row(self.jac, rv, 1.0, mu, sum, self.radius, d.vector(), m, arg);
    }

    /// The acceleration-level row of component `m` of an active law (`in_d`: whether
    /// it sticks on velocity level): its slip rate's row while it sticks (in E),
    /// λ_F + μ λ̂ along its sliding direction otherwise.
    fn acceleration_row(
        &mut self,
        at: &LawAt,
        m: usize,
        slides: Option<&GuardedDirection>,
        in_d: bool,
    ) {
        let (o, dt, w) = (self.o, self.dt, self.w);
        let c_pl = self.columns.c_ua;
        let c = at.f0 + m;
        let ra = o.lf + c;
        let Some(d) = slides else {
            self.copy_row(&w.dav, at.vs + m, ra, at.rl * dt);
            self.regularization_entry(ra, EpsScale::TimesDt);
            return;
        };
        self.jac.push((ra, o.lf + c, dt));
        self.radius.clear();
        self.radius
            .extend(at.law.normals.iter().map(|&k| (o.ln + k, 1.0)));
        let p_f_cols = at.p_f_columns(o, c_pl);
        let lambda_f_cols = [(o.lf + at.f0, 1.0)];
        let (vs, rl) = (at.vs, at.rl);
        let arg = match (in_d, d.projected) {
            (true, false) => SlipArgument::Rows(&w.dav, vs),
            (true, true) => SlipArgument::Projected(&w.dav, vs, rl, &lambda_f_cols),
            (false, false) => SlipArgument::Rows(&w.dgv, vs),
            (false, true) => SlipArgument::Projected(&w.dxv, vs, rl, &p_f_cols),
        };
        let (mu, sum) = (at.law.mu, at.l_sum);
        slip_row(self.jac, ra, dt, mu, sum, self.radius, d.vector(), m, arg);
    }
}

/// One active friction law at the iterate: its components from `f0`, its velocity
/// constraints from `vs`, its prox parameter, and the sums of its normals' percussions
/// and forces that bound it.
struct LawAt<'a> {
    law: &'a FrictionLaw,
    f0: usize,
    vs: usize,
    rl: f64,
    p_sum: f64,
    l_sum: f64,
}

impl LawAt<'_> {
    /// P_F = Λ_F + c λ_F, as the force columns of the prox argument r ξ − P_F.
    fn p_f_columns(&self, o: Offsets, c_pl: f64) -> [(usize, f64); 2] {
        [(o.cf + self.f0, 1.0), (o.lf + self.f0, c_pl)]
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

#[cfg(test)]
mod tests {
    use crate::systems::chain::Chain;
    use crate::{Options, Stepper};

    /// The top block of a resting column slides: its law's rows are sliding rows, whose
    /// radius columns are written into one buffer kept from matrix to matrix.
    #[test]
    fn sliding_rows_take_their_radius_columns_from_one_buffer() {
        let chain = Chain::benchmark(4);
        let (q0, u0) = chain.resting(1.0);
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, Options::default()).unwrap();
        let p = s.scheme(0.5);
        let x = s.state().x.clone();
        let sets = s.sets_of(&x, 0.5);
        let top = s.layout.friction.len() - 1;
        assert!(sets.a[top] && !sets.d[top] && !sets.e[top]);
        s.residual(&x, &sets, &p);
        s.jacobian(&x, &sets, &p);
        let entries = s.work.jac.clone();
        let buffer = s.work.radius_cols.as_ptr();
        assert!(s.work.radius_cols.capacity() > 0);
        s.jacobian(&x, &sets, &p);
        assert_eq!(s.work.jac, entries);
        assert_eq!(s.work.radius_cols.as_ptr(), buffer);
    }
}
