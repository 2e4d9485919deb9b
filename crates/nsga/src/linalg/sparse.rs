//! faer's supernodal sparse LU for the large Newton matrices of chains (tall block
//! columns), with everything that depends only on the sparsity pattern kept between
//! matrices.
//!
//! The Newton matrix of a chain of n bodies has O(n) nonzeros and, with a column
//! minimum-degree ordering, O(n) fill; the numeric factorization then costs O(n). What a
//! general sparse LU adds per matrix is not: sorting the triplets into compressed
//! columns (O(nnz log nnz)) and the symbolic analysis (ordering, elimination tree,
//! supernodes) cost as much as the factorization itself. Between Newton iterations and
//! steps with the same index sets the triplets arrive with the same (row, column)
//! sequence, so here
//!
//! - the map from each triplet to its slot in the compressed columns is kept, and a
//!   matrix with the same triplet sequence is assembled by one scatter;
//! - the matrix is stored on the *union* of the patterns seen at its size, explicit
//!   zeros included, so the symbolic analysis is redone only when a matrix brings an
//!   entry the union lacks: the index sets switch among a few patterns (a closed contact
//!   row holds W, an open one the identity), and after the first steps their union is
//!   complete. Partial pivoting works on values, so the zeros change no pivot choice
//!   beyond round-off. Unions of the last [`SYMBOLIC_CACHE`] sizes are kept (pruning
//!   changes the size);
//! - the supernodal factorization is forced: on these matrices its numeric phase is
//!   about twice as fast as the simplicial one faer would pick (measured on the Newton
//!   matrices of shaken columns of 15, 20 and 30 blocks: 103 against 184 µs at 255
//!   unknowns, 143 against 264 µs at 340, 205 against 355 µs at 510).

use super::{LinalgError, LinearSolver};
use faer::dyn_stack::MemStack;
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use std::mem::MaybeUninit;

/// Number of matrix sizes whose pattern and symbolic analysis are kept (pruning open
/// contacts changes the size of the Newton matrix), and whose orderings
/// [`BandLu`](super::BandLu) keeps. Set at run time by
/// [`LinearOptions::symbolic_cache`](crate::LinearOptions::symbolic_cache).
///
/// Why more than one: a step's attempts prune different contacts (a fixed-set re-solve
/// prunes only what its sets leave open, §7 of docs/method.md), so consecutive matrices
/// alternate between sizes, and a cache of one size would redo the symbolic analysis at
/// each switch. Only matrices above the block stack's Markowitz crossover reach sparse LU:
/// with the harness (`scripts/reference_workload.py target/release/rollstack --repeat 1
/// --variant linear.symbolic_cache=1`) the 135-run matrix does not change, and the kicked
/// 30-block column takes 146 linear solves against 143 (the union patterns' explicit
/// zeros move pivots at round-off); the time saved was not measured on a quiet machine,
/// so 8 is an argument: a few sizes per step, with room.
pub const SYMBOLIC_CACHE: usize = 8;

/// The matrices of one size: the union of their sparsity patterns in compressed
/// columns, its symbolic analysis, and the triplet → slot map of the last triplet
/// sequence.
#[derive(Debug, Clone)]
struct Assembly {
    n: usize,
    /// The (row, column) of each triplet of the last sequence, in arrival order.
    pattern: Vec<(usize, usize)>,
    /// The slot in `values` each triplet of that sequence adds to.
    slot: Vec<usize>,
    /// The union pattern: rows of each column, sorted.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// The symbolic analysis of the union pattern.
    symbolic: Option<SymbolicLu<usize>>,
}

impl Assembly {
    fn new(n: usize) -> Self {
        Self {
            n,
            pattern: Vec::new(),
            slot: Vec::new(),
            col_ptr: vec![0; n + 1],
            row_idx: Vec::new(),
            values: Vec::new(),
            symbolic: None,
        }
    }

    fn same_sequence(&self, triplets: &[(usize, usize, f64)]) -> bool {
        self.pattern.len() == triplets.len()
            && triplets
                .iter()
                .zip(&self.pattern)
                .all(|(&(r, c, _), &(pr, pc))| r == pr && c == pc)
    }

    /// Maps a new triplet sequence onto the union pattern, growing the union (and
    /// dropping its symbolic analysis) when the sequence has entries it lacks.
    fn map(&mut self, triplets: &[(usize, usize, f64)]) -> Result<(), LinalgError> {
        super::inside(self.n, triplets)?;
        self.pattern.clear();
        self.pattern
            .extend(triplets.iter().map(|&(r, c, _)| (r, c)));
        // One search per triplet while the union holds them all (it nearly always does:
        // on a tall column a second search pass cost a sixth of the run); where it
        // does not, the same pass lists what it lacks, and a second maps the grown union.
        let mut missing = Vec::new();
        if !self.map_slots(&mut missing) {
            self.grow(missing);
            assert!(
                self.map_slots(&mut Vec::new()),
                "the union holds every entry"
            );
        }
        Ok(())
    }

    /// The slot of each entry of `pattern`, in `slot`; false when the union lacks some,
    /// which are then in `missing` as (column, row), and `slot` is partial.
    fn map_slots(&mut self, missing: &mut Vec<(usize, usize)>) -> bool {
        self.slot.clear();
        for &(r, c) in &self.pattern {
            let (lo, hi) = (self.col_ptr[c], self.col_ptr[c + 1]);
            match self.row_idx[lo..hi].binary_search(&r) {
                Ok(i) => self.slot.push(lo + i),
                Err(_) => missing.push((c, r)),
            }
        }
        missing.is_empty()
    }

    /// The union grown by the `missing` entries, (column, row): sorted, merged into each
    /// column's sorted rows. (Sorting the whole union at each growth, about 21 000
    /// entries on a 100-block column whose union grows by a few entries at a time as its
    /// corners rock, took 11 % of that column's run.)
    fn grow(&mut self, mut missing: Vec<(usize, usize)>) {
        let n = self.n;
        let (col_ptr, row_idx) = (&self.col_ptr, &self.row_idx);
        missing.sort_unstable();
        missing.dedup();
        let mut rows = Vec::with_capacity(row_idx.len() + missing.len());
        let mut ptr = vec![0; n + 1];
        let mut new = missing.iter().peekable();
        for c in 0..n {
            let old = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            let mut i = 0;
            while let Some(&(_, r)) = new.next_if(|&&(nc, _)| nc == c) {
                let below = old[i..].partition_point(|&o| o < r);
                rows.extend_from_slice(&old[i..i + below]);
                i += below;
                rows.push(r);
            }
            rows.extend_from_slice(&old[i..]);
            ptr[c + 1] = rows.len();
        }
        self.row_idx = rows;
        self.col_ptr = ptr;
        self.symbolic = None;
    }

    fn scatter(&mut self, triplets: &[(usize, usize, f64)]) {
        self.values.clear();
        self.values.resize(self.row_idx.len(), 0.0);
        for (&s, &(_, _, v)) in self.slot.iter().zip(triplets) {
            self.values[s] += v;
        }
    }

    fn pattern_ref(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }

    fn analyse(&mut self) -> Result<(), LinalgError> {
        if self.symbolic.is_none() {
            let params = LuSymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            };
            let sym = factorize_symbolic_lu(self.pattern_ref(), params)
                .map_err(|e| LinalgError(format!("sparse LU analysis: {e:?}")))?;
            self.symbolic = Some(sym);
        }
        Ok(())
    }
}

/// Sparse LU (faer, supernodal, column minimum-degree ordering) on the union of the
/// patterns seen at each size, with its symbolic analysis and the assembly map kept
/// (see the module docs).
#[derive(Debug, Default, Clone)]
pub struct SparseLu {
    /// The matrices of recent sizes (most recent last).
    sizes: Vec<Assembly>,
    numeric: Option<NumericLu<usize, f64>>,
    /// Whether `numeric` holds the factors of the most recent size's matrix.
    factored: bool,
    scratch: Vec<MaybeUninit<u8>>,
    /// How many sizes are kept.
    kept: KeptSizes,
}

/// How many matrix sizes a [`SparseLu`] keeps: [`SYMBOLIC_CACHE`] unless
/// [`SparseLu::keeping`] says otherwise.
#[derive(Debug, Clone, Copy)]
struct KeptSizes(usize);

impl Default for KeptSizes {
    fn default() -> Self {
        Self(SYMBOLIC_CACHE)
    }
}

impl SparseLu {
    /// A solver that keeps the patterns and symbolic analyses of the last `sizes`
    /// matrix sizes (at least 1) instead of [`SYMBOLIC_CACHE`]
    /// ([`LinearOptions::symbolic_cache`](crate::LinearOptions::symbolic_cache)).
    #[must_use]
    pub fn keeping(sizes: usize) -> Self {
        Self {
            kept: KeptSizes(sizes.max(1)),
            ..Self::default()
        }
    }

    /// The assembly of size n, moved to the end (created when new).
    fn assembly(&mut self, n: usize) -> &mut Assembly {
        let entry = match self.sizes.iter().position(|a| a.n == n) {
            Some(i) => self.sizes.remove(i),
            None => {
                if self.sizes.len() >= self.kept.0 {
                    self.sizes.remove(0);
                }
                Assembly::new(n)
            }
        };
        self.sizes.push(entry);
        self.sizes.last_mut().expect("just pushed")
    }
}

impl LinearSolver for SparseLu {
    fn solve(
        &mut self,
        n: usize,
        triplets: &[(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinalgError> {
        self.factored = false;
        let a = self.assembly(n);
        if !a.same_sequence(triplets) {
            a.map(triplets)?;
        }
        a.analyse()?;
        a.scatter(triplets);
        let par = faer::Par::Seq;
        let bytes = {
            let sym = a.symbolic.as_ref().expect("analysed above");
            sym.factorize_numeric_lu_scratch::<f64>(par, Default::default())
                .unaligned_bytes_required()
        };
        super::grow_scratch(&mut self.scratch, bytes);
        let a = self.sizes.last().expect("the assembly of size n");
        let sym = a.symbolic.as_ref().expect("analysed above");
        let matrix = SparseColMatRef::new(a.pattern_ref(), &a.values);
        let numeric = self.numeric.get_or_insert_with(NumericLu::new);
        sym.factorize_numeric_lu(
            numeric,
            matrix,
            par,
            MemStack::new(&mut self.scratch),
            Default::default(),
        )
        .map_err(|e| LinalgError(format!("sparse LU: {e:?}")))?;
        self.factored = true;
        self.solve_again(rhs)
            .map_err(|_| LinalgError("singular matrix (sparse LU)".into()))
    }

    fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        let sym = self.sizes.last().and_then(|a| a.symbolic.as_ref());
        let (Some(numeric), Some(sym), true) = (&self.numeric, sym, self.factored) else {
            return Err(LinalgError("no factorization kept (sparse LU)".into()));
        };
        let par = faer::Par::Seq;
        let n = rhs.len();
        let bytes = sym
            .solve_in_place_scratch::<f64>(1, par)
            .unaligned_bytes_required();
        super::grow_scratch(&mut self.scratch, bytes);
        let lu = LuRef::new_unchecked(sym, numeric);
        let b = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        lu.solve_in_place_with_conj(faer::Conj::No, b, par, MemStack::new(&mut self.scratch));
        super::finite(rhs, "sparse LU")
    }

    fn name(&self) -> &'static str {
        "sparse"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::DenseLu;

    /// A tridiagonal matrix whose row `open` is replaced by the identity row (an open
    /// contact), as triplets with the diagonal split in two.
    fn chain(n: usize, open: Option<usize>, scale: f64) -> Vec<(usize, usize, f64)> {
        let mut t = Vec::new();
        for i in 0..n {
            if Some(i) == open {
                t.push((i, i, 1.0));
                continue;
            }
            t.push((i, i, 2.0 * scale));
            t.push((i, i, 1.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
            }
            if i > 0 {
                t.push((i, i - 1, -0.5 * scale));
            }
        }
        t
    }

    #[test]
    fn patterns_and_sizes_that_come_and_go_solve_like_dense_lu() {
        let mut sparse = SparseLu::default();
        let cases = [
            (12, None, 1.0),
            (12, Some(3), 1.1),
            (12, None, 0.9),
            (9, Some(0), 1.0),
            (12, Some(3), 1.3),
            (12, Some(7), 0.7),
            (9, None, 2.0),
            (12, Some(7), 0.8),
        ];
        for (n, open, scale) in cases {
            let t = chain(n, open, scale);
            let b: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5).cos()).collect();
            let (mut x, mut y) = (b.clone(), b.clone());
            sparse.solve(n, &t, &mut x).unwrap();
            DenseLu::default().solve(n, &t, &mut y).unwrap();
            for (xi, yi) in x.iter().zip(&y) {
                assert!((xi - yi).abs() < 1e-13, "{n} {open:?}: {xi} vs {yi}");
            }
            let mut again = b.clone();
            sparse.solve_again(&mut again).unwrap();
            assert_eq!(again, x);
        }
        // Two sizes seen: two unions, each grown to hold its patterns.
        assert_eq!(sparse.sizes.len(), 2);
        let twelve = sparse.sizes.iter().find(|a| a.n == 12).unwrap();
        assert!(twelve.symbolic.is_some());
        assert_eq!(twelve.row_idx.len(), 12 + 2 * 11);
    }

    /// Growing the union merges the entries it lacks into each column's sorted rows,
    /// wherever they fall: before, between and after the rows there, in empty columns,
    /// repeated in the sequence, and beside entries it already holds.
    #[test]
    fn the_union_grows_by_merging_sorted_columns() {
        let mut a = Assembly::new(4);
        let t = |entries: &[(usize, usize)]| -> Vec<(usize, usize, f64)> {
            entries.iter().map(|&(r, c)| (r, c, 1.0)).collect()
        };
        a.map(&t(&[(1, 0), (3, 0), (2, 2)])).unwrap();
        assert_eq!(
            (a.col_ptr.clone(), a.row_idx.clone()),
            (vec![0, 2, 2, 3, 3], vec![1, 3, 2])
        );
        a.map(&t(&[
            (0, 0),
            (2, 0),
            (2, 0),
            (3, 0),
            (0, 1),
            (3, 2),
            (1, 2),
            (0, 3),
            (3, 3),
        ]))
        .unwrap();
        assert_eq!(a.col_ptr, [0, 4, 5, 8, 10]);
        assert_eq!(a.row_idx, [0, 1, 2, 3, 0, 1, 2, 3, 0, 3]);
        // Every triplet has its slot in the union.
        for (&s, &(r, c)) in a.slot.iter().zip(&a.pattern) {
            assert!(a.col_ptr[c] <= s && s < a.col_ptr[c + 1] && a.row_idx[s] == r);
        }
    }

    #[test]
    fn an_entry_outside_the_matrix_is_an_error() {
        let mut sparse = SparseLu::default();
        let err = sparse.solve(2, &[(0, 0, 1.0), (2, 1, 1.0)], &mut [1.0, 1.0]);
        assert!(err.is_err());
        assert!(sparse.solve_again(&mut [1.0, 1.0]).is_err());
    }
}
