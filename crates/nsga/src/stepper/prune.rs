//! Open contacts pruned from an attempt's linear solve (docs/method.md §7, "Pruned
//! matrices"): a contact that is open, force-free and cannot close within the step keeps
//! its unknowns at zero, and the Newton matrix is factored without its rows and columns.

use super::Stepper;
use crate::system::System;

/// The map full → reduced index of the unknowns left in the linear solve
/// (`usize::MAX` for a pruned one) and the reduced size.
pub(super) type Pruning = (Vec<usize>, usize);

/// Writes the entries of the full-length `full` left in the linear solve into `reduced`,
/// in the reduced numbering of the prune `map` (all of them, in order, without one).
pub(super) fn restrict(map: Option<&[usize]>, full: &[f64], reduced: &mut [f64]) {
    let Some(map) = map else {
        reduced.copy_from_slice(full);
        return;
    };
    for (&m, &v) in map.iter().zip(full) {
        if m != usize::MAX {
            reduced[m] = v;
        }
    }
}

/// The inverse of [`restrict`]: `full` from `reduced`, the pruned entries 0.
pub(super) fn expand(map: Option<&[usize]>, reduced: &[f64], full: &mut [f64]) {
    let Some(map) = map else {
        full.copy_from_slice(reduced);
        return;
    };
    for (f, &m) in full.iter_mut().zip(map) {
        *f = if m == usize::MAX { 0.0 } else { reduced[m] };
    }
}

impl<S: System> Stepper<S> {
    /// Marks the unknowns of contacts that are open, force-free and cannot close within
    /// the step, sets them to zero in `x`, and returns the map full → reduced index
    /// (`usize::MAX` for pruned) and the reduced size; None when nothing is pruned. The
    /// map is written into the buffer of the last one given back
    /// ([`Stepper::give_back_pruning`]).
    ///
    /// The unknowns of the islands held at rest (`stepper/islands.rs`) are left out too,
    /// at their held values (the state's).
    pub(super) fn open_contacts(&mut self, x: &mut [f64], keep: &[bool]) -> Option<Pruning> {
        let unclosable = self.mark_unclosable(keep);
        if !unclosable && self.islands.held().is_empty() {
            return None;
        }
        let o = self.off;
        let st = &self.state;
        let pruned_n = &self.work.unclosable;
        let mut map = std::mem::take(&mut self.work.prune_map);
        map.clear();
        map.resize(o.n, 0);
        let prune_unknown = |i: usize, map: &mut Vec<usize>, x: &mut [f64]| {
            map[i] = usize::MAX;
            x[i] = 0.0;
        };
        for &i in self.islands.held() {
            map[i] = usize::MAX;
            x[i] = st.x[i];
        }
        for (k, &pr) in pruned_n.iter().enumerate() {
            if pr && unclosable {
                for base in [o.kn, o.cn, o.ln] {
                    prune_unknown(base + k, &mut map, x);
                }
            }
        }
        for (j, law) in self.layout.friction.iter().enumerate() {
            let f0 = self.law_off[j];
            let quiet = (0..law.components)
                .all(|m| st.lambda_f[f0 + m] == 0.0 && st.lambda_f_bar[f0 + m] == 0.0);
            if unclosable && quiet && law.normals.iter().all(|&k| pruned_n[k]) {
                for m in 0..law.components {
                    prune_unknown(o.cf + f0 + m, &mut map, x);
                    prune_unknown(o.lf + f0 + m, &mut map, x);
                }
            }
        }
        let n_red = number_kept(&mut map);
        Some((map, n_red))
    }

    /// Keeps the buffer of a prune map no longer used, for the next
    /// [`Stepper::open_contacts`].
    pub(super) fn give_back_pruning(&mut self, prune: Option<Pruning>) {
        if let Some((map, _)) = prune {
            self.work.prune_map = map;
        }
    }

    /// Flags in `work.unclosable` the normal contacts not in `keep` that are open,
    /// force-free and cannot close within the step; returns whether there is one.
    pub(super) fn mark_unclosable(&mut self, keep: &[bool]) -> bool {
        let o = self.off;
        let dt = self.options.dt;
        self.state_levels();
        let st = &self.state;
        let w = &mut self.work;
        let levels = &w.state_levels;
        // The normal contacts' rows, as slices: their pointers and lengths read once.
        let nr = o.ng..o.ng + o.nn;
        let (gap, rate) = (&levels.position[nr.clone()], &levels.rate[nr.clone()]);
        let acc = &levels.acceleration[nr];
        let (lambda_n, lambda_n_bar) = (&st.lambda_n[..], &st.lambda_n_bar[..]);
        let prune_margin = self.options.tuning.prune_margin;
        w.unclosable.clear();
        w.unclosable.extend((0..o.nn).map(|k| {
            let margin = prune_margin * dt * rate[k].abs() + dt * dt * acc[k].abs();
            !keep[k]
                && gap[k] > margin
                && gap[k] > 0.0
                && lambda_n[k] == 0.0
                && lambda_n_bar[k] == 0.0
        }));
        w.unclosable.iter().any(|&b| b)
    }

    /// Makes `work.state_levels` those of the current state: kept from the iterate that
    /// became it (`state_levels`), or evaluated here.
    pub(super) fn state_levels(&mut self) {
        let st = &self.state;
        let w = &mut self.work;
        if w.state_levels.describe(st) {
            return;
        }
        w.eval.reset();
        self.system.evaluate_real(st.t, &st.q, &st.u, &mut w.eval);
        w.state_levels.evaluate(st, &w.eval);
    }

    /// Marks the constraints whose unknowns the prune `map` leaves out (none without).
    pub(super) fn mark_unused(&mut self, map: Option<&[usize]>) {
        let o = self.off;
        let w = &mut self.work;
        w.unused_position.clear();
        w.unused_velocity.clear();
        if let Some(map) = map {
            let pruned = |i: usize| map[i] == usize::MAX;
            w.unused_position.resize(o.ng, false);
            w.unused_position
                .extend((0..o.nn).map(|k| pruned(o.kn + k)));
            w.unused_velocity.resize(o.nga, false);
            w.unused_velocity
                .extend((0..o.nf).map(|c| pruned(o.cf + c)));
        }
    }
}

/// Numbers the unknowns `map` keeps (those not `usize::MAX`) 0, 1, … in order, making it
/// a prune map; returns how many it keeps, the reduced size.
pub(super) fn number_kept(map: &mut [usize]) -> usize {
    let mut n_red = 0;
    for m in map.iter_mut().filter(|m| **m != usize::MAX) {
        *m = n_red;
        n_red += 1;
    }
    n_red
}

/// Whether the prune map `kept` (None: nothing pruned) keeps every unknown that `now`
/// keeps, so that factors made with `kept` hold all of `now`'s unknowns.
pub(super) fn keeps_all_of(kept: Option<&Vec<usize>>, now: Option<&[usize]>) -> bool {
    match (kept, now) {
        (None, _) => true,
        (Some(kept), None) => kept.iter().all(|&m| m != usize::MAX),
        (Some(kept), Some(now)) => kept
            .iter()
            .zip(now)
            .all(|(&k, &n)| n == usize::MAX || k != usize::MAX),
    }
}

#[cfg(test)]
mod tests {
    use crate::systems::chain::Chain;
    use crate::{Options, Stepper};

    /// The top block of a resting column 5 cm above the next: its contact is pruned, in
    /// the buffer of the map given back before.
    #[test]
    fn the_prune_map_is_written_into_the_buffer_given_back() {
        let chain = Chain::benchmark(4);
        let (mut q0, u0) = chain.resting(0.0);
        q0[7] += 0.05;
        let options = Options {
            dt: 1e-3,
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, options).unwrap();
        let (o, top) = (s.off, s.off.nn - 1);
        let mut x = s.state().x.clone();
        let keep = vec![false; o.nn];
        let (map, n_red) = s.open_contacts(&mut x, &keep).unwrap();
        let pruned = [o.kn + top, o.cn + top, o.ln + top];
        assert!(pruned.iter().all(|&i| map[i] == usize::MAX));
        assert_eq!(map.iter().filter(|&&m| m != usize::MAX).count(), n_red);
        let buffer = map.as_ptr();
        let first = map.clone();
        s.give_back_pruning(Some((map, n_red)));
        let again = s.open_contacts(&mut x, &keep).unwrap();
        assert_eq!(
            (&again.0, again.0.as_ptr(), again.1),
            (&first, buffer, n_red)
        );
        // A contact kept from pruning is not pruned.
        let mut keep_top = keep;
        keep_top[top] = true;
        assert!(s.open_contacts(&mut x, &keep_top).is_none());
    }
}
