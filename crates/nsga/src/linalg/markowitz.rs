//! Sparse LU for the small Newton matrices of contact problems: dense storage, bit-set
//! sparsity patterns, and pivots chosen per matrix by Markowitz's rule with threshold
//! partial pivoting (Duff, Erisman & Reid, *Direct Methods for Sparse Matrices*, §7.2
//! and §7.8).
//!
//! The Newton matrix of eq. 143 has tens to a few hundred unknowns and a few percent to
//! a fifth of its entries nonzero: the mass blocks of a, U and Q are as sparse as M, and
//! each contact row touches only the coordinates of the bodies it joins. Dense LU spends
//! most of its flops on zeros, and a general sparse LU spends them on a symbolic analysis
//! that the index sets invalidate whenever a contact opens or closes. Here the values
//! live in a dense n × n array (no indirection), the patterns of rows and columns in
//! bit sets (one 64-bit word per 64 rows or columns), and the elimination touches only
//! the nonzeros of the pivot row and column. Pivots are chosen as the factorization goes,
//! so a changed pattern costs nothing extra. A matrix found singular is handed to dense
//! LU with partial pivoting, whose verdict stands (see the `dense` field).

use super::{finite, regular_pivots, DenseLu, LinalgError, LinearSolver};

/// A pivot must be at least this fraction of the largest active entry of its column.
/// Duff, Erisman & Reid recommend 0.1: fill stays close to the Markowitz optimum and
/// the growth of the entries stays bounded by (1 + 1/0.1) per elimination step.
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// Most unknowns a [`MarkowitzLu`] takes. (Its dense storage of n² values is the
/// practical limit long before.)
pub const MAX_UNKNOWNS: usize = 0xFFFE;

/// Sparse LU with Markowitz pivoting on dense storage (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct MarkowitzLu {
    n: usize,
    /// 64-bit words per pattern.
    words: usize,
    /// The matrix, row-major in the original numbering with row length `stride`,
    /// reduced in place. All zeros between factorizations: entry (i, j) is written only
    /// where bit j of row i's pattern is set, and [`MarkowitzLu::clear_values`] zeroes
    /// those, so a matrix costs its nonzeros and fill, not n² stores.
    a: Vec<f64>,
    /// Row length of `a`: the largest n seen.
    stride: usize,
    /// Pattern of each row (bit j: column j), and of each column (bit i: row i).
    row_pattern: Vec<u64>,
    col_pattern: Vec<u64>,
    /// Counts of entries in the active submatrix, by row.
    row_count: Vec<u32>,
    /// The counts of the active columns, for the pivot search.
    counts: ColumnCounts,
    /// Rows and columns not yet pivoted.
    active_rows: Vec<u64>,
    active_cols: Vec<u64>,
    /// Pivot k is entry (row, column) with value `pivot_value[k]`.
    pivots: Vec<(usize, usize)>,
    pivot_value: Vec<f64>,
    /// The factors by pivot, compressed: the multipliers of L (row, l) and the entries
    /// of U besides the pivot (column, u), pivot k's in `l_ptr[k]..l_ptr[k + 1]` and
    /// `u_ptr[k]..u_ptr[k + 1]`.
    l_ptr: Vec<usize>,
    l_entries: Vec<(usize, f64)>,
    u_ptr: Vec<usize>,
    u_entries: Vec<(usize, f64)>,
    /// Scratch: the pivot column's active (row, entry), the pivot row's active
    /// columns, and the solution.
    column: Vec<(usize, f64)>,
    u_words: Vec<u64>,
    x: Vec<f64>,
    /// Whether the factors of a regular matrix are kept.
    factored: bool,
    /// Dense LU with partial pivoting, for the matrices this elimination finds singular.
    /// Threshold pivots favour sparsity over size, so on a nearly singular matrix (the
    /// Newton matrix of redundant contacts) they can leave a column that cancels to zero
    /// or a pivot below the singularity test where partial pivoting finds usable ones.
    /// Deferring to it makes the singular/regular decision that of dense LU, which the
    /// regularization of redundant contacts (`Options::regularization`) is tuned
    /// against. Without it, 2 of 60 neighbouring Lire collapses that run through with
    /// dense LU stopped with an error, one of them at a matrix it called singular.
    ///
    /// A matrix whose elimination leaves an active column without a single entry in its
    /// pattern is not handed on: the pattern (fill included) holds every entry the
    /// Schur complement can have whatever the values, so that column of it is zero and
    /// the matrix singular for every pivot order. In the piles of shaken columns these
    /// are 2 in 5 of the singular matrices, and their dense LU cost more than all the
    /// regular factorizations of a run: 98 of 242 over `rollstack blocks shake --blocks
    /// 6 --omega 2 --mu 0.3 --amplitude 0.2 --steps-per-period 200 --t-end 5` (counted
    /// on the matrices of that run written out by a scratch print), where dense LU
    /// agreed on each. Over the same command with 5 blocks, μ = 0.5 and t = 20 it called
    /// 6 of 315 regular, by round-off: their solutions for a unit right-hand side were
    /// 10¹⁰ to 10¹⁵.
    dense: DenseLu,
    /// Whether the last matrix was factorized by `dense`.
    by_dense: bool,
}

/// The entry counts of the active columns, with the columns of each count as a bit set,
/// so that the pivot search finds the column of least count (the first of equals) by
/// looking at a few counts from the least one occupied, not at every column (a scan of
/// the columns makes the search O(n²) per factorization).
#[derive(Debug, Clone, Default)]
struct ColumnCounts {
    words: usize,
    count: Vec<u32>,
    /// Count c's columns in words `c * words..(c + 1) * words`.
    buckets: Vec<u64>,
    /// No count below it has a column.
    lowest: usize,
}

impl ColumnCounts {
    /// Every column of `counts` active, with its count.
    fn reset(&mut self, words: usize, counts: impl Iterator<Item = u32>) {
        self.words = words;
        self.count.clear();
        self.count.extend(counts);
        let n = self.count.len();
        self.buckets.clear();
        self.buckets.resize((n + 1) * words, 0);
        self.lowest = n;
        for (j, &c) in self.count.iter().enumerate() {
            set(&mut self.buckets, c as usize * words, j);
            self.lowest = self.lowest.min(c as usize);
        }
    }

    /// The active column of least count, the first of equals.
    fn least(&mut self) -> Option<usize> {
        let w = self.words;
        while let Some(bucket) = self.buckets.get(self.lowest * w..(self.lowest + 1) * w) {
            if let Some((word, &bits)) = bucket.iter().enumerate().find(|(_, &b)| b != 0) {
                return Some(64 * word + bits.trailing_zeros() as usize);
            }
            self.lowest += 1;
        }
        None
    }

    /// Column j's count changes by one, up or down.
    fn step(&mut self, j: usize, up: bool) {
        let w = self.words;
        let c = self.count[j] as usize;
        let to = if up { c + 1 } else { c.saturating_sub(1) };
        clear(&mut self.buckets[c * w..], j);
        set(&mut self.buckets, to * w, j);
        self.count[j] = to as u32;
        self.lowest = self.lowest.min(to);
    }

    /// Column j leaves the search (it was pivoted).
    fn retire(&mut self, j: usize) {
        let c = self.count[j] as usize;
        clear(&mut self.buckets[c * self.words..], j);
    }
}

/// Why an elimination stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Singular {
    /// An active column has no entry in its pattern: singular whatever the values.
    Structurally,
    /// A column's entries are all zero, or a pivot fails the [`SINGULAR_PIVOT`] test:
    /// threshold pivoting may have caused it.
    ///
    /// [`SINGULAR_PIVOT`]: super::SINGULAR_PIVOT
    Numerically,
}

/// Sets bit `i` of the bit set that starts at word `base` of `words`.
fn set(words: &mut [u64], base: usize, i: usize) {
    words[base + i / 64] |= 1 << (i % 64);
}

fn clear(words: &mut [u64], i: usize) {
    words[i / 64] &= !(1 << (i % 64));
}

fn outside(r: usize, c: usize, n: usize) -> LinalgError {
    LinalgError(format!("entry ({r}, {c}) outside a {n} × {n} matrix"))
}

/// Calls `f` with the index of every set bit of `word`, offset by `base`.
fn each_bit(mut word: u64, base: usize, mut f: impl FnMut(usize)) {
    while word != 0 {
        f(base + word.trailing_zeros() as usize);
        word &= word - 1;
    }
}

impl MarkowitzLu {
    /// Loads J from triplets (duplicates summed; entries summing to zero are left out
    /// of the pattern).
    fn load(&mut self, n: usize, triplets: &[(usize, usize, f64)]) -> Result<(), LinalgError> {
        if n > MAX_UNKNOWNS {
            return Err(LinalgError(format!(
                "{n} unknowns: Markowitz LU takes at most {MAX_UNKNOWNS}"
            )));
        }
        if n > self.stride {
            self.stride = n;
            self.a = vec![0.0; n * n];
        }
        let (w, sa) = (n.div_ceil(64), self.stride);
        self.n = n;
        self.words = w;
        self.row_pattern.clear();
        self.row_pattern.resize(n * w, 0);
        self.col_pattern.clear();
        self.col_pattern.resize(n * w, 0);
        // The buffers as plain slices: the loops below write through them once per
        // triplet, and a field reached through `self` is reloaded after every store.
        let (a, rows, cols) = (
            &mut self.a[..],
            &mut self.row_pattern[..],
            &mut self.col_pattern[..],
        );
        for (k, &(r, c, v)) in triplets.iter().enumerate() {
            if r >= n || c >= n {
                // The storage stays zeroed between matrices: undo what was written.
                for &(r, c, _) in &triplets[..k] {
                    a[r * sa + c] = 0.0;
                }
                return Err(outside(r, c, n));
            }
            a[r * sa + c] += v;
            set(rows, r * w, c);
        }
        // Entries that summed to zero leave the row patterns, and the column patterns
        // are the rows' transposed: one pass over the distinct entries, where a pass per
        // triplet paid for the duplicates too (about half the triplets of eq. 143's
        // matrices, whose rows sum the system's derivatives).
        for r in 0..n {
            for word in 0..w {
                each_bit(rows[r * w + word], 64 * word, |c| {
                    if a[r * sa + c] == 0.0 {
                        clear(&mut rows[r * w..], c);
                    } else {
                        set(cols, c * w, r);
                    }
                });
            }
        }
        let count = |words: &[u64]| words.iter().map(|x| x.count_ones()).sum::<u32>();
        self.row_count.clear();
        self.row_count
            .extend((0..n).map(|r| count(&rows[r * w..(r + 1) * w])));
        self.counts
            .reset(w, (0..n).map(|c| count(&cols[c * w..(c + 1) * w])));
        for v in [&mut self.active_rows, &mut self.active_cols] {
            v.clear();
            v.resize(w, u64::MAX);
            if !n.is_multiple_of(64) {
                v[w - 1] = (1 << (n % 64)) - 1;
            }
        }
        self.pivots.clear();
        self.pivot_value.clear();
        self.l_ptr.clear();
        self.l_ptr.push(0);
        self.l_entries.clear();
        self.u_ptr.clear();
        self.u_ptr.push(0);
        self.u_entries.clear();
        Ok(())
    }

    /// The next pivot by Markowitz's rule, searched in one column: the active column of
    /// least count c (the first of equals), and in it, among the entries passing the
    /// threshold test, the one of least row count r, which minimizes (r − 1)(c − 1)
    /// there; ties go to the larger entry, then to the first row. An error when that
    /// column has no nonzero entry left (J is singular).
    ///
    /// Searching two or four columns of least count (Zlatev's strategy) lowered the fill
    /// on the Lire collapse's Newton matrices only slightly and cost more in the search
    /// than it saved.
    ///
    /// The active entries of the chosen column are left in `column` (rows in increasing
    /// order), for [`MarkowitzLu::eliminate`]: the column is read from the storage once.
    fn choose_pivot(&mut self) -> Result<(usize, usize), Singular> {
        let (sa, w) = (self.stride, self.words);
        let j = self.counts.least().ok_or(Singular::Structurally)?;
        self.column.clear();
        let mut largest = 0.0_f64;
        let (a, column) = (&self.a, &mut self.column);
        let col = &self.col_pattern[j * w..(j + 1) * w];
        for (word, (&rows, &active)) in col.iter().zip(&self.active_rows).enumerate() {
            each_bit(rows & active, 64 * word, |i| {
                let v = a[i * sa + j];
                largest = largest.max(v.abs());
                column.push((i, v));
            });
        }
        if self.column.is_empty() {
            return Err(Singular::Structurally);
        }
        // NaN entries fail this test too.
        let nonzero = largest > 0.0;
        if !nonzero {
            return Err(Singular::Numerically);
        }
        let mut best: Option<(u32, usize, f64)> = None;
        for &(i, v) in &self.column {
            let v = v.abs();
            let r = self.row_count[i];
            if v >= PIVOT_THRESHOLD * largest
                && best.is_none_or(|(br, _, bv)| r < br || (r == br && v > bv))
            {
                best = Some((r, i, v));
            }
        }
        best.map(|(_, i, _)| (i, j)).ok_or(Singular::Numerically)
    }

    /// Pivots on entry (p, c): stores U row k and the multipliers of L, and updates
    /// the active rows of column c by the pivot row, following its fill.
    fn eliminate(&mut self, p: usize, c: usize) {
        let (sa, w) = (self.stride, self.words);
        clear(&mut self.active_rows, p);
        clear(&mut self.active_cols, c);
        self.counts.retire(c);
        let u_start = self.u_entries.len();
        self.u_words.clear();
        {
            let (a, counts) = (&self.a[p * sa..(p + 1) * sa], &mut self.counts);
            let u_entries = &mut self.u_entries;
            let row = &self.row_pattern[p * w..(p + 1) * w];
            for (word, (&pattern, &active)) in row.iter().zip(&self.active_cols).enumerate() {
                let columns = pattern & active;
                self.u_words.push(columns);
                each_bit(columns, 64 * word, |j| {
                    u_entries.push((j, a[j]));
                    counts.step(j, false);
                });
            }
        }
        self.u_ptr.push(self.u_entries.len());
        let pivot = self.a[p * sa + c];
        self.pivots.push((p, c));
        self.pivot_value.push(pivot);
        let u_row = &self.u_entries[u_start..];
        let (rows, cols) = (&mut self.row_pattern[..], &mut self.col_pattern[..]);
        let counts = &mut self.counts;
        // The column's active rows and entries, as `choose_pivot` read them: the
        // elimination changes only other columns.
        for &(i, a_ic) in &self.column {
            if i == p {
                continue;
            }
            let row = &mut self.a[i * sa..(i + 1) * sa];
            let l = a_ic / pivot;
            self.l_entries.push((i, l));
            for &(j, u) in u_row {
                row[j] -= l * u;
            }
            // Fill: the pivot row's active columns new to row i.
            let pattern = &mut rows[i * w..(i + 1) * w];
            let mut count = self.row_count[i] - 1;
            for (fw, (&columns, old)) in self.u_words.iter().zip(pattern).enumerate() {
                let fill = columns & !*old;
                if fill != 0 {
                    *old |= fill;
                    count += fill.count_ones();
                    each_bit(fill, 64 * fw, |j| {
                        set(cols, j * w, i);
                        counts.step(j, true);
                    });
                }
            }
            self.row_count[i] = count;
        }
        self.l_ptr.push(self.l_entries.len());
    }

    /// Zeroes the entries of `a` the last matrix used: those in the row patterns, which
    /// cover every entry loaded or filled in.
    fn clear_values(&mut self) {
        let (sa, w) = (self.stride, self.words);
        for r in 0..self.n {
            let row = &mut self.a[r * sa..(r + 1) * sa];
            for word in 0..w {
                each_bit(self.row_pattern[r * w + word], 64 * word, |c| row[c] = 0.0);
            }
        }
    }

    /// Factorizes the loaded matrix; an error when it is singular.
    fn factor(&mut self) -> Result<(), Singular> {
        for _ in 0..self.n {
            let (p, c) = self.choose_pivot()?;
            self.eliminate(p, c);
        }
        if !regular_pivots(self.pivot_value.iter().copied()) {
            return Err(Singular::Numerically);
        }
        Ok(())
    }
}

impl LinearSolver for MarkowitzLu {
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        self.factored = false;
        self.by_dense = false;
        self.load(n, triplets)?;
        let factored = self.factor();
        self.clear_values();
        match factored {
            Ok(()) => {
                self.factored = true;
                self.solve_again(rhs)
            }
            Err(Singular::Structurally) => Err(LinalgError(
                "singular matrix (Markowitz LU: a column without entries)".into(),
            )),
            Err(Singular::Numerically) => {
                // The reference decides: see `MarkowitzLu::dense`.
                self.by_dense = true;
                self.dense.solve(n, triplets, rhs)
            }
        }
    }
    /// L y = b in pivot order, then U x = y backwards.
    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        if self.by_dense {
            return self.dense.solve_again(rhs);
        }
        if !self.factored {
            return Err(LinalgError("no factorization kept (Markowitz LU)".into()));
        }
        let y = rhs;
        for (&(p, _), l) in self.pivots.iter().zip(self.l_ptr.windows(2)) {
            let v = y[p];
            if v != 0.0 {
                for &(i, l) in &self.l_entries[l[0]..l[1]] {
                    y[i] -= l * v;
                }
            }
        }
        self.x.clear();
        self.x.resize(self.n, 0.0);
        let x = &mut self.x;
        let columns = self.pivots.iter().zip(&self.pivot_value);
        for ((&(p, c), pivot), u) in columns.zip(self.u_ptr.windows(2)).rev() {
            let s = self.u_entries[u[0]..u[1]]
                .iter()
                .fold(y[p], |s, &(j, u)| s - u * x[j]);
            x[c] = s / pivot;
        }
        y[..self.n].copy_from_slice(&self.x);
        finite(y, "Markowitz LU")
    }
    fn name(&self) -> &'static str {
        "markowitz"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random sequence in [−1, 1).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        // The top 53 bits as a fraction.
        #[allow(clippy::cast_precision_loss)]
        let f = (*seed >> 11) as f64 / (1u64 << 53) as f64;
        2.0 * f - 1.0
    }

    /// A sparse matrix with a strong diagonal block (like the mass blocks of eq. 143)
    /// and coupling rows and columns, of size n, as triplets with duplicates.
    fn saddle(n: usize, seed: u64) -> Vec<(usize, usize, f64)> {
        let mut s = seed;
        let mut t = Vec::new();
        let m = n.div_ceil(2);
        for i in 0..m {
            t.push((i, i, 2.0 + lcg(&mut s)));
        }
        for i in 0..n {
            for _ in 0..3 {
                let j = ((lcg(&mut s) + 1.0) * 0.5 * n as f64) as usize % n;
                t.push((i, j, lcg(&mut s)));
                t.push((j, i, lcg(&mut s)));
            }
        }
        // Multiplier rows with a zero diagonal: pivoting must look elsewhere.
        for i in m..n {
            t.push((i, i % m, 1.0));
            t.push((i % m, i, -1.0));
        }
        t
    }

    fn residual(n: usize, t: &[(usize, usize, f64)], x: &[f64], b: &[f64]) -> f64 {
        let mut r = b.to_vec();
        for &(i, j, v) in t {
            r[i] -= v * x[j];
        }
        r.iter().fold(0.0_f64, |m, v| m.max(v.abs())) / n as f64
    }

    #[test]
    fn agrees_with_dense_lu_on_sparse_matrices() {
        for (n, seed) in [(1, 1), (5, 2), (40, 3), (63, 4), (64, 5), (65, 6), (150, 7)] {
            let t = saddle(n, seed);
            let mut s = seed + 100;
            let b: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
            let (mut xd, mut xm) = (b.clone(), b.clone());
            DenseLu::default().solve(n, &t, &mut xd).unwrap();
            let mut lu = MarkowitzLu::default();
            lu.solve(n, &t, &mut xm).unwrap();
            assert!(residual(n, &t, &xm, &b) < 1e-12, "n = {n}");
            let diff = xd
                .iter()
                .zip(&xm)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            let size = xd.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
            assert!(diff <= 1e-9 * size, "n = {n}: {diff} vs {size}");
            // The kept factors solve another right-hand side.
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
            let (mut yd, mut ym) = (c.clone(), c.clone());
            DenseLu::default().solve(n, &t, &mut yd).unwrap();
            lu.solve_again(&mut ym).unwrap();
            assert!(residual(n, &t, &ym, &c) < 1e-12, "n = {n}");
        }
    }

    #[test]
    fn a_reused_solver_solves_like_a_fresh_one() {
        // The storage is cleared by pattern, not zeroed per matrix: sizes that shrink and
        // grow, a singular matrix and bad input in between must leave nothing behind.
        let mut reused = MarkowitzLu::default();
        let mut b = vec![1.0; 2];
        let cancelled = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-16)];
        for (k, (n, seed)) in [(150, 7), (5, 2), (64, 5), (40, 3), (65, 6), (1, 1), (63, 4)]
            .into_iter()
            .enumerate()
        {
            let t = saddle(n, seed);
            let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let (mut fresh, mut again) = (x.clone(), x);
            MarkowitzLu::default().solve(n, &t, &mut fresh).unwrap();
            reused.solve(n, &t, &mut again).unwrap();
            assert_eq!(fresh, again, "n = {n}");
            if k % 2 == 0 {
                assert!(reused.solve(2, &cancelled, &mut b).is_err());
            } else {
                assert!(reused
                    .solve(2, &[(0, 0, 1.0), (5, 0, 1.0)], &mut b)
                    .is_err());
            }
        }
    }

    #[test]
    fn fill_is_followed() {
        // An arrow matrix eliminated from its dense corner fills completely; the
        // solution must still be exact.
        let n = 70;
        let mut t = vec![(0, 0, 1.0)];
        for i in 1..n {
            t.push((0, i, 1.0));
            t.push((i, 0, 1.0));
            t.push((i, i, 3.0));
        }
        let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let mut x = b.clone();
        MarkowitzLu::default().solve(n, &t, &mut x).unwrap();
        assert!(residual(n, &t, &x, &b) < 1e-13);
    }

    #[test]
    fn singular_matrices_are_errors() {
        let mut lu = MarkowitzLu::default();
        let mut b = vec![1.0, 1.0];
        assert!(lu.solve_again(&mut b).is_err(), "nothing factorized yet");
        // An empty column.
        assert!(lu.solve(2, &[(0, 0, 1.0), (1, 0, 2.0)], &mut b).is_err());
        // Dependent rows whose entries cancel to round-off.
        let t = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0 + 1e-16)];
        assert!(lu.solve(2, &t, &mut b).is_err());
        assert!(
            lu.solve_again(&mut b).is_err(),
            "singular factors are not kept"
        );
        // Entries that sum to zero are not in the pattern.
        let t = [(0, 0, 1.0), (1, 1, 1.0), (1, 1, -1.0)];
        assert!(lu.solve(2, &t, &mut b).is_err());
        assert!(lu.solve(2, &[(2, 0, 1.0)], &mut b).is_err(), "outside");
    }

    #[test]
    fn an_entry_outside_leaves_no_values_behind() {
        let mut lu = MarkowitzLu::default();
        let mut b = vec![1.0, 1.0];
        // The entries before the one outside were written, and must be undone.
        let bad = [(0, 0, 1.0), (1, 1, 1.0), (0, 1, 5.0), (2, 0, 1.0)];
        let err = lu.solve(2, &bad, &mut b).unwrap_err();
        assert!(err.0.contains("outside"), "{}", err.0);
        let mut x = vec![2.0, 4.0];
        lu.solve(2, &[(0, 0, 2.0), (1, 1, 4.0)], &mut x).unwrap();
        assert_eq!(x, [1.0, 1.0]);
    }

    #[test]
    fn too_many_unknowns_are_an_error_not_an_allocation() {
        let n = super::MAX_UNKNOWNS + 1;
        let mut b = vec![1.0; n];
        let err = MarkowitzLu::default()
            .solve(n, &[(0, 0, 1.0)], &mut b)
            .unwrap_err();
        assert!(err.0.contains("at most"), "{}", err.0);
        // The automatic choice hands such sizes to sparse LU instead.
        let t: Vec<_> = (0..n).map(|i| (i, i, 2.0)).collect();
        crate::AutoSolver::markowitz(usize::MAX)
            .solve(n, &t, &mut b)
            .unwrap();
        assert!(b.iter().all(|&x| (x - 0.5).abs() < 1e-15));
    }

    /// A column the elimination leaves without entries is singular whatever the values
    /// (here the third: rows 0 and 1 hold it, and they are pivoted on the first two
    /// columns; row 2's only entry, a regularization slot at 0, leaves the pattern), and
    /// it is reported without the dense LU that numerical singularity asks.
    #[test]
    fn a_column_left_without_entries_is_singular_at_once() {
        let t = [
            (0, 0, 2.0),
            (1, 1, 3.0),
            (0, 2, 1.0),
            (1, 2, 1.0),
            (2, 2, 0.0),
        ];
        let mut lu = MarkowitzLu::default();
        let mut b = vec![1.0; 3];
        let err = lu.solve(3, &t, &mut b).unwrap_err();
        assert!(err.0.contains("without entries"), "{}", err.0);
        assert!(!lu.by_dense);
        // Dense LU agrees (row 2 is zero).
        let mut b = vec![1.0; 3];
        assert!(DenseLu::default().solve(3, &t, &mut b).is_err());
        // A numerically zero column (entries that cancel) is still left to dense LU.
        let cancelling = [(0, 0, 1.0), (1, 0, 1.0), (0, 1, 1.0), (1, 1, 1.0)];
        assert!(lu.solve(2, &cancelling, &mut b).is_err());
        assert!(lu.by_dense);
    }
}
