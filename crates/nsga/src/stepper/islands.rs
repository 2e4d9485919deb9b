//! Islands at rest held out of the solve (docs/method.md §8.2, "Islands at rest").
//!
//! The bodies of a system fall apart into **islands**: the connected components of the
//! velocity coordinates, joined by the mass matrix's couplings and by every contact that
//! could close within the next step (one that the pruning of §7 would not leave out).
//! A pile lying on the floor and a column standing on a shaken base are two islands: the
//! rows of one hold none of the other's unknowns.
//!
//! An island whose bodies have come to rest is **held**: after a step in which its
//! coordinates moved by round-off only, its velocities and accelerations weighed at most
//! the tolerance in the U and a rows of eq. 127, and its contacts kept their index sets,
//! its state is set to rest exactly (u, a, ā and its impulsive unknowns U, Q, κ, Λ zero,
//! its forces λ kept), as the whole system's settling does (`rest.rs`). From the next
//! step on its unknowns are left out of the linear solve, as pruned contacts are
//! (`prune.rs`), but at their values, not at zero: q + Δt·0 = q, and the island repeats
//! its state without a factorization of its rows.
//!
//! The step stays exact: its residual is evaluated in full and converges to the
//! tolerance in every row, the held ones included. An island **wakes** (its unknowns
//! return to the solve) when
//! - one of its held rows exceeds the tolerance at an iterate (a force on it changed,
//!   or a body it was coupled to in a way the components missed moved): the attempt
//!   restarts from that iterate with the island in the solve, and the island stays
//!   awake for the rest of the step;
//! - a contact that could close joins it to a body that moves (a falling block reaches
//!   the pile);
//! - one of its contacts' slots is given to another pair of bodies, or the caller
//!   changes the state, the layout or the options.
//!
//! Only systems whose q and u have the same size and that have no bilateral constraints
//! hold islands (the block stack); [`PolicyOptions::rest`](crate::PolicyOptions::rest)
//! and [`NewtonOptions::prune_open_contacts`](crate::NewtonOptions::prune_open_contacts)
//! switch them on.

use super::rest::{resolution, round_off_rates};
use super::Stepper;
use crate::sets::IndexSets;
use crate::system::System;

/// The islands held at rest, and what the last commit left to find new ones.
#[derive(Debug, Clone, Default)]
pub(super) struct Islands {
    /// Per velocity coordinate: held at rest.
    held_u: Vec<bool>,
    /// Per normal contact: its unknowns held with the island it joins.
    held_n: Vec<bool>,
    /// The held unknowns of x, in increasing order.
    held_x: Vec<usize>,
    /// Whether a held row exceeded the tolerance in the current step: every island is
    /// in the solve until the step is committed.
    woken: bool,
    /// Per coordinate: the last commit moved it by round-off at most.
    still: Vec<bool>,
    /// Per normal contact and per friction law: the last commit kept its sets.
    steady_n: Vec<bool>,
    steady_f: Vec<bool>,
    /// The component of each coordinate (a union–find forest, then the roots).
    root: Vec<usize>,
    /// Per constraint column of W_p and W_v: a coordinate it acts on, or `usize::MAX`.
    first_p: Vec<usize>,
    first_v: Vec<usize>,
    /// Per component root: it holds a coordinate that may not be held, and a closed
    /// normal contact.
    restless: Vec<bool>,
    any_closed: Vec<bool>,
    /// No contact kept from pruning, for the prune test of the components.
    keep_none: Vec<bool>,
    /// Per friction component: its law has a normal contact that could close.
    closable_v: Vec<bool>,
}

impl Islands {
    /// The held unknowns of x (empty while none is held or they were woken).
    pub(super) fn held(&self) -> &[usize] {
        if self.woken {
            &[]
        } else {
            &self.held_x
        }
    }

    /// Whether normal contact `k` is held with an island in the current attempt.
    pub(super) fn holds_contact(&self, k: usize) -> bool {
        !self.woken && self.held_n.get(k) == Some(&true)
    }

    /// Returns every island to the solve: the state, the system or the layout changed.
    pub(super) fn release(&mut self) {
        self.held_u.clear();
        self.held_n.clear();
        self.held_x.clear();
        self.woken = false;
        self.still.clear();
    }

    /// Returns every island to the solve if one of the normal contacts `forgotten` (whose
    /// slots now hold other pairs of bodies) is held.
    pub(super) fn forget_contacts(&mut self, forgotten: &[usize]) {
        if forgotten.iter().any(|&k| self.held_n.get(k) == Some(&true)) {
            self.release();
        }
    }

    /// Returns the islands to the solve for the rest of the step (a held row exceeded
    /// the tolerance); the commit releases them.
    pub(super) fn wake(&mut self) {
        self.woken = true;
    }

    /// Records what a commit from `q0` to `q1`, with sets `before` → `after`, left for
    /// the search of islands at rest.
    pub(super) fn committed(
        &mut self,
        (q0, q1): (&[f64], &[f64]),
        before: Option<&IndexSets>,
        after: &IndexSets,
    ) {
        let resolution = resolution(q1);
        self.still.clear();
        self.still
            .extend(q0.iter().zip(q1).map(|(a, b)| (a - b).abs() <= resolution));
        let same = |x: &[bool], y: &[bool], i: usize| x.get(i) == y.get(i);
        self.steady_n.clear();
        self.steady_n.extend((0..after.a.len()).map(|k| {
            before.is_some_and(|b| {
                same(&b.a, &after.a, k) && same(&b.b, &after.b, k) && same(&b.c, &after.c, k)
            })
        }));
        self.steady_f.clear();
        self.steady_f.extend(
            (0..after.d.len()).map(|j| {
                before.is_some_and(|b| same(&b.d, &after.d, j) && same(&b.e, &after.e, j))
            }),
        );
        if self.woken {
            self.held_u.clear();
            self.woken = false;
        }
    }
}

/// The root of `i` in the union–find forest `parent`, halving the path on the way.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Joins coordinate `i` to the component of the constraint whose first coordinate is
/// `first` (`usize::MAX`: `i` becomes its first).
fn join(parent: &mut [usize], first: &mut usize, i: usize) {
    match *first {
        usize::MAX => *first = i,
        f => union(parent, i, f),
    }
}

/// Joins the components of `i` and `j`.
fn union(parent: &mut [usize], i: usize, j: usize) {
    let (ri, rj) = (find(parent, i), find(parent, j));
    if ri != rj {
        parent[ri.max(rj)] = ri.min(rj);
    }
}

impl<S: System> Stepper<S> {
    /// Whether this stepper holds islands at rest (module docs).
    pub(super) fn holds_islands(&self) -> bool {
        let l = &self.layout;
        self.options.policy.rest
            && self.options.newton.prune_open_contacts
            && l.nq == l.nu
            && l.n_bilateral_position == 0
            && l.n_bilateral_velocity == 0
    }

    /// After a committed step: finds the islands of the state, releases the held ones
    /// that a contact now joins to a moving body, and holds the islands that came to
    /// rest, settling their state (module docs).
    pub(super) fn update_islands(&mut self) {
        // Where no coordinate stood still, no island rests (the usual step of a run
        // that moves: its components need not be found).
        // Nor are islands looked for while the whole system settles or rests (`rest.rs`):
        // it holds them all.
        let still = &self.islands.still;
        if !self.holds_islands()
            || self.rest != super::rest::Rest::Moving
            || still.len() != self.off.nq
            || !still.contains(&true)
        {
            self.islands.release();
            return;
        }
        self.island_components();
        self.mark_restless();
        // A component rests where nothing in it moves and a contact is closed; its
        // coordinates not held yet are settled. A held coordinate whose component now
        // holds one that moves returns to the solve.
        let is = &mut self.islands;
        let mut settle = false;
        is.held_u.resize(self.off.nu, false);
        for (i, held) in is.held_u.iter_mut().enumerate() {
            let r = is.root[i];
            let rests = !is.restless[r] && is.any_closed[r];
            settle |= rests && !*held;
            *held = rests;
        }
        self.list_held_unknowns();
        if settle {
            self.settle_islands();
        }
    }

    /// Flags per component root (`islands.restless`) whether a coordinate in it moved,
    /// or has a velocity or an acceleration the solver can tell from zero (|Mᵢᵢ uᵢ| or
    /// Δt |Mᵢᵢ aᵢ| above the tolerance), or whether one of its contacts changed its
    /// sets; and (`islands.any_closed`) whether one of its normal contacts is closed.
    fn mark_restless(&mut self) {
        let (o, tol, dt) = (self.off, self.options.tol, self.options.dt);
        let (st, is) = (&self.state, &mut self.islands);
        let sets = &self.last.as_ref().expect("a step was just committed").sets;
        is.restless.clear();
        is.restless.resize(o.nu, false);
        for &(i, j, m) in &self.work.eval.mass.entries {
            if i == j {
                let moving = !is.still[i] || !round_off_rates(m, st.u[i], st.a[i], tol, dt);
                is.restless[is.root[i]] |= moving;
            }
        }
        is.any_closed.clear();
        is.any_closed.resize(o.nu, false);
        for (k, &i) in is.first_p.iter().enumerate() {
            if i != usize::MAX {
                is.restless[is.root[i]] |= !is.steady_n[k];
                is.any_closed[is.root[i]] |= sets.a[k];
            }
        }
        for (j, &f0) in self.law_off.iter().enumerate() {
            let i = is.first_v.get(f0).copied().unwrap_or(usize::MAX);
            if i != usize::MAX {
                is.restless[is.root[i]] |= !is.steady_f[j];
            }
        }
    }

    /// The components of the velocity coordinates (module docs), into `islands.root`;
    /// `islands.first_p`, `first_v` name a coordinate of each constraint that joins.
    fn island_components(&mut self) {
        let o = self.off;
        let mut keep_none = std::mem::take(&mut self.islands.keep_none);
        keep_none.clear();
        keep_none.resize(o.nn, false);
        self.mark_unclosable(&keep_none);
        self.islands.keep_none = keep_none;
        let (w, is) = (&self.work, &mut self.islands);
        let parent = &mut is.root;
        parent.clear();
        parent.extend(0..o.nu);
        for &(i, j, _) in &w.eval.mass.entries {
            union(parent, i, j);
        }
        // A friction law joins where one of its normal contacts could close.
        is.closable_v.clear();
        for law in &self.layout.friction {
            let closable = law.normals.iter().any(|&k| !w.unclosable[k]);
            is.closable_v
                .extend(std::iter::repeat_n(closable, law.components));
        }
        // Without bilateral constraints (`holds_islands`), the columns of W_p are the
        // normal contacts and those of W_v the friction components.
        is.first_p.clear();
        is.first_p.resize(o.nn, usize::MAX);
        for &(i, k, _) in &w.eval.position_w.entries {
            if !w.unclosable[k] {
                join(parent, &mut is.first_p[k], i);
            }
        }
        is.first_v.clear();
        is.first_v.resize(o.nf, usize::MAX);
        for &(i, c, _) in &w.eval.velocity_w.entries {
            if is.closable_v[c] {
                join(parent, &mut is.first_v[c], i);
            }
        }
        for i in 0..o.nu {
            parent[i] = find(parent, i);
        }
    }

    /// Sets the held islands' state to rest exactly: u, a, ā and their impulsive
    /// unknowns zero, their forces kept (module docs). The levels kept for the pruning
    /// are those of the state before: they are evaluated again.
    fn settle_islands(&mut self) {
        let o = self.off;
        let is = &self.islands;
        let st = &mut self.state;
        for i in (0..o.nu).filter(|&i| is.held_u[i]) {
            st.u[i] = 0.0;
            st.a[i] = 0.0;
            st.a_bar[i] = 0.0;
            for base in [o.a, o.uu, o.qq] {
                st.x[base + i] = 0.0;
            }
        }
        self.work.state_levels.forget();
        for k in (0..o.nn).filter(|&k| is.held_n[k]) {
            st.x[o.kn + k] = 0.0;
            st.x[o.cn + k] = 0.0;
        }
        for (j, law) in self.layout.friction.iter().enumerate() {
            if law.normals.iter().any(|&k| is.held_n[k]) {
                for m in 0..law.components {
                    st.x[o.cf + self.law_off[j] + m] = 0.0;
                }
            }
        }
    }

    /// Lists the unknowns of the held coordinates and of the contacts and friction laws
    /// that join them (`islands.held_n`, `islands.held_x`).
    fn list_held_unknowns(&mut self) {
        let o = self.off;
        let is = &mut self.islands;
        is.held_n.clear();
        is.held_n.extend((0..o.nn).map(|k| {
            let i = is.first_p[k];
            i != usize::MAX && is.held_u[i]
        }));
        is.held_x.clear();
        for base in [o.a, o.uu, o.qq] {
            is.held_x
                .extend((0..o.nu).filter(|&i| is.held_u[i]).map(|i| base + i));
        }
        for base in [o.kn, o.cn, o.ln] {
            is.held_x
                .extend((0..o.nn).filter(|&k| is.held_n[k]).map(|k| base + k));
        }
        for base in [o.cf, o.lf] {
            for (j, law) in self.layout.friction.iter().enumerate() {
                if law.normals.iter().any(|&k| is.held_n[k]) {
                    let f0 = self.law_off[j];
                    is.held_x.extend((0..law.components).map(|m| base + f0 + m));
                }
            }
        }
    }

    /// Whether a held row of the residual just evaluated exceeds the tolerance; wakes
    /// the islands for the rest of the step when one does.
    pub(super) fn held_row_broken(&mut self, sets: &IndexSets) -> bool {
        let (tol, round_off) = (self.options.tol, self.gap_round_off());
        let res = &self.work.res;
        let broken = self
            .islands
            .held()
            .iter()
            .any(|&i| res[i].abs() - self.row_round_off(i, sets, round_off) > tol);
        if broken {
            self.stats.island_wakes += 1;
            self.islands.wake();
        }
        broken
    }
}

#[cfg(test)]
mod tests {
    use super::{find, join, union};

    /// Two constraints acting on coordinates 2, 0 and 4, 3 leave 1 and 5 alone: four
    /// components, each named by its smallest coordinate; a mass coupling of 5 and 2
    /// joins two of them.
    #[test]
    fn constraints_join_the_coordinates_they_act_on() {
        let mut parent: Vec<usize> = (0..6).collect();
        let (mut first_a, mut first_b) = (usize::MAX, usize::MAX);
        for i in [2, 0] {
            join(&mut parent, &mut first_a, i);
        }
        for i in [4, 3] {
            join(&mut parent, &mut first_b, i);
        }
        assert_eq!((first_a, first_b), (2, 4));
        let roots: Vec<usize> = (0..6).map(|i| find(&mut parent, i)).collect();
        assert_eq!(roots, [0, 1, 0, 3, 3, 5]);
        union(&mut parent, 5, 2);
        assert_eq!(find(&mut parent, 5), 0);
    }
}
