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
//! LU with partial pivoting, whose verdict stands (see the `dense` field), or, above
//! [`DENSE_VERDICT_UP_TO`] unknowns, factored again with partial pivoting.
//!
//! The number of words per pattern is a compile-time constant of the elimination
//! (1 to [`MAX_WORDS`]), so that the loops over the words of a row or column unroll and
//! need no bounds checks: with a run-time count, walking the patterns cost more than
//! the multiply-adds of the elimination.

use super::{finite, regular_pivots, DenseLu, LinalgError, LinearSolver};

/// A pivot must be at least this fraction of the largest active entry of its column.
/// Duff, Erisman & Reid recommend 0.1: fill stays close to the Markowitz optimum and
/// the growth of the entries stays bounded by (1 + 1/0.1) per elimination step. Set at
/// run time by [`LinearOptions::pivot_threshold`](crate::LinearOptions::pivot_threshold).
/// With the harness (`scripts/reference_workload.py target/release/rollstack --repeat 1
/// --variant linear.pivot_threshold=1 --variant linear.pivot_threshold=0.01`) the pivots
/// change which nearly singular matrices are called singular, and so the work, both ways:
/// partial pivoting (1) takes the matrix 352 847 linear solves against 367 707 (−4.0 %),
/// the Lire collapse 68 against 71, but its floor landing 622 against 567 (+9.7 %); 0.01
/// the matrix 350 186 (−4.8 %) and the floor landing 649 (+14.5 %). Neither pays 5 %
/// without losing more elsewhere; the times were not measured on a quiet machine.
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// Most 64-bit words in a row or column pattern.
const MAX_WORDS: usize = 6;

/// Unknowns up to which a matrix the threshold pivots leave numerically singular is
/// handed to dense LU, whose verdict stands (see `MarkowitzLu::dense`). Above, it is
/// factored again with partial pivoting (threshold 1) in the columns that Markowitz's
/// rule orders, and that verdict stands: dense LU's O(n³) cost, 400–600 µs at 260–300
/// unknowns, was spent mostly on confirming a singular matrix.
///
/// Over the matrices of blocks piled on a floor that the threshold pivots called
/// numerically singular, the two verdicts were compared one by one (a scratch print):
/// on a shaken 14-block column (`rollstack blocks shake --blocks 14 --omega 4 --mu 0.3
/// --amplitude 0.2 --periods 5 --json`) they agreed on 590 of 603 (dense LU: 17
/// regular), at 35 µs against 402 µs each; on a 20-block one (`--blocks 20 --omega 5
/// --amplitude 0.1`) on 222 of 247 (the partial pivots passed the singularity test on
/// 24 that dense LU called singular, and failed on 1 it called regular), at 63 µs
/// against 598 µs. Either verdict then sends a singular matrix to the regularized
/// solve (`LinearOptions::regularization`), which converges from both. Below this size,
/// where the Lire collapses' matrices are, dense LU costs little and keeps deciding.
pub const DENSE_VERDICT_UP_TO: usize = 200;

/// Most unknowns a [`MarkowitzLu`] takes: six words of 64 per pattern. On the chain
/// matrices of a tall column faer's sparse LU is as fast from about 264 unknowns
/// (`MARKOWITZ_SPARSE_THRESHOLD`, the stepper's default crossover), but on the matrices
/// of blocks piled on a floor Markowitz LU stays the faster up to this size (the block
/// stack's `SMALL_LU_UP_TO`); `AutoSolver::markowitz` hands larger matrices to sparse LU.
pub const MAX_UNKNOWNS: usize = 64 * MAX_WORDS;

/// A column's key for the pivot search: its entry count above [`KEY_SHIFT`] bits, its
/// index below, so that the least key is the column of least count, the first of
/// equals. Pivoted columns hold [`RETIRED`].
const KEY_SHIFT: u32 = 16;
const COUNT_ONE: u32 = 1 << KEY_SHIFT;
const RETIRED: u32 = u32::MAX;

/// Sparse LU with Markowitz pivoting on dense storage (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct MarkowitzLu {
    n: usize,
    /// 64-bit words per pattern.
    words: usize,
    /// The matrix, row-major in the original numbering with row length `stride`,
    /// reduced in place. All zeros between factorizations: entry (i, j) is written only
    /// where bit j of row i's pattern is set, the elimination takes each such entry out
    /// as it reads it for the last time (a stopped one leaves the rest to
    /// [`MarkowitzLu::clear_values`]), so a matrix costs its nonzeros and fill, not n²
    /// stores.
    a: Vec<f64>,
    /// Row length of `a`: the largest n seen.
    stride: usize,
    /// Pattern of each row (bit j: column j), and of each column (bit i: row i), in
    /// `words` words each.
    row_pattern: Vec<u64>,
    col_pattern: Vec<u64>,
    /// Counts of entries in the active submatrix, by row.
    row_count: Vec<u32>,
    /// The columns' keys for the pivot search (see [`KEY_SHIFT`]). A scan of the n keys
    /// per pivot, which vectorizes, cost less here than keeping the columns of each
    /// count in bit sets, whose updates (one per entry of U and per fill-in) it saves.
    keys: Vec<u32>,
    /// Pivot k is entry (row, column) with value `pivot_value[k]`.
    pivots: Vec<(usize, usize)>,
    pivot_value: Vec<f64>,
    /// The factors by pivot, compressed: the multipliers of L (rows `l_rows`, values
    /// `l_values`) and the entries of U besides the pivot (columns `u_cols`, values
    /// `u_values`), pivot k's in `l_ptr[k]..l_ptr[k + 1]` and `u_ptr[k]..u_ptr[k + 1]`.
    l_ptr: Vec<usize>,
    l_rows: Vec<u32>,
    l_values: Vec<f64>,
    u_ptr: Vec<usize>,
    u_cols: Vec<u32>,
    u_values: Vec<f64>,
    /// Scratch: the pivot column's active rows and entries, and the solution.
    column_rows: Vec<u32>,
    column_values: Vec<f64>,
    x: Vec<f64>,
    /// Whether the factors of a regular matrix are kept.
    factored: bool,
    /// Dense LU with partial pivoting, for the matrices this elimination finds singular.
    /// Threshold pivots favour sparsity over size, so on a nearly singular matrix (the
    /// Newton matrix of redundant contacts) they can leave a column that cancels to zero
    /// or a pivot below the singularity test where partial pivoting finds usable ones.
    /// Deferring to it makes the singular/regular decision that of dense LU, which the
    /// regularization of redundant contacts (`LinearOptions::regularization`) is tuned
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
    ///
    /// Only matrices of up to [`DENSE_VERDICT_UP_TO`] unknowns are handed on; larger
    /// ones are factored again with partial pivoting in Markowitz's column order.
    dense: DenseLu,
    /// Whether the last matrix was factorized by `dense`.
    by_dense: bool,
    /// The threshold of the pivot test.
    threshold: Threshold,
}

/// The threshold of the pivot test of a [`MarkowitzLu`]: [`PIVOT_THRESHOLD`] unless
/// [`MarkowitzLu::with_threshold`] says otherwise.
#[derive(Debug, Clone, Copy)]
struct Threshold(f64);

impl Default for Threshold {
    fn default() -> Self {
        Self(PIVOT_THRESHOLD)
    }
}

impl MarkowitzLu {
    /// A solver whose pivots pass the threshold test with `threshold` (in (0, 1]; 1 is
    /// partial pivoting) instead of [`PIVOT_THRESHOLD`]
    /// ([`LinearOptions::pivot_threshold`](crate::LinearOptions::pivot_threshold)).
    #[must_use]
    pub fn with_threshold(threshold: f64) -> Self {
        Self {
            threshold: Threshold(threshold),
            ..Self::default()
        }
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

fn bit(i: usize) -> u64 {
    1 << (i % 64)
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

/// The bit set of indices 0..n in `W` words.
fn first<const W: usize>(n: usize) -> [u64; W] {
    std::array::from_fn(|w| match n.saturating_sub(64 * w) {
        0 => 0,
        k if k >= 64 => u64::MAX,
        k => (1 << k) - 1,
    })
}

fn ones<const W: usize>(words: &[u64; W]) -> u32 {
    words.iter().map(|w| w.count_ones()).sum()
}

/// The least key of `keys` (see [`KEY_SHIFT`]): a branch-free fold, which vectorizes.
fn least_key(keys: &[u32]) -> u32 {
    keys.iter().fold(RETIRED, |m, &k| m.min(k))
}

/// The pivot row in a column whose active entries are `values` in `rows`, the largest
/// in magnitude `largest`: among the entries passing the threshold test (at least
/// `threshold` times the largest: [`PIVOT_THRESHOLD`], or 1 for partial pivoting), the
/// one of least row count, which minimizes Markowitz's (r − 1)(c − 1) within the column;
/// ties go to the larger entry, then to the first row: (row, entry). None when every
/// entry is zero (NaN entries fail the test too).
fn pivot_row(
    rows: &[u32],
    values: &[f64],
    largest: f64,
    row_count: &[u32],
    threshold: f64,
) -> Option<(usize, f64)> {
    let nonzero = largest > 0.0;
    if !nonzero {
        return None;
    }
    let mut best: Option<(u32, usize, f64, f64)> = None;
    for (&i, &value) in rows.iter().zip(values) {
        let (i, v) = (i as usize, value.abs());
        let r = row_count[i];
        if v >= threshold * largest
            && best.is_none_or(|(br, _, bv, _)| r < br || (r == br && v > bv))
        {
            best = Some((r, i, v, value));
        }
    }
    best.map(|(_, i, _, value)| (i, value))
}

impl MarkowitzLu {
    /// Loads J from triplets (duplicates summed; entries summing to zero are left out
    /// of the pattern), with `W` words per pattern.
    fn load<const W: usize>(
        &mut self,
        triplets: &[(usize, usize, f64)],
    ) -> Result<(), LinalgError> {
        let (n, sa) = (self.n, self.stride);
        self.row_pattern.clear();
        self.row_pattern.resize(n * W, 0);
        self.col_pattern.clear();
        self.col_pattern.resize(n * W, 0);
        // The buffers as plain slices: the loops below write through them once per
        // triplet, and a field reached through `self` is reloaded after every store.
        let a = &mut self.a[..];
        let rows = self.row_pattern.as_chunks_mut::<W>().0;
        let cols = self.col_pattern.as_chunks_mut::<W>().0;
        for (k, &(r, c, v)) in triplets.iter().enumerate() {
            if r >= n || c >= n {
                // The storage stays zeroed between matrices: undo what was written.
                for &(r, c, _) in &triplets[..k] {
                    a[r * sa + c] = 0.0;
                }
                return Err(outside(r, c, n));
            }
            a[r * sa + c] += v;
            rows[r][c / 64] |= bit(c);
        }
        // Entries that summed to zero leave the row patterns, and the column patterns
        // are the rows' transposed: one pass over the distinct entries, where a pass per
        // triplet paid for the duplicates too (about half the triplets of eq. 143's
        // matrices, whose rows sum the system's derivatives).
        for (r, row) in rows.iter_mut().enumerate() {
            let values = &a[r * sa..r * sa + n];
            for w in 0..W {
                let mut zero = 0;
                each_bit(row[w], 64 * w, |c| {
                    if values[c] == 0.0 {
                        zero |= bit(c);
                    } else {
                        cols[c][r / 64] |= bit(r);
                    }
                });
                row[w] &= !zero;
            }
        }
        self.row_count.clear();
        self.row_count.extend(rows.iter().map(ones));
        self.keys.clear();
        self.keys.extend(
            cols.iter()
                .enumerate()
                .map(|(c, col)| ones(col) << KEY_SHIFT | c as u32),
        );
        self.pivots.clear();
        self.pivot_value.clear();
        for ptr in [&mut self.l_ptr, &mut self.u_ptr] {
            ptr.clear();
            ptr.push(0);
        }
        self.l_rows.clear();
        self.l_values.clear();
        self.u_cols.clear();
        self.u_values.clear();
        Ok(())
    }

    /// Factorizes the loaded matrix, `W` words per pattern; an error when it is
    /// singular. Each step takes the pivot by Markowitz's rule, searched in one column:
    /// the active column of least count c (the first of equals), and in it, among the
    /// entries passing the threshold test, the one of least row count r, which minimizes
    /// (r − 1)(c − 1) there; ties go to the larger entry, then to the first row. Then
    /// it stores U row k and the multipliers of L, and updates the active rows of the
    /// pivot column by the pivot row, following its fill.
    ///
    /// Searching two or four columns of least count (Zlatev's strategy) lowered the fill
    /// on the Lire collapse's Newton matrices only slightly and cost more in the search
    /// than it saved.
    fn factor<const W: usize>(&mut self, threshold: f64) -> Result<(), Singular> {
        let (n, sa) = (self.n, self.stride);
        let rows = self.row_pattern.as_chunks_mut::<W>().0;
        let cols = self.col_pattern.as_chunks_mut::<W>().0;
        let (a, keys, row_count) = (&mut self.a[..], &mut self.keys[..], &mut self.row_count);
        let (l_rows, l_values) = (&mut self.l_rows, &mut self.l_values);
        let (u_cols, u_values) = (&mut self.u_cols, &mut self.u_values);
        let (column_rows, column_values) = (&mut self.column_rows, &mut self.column_values);
        let mut active_rows = first::<W>(n);
        let mut active_cols = active_rows;
        for _ in 0..n {
            // The column of least count, and its active entries (rows in increasing
            // order), read from the storage once: the elimination changes only other
            // columns.
            let key = least_key(keys);
            if key == RETIRED {
                return Err(Singular::Structurally);
            }
            let c = (key & (COUNT_ONE - 1)) as usize;
            column_rows.clear();
            column_values.clear();
            let mut largest = 0.0_f64;
            for w in 0..W {
                each_bit(cols[c][w] & active_rows[w], 64 * w, |i| {
                    // Read for the last time: the storage is left zeroed as it is read.
                    let v = std::mem::take(&mut a[i * sa + c]);
                    largest = largest.max(v.abs());
                    column_rows.push(i as u32);
                    column_values.push(v);
                });
            }
            if column_rows.is_empty() {
                return Err(Singular::Structurally);
            }
            let (p, pivot) = pivot_row(column_rows, column_values, largest, row_count, threshold)
                .ok_or(Singular::Numerically)?;

            // U row k: the pivot row's active entries, which leave their columns' counts.
            active_rows[p / 64] &= !bit(p);
            active_cols[c / 64] &= !bit(c);
            keys[c] = RETIRED;
            let u_start = u_cols.len();
            let mut u_words = [0; W];
            for w in 0..W {
                u_words[w] = rows[p][w] & active_cols[w];
                each_bit(u_words[w], 64 * w, |j| {
                    u_cols.push(j as u32);
                    u_values.push(std::mem::take(&mut a[p * sa + j]));
                    keys[j] -= COUNT_ONE;
                });
            }
            self.u_ptr.push(u_cols.len());
            self.pivots.push((p, c));
            self.pivot_value.push(pivot);
            let (u_row_cols, u_row) = (&u_cols[u_start..], &u_values[u_start..]);
            for (&i, &a_ic) in column_rows.iter().zip(column_values.iter()) {
                let i = i as usize;
                if i == p {
                    continue;
                }
                let row = &mut a[i * sa..(i + 1) * sa];
                let l = a_ic / pivot;
                l_rows.push(i as u32);
                l_values.push(l);
                for (&j, &u) in u_row_cols.iter().zip(u_row) {
                    row[j as usize] -= l * u;
                }
                // Fill: the pivot row's active columns new to row i.
                let mut count = row_count[i] - 1;
                for w in 0..W {
                    let fill = u_words[w] & !rows[i][w];
                    if fill != 0 {
                        rows[i][w] |= fill;
                        count += fill.count_ones();
                        each_bit(fill, 64 * w, |j| {
                            cols[j][i / 64] |= bit(i);
                            keys[j] += COUNT_ONE;
                        });
                    }
                }
                row_count[i] = count;
            }
            self.l_ptr.push(l_rows.len());
        }
        if !regular_pivots(self.pivot_value.iter().copied()) {
            return Err(Singular::Numerically);
        }
        Ok(())
    }

    /// Zeroes the entries of `a` the last matrix used: those in the row patterns, which
    /// cover every entry loaded or filled in. Needed only after an elimination that
    /// stopped: a whole one reads every entry for the last time as a pivot row or a
    /// pivot column retires, and zeroes it then.
    fn clear_values(&mut self) {
        let (sa, w) = (self.stride, self.words);
        for (r, row) in self.row_pattern.chunks_exact(w.max(1)).enumerate() {
            let values = &mut self.a[r * sa..(r + 1) * sa];
            for (word, &bits) in row.iter().enumerate() {
                each_bit(bits, 64 * word, |c| values[c] = 0.0);
            }
        }
    }

    /// Sizes the storage for matrices of n unknowns (at most [`MAX_UNKNOWNS`]).
    fn size_for(&mut self, n: usize) {
        if n > self.stride {
            self.stride = n;
            self.a = vec![0.0; n * n];
        }
        self.n = n;
        self.words = n.div_ceil(64);
    }

    /// [`MarkowitzLu::load_and_factor`] with the words of the current size, pivots
    /// passing `threshold` (see [`pivot_row`]).
    fn load_and_factor_any(
        &mut self,
        triplets: &[(usize, usize, f64)],
        threshold: f64,
    ) -> Result<Result<(), Singular>, LinalgError> {
        match self.words {
            0 | 1 => self.load_and_factor::<1>(triplets, threshold),
            2 => self.load_and_factor::<2>(triplets, threshold),
            3 => self.load_and_factor::<3>(triplets, threshold),
            4 => self.load_and_factor::<4>(triplets, threshold),
            5 => self.load_and_factor::<5>(triplets, threshold),
            _ => self.load_and_factor::<MAX_WORDS>(triplets, threshold),
        }
    }

    /// Loads and factorizes with `W` words per pattern, leaving the storage zeroed.
    fn load_and_factor<const W: usize>(
        &mut self,
        triplets: &[(usize, usize, f64)],
        threshold: f64,
    ) -> Result<Result<(), Singular>, LinalgError> {
        self.load::<W>(triplets)?;
        let factored = self.factor::<W>(threshold);
        if factored.is_err() {
            self.clear_values();
        }
        Ok(factored)
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
        if n > MAX_UNKNOWNS {
            return Err(LinalgError(format!(
                "{n} unknowns: Markowitz LU takes at most {MAX_UNKNOWNS}"
            )));
        }
        self.size_for(n);
        match self.load_and_factor_any(triplets, self.threshold.0)? {
            Ok(()) => {}
            Err(Singular::Structurally) => {
                return Err(LinalgError(
                    "singular matrix (Markowitz LU: a column without entries)".into(),
                ))
            }
            Err(Singular::Numerically) if n <= DENSE_VERDICT_UP_TO => {
                // The reference decides: see `MarkowitzLu::dense`.
                self.by_dense = true;
                return self.dense.solve(n, triplets, rhs);
            }
            Err(Singular::Numerically) => {
                // Partial pivoting within the columns Markowitz's rule orders decides.
                if self.load_and_factor_any(triplets, 1.0)?.is_err() {
                    return Err(LinalgError(
                        "singular matrix (Markowitz LU with partial pivoting)".into(),
                    ));
                }
            }
        }
        self.factored = true;
        self.solve_again(rhs)
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
                let (rows, values) = (&self.l_rows[l[0]..l[1]], &self.l_values[l[0]..l[1]]);
                for (&i, &l) in rows.iter().zip(values) {
                    y[i as usize] -= l * v;
                }
            }
        }
        self.x.clear();
        self.x.resize(self.n, 0.0);
        let x = &mut self.x;
        let columns = self.pivots.iter().zip(&self.pivot_value);
        for ((&(p, c), pivot), u) in columns.zip(self.u_ptr.windows(2)).rev() {
            let (cols, values) = (&self.u_cols[u[0]..u[1]], &self.u_values[u[0]..u[1]]);
            let s = cols
                .iter()
                .zip(values)
                .fold(y[p], |s, (&j, &u)| s - u * x[j as usize]);
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
mod tests;
