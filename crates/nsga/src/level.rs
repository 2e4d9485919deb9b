//! Contact laws on one kinematic level, as semismooth residual rows: the problem shape
//! shared by the consistent start (acceleration level, docs/method.md §5) and the
//! Moreau–Jean step (velocity level, §6).
//!
//! The unknowns are y = (v, μ_p, μ_v): a velocity-like vector (accelerations a, or
//! velocities u_{n+1}) and the multipliers of the position and velocity families
//! (forces λ, or percussions P). The dynamics rows are M v − b − W_p μ_p − W_v μ_v = 0
//! with b given; the constraint rows are those of the prox formulation on this level:
//!
//! - bilateral constraints: r · level = 0;
//! - normal contact k, closed (its gap closed at the start of the step):
//!   r · level_k if r · level_k − μ_k ≤ 0 (contact), else μ_k (separation); an open
//!   contact's row is μ_k;
//! - friction law j, active (one of its normal contacts closed), with radius
//!   ρ = μ Σ_k μ_{N,k} clamped at 0: stick (r · level = 0) where ‖r · level − μ_F‖ ≤ ρ
//!   and sticking is allowed, else slip μ_F + ρ d with d the unit direction of a given
//!   vector (the level itself, or a fixed slip velocity); inactive: μ_F = 0.

use crate::linalg::norm;
use crate::sets::beyond_the_strongest;
use crate::stepper::rows::{push_u_derivative, RowMat};
use crate::system::{Evaluation, Layout, Triplets};

/// The data of a one-level contact problem that stay fixed over its Newton iterations.
#[derive(Debug)]
pub(crate) struct LevelProblem<'a> {
    /// The system's sizes and friction laws.
    pub layout: &'a Layout,
    /// M, W_p, W_v (and the rest of the evaluation, unused here).
    pub eval: &'a Evaluation<f64>,
    /// b of the dynamics rows M v − b − W μ = 0.
    pub rhs: &'a [f64],
    /// The velocity-like part v the dynamics rows measure from (M (v − v_ref)): zero
    /// for the start, u_n for Moreau–Jean.
    pub v_ref: Option<&'a [f64]>,
    /// Per normal contact: whether its gap is closed.
    pub closed: &'a [bool],
    /// Per friction law: a fixed slip velocity whose direction the slip row takes (the
    /// start's sliding contacts), or None (direction of the level itself, and sticking
    /// allowed).
    pub fixed_slip: &'a [Option<Vec<f64>>],
    /// Prox parameters per position constraint, velocity constraint, friction law.
    pub r_pos: &'a [f64],
    /// See `r_pos`.
    pub r_vel: &'a [f64],
    /// See `r_pos`.
    pub r_law: &'a [f64],
    /// W_p and W_v of `eval` by constraint ([`by_constraint`]).
    pub w_p: RowMat,
    /// See `w_p`.
    pub w_v: RowMat,
}

/// W (entries (i, c, v)) compressed by constraint: row c holds the (i, v) of
/// constraint c in the order of the triplets, so that a constraint row of the Jacobian
/// costs the entries of its own column of W, not a scan of all of W (which made the
/// start of a 2000-block column spend half its time in [`push_level`], quadratic in n).
pub(crate) fn by_constraint(w: &Triplets<f64>, n_constraints: usize) -> RowMat {
    let mut m = RowMat::default();
    push_u_derivative(&mut m.tmp, w, true, 0, 1.0, &[(0, 1.0)]);
    m.build(n_constraints);
    m
}

/// The residual and Jacobian of one iterate, and its index sets (the rows whose
/// constraint is closed: contact, or stick).
#[derive(Debug, Default)]
pub(crate) struct LevelRows {
    pub res: Vec<f64>,
    pub jac: Vec<(usize, usize, f64)>,
    pub closed_rows: Vec<usize>,
    /// The normal contacts kept on their contact row although their prox says open
    /// ([`OpeningLimit`]), ascending.
    pub held: Vec<usize>,
    /// The friction laws kept on their stick rows although their prox says slip,
    /// ascending.
    pub held_stick: Vec<usize>,
    /// The largest prox argument among the held rows: by how much the iterate's sets
    /// differ from the problem's own (0 when nothing is held).
    pub held_violation: f64,
}

impl LevelRows {
    /// ‖R‖∞ of the iterate, or its [`LevelRows::held_violation`] where larger: zero only
    /// at a solution of the problem itself, with nothing held.
    pub fn free_residual(&self) -> f64 {
        crate::linalg::max_norm(&self.res).max(self.held_violation)
    }
}

/// At most `per_update` closed contacts that were on their contact row at the last
/// iterate leave it at this one, and at most `per_update` friction laws that stuck
/// there start to slip: those whose prox arguments pass their bounds the most (for a
/// contact r · level − μ past 0, for a law ‖r · level − μ_F‖ past its radius); the
/// others are held on their contact or stick rows.
///
/// Why: from zero forces, the first Newton solve of a tall column on a sliding base
/// holds every contact, and the rigid column it describes needs a negative force at
/// every second corner and is at the friction bound at every interface. Opening all of
/// those at once frees every interface, and the iterates then took about one update per
/// interface to close them again (88 evaluations at 100 blocks, 171 at 200). The
/// solution opens three corners; one opening per update finds it in 11 and 30
/// (docs/method.md §5).
#[derive(Debug, Clone, Copy)]
pub(crate) struct OpeningLimit<'a> {
    /// Per normal contact: on its contact row at the last iterate.
    pub was_contact: &'a [bool],
    /// Per friction law: on its stick rows at the last iterate.
    pub was_stick: &'a [bool],
    /// Openings of each kind allowed per update.
    pub per_update: usize,
}

impl LevelProblem<'_> {
    /// Number of unknowns: nu + (ng + nN) + (nγ + nF).
    pub fn n(&self) -> usize {
        self.layout.nu + self.layout.n_position() + self.layout.n_velocity()
    }

    /// Fills `out` at y, with the levels `level_p`, `level_v` (the constraint rates on
    /// this level at y: p̈, v̇ for the start; ξ_p, ξ_v for Moreau–Jean).
    /// With a `limit`, some contacts are held on their contact row
    /// ([`LevelRows::held`]).
    pub fn rows(
        &self,
        y: &[f64],
        (level_p, level_v): (&[f64], &[f64]),
        limit: Option<OpeningLimit<'_>>,
        out: &mut LevelRows,
    ) {
        let l = self.layout;
        let e = self.eval;
        let (nu, ng, nga) = (l.nu, l.n_bilateral_position, l.n_bilateral_velocity);
        let (op, ov) = (nu, nu + l.n_position());
        self.hold(y, (level_p, level_v), limit, out);
        let LevelRows {
            res,
            jac,
            closed_rows,
            held,
            held_stick,
            ..
        } = out;
        res.clear();
        res.resize(self.n(), 0.0);
        jac.clear();
        closed_rows.clear();
        for &(i, j, m) in &e.mass.entries {
            res[i] += m * (y[j] - self.v_ref.map_or(0.0, |v| v[j]));
            jac.push((i, j, m));
        }
        for i in 0..nu {
            res[i] -= self.rhs[i];
        }
        for &(i, c, v) in &e.position_w.entries {
            res[i] -= v * y[op + c];
            jac.push((i, op + c, -v));
        }
        for &(i, c, v) in &e.velocity_w.entries {
            res[i] -= v * y[ov + c];
            jac.push((i, ov + c, -v));
        }
        for i in 0..ng {
            res[op + i] = self.r_pos[i] * level_p[i];
            push_level(jac, &self.w_p, i, op + i, self.r_pos[i]);
        }
        for i in 0..nga {
            res[ov + i] = self.r_vel[i] * level_v[i];
            push_level(jac, &self.w_v, i, ov + i, self.r_vel[i]);
        }
        for k in 0..l.n_normal() {
            let pk = ng + k;
            let row = op + pk;
            let (r, lam) = (self.r_pos[pk], y[row]);
            let contact = self.opening_by(k, y, level_p) <= 0.0 || held.binary_search(&k).is_ok();
            if self.closed[k] && contact {
                res[row] = r * level_p[pk];
                push_level(jac, &self.w_p, pk, row, r);
                closed_rows.push(row);
            } else {
                res[row] = lam;
                jac.push((row, row, 1.0));
            }
        }
        let offsets = l.friction_offsets();
        for (j, law) in l.friction.iter().enumerate() {
            let vs = nga + offsets[j];
            let nc = law.components;
            let level = &level_v[vs..vs + nc];
            let active = law.normals.iter().any(|&k| self.closed[k]);
            let sum: f64 = law.normals.iter().map(|&k| y[op + ng + k]).sum();
            let radius = law.mu * sum.max(0.0);
            let stick = self
                .stick_excess(j, vs, y, level_v)
                .is_some_and(|x| x <= 0.0)
                || held_stick.binary_search(&j).is_ok();
            let dir: &[f64] = self.fixed_slip[j].as_deref().unwrap_or(level);
            let dn = norm(dir);
            for m in 0..nc {
                let row = ov + vs + m;
                if stick {
                    res[row] = self.r_law[j] * level[m];
                    push_level(jac, &self.w_v, vs + m, row, self.r_law[j]);
                    closed_rows.push(row);
                    continue;
                }
                res[row] = y[row];
                jac.push((row, row, 1.0));
                // ERRATA 24: no direction, no slip term.
                if !active || dn == 0.0 || sum <= 0.0 {
                    continue;
                }
                let dm = dir[m] / dn;
                res[row] += radius * dm;
                for &k in &law.normals {
                    jac.push((row, op + ng + k, law.mu * dm));
                }
                if self.fixed_slip[j].is_none() {
                    // ∂(level/‖level‖)/∂v through level = W_vᵀ v + const.
                    for mp in 0..nc {
                        let proj = f64::from(u8::from(m == mp)) - dm * dir[mp] / dn;
                        push_level(jac, &self.w_v, vs + mp, row, radius * proj / dn);
                    }
                }
            }
        }
    }

    /// ‖r · level − μ_F‖ − ρ of friction law j, whose components start at velocity
    /// constraint `vs`: its stick rows hold where this is not positive. None where the
    /// law cannot stick (none of its contacts closed, or a fixed slip).
    fn stick_excess(&self, j: usize, vs: usize, y: &[f64], level_v: &[f64]) -> Option<f64> {
        let l = self.layout;
        let law = &l.friction[j];
        if self.fixed_slip[j].is_some() || !law.normals.iter().any(|&k| self.closed[k]) {
            return None;
        }
        let (op, ov) = (l.nu + l.n_bilateral_position, l.nu + l.n_position());
        let sum: f64 = law.normals.iter().map(|&k| y[op + k]).sum();
        let d: f64 = (vs..vs + law.components)
            .map(|c| (self.r_law[j] * level_v[c] - y[ov + c]).powi(2))
            .sum();
        Some(d.sqrt() - law.mu * sum.max(0.0))
    }

    /// r · level − μ of normal contact k: its contact row holds where this is not
    /// positive.
    fn opening_by(&self, k: usize, y: &[f64], level_p: &[f64]) -> f64 {
        let pk = self.layout.n_bilateral_position + k;
        self.r_pos[pk] * level_p[pk] - y[self.layout.nu + pk]
    }

    /// Fills `out.held`, `out.held_stick` and `out.held_violation` under `limit`
    /// ([`OpeningLimit`]); empty and 0 without one.
    fn hold(
        &self,
        y: &[f64],
        (level_p, level_v): (&[f64], &[f64]),
        limit: Option<OpeningLimit<'_>>,
        out: &mut LevelRows,
    ) {
        out.held.clear();
        out.held_stick.clear();
        out.held_violation = 0.0;
        let Some(limit) = limit else { return };
        let opening_by = |k: usize| self.opening_by(k, y, level_p);
        let opening = (0..self.closed.len())
            .filter(|&k| limit.was_contact[k] && opening_by(k) > 0.0)
            .collect();
        out.held = beyond_the_strongest(opening, limit.per_update, opening_by);
        let (nga, offsets) = (
            self.layout.n_bilateral_velocity,
            self.layout.friction_offsets(),
        );
        let slipping_by = |j: usize| {
            self.stick_excess(j, nga + offsets[j], y, level_v)
                .unwrap_or(f64::NEG_INFINITY)
        };
        let slipping = (0..limit.was_stick.len())
            .filter(|&j| limit.was_stick[j] && slipping_by(j) > 0.0)
            .collect();
        out.held_stick = beyond_the_strongest(slipping, limit.per_update, slipping_by);
        out.held.sort_unstable();
        out.held_stick.sort_unstable();
        let held = out.held.iter().map(|&k| opening_by(k));
        let held_stick = out.held_stick.iter().map(|&j| slipping_by(j));
        out.held_violation = held.chain(held_stick).fold(0.0, f64::max);
    }
}

/// Pushes `r · (column c0 of W)ᵀ` as the entries of `row` over the velocity-like
/// unknowns (∂(r · level)/∂v = r Wᵀ).
fn push_level(jac: &mut Vec<(usize, usize, f64)>, w: &RowMat, c0: usize, row: usize, r: f64) {
    jac.extend(w.row(c0).map(|(i, v)| (row, i, r * v)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn by_constraint_keeps_the_order_of_the_triplets_per_constraint() {
        let w = Triplets {
            entries: vec![(0, 2, 1.0), (1, 0, 2.0), (2, 2, 3.0), (0, 0, 4.0)],
        };
        let by = by_constraint(&w, 4);
        let of = |c| by.row(c).collect::<Vec<_>>();
        assert_eq!(of(0), [(1, 2.0), (0, 4.0)]);
        assert_eq!(of(1), []);
        assert_eq!(of(2), [(0, 1.0), (2, 3.0)]);
        // A constraint W has no entry for, past its last one, has an empty row.
        assert_eq!(of(3), []);
    }
}
