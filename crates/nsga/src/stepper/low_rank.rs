//! A simplified Newton update for index sets other than those of the kept factors: the
//! kept matrix with the rows whose form the sets change replaced, solved from the kept
//! factors by the Sherman–Morrison–Woodbury formula (docs/method.md §7, "Low-rank
//! updates for changed index sets").
//!
//! A contact that opens or closes on one level, or a friction law that switches between
//! sticking and slipping, changes one or two rows of the Newton matrix of eq. 143 from
//! one form to the other (§3: a closed row holds W, an open one the identity). With the
//! kept matrix J₀ and D the k changed rows' differences (new minus kept), the matrix
//! J₀ + E D (E: the unit columns of those rows) is solved as
//!
//! ```text
//! y = J₀⁻¹ b,   Z = J₀⁻¹ E,   (I + D Z) w = D y,   x = y − Z w:
//! ```
//!
//! one substitution with the kept factors for y, the columns of Z (kept while the
//! factors are, since they depend on nothing else), and a k × k solve, instead of new
//! derivatives and a new factorization. The new rows are formed at the kept factors'
//! linearization point, from the derivative rows computed with them, so that the matrix
//! solved is the Newton matrix of that point for the new sets. Like every simplified
//! update it is taken only while the residual contracts.

use super::assemble::ContactRows;
use super::kinematic::KinematicColumns;
use super::prune::{expand, restrict, Pruning};
use super::scheme::Scheme;
use super::z_columns::ZColumns;
use super::Stepper;
use crate::sets::IndexSets;
use crate::system::System;

/// Most rows a low-rank update replaces by default
/// ([`Tuning::low_rank_rows`](crate::Tuning::low_rank_rows)); where the sets change more,
/// the matrix is factorized anew.
pub const LOW_RANK_ROWS: usize = 8;

/// The kept matrix and the scratch of low-rank updates.
#[derive(Debug, Clone, Default)]
pub(super) struct LowRank {
    /// The kept factors' matrix, as factorized (reduced numbering), as triplets.
    kept: Vec<(usize, usize, f64)>,
    /// `kept` by row ([`group_by_key`]), made at the first update on the factors (empty
    /// until then): an update reads its k rows there, not in a pass over the whole
    /// matrix, which tall columns' updates of about 30 rows made at every update. (A
    /// counting sort, not `RowMat::build`, which was 3 % of the matrix's stick–slip rows
    /// in `perf`, at about 1.3 low-rank updates per factorization.)
    kept_at: Vec<usize>,
    kept_by_row: Vec<usize>,
    /// Columns J₀⁻¹ e_r of the kept factors.
    z: ZColumns,
    /// The changed rows (full numbering, then reduced) and their contacts.
    rows: Vec<usize>,
    reduced: Vec<usize>,
    only: ContactRows,
    /// For each reduced row, its place among the changed rows (`usize::MAX`: none).
    slot: Vec<usize>,
    /// The terms of D as (changed row, column, value), new rows' then the kept rows'
    /// negated; D by its nonzeros, row by row (row i's columns and values in
    /// `d_ptr[i]..d_ptr[i + 1]` of `d_cols` and `d`); and y.
    d_terms: Vec<(usize, usize, f64)>,
    /// The terms by row ([`group_by_key`]).
    term_at: Vec<usize>,
    term_order: Vec<usize>,
    d_cols: Vec<usize>,
    d: Vec<f64>,
    d_ptr: Vec<usize>,
    y: Vec<f64>,
    /// For each column, its place in `d` while a row of D is summed (`usize::MAX`:
    /// none), and that row's entries, to be put in column order.
    d_at: Vec<usize>,
    d_row: Vec<(usize, f64)>,
    /// The changed rows' places among the kept columns of Z, and the k × k system
    /// (I + D Z) w = D y.
    z_at: Vec<usize>,
    c: Vec<f64>,
    rhs: Vec<f64>,
}

impl LowRank {
    /// D by its nonzeros from its terms, of `n` columns: the terms of each entry summed
    /// in the order they were pushed (a dense D summed them so, and the sums are the
    /// same), the entries of a row by column, exact zeros left out (the products with
    /// them are). One pass over the terms per row: a row's terms are a few bodies'.
    fn by_entry(&mut self, n: usize) {
        // Every place is reset after its row, so only new columns need one.
        self.d_at.resize(n, usize::MAX);
        self.d_cols.clear();
        self.d.clear();
        self.d_ptr.clear();
        self.d_ptr.push(0);
        let k = self.reduced.len();
        let rows = self.d_terms.iter().map(|t| t.0);
        group_by_key(rows, k, &mut self.term_at, &mut self.term_order);
        for i in 0..k {
            self.d_row.clear();
            for &t in &self.term_order[self.term_at[i]..self.term_at[i + 1]] {
                let (_, c, v) = self.d_terms[t];
                if self.d_at[c] == usize::MAX {
                    self.d_at[c] = self.d_row.len();
                    self.d_row.push((c, 0.0));
                }
                self.d_row[self.d_at[c]].1 += v;
            }
            // The columns are distinct.
            self.d_row.sort_unstable_by_key(|&(c, _)| c);
            for &(c, v) in &self.d_row {
                self.d_at[c] = usize::MAX;
                if v != 0.0 {
                    self.d_cols.push(c);
                    self.d.push(v);
                }
            }
            self.d_ptr.push(self.d.len());
        }
    }

    /// New kept factors, of the matrix `kept` (reduced numbering), taken by swapping
    /// buffers: the caller's assembles its next matrix from scratch. (A copy cost a
    /// memcpy of 30 kB per factorization of a six-block pile.)
    pub fn factored(&mut self, kept: &mut Vec<(usize, usize, f64)>) {
        std::mem::swap(&mut self.kept, kept);
        self.kept_at.clear();
        self.z.clear();
    }

    /// Appends the terms −J₀ of the changed rows to D's, row by row, each row's in the
    /// kept matrix's order (that of its entries' sums, as a pass over it gave), for a
    /// kept matrix of `n` rows.
    fn push_kept_rows(&mut self, n: usize) {
        if self.kept_at.is_empty() {
            let rows = self.kept.iter().map(|t| t.0);
            group_by_key(rows, n, &mut self.kept_at, &mut self.kept_by_row);
        }
        for (i, &r) in self.reduced.iter().enumerate() {
            for &t in &self.kept_by_row[self.kept_at[r]..self.kept_at[r + 1]] {
                let (_, c, v) = self.kept[t];
                self.d_terms.push((i, c, -v));
            }
        }
    }
}

/// A stable counting sort of items by key: `order` lists the items' indices by key, each
/// key's in their order, key r's at `order[at[r]..at[r + 1]]`, for keys below `keys`.
fn group_by_key(
    item_keys: impl Iterator<Item = usize> + Clone,
    keys: usize,
    at: &mut Vec<usize>,
    order: &mut Vec<usize>,
) {
    at.clear();
    at.resize(keys + 1, 0);
    for r in item_keys.clone() {
        at[r + 1] += 1;
    }
    for r in 0..keys {
        at[r + 1] += at[r];
    }
    order.clear();
    order.resize(at[keys], 0);
    for (i, r) in item_keys.enumerate() {
        order[at[r]] = i;
        at[r] += 1;
    }
    // Each at[r] is now the end of key r's items, the start of key r + 1's.
    at.copy_within(0..keys, 1);
    at[0] = 0;
}

/// The rows of the Newton matrix whose form differs between `kept` and `sets`, full
/// numbering, and their contacts: κ, Λ, λ of a normal contact whose A, B, C membership
/// differs; both rows of every component of a friction law whose activity (a normal in
/// A), D or E membership differs. False when there are more than `most`.
fn changed_rows<S: System>(
    stepper: &Stepper<S>,
    kept: &IndexSets,
    sets: &IndexSets,
    most: usize,
    rows: &mut Vec<usize>,
    only: &mut ContactRows,
) -> bool {
    let o = stepper.off;
    rows.clear();
    only.normals.clear();
    only.laws.clear();
    for k in 0..o.nn {
        let len = rows.len();
        for (changed, row) in [
            (kept.a[k] != sets.a[k], o.kn + k),
            (kept.b[k] != sets.b[k], o.cn + k),
            (kept.c[k] != sets.c[k], o.ln + k),
        ] {
            if changed {
                rows.push(row);
            }
        }
        only.normals.push(rows.len() > len);
    }
    for (j, law) in stepper.layout.friction.iter().enumerate() {
        let active = |s: &IndexSets| law.normals.iter().any(|&k| s.a[k]);
        let changed =
            active(kept) != active(sets) || kept.d[j] != sets.d[j] || kept.e[j] != sets.e[j];
        if changed {
            let f0 = stepper.law_off[j];
            for m in 0..law.components {
                rows.extend([o.cf + f0 + m, o.lf + f0 + m]);
            }
        }
        only.laws.push(changed);
    }
    rows.len() <= most
}

/// Solves the k × k system `c` w = `rhs` (row-major) in place by Gaussian elimination
/// with partial pivoting; false when a pivot is not above 10⁻¹² times the largest entry
/// (the updated matrix is then taken as singular, and factorized anew).
fn solve_small(k: usize, c: &mut [f64], rhs: &mut [f64]) -> bool {
    let largest = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for col in 0..k {
        let p = (col..k)
            .max_by(|&i, &j| c[i * k + col].abs().total_cmp(&c[j * k + col].abs()))
            .unwrap_or(col);
        // NaN entries fail this test too.
        let usable = c[p * k + col].abs() > 1e-12 * largest;
        if !usable {
            return false;
        }
        if p != col {
            for m in 0..k {
                c.swap(p * k + m, col * k + m);
            }
            rhs.swap(p, col);
        }
        for i in col + 1..k {
            let l = c[i * k + col] / c[col * k + col];
            for m in col..k {
                c[i * k + m] -= l * c[col * k + m];
            }
            rhs[i] -= l * rhs[col];
        }
    }
    for col in (0..k).rev() {
        let s = (col + 1..k).fold(rhs[col], |s, m| s - c[col * k + m] * rhs[m]);
        rhs[col] = s / c[col * k + col];
    }
    rhs.iter().all(|v| v.is_finite())
}

impl<S: System> Stepper<S> {
    /// The low-rank update (module docs) at `x` for `sets` into `dx`, when the kept
    /// factors fit but for at most `p.low_rank_rows` rows
    /// ([`Tuning::low_rank_rows`](crate::Tuning::low_rank_rows), or
    /// [`Tuning::held_low_rank_rows`](crate::Tuning::held_low_rank_rows) in a held-sets
    /// attempt); false otherwise (`dx` then holds nothing that counts). `prune` is this
    /// attempt's prune map and reduced size, the kept factors' too.
    pub(super) fn low_rank_direction(
        &mut self,
        x: &[f64],
        sets: &IndexSets,
        p: &Scheme,
        prune: Option<&Pruning>,
        dx: &mut [f64],
    ) -> bool {
        let Some(kept) = self.work.factored.as_ref() else {
            return false;
        };
        let mut rows = std::mem::take(&mut self.work.low_rank.rows);
        let mut only = std::mem::take(&mut self.work.low_rank.only);
        let most = p.low_rank_rows;
        let fits =
            changed_rows(self, &kept.sets, sets, most, &mut rows, &mut only) && !rows.is_empty();
        if fits {
            // The derivative rows are still those of the kept factors' point: only a
            // plain factorization's factors take low-rank updates, and it keeps them
            // right after computing those rows.
            self.assemble_jacobian(x, sets, p, Some(&only));
        }
        self.work.low_rank.rows = rows;
        self.work.low_rank.only = only;
        let ok = fits && self.low_rank_solve(prune, dx);
        if ok {
            KinematicColumns::new(self.options.dt, &p.alpha).to_unknowns(&self.off, dx);
        }
        ok
    }

    /// The Woodbury solve of the module docs, with the changed rows in `work.jac` and the
    /// residual in `work.res`.
    fn low_rank_solve(&mut self, prune: Option<&Pruning>, dx: &mut [f64]) -> bool {
        let map = prune.map(|(map, _)| map.as_slice());
        let n = prune.map_or(self.off.n, |&(_, n_red)| n_red);
        let reduce = |i: usize| map.map_or(i, |m| m[i]);
        let w = &mut self.work;
        let lr = &mut w.low_rank;
        lr.reduced.clear();
        lr.reduced.extend(
            lr.rows
                .iter()
                .map(|&r| reduce(r))
                .filter(|&r| r != usize::MAX),
        );
        let k = lr.reduced.len();
        if k == 0 {
            return false;
        }
        lr.slot.clear();
        lr.slot.resize(n, usize::MAX);
        for (s, &r) in lr.reduced.iter().enumerate() {
            lr.slot[r] = s;
        }
        // D: the new rows minus the kept ones, by its nonzeros: a changed row touches a
        // few bodies' unknowns, and a dense k × n D cost 87 MB per update of 64 rows of
        // a 10 000-block column.
        lr.d_terms.clear();
        for &(r, c, v) in &w.jac {
            let (r, c) = (reduce(r), reduce(c));
            if r != usize::MAX && c != usize::MAX && lr.slot[r] != usize::MAX {
                lr.d_terms.push((lr.slot[r], c, v));
            }
        }
        lr.push_kept_rows(n);
        lr.by_entry(n);
        // y = J₀⁻¹ b with b = −R.
        lr.y.clear();
        lr.y.resize(n, 0.0);
        restrict(map, &w.res, &mut lr.y);
        lr.y.iter_mut().for_each(|v| *v = -*v);
        if w.solver.solve_again(&mut lr.y).is_err() {
            return false;
        }
        // The columns of Z, kept from earlier updates on these factors where they can be.
        lr.z.make_room(&lr.reduced, self.options.tuning.kept_columns.max(k));
        lr.z_at.clear();
        for &r in &lr.reduced {
            let at = match lr.z.place(r) {
                Some(at) => at,
                None => {
                    let col = lr.z.spare();
                    col.clear();
                    col.resize(n, 0.0);
                    col[r] = 1.0;
                    if w.solver.solve_again(col).is_err() {
                        return false;
                    }
                    lr.z.push(r)
                }
            };
            lr.z_at.push(at);
        }
        // (I + D Z) w = D y.
        lr.c.clear();
        lr.c.resize(k * k, 0.0);
        lr.rhs.clear();
        lr.rhs.resize(k, 0.0);
        for i in 0..k {
            let row = lr.d_ptr[i]..lr.d_ptr[i + 1];
            let (cols, d_i) = (&lr.d_cols[row.clone()], &lr.d[row]);
            let dot = |v: &[f64]| cols.iter().zip(d_i).map(|(&c, d)| d * v[c]).sum::<f64>();
            lr.rhs[i] = dot(&lr.y);
            for j in 0..k {
                lr.c[i * k + j] = f64::from(u8::from(i == j)) + dot(lr.z.column(lr.z_at[j]));
            }
        }
        if !solve_small(k, &mut lr.c, &mut lr.rhs) {
            return false;
        }
        for (&wj, &at) in lr.rhs.iter().zip(&lr.z_at) {
            for (yi, zi) in lr.y.iter_mut().zip(lr.z.column(at)) {
                *yi -= zi * wj;
            }
        }
        if !lr.y.iter().all(|v| v.is_finite()) {
            return false;
        }
        expand(map, &lr.y, dx);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::chain::Chain;
    use crate::{LinearOptions, Options};

    fn max_difference(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
    }

    /// A resting chain of n blocks, the top one slipping, with its Newton matrix at the
    /// start factorized for the sets there: the stepper, x, the parameters, those sets,
    /// and the update they give.
    fn factored_chain(n: usize) -> (Stepper<Chain>, Vec<f64>, Scheme, IndexSets, Vec<f64>) {
        let chain = Chain::benchmark(n);
        let (q0, u0) = chain.resting(0.3);
        let options = Options {
            dt: 1e-3,
            linear: LinearOptions {
                reuse_factorization: true,
                low_rank_updates: true,
                ..LinearOptions::default()
            },
            ..Options::default()
        };
        let mut s = Stepper::new(chain, 0.0, &q0, &u0, options).unwrap();
        let x = s.state().x.clone();
        let p = s.scheme(0.5);
        let kept = s.sets_of(&x, 0.5);
        assert!(
            kept.a.iter().all(|&a| a) && !kept.d[n - 1],
            "{}",
            kept.describe()
        );
        let mut dx = vec![0.0; x.len()];
        s.residual(&x, &kept, &p);
        s.exact_direction(&x, &kept, &p, None, &mut dx).unwrap();
        (s, x, p, kept, dx)
    }

    /// At the kept factors' own iterate, the kept matrix with the changed rows replaced
    /// is the Newton matrix of the new sets there: the low-rank update must equal the
    /// exact update for those sets.
    #[test]
    fn at_the_kept_iterate_the_low_rank_update_is_the_exact_one() {
        let (_, _, _, kept, _) = factored_chain(4);
        // The top block sticks instead of slipping (2 rows); the top contact opens on
        // every level, which also frees its friction law (5 rows).
        let mut sticking = kept.clone();
        (sticking.d[3], sticking.e[3]) = (true, true);
        let mut opened = kept.clone();
        (opened.a[3], opened.b[3], opened.c[3]) = (false, false, false);
        for (sets, rows) in [(sticking, 2), (opened, 5)] {
            let (mut s, x, p, _, kept_update) = factored_chain(4);
            s.residual(&x, &sets, &p);
            let mut low = vec![0.0; x.len()];
            assert!(s.low_rank_direction(&x, &sets, &p, None, &mut low));
            assert_eq!(s.work.low_rank.rows.len(), rows);
            let mut exact = vec![0.0; x.len()];
            s.exact_direction(&x, &sets, &p, None, &mut exact).unwrap();
            let size = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(size > 0.0);
            let diff = max_difference(&low, &exact);
            assert!(diff <= 1e-10 * size, "{diff} against {size}");
            // Not the kept sets' update: the changed rows matter.
            assert!(max_difference(&low, &kept_update) > 1e-6 * size);
        }
    }

    #[test]
    fn more_changed_rows_than_the_limit_are_left_to_a_factorization() {
        let (mut s, x, p, kept, mut dx) = factored_chain(12);
        // Three contacts opened: 3 × (3 + 2) rows.
        let mut sets = kept.clone();
        for k in [1, 5, 9] {
            (sets.a[k], sets.b[k], sets.c[k]) = (false, false, false);
        }
        s.residual(&x, &sets, &p);
        assert!(!s.low_rank_direction(&x, &sets, &p, None, &mut dx));
        assert!(s.work.low_rank.rows.len() > p.low_rank_rows);
        // With room for them (a held-sets attempt's `Tuning::held_low_rank_rows`), the
        // kept factors serve, and the update is the exact one of the kept iterate for
        // these sets.
        let (mut s, x, p, _, _) = factored_chain(12);
        let p = Scheme {
            low_rank_rows: s.options.tuning.held_low_rank_rows,
            ..p
        };
        assert!(p.low_rank_rows >= 15);
        s.residual(&x, &sets, &p);
        assert!(s.low_rank_direction(&x, &sets, &p, None, &mut dx));
        assert_eq!(s.work.low_rank.rows.len(), 15);
        let mut exact = vec![0.0; x.len()];
        s.exact_direction(&x, &sets, &p, None, &mut exact).unwrap();
        let size = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(max_difference(&dx, &exact) <= 1e-10 * size);
    }

    /// Updates on one factorization whose rows need more columns than are kept: the
    /// least recently used columns make room, and the updates are those that kept every
    /// column gives, to the bit, and the exact ones of the kept iterate.
    #[test]
    fn columns_dropped_for_room_leave_the_updates_as_they_are() {
        let opened = |contacts: &[usize]| {
            let (_, _, _, mut sets, _) = factored_chain(12);
            for &k in contacts {
                (sets.a[k], sets.b[k], sets.c[k]) = (false, false, false);
            }
            sets
        };
        let held = |s: &Stepper<Chain>, p: Scheme| Scheme {
            low_rank_rows: s.options.tuning.held_low_rank_rows,
            ..p
        };
        let (mut few, x, p, _, _) = factored_chain(12);
        few.options.tuning.kept_columns = 5;
        let (mut all, _, _, _, _) = factored_chain(12);
        let p = held(&few, p);
        // 5 rows each for one contact, 10 for two: the second and third updates drop
        // columns, the fourth needs some of those dropped again.
        for contacts in [&[1][..], &[5], &[1, 9], &[5]] {
            let sets = opened(contacts);
            let (mut a, mut b) = (vec![0.0; x.len()], vec![0.0; x.len()]);
            few.residual(&x, &sets, &p);
            assert!(few.low_rank_direction(&x, &sets, &p, None, &mut a));
            all.residual(&x, &sets, &p);
            assert!(all.low_rank_direction(&x, &sets, &p, None, &mut b));
            let k = few.work.low_rank.reduced.len();
            assert!(few.work.low_rank.z.kept() <= k.max(5), "{contacts:?}");
            assert_eq!(a, b, "{contacts:?}");
            let (mut fresh, _, _, _, _) = factored_chain(12);
            let mut exact = vec![0.0; x.len()];
            fresh.residual(&x, &sets, &p);
            fresh
                .exact_direction(&x, &sets, &p, None, &mut exact)
                .unwrap();
            let size = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(max_difference(&a, &exact) <= 1e-10 * size, "{contacts:?}");
        }
        assert!(all.work.low_rank.z.kept() > 5);
    }

    /// Items grouped by key keep their order within a key, and keys without items
    /// get empty ranges.
    #[test]
    fn grouping_by_key_is_stable() {
        let keys = [2, 0, 2, 3, 0, 2];
        let (mut at, mut order) = (Vec::new(), Vec::new());
        group_by_key(keys.iter().copied(), 5, &mut at, &mut order);
        assert_eq!(at, [0, 2, 2, 5, 6, 6]);
        assert_eq!(order, [1, 4, 0, 2, 5, 3]);
    }

    /// D by its nonzeros sums each entry's terms in the order they came, as a dense D
    /// did, and leaves out the entries that cancel.
    #[test]
    fn d_by_its_nonzeros_sums_each_entry_in_order() {
        let mut lr = LowRank {
            reduced: vec![4, 7],
            ..LowRank::default()
        };
        let (a, b, c) = (0.1, 0.2, 0.3);
        lr.d_terms = vec![(1, 5, a), (0, 9, 1.0), (1, 5, b), (0, 2, 2.0), (1, 5, -c)];
        lr.d_terms.push((0, 9, -1.0));
        lr.by_entry(10);
        assert_eq!(lr.d_ptr, [0, 1, 2]);
        assert_eq!(lr.d_cols, [2, 5]);
        assert_eq!(lr.d, [2.0, (0.0 + a + b) - c]);
    }

    #[test]
    fn small_systems_are_solved_with_pivoting() {
        // A zero leading entry needs the row swap.
        let mut c = [0.0, 1.0, 2.0, 1.0];
        let mut rhs = [3.0, 5.0];
        assert!(solve_small(2, &mut c, &mut rhs));
        assert!((rhs[0] - 1.0).abs() < 1e-15 && (rhs[1] - 3.0).abs() < 1e-15);
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert!(!solve_small(2, &mut singular, &mut [1.0, 1.0]));
    }
}
