//! One Newton iterate of a step: the kinematic updates that derive q_{n+1}, u_{n+1},
//! the percussions and the auxiliary variables from the unknowns x (eqs. 71, 73, 95,
//! 96, 102, 113, 114, 125), the system evaluated there, and the index sets the contact
//! laws give (eqs. 128–142).

use super::scheme::Scheme;
use super::Stepper;
use crate::params::GenAlpha;
use crate::prox::prox_parameters;
use crate::sets::{beyond_the_strongest, IndexSets};
use crate::system::System;
use std::borrow::Cow;

/// Relative width of the ties in the index-set decisions of an arriving contact (one
/// that approaches its surface at the step's start, at speed v): a gap closed by less
/// than this fraction of the distance vΔt the contact travels in the step still counts
/// as open, and a friction law whose excess over its bound is below this fraction of
/// μ r v sticks (μ r v/Δt on acceleration level). At the first iterate of a step with
/// an impact, every closed contact counts as closed on velocity level within this
/// fraction of r v for the fastest arrival v (see `Stepper::compute_sets`). Far below
/// anything physical, above the round-off that otherwise decided these ties
/// (docs/method.md §8.2, "Simultaneous impacts").
pub const SET_TIE: f64 = 1e-9;

/// How fast a contact of normal velocity `rate` (γ_N at the step's start) arrives: −rate
/// when it approaches, 0 when it rests or leaves, so that the ties of a resting contact
/// stay at zero width.
fn arrival(rate: f64) -> f64 {
    (-rate).max(0.0)
}

/// `to` becomes the entries of `from`, in `to`'s buffer.
fn refill(to: &mut Vec<f64>, from: impl Iterator<Item = f64>) {
    to.clear();
    to.extend(from);
}

/// The auxiliary variables of one family at the iterate (eqs. 71, 95, 113): per entry,
/// ā_{n+1} from the last step's value `old`, the iterate's `new` and the last ā `old_bar`.
fn refill_bars(to: &mut Vec<f64>, alpha: &GenAlpha, (old, new, old_bar): (&[f64], &[f64], &[f64])) {
    refill(
        to,
        old.iter()
            .zip(new)
            .zip(old_bar)
            .map(|((&o, &n), &ob)| alpha.bar(o, n, ob)),
    );
}

/// The percussions of one family at the iterate (eqs. 96, 114): per entry, the impulsive
/// part `impulsive` plus Δt((1 − γ) λ̄_n + γ λ̄_{n+1}) of the smooth forces.
fn refill_percussions(
    to: &mut Vec<f64>,
    (dt, gamma): (f64, f64),
    impulsive: &[f64],
    (old_bar, bar): (&[f64], &[f64]),
) {
    refill(
        to,
        impulsive
            .iter()
            .zip(old_bar)
            .zip(bar)
            .map(|((&c, &ob), &b)| c + dt * ((1.0 - gamma) * ob + gamma * b)),
    );
}

/// Quantities derived from x at one Newton iterate (eqs. 71, 73, 125, 95, 102, 113).
#[derive(Debug, Clone, Default)]
pub(super) struct Iterate {
    pub(super) q1: Vec<f64>,
    pub(super) u1: Vec<f64>,
    pub(super) a_bar1: Vec<f64>,
    pub(super) lbar_n1: Vec<f64>,
    pub(super) p_n: Vec<f64>,
    pub(super) kappa_hat: Vec<f64>,
    pub(super) lbar_f1: Vec<f64>,
    pub(super) p_f: Vec<f64>,
    // evaluated
    pub(super) p: Vec<f64>,
    pub(super) xi_p: Vec<f64>,
    pub(super) acc_p: Vec<f64>,
    pub(super) xi_v: Vec<f64>,
    pub(super) v: Vec<f64>,
    pub(super) acc_v: Vec<f64>,
    // scratch: ṗ at u_{n+1} and u_n, v at u_n
    pub(super) rate_new: Vec<f64>,
    pub(super) rate_old: Vec<f64>,
    pub(super) v_old: Vec<f64>,
    // multipliers reassembled per family, for the probes
    pub(super) lam_p: Vec<f64>,
    pub(super) lam_v: Vec<f64>,
    pub(super) cap_p: Vec<f64>,
    pub(super) cap_v: Vec<f64>,
    pub(super) kap_p: Vec<f64>,
    pub(super) half_cap_v: Vec<f64>,
    /// Per position-level constraint: whether W_p has an entry in its column at q_{n+1}.
    pub(super) supported: Vec<bool>,
}

impl<S: System> Stepper<S> {
    /// B(q_n) and Ḃu at the start of the step.
    pub(super) fn prepare_step(&mut self) {
        let w = &mut self.work;
        let st = &self.state;
        w.bt.clear();
        self.system.kinematics(st.t, &st.q, &mut w.bt);
        w.b.tmp.clear();
        w.b.tmp.extend(w.bt.entries.iter().copied());
        w.b.build(self.off.nq);
        w.bdot_u.iter_mut().for_each(|x| *x = 0.0);
        self.system
            .kinematics_rate(st.t, &st.q, &st.u, &mut w.bdot_u);
    }

    /// Kinematic updates (eqs. 71, 73, 125, 95, 96, 102, 113, 114).
    pub(super) fn derive(&mut self, x: &[f64], p: &Scheme) {
        let o = self.off;
        let st = &self.state;
        let dt = self.options.dt;
        let it = &mut self.work.it;
        let b = &self.work.b;
        let bdot_u = &self.work.bdot_u;
        let (beta, gamma) = (p.alpha.beta, p.alpha.gamma);
        // Each vector filled by one `extend` over its indices, which reserves once,
        // rather than a `push` per entry, which checks the capacity each time (the
        // iterate is derived at every Newton iterate; same numbers either way).
        let xs = |at: usize, n: usize| &x[at..at + n];
        refill_bars(&mut it.a_bar1, &p.alpha, (&st.a, xs(o.a, o.nu), &st.a_bar));
        let a_bar1 = &it.a_bar1;
        refill(
            &mut it.u1,
            (0..o.nu).map(|i| {
                st.u[i] + dt * ((1.0 - gamma) * st.a_bar[i] + gamma * a_bar1[i]) + x[o.uu + i]
            }),
        );
        // q_{n+1} = q_n + Δt B u_n + ½Δt²(B a_β + Ḃu_n) + B Q   (eq. 125, second order),
        // through slices: each vector's pointer and length read once, not per entry of B.
        let (u, a_bar, a_bar1) = (&st.u[..], &st.a_bar[..], &a_bar1[..]);
        let (q, xq, bdot_u) = (&st.q[..], xs(o.qq, o.nu), &bdot_u[..]);
        refill(
            &mut it.q1,
            (0..o.nq).map(|j| {
                let mut bu = 0.0;
                let mut ba = 0.0;
                let mut bq = 0.0;
                for (i, bij) in b.row(j) {
                    bu += bij * u[i];
                    let a_beta = (1.0 - 2.0 * beta) * a_bar[i] + 2.0 * beta * a_bar1[i];
                    ba += bij * a_beta;
                    bq += bij * xq[i];
                }
                q[j] + dt * bu + 0.5 * dt * dt * (ba + bdot_u[j]) + bq
            }),
        );
        refill_bars(
            &mut it.lbar_n1,
            &p.alpha,
            (&st.lambda_n, xs(o.ln, o.nn), &st.lambda_n_bar),
        );
        let lbar_n1 = &it.lbar_n1;
        refill_percussions(
            &mut it.p_n,
            (dt, gamma),
            xs(o.cn, o.nn),
            (&st.lambda_n_bar, lbar_n1),
        );
        refill(
            &mut it.kappa_hat,
            (0..o.nn).map(|k| {
                x[o.kn + k] + dt * dt * ((0.5 - beta) * st.lambda_n_bar[k] + beta * lbar_n1[k])
            }),
        );
        refill_bars(
            &mut it.lbar_f1,
            &p.alpha,
            (&st.lambda_f, xs(o.lf, o.nf), &st.lambda_f_bar),
        );
        refill_percussions(
            &mut it.p_f,
            (dt, gamma),
            xs(o.cf, o.nf),
            (&st.lambda_f_bar, &it.lbar_f1),
        );
        // Multipliers per family, for the smooth rows and the derivative probes.
        let fam = |v: &mut Vec<f64>, first: &[f64], second: &[f64]| {
            v.clear();
            v.extend_from_slice(first);
            v.extend_from_slice(second);
        };
        fam(&mut it.lam_p, &x[o.lg..o.lg + o.ng], &x[o.ln..o.ln + o.nn]);
        fam(
            &mut it.lam_v,
            &x[o.lga..o.lga + o.nga],
            &x[o.lf..o.lf + o.nf],
        );
        fam(&mut it.cap_p, &x[o.cg..o.cg + o.ng], &x[o.cn..o.cn + o.nn]);
        fam(
            &mut it.cap_v,
            &x[o.cga..o.cga + o.nga],
            &x[o.cf..o.cf + o.nf],
        );
        fam(&mut it.kap_p, &x[o.kg..o.kg + o.ng], &x[o.kn..o.kn + o.nn]);
        it.half_cap_v.clear();
        // ½Δt Λ_v of the Q rows (eq. 127); the friction part only with the shift.
        let shifted = self.shifted_velocity_constraints(p.friction_shift);
        let it = &mut self.work.it;
        it.half_cap_v
            .extend(it.cap_v.iter().take(shifted).map(|c| 0.5 * dt * c));
        it.half_cap_v.resize(it.cap_v.len(), 0.0);
    }

    /// Evaluates the system at (t_{n+1}, q_{n+1}, u_{n+1}) and the constraint levels at
    /// the unknowns `x` (whose a gives the acceleration levels W_pᵀa + ζ_p, W_vᵀa + ζ_v).
    pub(super) fn evaluate_iterate(&mut self, x: &[f64], update_prox: bool) {
        let t1 = self.t_next();
        let w = &mut self.work;
        w.eval.reset();
        self.system
            .evaluate_real(t1, &w.it.q1, &w.it.u1, &mut w.eval);
        if update_prox {
            prox_parameters(
                self.options.prox,
                &self.layout,
                &w.eval,
                (&mut w.r_pos, &mut w.r_vel, &mut w.r_law),
                &mut w.mass_diagonal,
            );
        }
        let l = &self.layout;
        let (np, nv, ng, nga) = (
            l.n_position(),
            l.n_velocity(),
            l.n_bilateral_position,
            l.n_bilateral_velocity,
        );
        let e = &w.eval;
        let it = &mut w.it;
        // Slices in the loops over the triplets: each vector's pointer and length read
        // once, not at every entry.
        let (u0, u1) = (&self.state.u[..], &it.u1[..]);
        let o = self.off;
        let a = &x[o.a..o.a + o.nu];
        // ṗ(q1,u1), ṗ(q1,u_n), p̈ = W_pᵀa + ζ_p in one pass over W_p (buffers reused: no
        // allocation per iterate)
        it.rate_new.clone_from(&e.position_chi);
        it.rate_old.clone_from(&e.position_chi);
        it.acc_p.clone_from(&e.position_zeta);
        it.supported.clear();
        it.supported.resize(np, false);
        let (rate_new, rate_old) = (&mut it.rate_new[..], &mut it.rate_old[..]);
        let (acc_p, supported) = (&mut it.acc_p[..], &mut it.supported[..]);
        for &(r, c, v) in &e.position_w.entries {
            rate_new[c] += v * u1[r];
            rate_old[c] += v * u0[r];
            acc_p[c] += v * a[r];
            supported[c] = true;
        }
        it.p.clone_from(&e.position);
        let (rate_new, rate_old) = (&it.rate_new, &it.rate_old);
        refill(
            &mut it.xi_p,
            (0..np).map(|k| {
                let en = if k < ng { 0.0 } else { l.e_n[k - ng] };
                rate_new[k] + en * rate_old[k]
            }),
        );
        // velocity level, and W_vᵀa + ζ_v
        it.v.clone_from(&e.velocity_chi);
        it.v_old.clone_from(&e.velocity_chi);
        it.acc_v.clone_from(&e.velocity_zeta);
        let (v_new, v_old) = (&mut it.v[..], &mut it.v_old[..]);
        let acc_v = &mut it.acc_v[..];
        for &(r, c, v) in &e.velocity_w.entries {
            v_new[c] += v * u1[r];
            v_old[c] += v * u0[r];
            acc_v[c] += v * a[r];
        }
        let (v, v_old) = (&it.v, &it.v_old);
        refill(
            &mut it.xi_v,
            (0..nv).map(|k| {
                let ef = if k < nga { 0.0 } else { self.comp_ef[k - nga] };
                v[k] + ef * v_old[k]
            }),
        );
    }

    /// The normal contacts that have no W and a positive gap at the current iterate: a
    /// system's "open contact that cannot close" (a corner slid past the end of its
    /// face), which transmits no force whatever its multipliers say. Closed, its rows
    /// would hold nothing but the regularization: the Newton matrix would be singular at
    /// every Δt (docs/method.md §8.2). A gap at or below zero without W is not among
    /// them: no force can keep it closed, and the singular matrix says so.
    fn unsupported_contacts(&self) -> impl Iterator<Item = usize> + '_ {
        let it = &self.work.it;
        let ng = self.off.ng;
        let supported = it.supported.get(ng..).unwrap_or(&[]);
        supported
            .iter()
            .enumerate()
            .filter(move |&(k, &w)| !w && it.p[ng + k] > 0.0)
            .map(|(k, _)| k)
    }

    /// Opens the [`Self::unsupported_contacts`] in `s`, on every level.
    pub(super) fn open_unsupported(&self, s: &mut IndexSets) {
        for k in self.unsupported_contacts() {
            s.a[k] = false;
            s.b[k] = false;
            s.c[k] = false;
        }
    }

    /// `sets` with the [`Self::unsupported_contacts`] open: borrowed where none of them
    /// is closed in `sets` (consistent sets nest B and C in A), a copy otherwise.
    pub(super) fn with_unsupported_open<'a>(&self, sets: &'a IndexSets) -> Cow<'a, IndexSets> {
        if self.unsupported_contacts().any(|k| sets.a[k]) {
            let mut opened = sets.clone();
            self.open_unsupported(&mut opened);
            Cow::Owned(opened)
        } else {
            Cow::Borrowed(sets)
        }
    }

    /// How many velocity-level constraints, counted from the first, shift the position
    /// by half a step of their percussions in the Q rows (eq. 127): the bilateral ones,
    /// and with `friction_shift` ([`Scheme::friction_shift`]) the friction laws'.
    pub(super) fn shifted_velocity_constraints(&self, friction_shift: bool) -> usize {
        let o = &self.off;
        if friction_shift {
            o.nga + o.nf
        } else {
            o.nga
        }
    }

    /// t_{n+1} = t_base + (k + 1 − k_base) Δt: the integrator's own time grid, not an
    /// accumulated sum (ERRATA 20).
    pub(super) fn t_next(&self) -> f64 {
        self.grid_time(self.state.k + 1)
    }

    /// t_k = t_base + (k − k_base)Δt on the current grid.
    pub(super) fn grid_time(&self, k: u64) -> f64 {
        let (t_base, k_base) = self.time_base;
        t_base + (k - k_base) as f64 * self.options.dt
    }

    /// Index sets from the current iterate (eqs. 128–142).
    ///
    /// The prox conditions decide by sign, except for a contact that arrives (approaches
    /// at the step's start): within ties of width [`SET_TIE`] relative to its arrival,
    /// its gap stays open (A) and its friction law sticks (D, E). Two corners of a block
    /// that lands flat reach their surface together up to round-off, and at the first
    /// iterate of the landing their friction laws sit at the apex of their cones (no
    /// percussion yet) with tangential velocities of round-off size; decided by the
    /// sign of that round-off, one corner took the impact alone, or one law slid in a
    /// round-off direction with the full bound μP_N, and the block flew off spinning.
    /// A gap that closes exactly at the step's end stays open rather than closed: the
    /// impact then comes in the next step, whose restitution law sees the arrival
    /// velocity, where closing it here would apply the law to the start of this step's,
    /// slower by gΔt. A resting contact (no arrival) keeps the exact sign rule, so that
    /// redundant contacts of a pile are not closed or stuck by a tie, with one exception:
    /// at the `first` iterate of an attempt at a step in which a contact arrives, every
    /// contact closed on position level counts as closed on velocity level (B) within
    /// [`SET_TIE`] of the fastest arrival. There a resting contact has no percussion yet
    /// and a normal velocity of round-off size, and when a column landed flat, the sign
    /// of that round-off opened one corner of an interface above the landing one: the
    /// interface passed the impact on through the other corner alone, and the column
    /// tipped. From the second iterate on, Newton decides these contacts by sign again,
    /// so that a pile's redundant contacts are not held closed.
    ///
    /// With `limit` = (the sets of the last Newton update, k), at most k of the normal
    /// contacts closed there on position level open at this iterate: those whose prox
    /// argument r g_N − κ̂_N is largest. The others stay in A. Likewise at most k of the
    /// contacts that stay in A leave B or C (by their prox arguments r ξ_N − P_N and
    /// (r g̈_N − λ_N)Δt, both impulses); the others keep the levels of the last update.
    /// The friction sets follow (see [`NewtonOptions::max_openings_per_update`]).
    ///
    /// [`NewtonOptions::max_openings_per_update`]: crate::NewtonOptions::max_openings_per_update
    pub(super) fn compute_sets(
        &mut self,
        x: &[f64],
        limit: Option<(&IndexSets, usize)>,
        first: bool,
    ) -> IndexSets {
        let o = self.off;
        let mut s = self.work.spare_sets.pop().unwrap_or_default();
        s.reset(o.nn, self.layout.friction.len());
        let l = &self.layout;
        let w = &self.work;
        let it = &w.it;
        // The normal contacts' rows of the position constraints' vectors, as slices: their
        // pointers and lengths read once, not per contact.
        let nr = o.ng..o.ng + o.nn;
        let (r_pos, rate_old) = (&w.r_pos[nr.clone()], &it.rate_old[nr.clone()]);
        let (gap, xi, acc) = (&it.p[nr.clone()], &it.xi_p[nr.clone()], &it.acc_p[nr]);
        let (kappa_hat, p_n, lambda_n) = (&it.kappa_hat[..], &it.p_n[..], &x[o.ln..o.ln + o.nn]);
        // The prox arguments of the normal contacts' laws on position, velocity and
        // acceleration level: positive where the law opens the contact.
        let open_by = |k: usize| r_pos[k] * gap[k] - kappa_hat[k];
        let leaves_b_by = |k: usize| r_pos[k] * xi[k] - p_n[k];
        let leaves_c_by = |k: usize| r_pos[k] * acc[k] - lambda_n[k];
        // The fastest arrival among the normal contacts `ks` (0 when none arrives).
        let fastest = |ks: &mut dyn Iterator<Item = usize>| {
            ks.map(|k| arrival(rate_old[k])).fold(0.0, f64::max)
        };
        let dt = self.options.dt;
        for k in 0..o.nn {
            s.a[k] = open_by(k) <= -SET_TIE * r_pos[k] * dt * arrival(rate_old[k]);
        }
        let limit = limit.filter(|(last, _)| last.a.len() == o.nn);
        if let Some((last, most)) = limit {
            let opening: Vec<usize> = (0..o.nn).filter(|&k| last.a[k] && !s.a[k]).collect();
            for k in beyond_the_strongest(opening, most, open_by) {
                s.a[k] = true;
            }
        }
        self.open_unsupported(&mut s);
        // At an attempt's first iterate, the fastest arrival among the contacts closed
        // on position level: nonzero only in a step with an impact.
        let impact = if first {
            fastest(&mut (0..o.nn).filter(|&k| s.a[k]))
        } else {
            0.0
        };
        for k in 0..o.nn {
            s.b[k] = s.a[k] && leaves_b_by(k) <= SET_TIE * r_pos[k] * impact;
            s.c[k] = s.b[k] && leaves_c_by(k) <= 0.0;
        }
        if let Some((last, most)) = limit {
            // Openings on velocity level (B) and acceleration level (C) of contacts that
            // stay in A, ranked by their prox arguments in impulse units.
            let leaves_b = |k: usize| last.b[k] && !s.b[k];
            let leaves = |k: usize| s.a[k] && (leaves_b(k) || (last.c[k] && s.b[k] && !s.c[k]));
            let strength = |k: usize| {
                if leaves_b(k) {
                    leaves_b_by(k)
                } else {
                    leaves_c_by(k) * dt
                }
            };
            let opening: Vec<usize> = (0..o.nn).filter(|&k| leaves(k)).collect();
            for k in beyond_the_strongest(opening, most, strength) {
                s.b[k] |= last.b[k];
                s.c[k] |= last.c[k];
            }
        }
        for (j, law) in l.friction.iter().enumerate() {
            let active = law.normals.iter().any(|&k| s.a[k]);
            if !active {
                continue;
            }
            let f0 = self.law_off[j];
            let r = w.r_law[j];
            let p_hat: f64 = law.normals.iter().map(|&k| it.p_n[k]).sum::<f64>().max(0.0);
            let l_hat: f64 = law
                .normals
                .iter()
                .map(|&k| x[o.ln + k])
                .sum::<f64>()
                .max(0.0);
            let mut nd = 0.0;
            let mut ne = 0.0;
            for m in 0..law.components {
                let c = f0 + m;
                let vc = o.nga + c;
                nd += (r * it.xi_v[vc] - it.p_f[c]).powi(2);
                ne += (r * it.acc_v[vc] - x[o.lf + c]).powi(2);
            }
            // The tie is μ r v SET_TIE for the fastest arrival v among the law's contacts
            // closed on velocity level (per Δt on acceleration level).
            let arriving = fastest(&mut law.normals.iter().copied().filter(|&k| s.b[k]));
            let tie = law.mu * SET_TIE * r * arriving;
            s.d[j] = nd.sqrt() <= law.mu * p_hat + tie;
            s.e[j] = s.d[j] && ne.sqrt() <= law.mu * l_hat + tie / dt;
        }
        s
    }
}
