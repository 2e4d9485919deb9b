//! Sparse rows over the unknowns x, and the chain rule through q_{n+1}(x) and
//! u_{n+1}(x) that turns the system's derivatives into rows of the Newton matrix.

use crate::system::Triplets;

/// Rows of a sparse matrix over the columns of x, compressed by row.
#[derive(Debug, Clone, Default)]
pub(crate) struct RowMat {
    ptr: Vec<usize>,
    /// (column, value) of every entry, row after row.
    entries: Vec<(usize, f64)>,
    fill: Vec<usize>,
    pub tmp: Vec<(usize, usize, f64)>,
}

impl RowMat {
    /// Compresses `tmp` (row, col, value) into rows 0..nrows, each row's entries in the
    /// order of `tmp` (a stable counting sort).
    pub(crate) fn build(&mut self, nrows: usize) {
        // Through local slices: a field reached through `self` is reloaded after every
        // store (it compresses the derivative rows of every Newton matrix).
        let ptr = &mut self.ptr;
        ptr.clear();
        ptr.resize(nrows + 1, 0);
        for &(r, _, _) in &self.tmp {
            ptr[r + 1] += 1;
        }
        for i in 0..nrows {
            ptr[i + 1] += ptr[i];
        }
        let fill = &mut self.fill;
        fill.clear();
        fill.extend_from_slice(&ptr[..nrows]);
        self.entries.resize(self.tmp.len(), (0, 0.0));
        let entries = &mut self.entries[..];
        for &(r, c, v) in &self.tmp {
            let at = &mut fill[r];
            entries[*at] = (c, v);
            *at += 1;
        }
        self.tmp.clear();
    }
    pub(crate) fn row(&self, r: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.entries[self.ptr[r]..self.ptr[r + 1]].iter().copied()
    }
}

/// Pushes `scale · D · B` into `out` rows, with `D` given in q-columns, placing the
/// result in the a-block (× c_qa) and the Q-block (× 1): ∂q_{n+1}/∂a = Δt²βα_r B,
/// ∂q_{n+1}/∂Q = B (docs/method.md §4).
pub(crate) fn push_q_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    b: &RowMat,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r, j, v) in &d.entries {
        for (i, bij) in b.row(j) {
            for &(off, c) in cols {
                out.push((row_off + r, off + i, scale * c * v * bij));
            }
        }
    }
}

/// Pushes `scale · D` (D in u-columns, or transposed W when `transpose`) into the
/// column blocks `cols` (offset, factor).
pub(crate) fn push_u_derivative(
    out: &mut Vec<(usize, usize, f64)>,
    d: &Triplets<f64>,
    transpose: bool,
    row_off: usize,
    scale: f64,
    cols: &[(usize, f64)],
) {
    for &(r0, c0, v) in &d.entries {
        let (r, c) = if transpose { (c0, r0) } else { (r0, c0) };
        for &(off, f) in cols {
            out.push((row_off + r, off + c, scale * f * v));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::RowMat;

    /// Each row keeps its entries in the order they were pushed, duplicates included:
    /// the chain rule sums them in that order, and the step's results depend on it to
    /// the last bit.
    #[test]
    fn rows_keep_the_push_order_of_their_entries() {
        let mut m = RowMat::default();
        m.tmp.extend([
            (2, 0, 1.0),
            (0, 3, 2.0),
            (2, 1, 3.0),
            (0, 3, 4.0),
            (2, 0, 5.0),
        ]);
        m.build(4);
        assert!(m.tmp.is_empty());
        let row = |r| m.row(r).collect::<Vec<_>>();
        assert_eq!(row(0), [(3, 2.0), (3, 4.0)]);
        assert!(row(1).is_empty() && row(3).is_empty());
        assert_eq!(row(2), [(0, 1.0), (1, 3.0), (0, 5.0)]);
        // Built again from other entries, nothing of the first matrix is left.
        m.tmp.push((1, 2, 6.0));
        m.build(2);
        assert_eq!(m.row(1).collect::<Vec<_>>(), [(2, 6.0)]);
        assert!(m.row(0).next().is_none());
    }
}
